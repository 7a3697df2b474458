#!/usr/bin/env python3
"""Copy a simulated dataset (written by `objmodel dataset`) with tracker faults in its pose
files, to measure what they teach (`bench/precision.py` on the copy).

    python3 bench/glitch_copy.py SRC DST [--fault glitch] [--every 5] [--levels real,mocap]
                                 [--max-run 6] [--seed 1]

`--fault glitch` (default): a run of 1 to MAX_RUN consecutive frames whose pose is wrong by one
error, 5-30 mm and 2-10 degrees (a misread tag, a swapped marker), after which the tracker is
right again. Runs start at random frames, one per EVERY seconds of each file on average
(Poisson), in the object's files and the palm's alike.

`--fault dropout`: the tracker loses the object, one or two times per object file (equally
likely), each for 0.1-1.0 s (uniform; at least 3 frames) starting at a random frame: those
frames are missing.

`--fault hold`: the tracker loses the object once per object file for 0.1-1.0 s and goes on
writing its last pose at the frames' stamps (held poses), or, one time in four, the null pose
(0 0 0, identity).

Only the demonstrations at the noise levels LEVELS are copied (with their truth files and a
filtered manifest). DST/glitches.log lists every fault: file, first frame, length, time from
the file's start [s], and for a glitch the position error [mm] and rotation error [deg] (for a
dropout or a hold: 0 0, or -1 -1 for a null pose). Deterministic for a given seed.

Needs numpy and scipy.
"""
import argparse
import json
import os
import shutil

import numpy as np
from scipy.spatial.transform import Rotation


def lost_frames(rows, rng):
    """A random span of 0.1-1.0 s of `rows` (at least 3 frames, away from the ends): (first, n)."""
    rate = (len(rows) - 1) / max(rows[-1, 0] - rows[0, 0], 1e-9)
    n = max(3, int(rng.uniform(0.1, 1.0) * rate))
    return int(rng.integers(5, max(6, len(rows) - n - 5))), n


def fault_file(src, dst, fault, every, max_run, rng, log, palm):
    lines = open(src).read().splitlines()
    head = [l for l in lines if l.startswith("#")]
    rows = np.array([[float(x) for x in l.split()] for l in lines if l and not l.startswith("#")])
    if len(rows) < (10 if fault == "glitch" else 20) or (palm and fault != "glitch"):
        shutil.copy(src, dst)
        return
    name = os.path.basename(src)
    if fault == "dropout":
        keep = np.ones(len(rows), bool)
        for _ in range(int(rng.integers(1, 3))):
            i, n = lost_frames(rows, rng)
            keep[i:i + n] = False
            log.write("%s %d %d %.4f 0 0\n" % (name, i, n, rows[i, 0] - rows[0, 0]))
        rows = rows[keep]
    elif fault == "hold":
        i, n = lost_frames(rows, rng)
        null = rng.uniform() < 0.25
        rows[i:i + n, 1:] = [0, 0, 0, 0, 0, 0, 1] if null else rows[i - 1, 1:]
        log.write("%s %d %d %.4f %d %d\n" % (name, i, n, rows[i, 0] - rows[0, 0], -null, -null))
    else:
        glitch_rows(rows, every, max_run, rng, log, name)
    with open(dst, "w") as out:
        for h in head:
            out.write(h + "\n")
        for r in rows:
            out.write("%.6f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n" % tuple(r))


def glitch_rows(rows, every, max_run, rng, log, name):
    duration = rows[-1, 0] - rows[0, 0]
    for _ in range(rng.poisson(max(duration, 0.0) / every)):
        n = int(rng.integers(1, max_run + 1))
        i = int(rng.integers(0, len(rows) - n))
        dp = rng.normal(size=3)
        dp *= rng.uniform(5e-3, 30e-3) / np.linalg.norm(dp)
        dr = rng.normal(size=3)
        dr *= np.radians(rng.uniform(2.0, 10.0)) / np.linalg.norm(dr)
        q = Rotation.from_quat(rows[i:i + n, 4:8])
        rows[i:i + n, 1:4] += dp
        rows[i:i + n, 4:8] = (Rotation.from_rotvec(dr) * q).as_quat()
        log.write("%s %d %d %.4f %.1f %.1f\n" % (name, i, n, rows[i, 0] - rows[0, 0],
                                                 np.linalg.norm(dp) * 1e3,
                                                 np.degrees(np.linalg.norm(dr))))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("src")
    ap.add_argument("dst")
    ap.add_argument("--fault", choices=["glitch", "dropout", "hold"], default="glitch")
    ap.add_argument("--every", type=float, default=5.0, help="seconds per glitch run (mean)")
    ap.add_argument("--levels", default="real,mocap", help="noise levels to copy")
    ap.add_argument("--max-run", type=int, default=6, help="longest run [frames]")
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    levels = set(args.levels.split(","))
    os.makedirs(args.dst, exist_ok=True)
    manifest = json.load(open(os.path.join(args.src, "manifest.json")))
    manifest["demos"] = [d for d in manifest["demos"] if d.get("noise") in levels]
    json.dump(manifest, open(os.path.join(args.dst, "manifest.json"), "w"))
    rng = np.random.default_rng(args.seed)
    with open(os.path.join(args.dst, "glitches.log"), "w") as log:
        for d in manifest["demos"]:
            for key in ("tum", "palm"):
                if d.get(key):
                    fault_file(os.path.join(args.src, d[key]), os.path.join(args.dst, d[key]),
                               args.fault, args.every, args.max_run, rng, log, key == "palm")
            shutil.copy(os.path.join(args.src, d["truth"]), os.path.join(args.dst, d["truth"]))


if __name__ == "__main__":
    main()
