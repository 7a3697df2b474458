"""Learning from arrays and files against the analytic truth of exact topples."""

import os
import warnings

import numpy as np
import pytest

import objmodel
import topple
from conftest import write_tum


def nearest_edge(tree, truth):
    """(distance, angle) of the learnt edge closest to the true one."""
    return min(topple.line_distance(truth["point"], truth["direction"], e[:3], e[3:])
               for e in tree.edges)


def test_one_topple_gives_its_edge_and_phi(box):
    t, m, truth = topple.topple(box, "+x")
    tree = objmodel.learn([topple.rows_of(t, m)], gravity=(0, 0, -1))
    assert tree.edges.shape == (1, 6)
    dist, ang = nearest_edge(tree, truth)
    assert dist < 1e-6 and ang < 1e-6, (dist, ang)
    p = tree.pendulums
    assert p.shape == (1, len(objmodel.Tree.PENDULUM_COLUMNS))
    phi = p[0, objmodel.Tree.PENDULUM_COLUMNS.index("phi")]
    assert abs(phi - truth["phi"]) < np.radians(0.1), (phi, truth["phi"])
    assert tree.demos == ["demo0"]


def test_every_face_gives_the_box(every_face, full_tree, box):
    demos, _ = every_face
    tree = full_tree
    assert tree.edges.shape == (6, 6) and tree.faces.shape == (6, 4)
    for _, _, truth in demos:
        dist, ang = nearest_edge(tree, truth)
        assert dist < 1e-6 and ang < 1e-6, (dist, ang)
    # The centre of mass of a uniform box is its centre.
    com = demos[0][2]["com"]
    assert tree.com.shape == (3,)
    assert np.linalg.norm(tree.com - com) < 1e-4, (tree.com, com)
    # Every face's offset is known; the shape's vertices are the box's corners.
    assert not np.isnan(tree.faces[:, 3]).any()
    v = tree.vertices
    assert v.shape == (8, 3)
    tag_from_box = np.linalg.inv(box.box_from_tag)
    corners = np.array([(tag_from_box @ np.r_[np.array([sx, sy, sz]) * box.half, 1])[:3]
                        for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    for c in corners:
        assert np.min(np.linalg.norm(v - c, axis=1)) < 1e-4


def test_arrays_and_a_tum_file_give_the_same_tree(tmp_path, box):
    t, m, _ = topple.topple(box, "-y")
    rows = topple.rows_of(t, m)
    path = write_tum(tmp_path / "push.tum", rows)
    from_file = objmodel.learn([path])
    from_str = objmodel.learn(str(path))
    from_array = objmodel.learn([rows], names=["push.tum"])
    assert from_file.to_dict() == from_array.to_dict()
    assert from_str == from_file
    assert from_file.demos == ["push.tum"]


def test_matrices_with_times_equal_rows(box):
    t, m, truth = topple.topple(box, "+y")
    a = objmodel.learn([topple.rows_of(t, m)])
    b = objmodel.learn([m], times=[t])
    np.testing.assert_allclose(a.edges, b.edges, atol=1e-9)
    np.testing.assert_allclose(a.pendulums, b.pendulums, atol=1e-7)
    c = objmodel.learn(m, times=t)  # one demonstration alone
    np.testing.assert_allclose(b.edges, c.edges, atol=0)
    assert objmodel.learn(m, times=[t]) == c  # its times given as for many


def test_wxyz_order_is_honoured(box):
    t, m, truth = topple.topple(box, "-x")
    rows = topple.rows_of(t, m)
    wxyz = rows[:, [0, 1, 2, 3, 7, 4, 5, 6]]
    a = objmodel.learn([rows])
    b = objmodel.learn([wxyz], quat_order="wxyz")
    assert a == b
    # The same numbers read in the wrong order are another motion: not this edge (if any).
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            wrong = objmodel.learn([wxyz])
        except objmodel.ObjmodelError:
            return
    if len(wrong.edges):
        dist, ang = nearest_edge(wrong, truth)
        assert dist > 1e-3 or ang > 1e-3


def test_wxyz_order_is_honoured_in_tum_files(box, tmp_path):
    t, m, truth = topple.topple(box, "-x")
    rows = topple.rows_of(t, m)
    path = write_tum(tmp_path / "w_first.tum", rows[:, [0, 1, 2, 3, 7, 4, 5, 6]])
    b = objmodel.learn(str(path), quat_order="wxyz")
    a = objmodel.learn([rows])
    np.testing.assert_allclose(a.edges, b.edges, atol=1e-9)
    dist, ang = nearest_edge(b, truth)
    assert dist < 1e-6 and ang < 1e-6, (dist, ang)


def test_a_palm_at_rest_changes_nothing(box):
    t, m, truth = topple.topple(box, "+x")
    rows = topple.rows_of(t, m)
    palm = np.tile([0.0, 0.1, 0.2, 0.0, 0.0, 0.0, 0.0, 1.0], (len(t), 1))
    palm[:, 0] = t
    tree = objmodel.learn([rows], palms=[palm])
    dist, ang = nearest_edge(tree, truth)
    assert dist < 1e-6 and ang < 1e-6
    assert tree.to_dict()["demos"][0]["instrumented"] is True


def write_motive_take(path, bodies):
    """A Motive take (CSV export, millimetres) of `bodies`: (name, rows t x y z qx qy qz qw)
    sharing their times."""
    head = [",Type", ",Name", ",ID", ",", "Frame,Time (Seconds)"]
    for k, (name, _) in enumerate(bodies):
        head[0] += ",Rigid Body" * 7
        head[1] += f",{name}" * 7
        head[2] += f",{k}" * 7
        head[3] += ",Rotation" * 4 + ",Position" * 3
        head[4] += ",X,Y,Z,W,X,Y,Z"
    with open(path, "w") as f:
        f.write("Format Version,1.23,Rotation Type,Quaternion,Length Units,Millimeters\n\n")
        f.write("\n".join(head) + "\n")
        for i, t in enumerate(bodies[0][1][:, 0]):
            cells = [str(i), repr(float(t))]
            for _, rows in bodies:
                r = rows[i]
                cells += [repr(float(x)) for x in r[4:8]] + [repr(float(x) * 1e3) for x in r[1:4]]
            f.write(",".join(cells) + "\n")
    return path


def test_motive_takes_by_their_rigid_bodies(tmp_path, box):
    t, m, truth = topple.topple(box, "+x")
    rows = topple.rows_of(t, m)
    palm = np.tile([0.0, 0.1, 0.2, 0.0, 0.0, 0.0, 0.0, 1.0], (len(t), 1))
    palm[:, 0] = t
    take = write_motive_take(tmp_path / "take.csv", [("hand", palm), ("box", rows)])
    tree = objmodel.learn(str(take), rigid_bodies=("box", "hand"))
    np.testing.assert_allclose(tree.edges, objmodel.learn([rows], palms=[palm]).edges, atol=1e-9)
    assert tree.to_dict()["demos"][0]["instrumented"] is True
    c = objmodel.classify(take, rigid_bodies="box")
    assert c["kind"] == "topple" and c["instrumented"] is False
    assert c["file"] == str(take) and c["palm_file"] is None
    with pytest.raises(objmodel.ObjmodelError, match=r"2 rigid bodies \(hand, box\)"):
        objmodel.learn(str(take))
    with pytest.raises(objmodel.ObjmodelError, match="not a file"):
        objmodel.learn([rows], rigid_bodies="box")


def test_palm_files_beside_their_demonstration(tmp_path, box):
    t, m, truth = topple.topple(box, "+x")
    rows = topple.rows_of(t, m)
    palm = np.tile([0.0, 0.1, 0.2, 0.0, 0.0, 0.0, 0.0, 1.0], (len(t), 1))
    palm[:, 0] = t
    write_tum(tmp_path / "d.tum", rows)
    write_tum(tmp_path / "d.palm.tum", palm)
    # As on the command line: the palm file is found beside the demonstration, and given
    # among the demonstrations it is not one.
    tree = objmodel.learn(sorted(tmp_path.iterdir()))
    assert tree.demos == ["d.tum"]
    assert tree.to_dict()["demos"][0]["instrumented"] is True
    assert objmodel.learn([tmp_path / "d.tum"], no_palm=True).to_dict()["demos"][0][
        "instrumented"] is False


def test_learning_into_a_tree_and_into_a_file(tmp_path, every_face):
    _, rows = every_face
    tree = objmodel.Tree()
    same = objmodel.learn(rows[:2], into=tree)
    assert same is tree and len(tree.demos) == 2
    path = tmp_path / "box.json"
    objmodel.learn(rows[:3], into=path)
    t = objmodel.learn(rows[3:], into=str(path), names=["demo3", "demo4", "demo5"])
    assert objmodel.Tree.load(path) == t
    assert len(t.demos) == 6 and t.edges.shape == (6, 6)
    # An error learns none of them: the tree is as it was.
    before = tree.to_json()
    with pytest.raises(objmodel.ObjmodelError):
        objmodel.learn([rows[2], rows[3][:, :7]], into=tree)
    assert tree.to_json() == before


def test_unknown_gravity_warns_and_teaches_no_edge_in_the_world(box):
    # Without gravity a topple in the world cannot be told from a slide turning about a fixed
    # point: no edge, no pendulum, and a warning that says why.
    t, m, _ = topple.topple(box, "+x")
    with pytest.warns(objmodel.ObjmodelWarning, match="gravity is unknown.*taught no edge"):
        tree = objmodel.learn([topple.rows_of(t, m)], gravity=None)
    assert tree.edges.shape[0] == 0 and tree.pendulums.shape[0] == 0


def test_a_demonstration_at_rest_teaches_nothing():
    rows = np.tile([0.0, 0, 0, 0.1, 0, 0, 0, 1], (200, 1))
    rows[:, 0] = np.arange(200) / 30
    with pytest.warns(objmodel.ObjmodelWarning, match="nothing to learn"):
        tree = objmodel.learn(rows)
    assert tree.demos == []


# At "clean" the edges are exact to rounding: within 1 mm and 1e-5 rad (2 arcseconds; each edge
# is conditioned on its faces, whose normals the rests give to rounding too: 1.06e-6 rad seen).
@pytest.mark.parametrize("noise, metres, radians", [("clean", 1e-3, 1e-5), ("real", 5e-3, np.radians(1))])
def test_the_librarys_synthetic_topples(noise, metres, radians):
    demos = objmodel.synthetic_topples(noise=noise, seed=3)
    assert [d["name"] for d in demos] == [f"topple{k}" for k in range(6)]
    tree = objmodel.learn([d["poses"] for d in demos], names=[d["name"] for d in demos])
    assert tree.edges.shape == (6, 6) and tree.vertices is not None
    for d in demos:
        truth = {"point": d["edge_point"], "direction": d["edge_direction"]}
        dist, ang = nearest_edge(tree, truth)
        assert dist < metres and ang < radians, (d["name"], dist, ang)
    with pytest.raises(objmodel.ObjmodelError, match='noise must be "clean" or "real"'):
        objmodel.synthetic_topples(noise="loud")


def _y_up(rows):
    # The poses in a tracker frame whose y axis is the world's z (up): a quarter turn about x,
    # positions (x, y, z) -> (x, z, -y), quaternions r * q with r = (-h, 0, 0, h) (x y z w).
    h = np.sqrt(0.5)
    out = rows.copy()
    out[:, 2], out[:, 3] = rows[:, 3], -rows[:, 2]
    qx, qy, qz, qw = rows[:, 4], rows[:, 5], rows[:, 6], rows[:, 7]
    out[:, 4] = h * qx - h * qw
    out[:, 5] = h * qy + h * qz
    out[:, 6] = h * qz - h * qy
    out[:, 7] = h * qw + h * qx
    return out


def test_a_gravity_the_demonstrations_contradict_raises_and_names_theirs():
    # Topples at many headings, tracked with y up, learnt with the default z up.
    demos = objmodel.synthetic_topples(noise="real", seed=0) + objmodel.synthetic_topples(
        noise="real", seed=10)
    rows = [_y_up(d["poses"]) for d in demos]
    with pytest.raises(objmodel.ObjmodelError, match=r"gravity given contradicts.*--gravity 0\.000,-?1\.000,"):
        objmodel.learn(rows)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        right = objmodel.learn(rows, gravity=(0, -1, 0))
        unchecked = objmodel.learn(rows, gravity_check=False)
    assert right.edges.shape[0] > 0 and len(unchecked.demos) == len(demos)


def test_millimetres_given_or_refused(box):
    """Positions in millimetres: with length_unit="mm" they teach what metres do; read as
    metres (a real tracker's noise, 1 mm) they teach nothing, and the warning names the unit."""
    t, m, truth = topple.topple(box, "+x")
    rows = topple.rows_of(t, m)
    mm = rows.copy()
    mm[:, 1:4] *= 1e3
    tree = objmodel.learn([mm], length_unit="mm")
    dist, ang = nearest_edge(tree, truth)
    assert dist < 1e-6 and ang < 1e-6, (dist, ang)
    noisy = mm.copy()
    noisy[:, 1:4] += np.random.default_rng(3).normal(0.0, 1.0, (len(mm), 3))
    with pytest.warns(objmodel.ObjmodelWarning, match=r"do not look like metres.*length-unit mm"):
        refused = objmodel.learn([noisy])
    assert refused.edges.shape[0] == 0 and refused.faces.shape[0] == 0
    with pytest.raises(objmodel.ObjmodelError, match="unknown length unit \"in\""):
        objmodel.learn([mm], length_unit="in")


def test_real_tosses_with_the_supports_height_give_the_cube(tmp_path):
    """The ContactNets cube's tosses (crates/objmodel/tests/data/contactnets_tosses): with the
    board's height given, the rests give all six faces their offsets and the cube its eight
    corners; without it, the faces have none; a height that is not finite is refused."""
    data = os.path.join(os.path.dirname(__file__), "..", "..", "objmodel", "tests", "data",
                        "contactnets_tosses")
    files = sorted(os.path.join(data, f) for f in os.listdir(data) if f.endswith(".tum"))
    assert len(files) == 58
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        without = objmodel.learn(files)
        tree = objmodel.learn(files, support_height=0.0, support_sigma=0.001)
        with pytest.raises(objmodel.ObjmodelError, match="support_height"):
            objmodel.learn(files, support_height=float("nan"))
    assert without.faces.shape[0] == 6 and np.isnan(without.faces[:, 3]).all()
    assert without.vertices is None
    faces = tree.faces
    assert faces.shape[0] == 6
    assert np.all(np.abs(faces[:, 3] - 0.0524) < 5e-3), faces
    corners = tree.vertices
    assert corners.shape == (8, 3)
    assert np.all(np.abs(np.abs(corners) - 0.0524) < 5e-3), corners


def test_a_loosely_located_edge_is_held_back_until_another_demonstration(box):
    """A topple tracked at 8 mm / 1 deg (a tracker far worse than a user's): one demonstration
    locates its edge to about 2.2 mm, too loosely to be taught (within 5 mm and 3 deg at 95%),
    so the edges array leaves it out and a warning says why; a second demonstration of the same
    topple locates it, and it is the box's edge."""
    t, m, truth = topple.topple(box, "+x")

    def noisy(seed):
        rng = np.random.default_rng(seed)
        out = np.array(m, float)
        for k in range(len(out)):
            turn = topple.rot(rng.normal(size=3), np.radians(1.0) * abs(rng.normal()))
            out[k][:3, :3] = turn @ out[k][:3, :3]
            out[k][:3, 3] += rng.normal(0, 8e-3, 3)
        return topple.rows_of(t, out)

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        one = objmodel.learn([noisy(0)], names=["d0"], gravity=(0, 0, -1))
    held = [w for w in one.to_dict()["withheld_edges"] if w.get("unlocated")]
    assert one.edges.shape == (0, 6) and len(held) == 1
    assert any("held back: edge e0 is located to" in str(w.message) for w in caught), \
        [str(w.message) for w in caught]
    two = objmodel.learn([noisy(0), noisy(1)], names=["d0", "d1"], gravity=(0, 0, -1))
    assert two.edges.shape == (1, 6)
    assert not two.to_dict().get("withheld_edges")
    dist, ang = nearest_edge(two, truth)
    assert dist < 5e-3 and ang < np.radians(3), (dist, ang)
