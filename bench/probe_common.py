"""What the probes with other simulators share (`pybullet_probe.py`, `drake_probe.py`): the
resting pose a box is set down in, the sampling of a world's poses at the tracker's rate, the
TUM writer, and the probe itself: per box, demonstrations of each kind made in the simulator,
tracked with noise, learnt into one tree and every learnt feature checked against the box.

A simulator's world offers `pose(body) -> (position, Rotation)` and `box` (the box's body);
its probe module offers `push`, `palm_tilt` and `toss` (see `pybullet_probe.py`), each
returning `(box rows, palm rows or None)` or None when the motion did not do as meant.
"""
import json
import math
import os

import numpy as np
from scipy.spatial.transform import Rotation as R

from mujoco_box_set import orientations
from mujoco_tosses import learn_and_score, random_box, track


def settle(half, rot):
    """The box resting with rotation `rot` on the table: (position, rotation)."""
    h = np.abs(rot.as_matrix()) @ half
    return np.array([0.0, 0.0, h[2] + 1e-4]), rot


def record(w, rows, t, t_next, rate, palm=None, palm_rows=None):
    """Append the box's pose (and the palm's) to the rows when the tracker's next frame is due:
    the time of the frame after."""
    if t >= t_next:
        p, q = w.pose(w.box)
        rows.append([t, *p, *q.as_quat()])
        if palm is not None:
            pp, pq = w.pose(palm)
            palm_rows.append([t, *pp, *pq.as_quat()])
        return t_next + 1.0 / rate
    return t_next


def write(path, rows, what):
    """Rows `[t x y z qx qy qz qw]` as a TUM file, `what` in its header."""
    with open(path, "w") as f:
        f.write(f"# timestamp tx ty tz qx qy qz qw  ({what})\n")
        for r in rows:
            f.write("%.6f " % r[0] + " ".join("%.9f" % x for x in r[1:]) + "\n")


def run(sim, name, boxes, per_kind, rng, level, binary, out_dir):
    """The probe: `boxes` random boxes, `per_kind` demonstrations of each kind made by the
    module `sim`, learnt together per box; prints each box's features and the precision."""
    os.makedirs(out_dir, exist_ok=True)
    poses = orientations()
    totals = [0, 0, 0, 0]
    for k in range(boxes):
        half, mu, bt_t, bt_r, faces, edges = random_box(
            rng, [(0.025, 0.045), (0.02, 0.04), (0.035, 0.07)], (0.5, 0.9),
            f"{out_dir}/box{k}_{level}.truth.json")
        paths, made = [], {}
        for kind in ("topple", "slide", "palm", "toss"):
            made[kind] = 0
            tries = 0
            while made[kind] < per_kind and tries < 4 * per_kind:
                tries += 1
                if level == "camera":
                    rate, sp, sr = 30.0, 1e-3, math.radians(0.5)
                else:
                    rate = rng.uniform(150, 250)
                    sp, sr = rng.uniform(1e-4, 5e-4), math.radians(rng.uniform(0.05, 0.3))
                rot = R.from_matrix(poses[rng.integers(len(poses))])
                if kind == "topple":
                    got = sim.push(half, max(mu, 0.9), rot, rng.uniform(0.8, 0.95), rng.uniform(-0.3, 0.3), True, rate, rng)
                elif kind == "slide":
                    got = sim.push(half, rng.uniform(0.2, 0.35), rot, rng.uniform(0.15, 0.3), rng.uniform(-0.5, 0.5), False, rate, rng)
                elif kind == "palm":
                    got = sim.palm_tilt(half, mu, rot, rate, rng)
                else:
                    got = sim.toss(half, mu, rate, rng)
                if got is None:
                    continue
                rows, palm = got
                stem = f"{out_dir}/box{k}_{level}_{kind}{made[kind]}"
                write(stem + ".tum", track(rows, bt_t, bt_r, sp, sr, rng, drop=0.02), f"{name} {kind}")
                if palm is not None:
                    write(stem + ".palm.tum", track(palm, np.zeros(3), R.identity(), sp / 3, sr / 3, rng,
                                                    drop=0, sign_flip=0), f"{name} palm")
                paths.append(stem + ".tum")
                made[kind] += 1
        scored = learn_and_score([binary, "learn", *paths, "--json"], f"{out_dir}/box{k}_{level}.json",
                                 faces, edges)
        if scored is None:
            print(f"box {k}: learn failed")
            continue
        tree, et, ft, wrong = scored
        totals = [totals[0] + et, totals[1] + len(tree["edges"]), totals[2] + ft, totals[3] + len(tree["faces"])]
        print(f"box {k} {np.round(2e3 * half, 1)} mm, mu {mu:.2f}, demos {made}: edges "
              f"{et}/{len(tree['edges'])}, faces {ft}/{len(tree['faces'])} (of 6), with offsets "
              f"{sum(f.get('offset') is not None for f in tree['faces'])}"
              + (f"; WRONG: {wrong}" if wrong else ""), flush=True)
    learnt = totals[1] + totals[3]
    print(json.dumps({"level": level, "boxes": boxes, "edges true/learnt": f"{totals[0]}/{totals[1]}",
                      "faces true/learnt": f"{totals[2]}/{totals[3]}",
                      "precision": f"{100.0 * (totals[0] + totals[2]) / learnt:.0f}%" if learnt else "-"}))
