#!/usr/bin/env python3
"""Tosses from another simulator: boxes thrown onto a table in MuJoCo, learnt by objmodel, every
learnt feature checked against the box.

The learner's toss handling (flights, impacts, rolls, landings, the support's height) was built
on rapier's tosses (`objmodel dataset --tosses N`). This throws boxes with an independent engine
(MuJoCo: soft contacts, its own friction cones and integrator, bounces that differ) and asks the
question that matters most: does any learnt feature lie off the box?

Per box (random size), N tosses: the box is held still in the air for 0.4-0.8 s (a rest that is
not on a support: it must teach no face), swung for 0.15 s to a random speed and spin, released
20-45 cm above a table, and tracked until it has rested for 1.0-1.5 s. The tracked frame is a
tag on the box (one offset and turn per box, the same in all its tosses, as a real tag is), with
tracking noise, dropped frames and quaternion sign flips. All tosses of a box at one noise level
are learnt together (`objmodel learn --json`); a learnt edge is true when it is within 5 mm and
3° of an edge of the box, a face when its normal is within 5° of a face's outward normal and its
offset, if known, within 5 mm (as `bench/precision.py`).

    python3 bench/mujoco_tosses.py [N per box, default 40]
    LEVEL=camera python3 bench/mujoco_tosses.py      (30 Hz, 1 mm / 0.5 deg; default mocap:
                                                      150-250 Hz, 0.1-0.5 mm / 0.05-0.3 deg)
    NOISE_GIVEN=1 ...                                (pass the tracker's noise to the learner)
    EXACT_TOO=1 ...                                  (also write NAME.exact.tum, for diagnosis)
    BOXES=5 SEED=3 ...

Needs numpy, scipy and mujoco. Writes into $PROBE_DIR (default /tmp/objmodel-mujoco-tosses).
Not a test: the numbers are for reading (see the notes on issue 20).
"""
import json
import math
import os
import sys

import mujoco
import numpy as np
from scipy.spatial.transform import Rotation as R

from scoring import learn_and_score  # noqa: F401 (probe_common takes it from here too)

BIN = os.environ.get("OBJMODEL", "target/release/objmodel")
DIR = os.environ.get("PROBE_DIR", "/tmp/objmodel-mujoco-tosses")
LEVEL = os.environ.get("LEVEL", "mocap")
DT = 0.0005


def model(half, mu):
    hx, hy, hz = half
    return mujoco.MjModel.from_xml_string(f"""
<mujoco>
  <option timestep="{DT}" gravity="0 0 -9.81" cone="elliptic"/>
  <worldbody>
    <geom type="plane" size="3 3 0.1" friction="{mu} 0.005 0.0001"/>
    <body name="box" pos="0 0 0.5">
      <freejoint/>
      <geom type="box" size="{hx} {hy} {hz}" mass="0.4" friction="{mu} 0.005 0.0001"/>
    </body>
  </worldbody>
</mujoco>""")


def toss(half, mu, rate, rng):
    """World-from-box poses [t x y z qx qy qz qw] of one toss, sampled at `rate`."""
    m = model(half, mu)
    d = mujoco.MjData(m)
    hold = rng.uniform(0.4, 0.8)
    swing = 0.15
    q0 = R.random(random_state=rng.integers(1 << 31))
    p0 = np.array([0.0, 0.0, rng.uniform(0.2, 0.45)])
    v1 = np.array([rng.uniform(0.3, 1.2), rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 1.0)])
    w1 = R.random(random_state=rng.integers(1 << 31)).apply([1.0, 0.0, 0.0]) * rng.uniform(3, 15)
    rest_after = rng.uniform(1.0, 1.5)
    d.qpos[:3] = p0
    d.qpos[3:7] = np.roll(q0.as_quat(), 1)
    t, t_next, still_since, rows = 0.0, 0.0, None, []
    while t < 8.0:
        if t < hold + swing:
            # Held, then swung: the hand sets the pose and velocity (speed ramping up).
            s = max(0.0, t - hold) / swing
            v, w = v1 * s, w1 * s
            d.qvel[:3] = v
            # A free joint's angular velocity is in the body's frame.
            d.qvel[3:6] = R.from_quat(np.roll(d.qpos[3:7], -1)).inv().apply(w)
            if t < hold:
                d.qpos[:3] = p0
                d.qpos[3:7] = np.roll(q0.as_quat(), 1)
                d.qvel[:] = 0.0
            else:
                d.qvel[:3] += np.array([0.0, 0.0, 9.81]) * DT  # the hand holds it up
        mujoco.mj_step(m, d)
        t += DT
        if t >= t_next:
            w, x, y, z = d.qpos[3:7]
            rows.append([t, *d.qpos[:3], x, y, z, w])
            t_next += 1.0 / rate
        if t > hold + swing + 0.2:
            moving = np.linalg.norm(d.qvel[:3]) > 2e-3 or np.linalg.norm(d.qvel[3:6]) > 2e-2
            still_since = None if moving else (still_since if still_since is not None else t)
            if still_since is not None and t - still_since > rest_after:
                break
    return np.array(rows)


def track(poses, box_from_tag_t, box_from_tag_r, sp, sr, rng, drop=0.01, sign_flip=0.03):
    """The tag's tracked poses: noise (sp [m], sr [rad] per axis), a share `drop` of frames
    dropped and `sign_flip` of quaternions negated (0: no draw for them)."""
    out = []
    for row in poses:
        if drop and rng.random() < drop:
            continue  # dropped frame
        wb = R.from_quat(row[4:8])
        p = row[1:4] + wb.apply(box_from_tag_t) + rng.normal(scale=sp, size=3)
        r = wb * box_from_tag_r * R.from_rotvec(rng.normal(scale=sr, size=3))
        q = r.as_quat()
        if sign_flip and rng.random() < sign_flip:
            q = -q
        out.append([row[0], *p, *q])
    return np.array(out)


