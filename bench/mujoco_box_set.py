#!/usr/bin/env python3
"""One box, many pushes, learnt together: the fused tree's edges against MuJoCo's truth.

`bench/mujoco_probe.py` makes a new box for every demonstration, so each tree there holds one
topple. Here one box (one tag on it) is pushed over N times in MuJoCo, each time from one of
its axis-aligned resting poses (a face down, one of the four faces toward the finger) with a
high push along +x on high friction, until it passes its balance point; the pushes that did
not topple it are skipped. All of them are then learnt into one tree (`objmodel learn
*.tum --json`), as a user who demonstrates a box's topples would, and every learnt edge is
compared with the box's edges: its error along the outward bisector of the two faces that
meet there and across it (normal to the edge and the bisector), each over its σ from the
edge's `point_cov` (and, where the edge was conditioned on its faces, the same for its
`observed` estimate), and its direction error.

    PATH=/tmp/venv/bin:$PATH OBJMODEL=target/release/objmodel python3 bench/mujoco_box_set.py 24
    RATE=120 NOISE=0.3 ... (a motion-capture tracker); SEED=5 ... (another box and stream)

Writes the box's edges and faces in the tag frame to box.truth.json beside the files
(`crates/objmodel/tests/data/mujoco_box_set_30hz` is SEED=11 at 30 Hz: `tests/box_set.rs`).
Tracking noise, rate and correlation as in `bench/mujoco_probe.py` (RATE, NOISE,
CORRELATION). Writes into $PROBE_DIR (default /tmp/objmodel-mujoco-set). Needs numpy, scipy
and mujoco. Not a test: the numbers are for reading.
"""
import itertools
import json
import math
import os
import subprocess
import sys

import mujoco
import numpy as np
from scipy.spatial.transform import Rotation as R

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mujoco_probe as probe  # noqa: E402  (its scene, tracker and writer)

BIN = os.environ.get("OBJMODEL", "target/release/objmodel")
DIR = os.environ.get("PROBE_DIR", "/tmp/objmodel-mujoco-set")
DEG = math.pi / 180


def orientations():
    """The 24 axis-aligned world_from_box rotations."""
    out = []
    for perm in itertools.permutations(range(3)):
        for signs in itertools.product((1, -1), repeat=3):
            m = np.zeros((3, 3))
            for i, (j, s) in enumerate(zip(perm, signs)):
                m[i, j] = s
            if np.linalg.det(m) > 0:
                out.append(m)
    return out


def push(half, world_from_box, rng):
    """One push of the box resting as `world_from_box` turns it: (times and world_from_box
    poses as (N, 8) rows, the toppled edge in the box frame (point, direction), whether it
    toppled)."""
    extent = np.abs(world_from_box) @ half  # the half extents along the world axes
    ex, ey, ez = extent
    rot = R.from_matrix(world_from_box)
    x, y, z, w = rot.as_quat()
    start = np.array([-ex - 0.03, 0.0, 1.8 * ez])
    xml = probe.scene(half, 0.9, start, quat=(w, x, y, z), height=ez)
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    box = m.body("box").id
    speed = rng.uniform(0.05, 0.12)
    phi = math.atan2(ex, ez)
    rest_before, rest_after = rng.uniform(0.8, 1.5), 1.5
    up0 = []  # the box's up in its own frame when the finger starts to push

    def pushed_enough(d, pushed):
        up = d.xmat[box].reshape(3, 3).T @ np.array([0, 0, 1.0])
        if not up0:
            up0.append(up)
        return math.acos(np.clip(up @ up0[0], -1, 1)) > phi + 8 * DEG

    samples = probe.finger_push(m, d, box, start, speed, rest_before, rest_after, pushed_enough)
    poses = np.array(samples)
    # The far bottom edge: between the face down (-z) and the face toward +x, in the box frame.
    down = world_from_box.T @ np.array([0, 0, -1.0])
    ahead = world_from_box.T @ np.array([1.0, 0, 0])
    point = half * (down + ahead)
    direction = np.cross(down, ahead)
    up_end = R.from_quat(poses[-1, 4:8]).as_matrix().T @ np.array([0, 0, 1.0])
    toppled = math.acos(np.clip(up_end @ (-down), -1, 1)) > 60 * DEG
    return poses, (point, direction, down + ahead), toppled


