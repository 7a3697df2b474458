"""Bad input raises ObjmodelError (a ValueError) that names the array, the row and the
problem; files give the command line's messages."""

import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

import objmodel
import topple
from conftest import write_tum


@pytest.fixture(scope="module")
def rows():
    t, m, _ = topple.topple(topple.Box(), "+x")
    return topple.rows_of(t, m), t, m


def raises(match, *args, **kwargs):
    with pytest.raises(objmodel.ObjmodelError, match=match) as e:
        objmodel.learn(*args, **kwargs)
    assert isinstance(e.value, ValueError)
    return str(e.value)


def test_shapes(rows):
    r, t, m = rows
    raises(r"demos\[0\]: shape \(543, 7\): rows need 8 columns.*time column missing", [r[:, 1:]])
    raises(r"demos\[1\]: shape \(543, 3, 3\); expected \(N, 8\) rows", [r, m[:, :3, :3]], times=[None, t])
    raises(r"demos: shape \(8,\); expected \(N, 8\)", r[0])
    raises(r"demos\[0\]: no poses: the array is empty", [r[:0]])
    raises(r"need their times: pass times=", [m])
    raises(r"\(N, 8\) rows carry their times in column 0; `times` goes with \(N, 4, 4\)", [r], times=[t])
    raises(r"543 matrices but times of shape \(542,\)", [m], times=[t[1:]])
    raises(r"not an array of numbers", [[[1, 2], [3]]])
    raises(r"palms has 1 entries for 2 demonstrations", [r, r], palms=[None])
    raises(r"no demonstrations given", [])


def test_values(rows):
    r, t, m = rows
    bad = r.copy()
    bad[5, 2] = np.nan
    raises(r"^demos\[0\]\[5\]: ty is NaN; every value must be a finite number \(rows are t x y z qx qy qz qw\)$", [bad])
    bad = r.copy()
    bad[7, 4:] *= 2
    raises(r"demos\[0\]\[7\]: quaternion \(qx qy qz qw\) = .* has norm 2, which differs from 1 by more than the tolerance 0.01", [bad])
    bad = r.copy()
    bad[9, 0] = bad[8, 0]
    bad[9, 1] += 1e-3  # (the same pose again is a copy: below)
    raises(r"demos\[0\]\[9\]: timestamp .* repeats timestamp .* of row 8 \(timestamps must strictly increase\)", [bad])
    bad = r.copy()
    bad[9, 0] = bad[7, 0]
    raises(r"demos\[0\]\[9\]: timestamp .* goes back from timestamp", [bad])


def test_lost_rows_are_left_out_with_a_warning(rows):
    """Rows where the tracker lost the object (every pose value NaN, or zero; a matrix NaN
    above its last row) are frames not recorded: the tree is the one without them."""
    r, t, m = rows
    lost = r.copy()
    lost[100:111, 1:] = np.nan
    lost[300, 1:] = 0.0
    with pytest.warns(objmodel.ObjmodelWarning,
                      match=r"demos\[0\]: the tracker lost the object in 12 rows \(the first 100, the last 300\)"):
        a = objmodel.learn([lost])
    keep = np.ones(len(r), bool)
    keep[100:111] = keep[300] = False
    b = objmodel.learn([r[keep]])
    assert a.edges.shape == (1, 6)
    np.testing.assert_array_equal(a.edges, b.edges)
    lost_m = m.copy()
    lost_m[100:111, :3, :] = np.nan
    lost_m[300, :3, :] = np.nan
    with pytest.warns(objmodel.ObjmodelWarning, match=r"lost the object in 12 rows"):
        c = objmodel.learn([lost_m], times=[t])
    np.testing.assert_allclose(c.edges, b.edges, atol=1e-9)
    # Some values NaN and others not: still an error (above); all rows lost: no poses.
    raises(r"demos\[0\]: no poses: every row is a frame where the tracker lost the object",
           [np.column_stack([t, np.full((len(t), 7), np.nan)])])


