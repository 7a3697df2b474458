#!/usr/bin/env python3
"""Robustness probe: classify and learn transformed kinematic demonstrations against truth.

Generates demonstrations with `objmodel synth` (30 per kind), applies a transform to each
(frame rate, cut rests, extra noise, timestamp jitter, a rotated world frame, correlated noise,
...), and prints per transform the kinds classified right and the learnt edge's errors against
the generator's truth (median and largest: direction in degrees, distance of the learnt point
from the true line in mm). Instrumented demonstrations get the transform on both files.

    python3 bench/robustness_probe.py [TRANSFORM ...]     (default: all)
    OBJMODEL=target/release/objmodel EXTRA="--gravity none" python3 bench/robustness_probe.py world

Needs numpy and scipy. Writes into $PROBE_DIR (default /tmp/objmodel-probe). Not a test: the
numbers are for reading (see the notes on issue 3).
"""
import glob
import json
import math
import os
import subprocess
import sys

import numpy as np
from scipy.spatial.transform import Rotation as R, Slerp

BIN = os.environ.get("OBJMODEL", "target/release/objmodel")
EXTRA = os.environ.get("EXTRA", "").split()
DIR = os.environ.get("PROBE_DIR", "/tmp/objmodel-probe")
rng = np.random.default_rng(5)


def read(path):
    rows = [l.split() for l in open(path) if l.strip() and not l.startswith("#")]
    return np.array(rows, dtype=float)


def write(path, a):
    with open(path, "w") as f:
        f.write("# timestamp tx ty tz qx qy qz qw\n")
        for r in a:
            f.write("%.6f " % r[0] + " ".join("%.9f" % x for x in r[1:]) + "\n")


def noise(a, sp, sr):
    b = a.copy()
    b[:, 1:4] += rng.normal(scale=sp, size=(len(a), 3))
    b[:, 4:8] = (R.from_quat(a[:, 4:8]) * R.from_rotvec(rng.normal(scale=sr, size=(len(a), 3)))).as_quat()
    return b


def upsample(a, k):
    """k frames per input interval, interpolated (slerp, linear)."""
    out = []
    for i in range(len(a) - 1):
        sl = Slerp([0, 1], R.from_quat([a[i, 4:8], a[i + 1, 4:8]]))
        for j in range(k):
            s = j / k
            out.append(np.concatenate([[a[i, 0] * (1 - s) + a[i + 1, 0] * s],
                                       a[i, 1:4] * (1 - s) + a[i + 1, 1:4] * s, sl(s).as_quat()]))
    return np.array(out)


def trim_start(a):
    """Cut the rest before the motion (from 3 frames before 2 cm or 3 degrees of motion)."""
    ang = (R.from_quat(a[0, 4:8]).inv() * R.from_quat(a[:, 4:8])).magnitude()
    d = np.linalg.norm(a[:, 1:4] - a[0, 1:4], axis=1)
    i = int(np.argmax((ang > 0.05) | (d > 0.02)))
    return a[max(i - 3, 0):]


def jitter(a):
    b = a.copy()
    b[:, 0] += rng.uniform(0, 0.01, size=len(a))
    b[:, 0] = np.maximum.accumulate(b[:, 0] + np.arange(len(a)) * 1e-7)
    return b


def world(a, T=None, t=None):
    T = T or R.random(random_state=int(rng.integers(1e9)))
    t = rng.normal(size=3) if t is None else t
    b = a.copy()
    b[:, 1:4] = T.apply(a[:, 1:4]) + t
    b[:, 4:8] = (T * R.from_quat(a[:, 4:8])).as_quat()
    return b


def ema(a, alpha):
    b = a.copy()
    for i in range(1, len(a)):
        b[i, 1:4] = alpha * a[i, 1:4] + (1 - alpha) * b[i - 1, 1:4]
        q = alpha * a[i, 4:8] * np.sign(a[i, 4:8] @ b[i - 1, 4:8] or 1) + (1 - alpha) * b[i - 1, 4:8]
        b[i, 4:8] = q / np.linalg.norm(q)
    return b


