"""classify() gives `objmodel classify --json`; plan() gives `objmodel plan --json`."""

import json
import subprocess

import numpy as np
import pytest

import objmodel
import topple
from conftest import write_tum
from test_inputs import cli


def test_classify_an_array(box):
    t, m, truth = topple.topple(box, "+y")
    c = objmodel.classify(topple.rows_of(t, m))
    assert c["kind"] == "topple"
    assert c["file"] is None and c["palm_file"] is None
    assert c["name"] == "demo"
    assert [s["kind"] for s in c["segments"]] == ["topple"]
    e = c["segments"][0]["edge"]
    dist, ang = topple.line_distance(truth["point"], truth["direction"],
                                     np.array(e["line"]["point"]), np.array(e["line"]["direction"]))
    assert dist < 1e-6 and ang < 1e-6


def test_classify_a_file_is_the_command_lines(tmp_path, box):
    t, m, truth = topple.topple(box, "-x")
    path = write_tum(tmp_path / "d.tum", topple.rows_of(t, m))
    c = objmodel.classify(path)
    assert c["kind"] == "topple" and c["file"] == str(path)
    same = objmodel.classify(m, times=t, name="d.tum")
    assert same["kind"] == "topple" and same["frames"] == c["frames"]
    exe = cli()
    if exe is None:
        pytest.skip("no objmodel command-line tool built (set OBJMODEL_CLI)")
    out = subprocess.run([exe, "classify", "--json", str(path)], capture_output=True, text=True, check=True)
    assert json.loads(out.stdout) == c


def test_classify_at_rest_is_an_error():
    rows = np.tile([0.0, 0, 0, 0.1, 0, 0, 0, 1], (100, 1))
    rows[:, 0] = np.arange(100) / 30
    with pytest.raises(objmodel.ObjmodelError, match=r"^still: nothing to learn: no motion in its 100 frames"):
        objmodel.classify(rows, name="still")


def test_plan_on_a_level_palm(full_tree, box):
    # The box stands on its bottom face on a level palm: the tag frame is level, the tag at
    # the box's height above the palm. The easiest topple is over a long edge, across the
    # short half extent (0.035 m): phi = atan(0.035 / 0.08).
    p = objmodel.plan(full_tree, object_in_palm=[0.01, 0.02, 2 * box.half[2], 0, 0, 0, 1])
    phi = np.arctan2(box.half[1], box.half[2])
    assert p["phi"] == pytest.approx(phi, abs=np.radians(0.1))
    assert p["tilt"] == pytest.approx(p["phi"] - p["current_tilt"] + p["margin"])
    assert abs(p["axis_direction"][2]) < 1e-6  # a horizontal tilt axis
    assert p["axis_point"][2] == pytest.approx(0.0, abs=1e-6)  # on the palm's surface
    assert p["edge"] in [e["id"] for e in full_tree.to_dict()["edges"]]
    # The same pose as a matrix, and towards a direction.
    m = np.eye(4)
    m[:3, 3] = [0.01, 0.02, 2 * box.half[2]]
    assert objmodel.plan(full_tree, object_in_palm=m) == p
    toward = objmodel.plan(full_tree, object_in_palm=m, towards=-np.array(p["topple_direction"]))
    assert np.dot(toward["topple_direction"], p["topple_direction"]) < -0.99


def test_plan_from_a_file_and_its_errors(tmp_path, full_tree, box):
    path = tmp_path / "box.json"
    full_tree.save(path)
    a = objmodel.plan(path, object_in_palm="0 0 0.16 0 0 0 1")
    assert a == objmodel.plan(full_tree, object_in_palm=[0, 0, 0.16, 0, 0, 0, 1])
    with pytest.raises(objmodel.ObjmodelError, match="give object_in_palm or from_demo"):
        objmodel.plan(full_tree)
    with pytest.raises(objmodel.ObjmodelError, match="quaternion .* has norm 2"):
        objmodel.plan(full_tree, object_in_palm=[0, 0, 0.16, 0, 0, 0, 2])
    # On its side, the object rests on a face no demonstration toppled it from.
    with pytest.raises(objmodel.ObjmodelError, match="a demonstration of toppling it from this face is needed"):
        objmodel.plan(full_tree, object_in_palm=[0, 0, 0.1, np.sin(np.pi / 4), 0, 0, np.cos(np.pi / 4)])
    exe = cli()
    if exe is None:
        pytest.skip("no objmodel command-line tool built (set OBJMODEL_CLI)")
    out = subprocess.run([exe, "plan", "--model", str(path), "--object-in-palm", "0 0 0.16 0 0 0 1",
                          "--json"], capture_output=True, text=True, check=True)
    assert json.loads(out.stdout) == a


def test_plan_from_a_demonstration_on_a_palm(full_tree, every_face):
    # A palm turned by 90 degrees about z and raised: the object's first pose on it, and
    # gravity in its frame, come from the first poses of both.
    _, rows = every_face
    obj = rows[0]
    c, s = np.cos(np.pi / 4), np.sin(np.pi / 4)
    palm = np.tile([0.0, 0.2, -0.1, 0.05, 0.0, 0.0, s, c], (len(obj), 1))
    palm[:, 0] = obj[:, 0]
    world_from_palm = np.eye(4)
    world_from_palm[:3, :3] = topple.rot((0, 0, 1), np.pi / 2)
    world_from_palm[:3, 3] = [0.2, -0.1, 0.05]
    world_from_obj = np.eye(4)
    world_from_obj[:3, 3] = obj[0, 1:4]
    x, y, z, w = obj[0, 4:]
    world_from_obj[:3, :3] = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                              [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                              [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    palm_from_obj = np.linalg.inv(world_from_palm) @ world_from_obj
    want = objmodel.plan(full_tree, object_in_palm=palm_from_obj)
    got = objmodel.plan(full_tree, from_demo=obj, palm=palm)
    assert got.keys() == want.keys()
    for k, v in want.items():
        if isinstance(v, str) or v is None:
            assert got[k] == v, k
        else:
            np.testing.assert_allclose(got[k], v, atol=1e-9, err_msg=k)
    with pytest.raises(objmodel.ObjmodelError, match="from_demo: no palm given"):
        objmodel.plan(full_tree, from_demo=obj)


def test_held_poses_are_counted(box):
    """A tracker that held its last pose for 0.3 s while the box turned: with 1 mm of noise at
    rest, its 30 repeats are left out and counted; exact poses repeat at rest and keep them."""
    t, m, truth = topple.topple(box, "+x")
    rows = topple.rows_of(t, m)
    assert objmodel.classify(rows)["held_frames"] == 0
    rng = np.random.default_rng(7)
    noisy = rows.copy()
    noisy[:, 1:4] += rng.normal(0.0, 1e-3, (len(rows), 3))
    q = noisy[:, 4:8] + rng.normal(0.0, 2e-3, (len(rows), 4))
    noisy[:, 4:8] = q / np.linalg.norm(q, axis=1)[:, None]
    moving = np.flatnonzero(np.any(np.diff(rows[:, 1:], axis=0) != 0.0, axis=1))
    k = moving[len(moving) // 2]
    noisy[k + 1:k + 31, 1:] = noisy[k, 1:]
    c = objmodel.classify(noisy)
    assert c["held_frames"] == 30, c["warnings"]
    assert any("holding its last pose" in w for w in c["warnings"])