def test_rows_written_twice_are_kept_once_with_a_warning(rows):
    """A row that repeats the row before exactly (its time and pose: a logger that wrote it
    twice) is the same frame: left out, counted, and the tree is the one without the copies.
    The same time with another pose is still an error, naming the row of the pose before."""
    r, _, _ = rows
    doubled = np.insert(r, [50, 50, 200], r[[49, 49, 199]], axis=0)
    with pytest.warns(objmodel.ObjmodelWarning,
                      match=r"demos\[0\]: 3 rows repeat the row before exactly \(the first 50: the same time and pose\)"):
        a = objmodel.learn([doubled])
    b = objmodel.learn([r])
    assert a.edges.shape == (1, 6)
    np.testing.assert_array_equal(a.edges, b.edges)
    # After lost rows, the row a repeated time repeats is the last one kept.
    bad = r.copy()
    bad[10:12, 1:] = np.nan
    bad[12, 0] = bad[9, 0]
    bad[12, 1] += 1e-3
    raises(r"demos\[0\]\[12\]: timestamp .* repeats timestamp .* of row 9 ", [bad])


def test_keep_going_leaves_out_what_cannot_be_read(tmp_path, rows):
    """keep_going=True: an unreadable file is left out with a warning giving its error, and
    the tree is the one the others give alone; without it, the error is raised."""
    r, _, _ = rows
    good = tmp_path / "good.tum"
    write_tum(good, r)
    broken = tmp_path / "broken.tum"
    broken.write_text("1 0 0 0 0 0 0 1\n2 0 0 0 0 0 1\n")
    raises(r"broken.tum:2: expected 8 columns", [str(good), str(broken)])
    with pytest.warns(objmodel.ObjmodelWarning,
                      match=r"broken.tum: could not be read and was left out \(keep_going\): .*broken.tum:2: expected 8 columns"):
        tree = objmodel.learn([str(broken), str(good), r], names=[None, None, "rows"],
                              keep_going=True)
    alone = objmodel.learn([str(good), r], names=[None, "rows"])
    assert tree.to_json() == alone.to_json()
    model = tmp_path / "model.json"
    with pytest.warns(objmodel.ObjmodelWarning, match=r"left out \(keep_going\)"):
        objmodel.learn([str(good), str(broken)], into=str(model), keep_going=True)
    assert objmodel.Tree.load(str(model)).to_json() == objmodel.learn([str(good)]).to_json()


def test_quaternion_order_mistakes(rows):
    r, t, m = rows
    with pytest.raises(objmodel.ObjmodelError, match=r'quat_order must be "xyzw" .* or "wxyz"'):
        objmodel.learn([r], quat_order="wzyx")
    # Columns t qx qy qz qw x y z (quaternion before position): the "quaternion" is a
    # position, whose norm is far from 1.
    swapped = r[:, [0, 4, 5, 6, 7, 1, 2, 3]]
    raises(r"demos\[0\]\[0\]: quaternion .* has norm .* \(rows are t x y z qx qy qz qw\)", [swapped])
    # Rows with the quaternion first and no time: 7 columns.
    raises(r"rows need 8 columns", [r[:, [4, 5, 6, 7, 1, 2, 3]]])


def test_rows_written_w_first_teach_nothing_and_name_the_order(rows):
    """Rows t x y z qw qx qy qz given as TUM's x y z w: read so, the topple turns about no
    edge, which read w first it does; nothing is learnt, and the warning names quat_order."""
    r, t, m = rows
    w_first = r[:, [0, 1, 2, 3, 7, 4, 5, 6]]
    with pytest.warns(objmodel.ObjmodelWarning, match=r'written in w x y z order.*quat_order="wxyz"'):
        tree = objmodel.learn([w_first])
    assert len(tree.edges) == 0 and len(tree.faces) == 0
    given = objmodel.learn([w_first], quat_order="wxyz")
    right = objmodel.learn([r])
    assert len(given.edges) == len(right.edges) == 1
    assert np.allclose(given.edges, right.edges, atol=1e-12)


