"""Fixtures: exact demonstrations (topple.py) and the tree learnt from a box toppled onto
every face, shared by the tests of a module."""

import numpy as np
import pytest

import objmodel
import topple


@pytest.fixture(scope="session")
def box():
    return topple.Box(half=(0.05, 0.035, 0.08))


@pytest.fixture(scope="session")
def every_face(box):
    """Six topples (times, world_from_tag matrices, truth) and their (N, 8) rows."""
    demos = topple.every_face(box)
    return demos, [topple.rows_of(t, m) for t, m, _ in demos]


@pytest.fixture(scope="session")
def full_tree(every_face):
    _, rows = every_face
    return objmodel.learn(rows, gravity=(0, 0, -1))


def write_tum(path, rows):
    """Rows as a TUM file, every number round-tripping exactly."""
    with open(path, "w") as f:
        f.write("# t x y z qx qy qz qw\n")
        for r in rows:
            f.write(" ".join(repr(float(x)) for x in r) + "\n")
    return path