DEG = math.radians(1)
# name: (source noise of `objmodel synth`, transform)
TRANSFORMS = {
    "as-generated": ("real", lambda a: a),
    "15Hz": ("real", lambda a: a[::2]),
    "no-rest-before": ("real", trim_start),
    "no-rest-after": ("real", lambda a: trim_start(a[::-1])[::-1]),
    "noise-2mm-1deg-added": ("real", lambda a: noise(a, 2e-3, DEG)),
    "jitter-10ms": ("real", jitter),
    "world-rotated": ("real", world),
    "clean+white": ("clean", lambda a: noise(a, 1e-3, 0.5 * DEG)),
    "clean-60Hz+white": ("clean", lambda a: noise(upsample(a, 2), 1e-3, 0.5 * DEG)),
    "clean-120Hz+white": ("clean", lambda a: noise(upsample(a, 4), 1e-3, 0.5 * DEG)),
    "real-interpolated-120Hz": ("real", lambda a: upsample(a, 4)),
    "white+ema0.3": ("clean", lambda a: ema(noise(a, 1e-3, 0.5 * DEG), 0.3)),
}


def angle_deg(u, v):
    u, v = np.asarray(u) / np.linalg.norm(u), np.asarray(v) / np.linalg.norm(v)
    return math.degrees(math.acos(min(1.0, abs(float(u @ v)))))


def off_line_mm(p, q, v):
    v = np.asarray(v) / np.linalg.norm(v)
    w = np.asarray(p) - np.asarray(q)
    return 1e3 * float(np.linalg.norm(w - (w @ v) * v))


def demos(kind, noise_kind):
    out = f"{DIR}/{kind}-{noise_kind}"
    if not glob.glob(f"{out}/*.tum"):
        seed = {"topple": 21, "slide": 22, "general": 23, "instrumented": 24}[kind]
        subprocess.run([BIN, "synth", kind, "-o", out, "-c", "30", "--seed", str(seed),
                        "--noise", noise_kind], check=True, capture_output=True)
    return sorted(p for p in glob.glob(f"{out}/*.tum") if not p.endswith(".palm.tum"))


def probe(name):
    noise_kind, f = TRANSFORMS[name]
    row = {}
    for kind in ("topple", "slide", "general", "instrumented"):
        ok, errs = 0, []
        paths = demos(kind, noise_kind)
        for path in paths:
            truth = json.load(open(path[:-4] + ".truth.json"))
            x = f"{DIR}/x.tum"
            if kind == "instrumented":
                # The same transform for the palm (world changes must be the same rigid one),
                # and the palm cut to the object's time span (cuts are decided on the object).
                state = rng.bit_generator.state
                obj = f(read(path))
                write(x, obj)
                if name == "world-rotated":
                    rng.bit_generator.state = state  # (the noise stays independent)
                palm = f(read(path[:-4] + ".palm.tum"))
                if name.startswith("no-rest"):
                    palm = read(path[:-4] + ".palm.tum")
                    palm = palm[(palm[:, 0] >= obj[0, 0] - 0.1) & (palm[:, 0] <= obj[-1, 0] + 0.1)]
                write(f"{DIR}/x.palm.tum", palm)
            else:
                if os.path.exists(f"{DIR}/x.palm.tum"):
                    os.remove(f"{DIR}/x.palm.tum")
                write(x, f(read(path)))
            r = subprocess.run([BIN, "classify", x, "--json"] + EXTRA, capture_output=True, text=True)
            if r.returncode != 0:
                print(f"{name}: {path}: exit {r.returncode}: {r.stderr.strip()[:200]}")
                continue
            got = json.loads(r.stdout)["kind"]
            ok += got == truth["kind"]
            if truth["kind"] == "topple" and got == "topple":
                r = subprocess.run([BIN, "learn", x, "--json"] + EXTRA, capture_output=True, text=True)
                edges = json.loads(r.stdout)["edges"] if r.returncode == 0 else []
                if edges:
                    e, t = edges[0], truth["edge"]
                    errs.append((angle_deg(e["direction"], t["direction"]),
                                 off_line_mm(e["point"], t["point"], t["direction"])))
        row[kind] = f"{ok}/{len(paths)}"
        if errs:
            e = np.array(errs)
            row[kind + " edge"] = "%.2f°/%.1f mm, max %.2f°/%.1f mm" % (
                np.median(e[:, 0]), np.median(e[:, 1]), e[:, 0].max(), e[:, 1].max())
    print(name, json.dumps(row, ensure_ascii=False), flush=True)


if __name__ == "__main__":
    os.makedirs(DIR, exist_ok=True)
    for name in sys.argv[1:] or TRANSFORMS:
        probe(name)