def test_matrices(rows):
    r, t, m = rows
    bad = m.copy()
    bad[3] = bad[3].T
    raises(r"demos\[0\]\[3\]: last row is .*expected \[0, 0, 0, 1\] \(is the matrix transposed", [bad], times=[t])
    bad = m.copy()
    bad[4, :3, 0] *= -1
    raises(r"demos\[0\]\[4\]: the rotation part has determinant -1.*reflection", [bad], times=[t])
    bad = m.copy()
    bad[6, :3, :3] *= 1.1
    raises(r"demos\[0\]\[6\]: the rotation part is not orthonormal", [bad], times=[t])
    bad = m.copy()
    bad[2, 1, 3] = np.inf
    raises(r"demos\[0\]\[2\]: element \[1, 3\] is inf", [bad], times=[t])


def test_arguments(rows):
    r, _, _ = rows
    raises(r"gravity must not be zero \(use None if unknown\)", [r], gravity=(0, 0, 0))
    raises(r"gravity must be three finite numbers", [r], gravity=(0, 0))
    raises(r"--gravity: '1,x,2' is not three comma-separated numbers", [r], gravity="1,x,2")
    raises(r'method must be "robust" or "paper"', [r], method="fast")
    raises(r"alpha must be a probability in \(0, 1\), got 2", [r], alpha=2)
    raises(r"give both noise_position and noise_rotation", [r], noise_position=1e-3)
    raises(r"noise_rotation must be zero or positive \(radians\), got -0.01", [r],
           noise_position=1e-3, noise_rotation=-0.01)
    raises(r"palm_noise_position and palm_noise_rotation need noise_position", [r],
           palm_noise_position=1e-3, palm_noise_rotation=1e-2)
    with pytest.raises(TypeError, match="unexpected keyword argument 'alhpa'"):
        objmodel.learn([r], alhpa=0.1)


def cli():
    """The command-line tool, if built (OBJMODEL_CLI, or target/*/objmodel of the workspace)."""
    if os.environ.get("OBJMODEL_CLI"):  # given: it must be there
        assert os.path.exists(os.environ["OBJMODEL_CLI"]), os.environ["OBJMODEL_CLI"]
        return os.environ["OBJMODEL_CLI"]
    root = Path(__file__).resolve().parents[3]
    for p in (root / "target/debug/objmodel", root / "target/release/objmodel"):
        if p.exists():
            return str(p)
    return None


BAD_FILES = {
    "seven.tum": "1 0 0 0 0 0 0 1\n2 0 0 0 0 0 1\n",
    "norm.tum": "1 0 0 0 0 0 0 1\n2 0 0 0 0 0 0 2\n",
    "back.tum": "1 0 0 0 0 0 0 1\n0.5 0 0 0 0 0 0 1\n",
    "empty.tum": "",
    "nan.csv": "t,x,y,z,qx,qy,qz,qw\n1,nan,0,0,0,0,0,1\n",
}


@pytest.mark.parametrize("name", sorted(BAD_FILES))
def test_file_errors_are_the_command_lines(tmp_path, name):
    path = tmp_path / name
    path.write_text(BAD_FILES[name])
    with pytest.raises(objmodel.ObjmodelError) as e:
        objmodel.learn([str(path)])
    msg = str(e.value)
    assert msg.startswith(str(path) + ":"), msg
    exe = cli()
    if exe is None:
        pytest.skip("no objmodel command-line tool built (set OBJMODEL_CLI)")
    out = subprocess.run([exe, "learn", str(path)], capture_output=True, text=True)
    assert out.returncode == 2
    assert out.stderr.strip() == f"objmodel: error: {msg}"
    with pytest.raises(objmodel.ObjmodelError) as e:
        objmodel.classify(str(path))
    out = subprocess.run([exe, "classify", str(path)], capture_output=True, text=True)
    assert out.stderr.strip() == f"objmodel: error: {e.value}"


def test_missing_file_names_it(tmp_path):
    with pytest.raises(objmodel.ObjmodelError, match=r"nowhere\.tum: No such file"):
        objmodel.learn([tmp_path / "nowhere.tum"])
