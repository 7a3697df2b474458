"""The Python examples of README.md and crates/objmodel-py/README.md run as written, with
`poses_a` and `poses_b` two exact demonstrations (a box toppled three times in a row, and
twice: together they rest it on every face) and `demo.tum` the first as a file."""

import re
from pathlib import Path

import numpy as np
import pytest

import objmodel
import topple
from conftest import write_tum

ROOT = Path(__file__).resolve().parents[3]


def python_blocks(path):
    return re.findall(r"```python\n(.*?)```", path.read_text(), re.S)


@pytest.mark.parametrize("readme", ["README.md", "crates/objmodel-py/README.md"])
def test_the_readme_examples_run(readme, tmp_path, monkeypatch, box):
    blocks = python_blocks(ROOT / readme)
    assert blocks, f"no python example in {readme}"
    ta, ma, truths_a = topple.rolls(box, ["+x", "+x", "+y"])
    tb, mb, truths_b = topple.rolls(box, ["-x", "-y"], yaw=-0.5, t0=2000.0)
    poses_a, poses_b = topple.rows_of(ta, ma), topple.rows_of(tb, mb)
    monkeypatch.chdir(tmp_path)
    write_tum(tmp_path / "demo.tum", poses_a)
    scope = {"poses_a": poses_a, "poses_b": poses_b}
    for code in blocks:
        exec(compile(code, readme, "exec"), scope)
    tree = scope["tree"]
    assert isinstance(tree, objmodel.Tree)
    assert (tmp_path / "box.xml").exists() and (tmp_path / "box.urdf").exists()
    # The tree is the box's: the five edges toppled over, its six faces, its centre.
    assert tree.edges.shape == (5, 6) and tree.faces.shape == (6, 4)
    assert np.linalg.norm(tree.com - truths_a[0]["com"]) < 1e-4
    for truth in truths_a + truths_b:
        dist, ang = min(topple.line_distance(truth["point"], truth["direction"], e[:3], e[3:])
                        for e in tree.edges)
        assert dist < 1e-5 and ang < 1e-6
