#!/usr/bin/env python3
"""Copy a simulated dataset (written by `objmodel dataset`) with tracker glitches in its pose
files, to measure what glitches teach (`bench/precision.py` on the copy).

    python3 bench/glitch_copy.py SRC DST [--every 5] [--levels real,mocap] [--max-run 6] [--seed 1]

A glitch is a run of 1 to MAX_RUN consecutive frames whose pose is wrong by one error, 5-30 mm
and 2-10 degrees (a misread tag, a swapped marker), after which the tracker is right again.
Runs start at random frames, one per EVERY seconds of each file on average (Poisson), in the
object's files and the palm's alike. Only the demonstrations at the noise levels LEVELS are
copied (with their truth files and a filtered manifest). DST/glitches.log lists every run:
file, first frame, length, time from the file's start [s], position error [mm], rotation
error [deg]. Deterministic for a given seed.

Needs numpy and scipy.
"""
import argparse
import json
import os
import shutil

import numpy as np
from scipy.spatial.transform import Rotation


def glitch_file(src, dst, every, max_run, rng, log):
    lines = open(src).read().splitlines()
    head = [l for l in lines if l.startswith("#")]
    rows = np.array([[float(x) for x in l.split()] for l in lines if l and not l.startswith("#")])
    if len(rows) < 10:
        shutil.copy(src, dst)
        return
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
        log.write("%s %d %d %.4f %.1f %.1f\n" % (os.path.basename(src), i, n, rows[i, 0] - rows[0, 0],
                                                 np.linalg.norm(dp) * 1e3,
                                                 np.degrees(np.linalg.norm(dr))))
    with open(dst, "w") as out:
        for h in head:
            out.write(h + "\n")
        for r in rows:
            out.write("%.6f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n" % tuple(r))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("src")
    ap.add_argument("dst")
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
                    glitch_file(os.path.join(args.src, d[key]), os.path.join(args.dst, d[key]),
                                args.every, args.max_run, rng, log)
            shutil.copy(os.path.join(args.src, d["truth"]), os.path.join(args.dst, d["truth"]))


if __name__ == "__main__":
    main()