def truth(half, bt_t, bt_r):
    """The box's faces (outward normal, offset) and edges (point, direction) in the tag frame."""
    inv = bt_r.inv()
    faces, edges = [], []
    for a in range(3):
        for s in (-1.0, 1.0):
            n = np.zeros(3)
            n[a] = s
            faces.append((inv.apply(n), half[a] - n @ bt_t))
    for a in range(3):
        b, c = [k for k in range(3) if k != a]
        for sb in (-1.0, 1.0):
            for sc in (-1.0, 1.0):
                p = np.zeros(3)
                p[b], p[c] = sb * half[b], sc * half[c]
                u = np.zeros(3)
                u[a] = 1.0
                edges.append((inv.apply(p - bt_t), inv.apply(u)))
    return faces, edges


def write_truth(path, half, mu, bt_t, bt_r, faces, edges):
    """The box, its tag and its faces and edges in the tag frame, as JSON."""
    with open(path, "w") as f:
        json.dump({"half": list(half), "mu": mu, "box_from_tag_t": list(bt_t),
                   "box_from_tag_q": list(bt_r.as_quat()),
                   "faces": [{"normal": list(n), "offset": d} for n, d in faces],
                   "edges": [{"point": list(p), "direction": list(u)} for p, u in edges]}, f)


def random_box(rng, half_ranges, mu_range, path):
    """A box drawn from `rng`: half extents [m] from `half_ranges` (three (low, high)), friction
    from `mu_range`, a tag on its top face up to 1 cm off centre and turned at random; its truth
    written to `path`. Returns (half, mu, bt_t, bt_r, faces, edges)."""
    half = np.array([rng.uniform(lo, hi) for lo, hi in half_ranges])
    mu = rng.uniform(*mu_range)
    bt_t = np.array([rng.uniform(-0.01, 0.01), rng.uniform(-0.01, 0.01), half[2]])
    bt_r = R.from_euler("z", rng.uniform(-180, 180), degrees=True)
    faces, edges = truth(half, bt_t, bt_r)
    write_truth(path, half, mu, bt_t, bt_r, faces, edges)
    return half, mu, bt_t, bt_r, faces, edges


def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 40
    boxes = int(os.environ.get("BOXES", "3"))
    rng = np.random.default_rng(int(os.environ.get("SEED", "5")))
    os.makedirs(DIR, exist_ok=True)
    totals = {"edges": [0, 0], "faces": [0, 0]}
    for k in range(boxes):
        half, mu, bt_t, bt_r, faces, edges = random_box(
            rng, [(0.02, 0.04), (0.02, 0.04), (0.03, 0.06)], (0.3, 0.8),
            f"{DIR}/box{k}_{LEVEL}.truth.json")
        paths, sps, srs = [], [], []
        for i in range(n):
            if LEVEL == "camera":
                rate, sp, sr = 30.0, 1e-3, math.radians(0.5)
            else:
                rate = rng.uniform(150, 250)
                sp, sr = rng.uniform(1e-4, 5e-4), math.radians(rng.uniform(0.05, 0.3))
            poses = toss(half, mu, rate, rng)
            path = f"{DIR}/box{k}_{LEVEL}_{i}.tum"
            with open(path, "w") as f:
                f.write("# timestamp tx ty tz qx qy qz qw  (MuJoCo toss)\n")
                for r in track(poses, bt_t, bt_r, sp, sr, rng):
                    f.write("%.6f " % r[0] + " ".join("%.9f" % x for x in r[1:]) + "\n")
            if os.environ.get("EXACT_TOO"):
                # The tag's exact poses beside the tracked ones, for diagnosis (no random draws).
                with open(path[:-4] + ".exact.tum", "w") as f:
                    for r in poses:
                        wb = R.from_quat(r[4:8])
                        q = (wb * bt_r).as_quat()
                        p = r[1:4] + wb.apply(bt_t)
                        f.write("%.6f " % r[0] + " ".join("%.9f" % x for x in [*p, *q]) + "\n")
            paths.append(path)
            sps.append(sp)
            srs.append(sr)
        args = [BIN, "learn", *paths, "--json"]
        if os.environ.get("NOISE_GIVEN"):
            # One learner call takes one noise: the largest of the tosses' (a pessimistic σ).
            args += ["--noise-position", str(max(sps)), "--noise-rotation", str(max(srs))]
        scored = learn_and_score(args, f"{DIR}/box{k}_{LEVEL}.json", faces, edges)
        if scored is None:
            print(f"box {k}: learn failed")
            continue
        tree, et, ft, wrong = scored
        totals["edges"][0] += et
        totals["edges"][1] += len(tree["edges"])
        totals["faces"][0] += ft
        totals["faces"][1] += len(tree["faces"])
        print(f"box {k} {2 * half * 1e3} mm, mu {mu:.2f}: edges {et}/{len(tree['edges'])}, "
              f"faces {ft}/{len(tree['faces'])} (of 6), with offsets "
              f"{sum(f.get('offset') is not None for f in tree['faces'])}"
              + (f"; WRONG: {wrong}" if wrong else ""), flush=True)
    e, f = totals["edges"], totals["faces"]
    learnt = e[1] + f[1]
    print(json.dumps({"level": LEVEL, "tosses": n * boxes, "edges true/learnt": f"{e[0]}/{e[1]}",
                      "faces true/learnt": f"{f[0]}/{f[1]}",
                      "precision": f"{100.0 * (e[0] + f[0]) / learnt:.0f}%" if learnt else "-"}))


if __name__ == "__main__":
    main()