def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 24
    os.makedirs(DIR, exist_ok=True)
    for f in os.listdir(DIR):
        if f.endswith((".tum", ".json")):
            os.remove(os.path.join(DIR, f))
    rng = np.random.default_rng(int(os.environ.get("SEED", "11")))
    half = np.array([rng.uniform(0.03, 0.045), rng.uniform(0.035, 0.05), rng.uniform(0.06, 0.09)])
    tag_t = np.array([rng.uniform(-0.01, 0.01), rng.uniform(-0.01, 0.01), half[2]])
    tag_r = R.from_euler("zyx", rng.uniform(-180, 180, size=3), degrees=True)
    rots = orientations()
    paths, truths, tries = [], [], 0
    while len(paths) < n and tries < 6 * n:
        tries += 1
        rot = rots[rng.integers(len(rots))]
        poses, edge, toppled = push(half, rot, rng)
        if not toppled:
            continue
        # The tag's poses: box pose times box_from_tag.
        tagged = []
        for row in poses:
            r = R.from_quat(row[4:8])
            tagged.append([row[0], *(row[1:4] + r.apply(tag_t)), *(r * tag_r).as_quat()])
        track = probe.track(tagged, rng)
        path = f"{DIR}/push_{len(paths) + 1}.tum"
        probe.write(path, track)
        paths.append(path)
        truths.append(edge)
    to_tag = lambda x: tag_r.inv().apply(np.array(x) - tag_t)
    box_edges = []
    for a in range(3):
        b, c = [k for k in range(3) if k != a]
        for sb, sc in itertools.product((1, -1), repeat=2):
            p = np.zeros(3)
            p[b], p[c] = sb * half[b], sc * half[c]
            u = np.zeros(3)
            u[a] = 1
            box_edges.append((to_tag(p), tag_r.inv().apply(u), tag_r.inv().apply(np.sign(p) / np.sqrt(2))))
    shown = {tuple(np.round(to_tag(p), 6)) for p, _, _ in truths}
    # The box's edges and faces in the tag (object) frame, for readers of the files (the test
    # fixture `crates/objmodel/tests/data/mujoco_box_set_30hz` is one such directory).
    faces = []
    for a in range(3):
        for s in (1, -1):
            n_box = np.zeros(3)
            n_box[a] = s
            n = tag_r.inv().apply(n_box)
            faces.append({"normal": n.tolist(), "offset": float(n @ to_tag(n_box * half))})
    with open(f"{DIR}/box.truth.json", "w") as f:
        json.dump({"half_extents": half.tolist(),
                   "edges": [{"point": p.tolist(), "direction": u.tolist(), "outward": o.tolist()}
                             for p, u, o in box_edges],
                   "faces": faces,
                   "rate_hz": probe.RATE, "noise": probe.NOISE, "correlation": probe.CORRELATION,
                   "seed": int(os.environ.get("SEED", "11")), "pushes": len(paths)}, f, indent=1)
    r = subprocess.run([BIN, "learn", *paths, "--json", "--quiet"], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"objmodel learn: {r.stderr.strip()[:300]}")
    tree = json.loads(r.stdout)
    print(f"box half extents {np.round(half * 1e3, 1)} mm, {len(paths)} pushes that toppled it "
          f"({tries} tried), rate {probe.RATE:g} Hz, noise x{probe.NOISE:g}, correlation "
          f"{probe.CORRELATION:g}; box edges shown: {len(shown)}; learnt edges: {len(tree['edges'])}")
    print("| edge | faces | observations | conditioned on | along bisector mm (z) | across mm (z) "
          "| direction deg | own: along (z) | own: across (z) | own: direction deg |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    rows = []

    def errors(est):
        p, u = np.array(est["point"]), np.array(est["direction"])
        cov = np.array(est["point_cov"])
        best = min(box_edges, key=lambda t: np.linalg.norm((p - t[0]) - u * ((p - t[0]) @ u)) / 5e-3
                   + math.degrees(math.acos(min(1, abs(u @ t[1])))) / 3)
        q, v, b = best
        d = p - q
        d = d - u * (d @ u)
        b = b - u * (b @ u)
        b /= np.linalg.norm(b)
        a = np.cross(u, b)
        ang = math.degrees(math.acos(min(1, abs(u @ v))))
        zb = (d @ b) / math.sqrt(max(b @ cov @ b, 1e-18))
        za = (d @ a) / math.sqrt(max(a @ cov @ a, 1e-18))
        return d @ b * 1e3, zb, d @ a * 1e3, za, ang

    for e in tree["edges"]:
        new = errors(e)
        own = errors(e["observed"]) if e.get("observed") else new
        rows.append((new, own, bool(e.get("conditioned_on"))))
        print(f"| {e['id']} | {','.join(e['faces'])} | {len(e['observations'])} | "
              f"{','.join(e.get('conditioned_on', [])) or '-'} | {new[0]:+.2f} ({new[1]:+.1f}) | "
              f"{new[2]:+.2f} ({new[3]:+.1f}) | {new[4]:.2f} | {own[0]:+.2f} ({own[1]:+.1f}) | "
              f"{own[2]:+.2f} ({own[3]:+.1f}) | {own[4]:.2f} |")
    # Each push learnt alone: the edges off the box (beyond 5 mm or 3 degrees).
    alone_wrong, alone_edges = [], 0
    for path in paths:
        r = subprocess.run([BIN, "learn", path, "--json", "--quiet"], capture_output=True, text=True)
        edges = json.loads(r.stdout)["edges"] if r.returncode == 0 else []
        alone_edges += len(edges)
        for e in edges:
            along, _, across, _, ang = errors(e)
            if math.hypot(along, across) >= 5 or ang >= 3:
                alone_wrong.append(f"{os.path.basename(path)} {e['id']}: {math.hypot(along, across):.1f} mm, {ang:.1f} deg")
    print(f"each push alone: {alone_edges} edges, {len(alone_wrong)} off the box: {alone_wrong}")
    for name, k in (("tree", 0), ("own", 1)):
        a = np.array([r[k] for r in rows])
        if len(a):
            print(f"{name}: along bisector mean {a[:, 0].mean():+.2f} mm, rms z {np.sqrt((a[:, 1] ** 2).mean()):.2f};"
                  f" across rms {np.sqrt((a[:, 2] ** 2).mean()):.2f} mm, rms z {np.sqrt((a[:, 3] ** 2).mean()):.2f};"
                  f" distance max {np.hypot(a[:, 0], a[:, 2]).max():.2f} mm; direction max {a[:, 4].max():.2f} deg;"
                  f" within 5 mm and 3 deg: {int(((np.hypot(a[:, 0], a[:, 2]) < 5) & (a[:, 4] < 3)).sum())}/{len(a)}")


if __name__ == "__main__":
    main()
