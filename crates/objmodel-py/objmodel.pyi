"""Type hints of the objmodel extension module (src/*.rs holds the implementation and the
docstrings; maturin puts this file and py.typed in the wheel)."""

import os
from typing import Any, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

__version__: str
QUAT_NORM_TOLERANCE: float

PathLike = Union[str, os.PathLike]
# A pose file, (N, 8) rows t x y z qx qy qz qw, or (N, 4, 4) matrices (with times).
Poses = Union[PathLike, npt.ArrayLike]
Vec3 = Union[Sequence[float], npt.ArrayLike]
Gravity = Union[Vec3, str, None]

class ObjmodelError(ValueError): ...
class ObjmodelWarning(UserWarning): ...

class Tree:
    EDGE_COLUMNS: tuple[str, str, str, str, str, str]
    FACE_COLUMNS: tuple[str, str, str, str]
    PENDULUM_COLUMNS: list[str]
    def __init__(self) -> None: ...
    @staticmethod
    def load(path: PathLike) -> Tree: ...
    def save(self, path: PathLike) -> None: ...
    @property
    def edges(self) -> np.ndarray: ...
    @property
    def faces(self) -> np.ndarray: ...
    @property
    def pendulums(self) -> np.ndarray: ...
    @property
    def com(self) -> Optional[np.ndarray]: ...
    @property
    def vertices(self) -> Optional[np.ndarray]: ...
    @property
    def demos(self) -> list[str]: ...
    def to_json(self) -> str: ...
    def to_dict(self) -> dict[str, Any]: ...
    def export_mjcf(self, path: PathLike, mass: float, *, friction: Optional[float] = None,
                    name: Optional[str] = None) -> list[str]: ...
    def export_urdf(self, path: PathLike, mass: float, *, friction: Optional[float] = None,
                    name: Optional[str] = None) -> list[str]: ...

def learn(demos: Union[Poses, Sequence[Poses]], *,
          palms: Union[Poses, Sequence[Optional[Poses]], None] = None,
          times: Union[npt.ArrayLike, Sequence[Optional[npt.ArrayLike]], None] = None,
          names: Union[str, Sequence[Optional[str]], None] = None,
          gravity: Gravity = (0.0, 0.0, -1.0),
          into: Union[Tree, PathLike, None] = None,
          no_palm: bool = False, quat_order: str = "xyzw", method: str = "robust",
          gravity_check: bool = True,
          rigid_bodies: Union[str, tuple[str, Optional[str]], None] = None,
          support_height: Optional[float] = None, support_sigma: float = 0.001,
          keep_going: bool = False,
          **options: Union[float, str]) -> Tree: ...

def classify(demo: Poses, *, palm: Optional[Poses] = None,
             times: Optional[npt.ArrayLike] = None, name: Optional[str] = None,
             gravity: Gravity = (0.0, 0.0, -1.0), no_palm: bool = False,
             quat_order: str = "xyzw", method: str = "robust",
             rigid_bodies: Union[str, tuple[str, Optional[str]], None] = None,
             **options: Union[float, str]) -> dict[str, Any]: ...

def plan(tree: Union[Tree, PathLike], *, object_in_palm: Union[str, npt.ArrayLike, None] = None,
         gravity_in_palm: Optional[Vec3] = None, from_demo: Optional[Poses] = None,
         palm: Optional[Poses] = None, times: Optional[npt.ArrayLike] = None,
         gravity: Gravity = (0.0, 0.0, -1.0), towards: Optional[Vec3] = None,
         margin: Optional[float] = None, quat_order: str = "xyzw") -> dict[str, Any]: ...

def synthetic_topples(half: tuple[float, float, float] = (0.05, 0.035, 0.08), *,
                      tag_offset: tuple[float, float] = (0.01, -0.005), tag_yaw: float = 0.7,
                      noise: str = "clean", seed: int = 0) -> list[dict[str, Any]]: ...
