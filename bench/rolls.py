#!/usr/bin/env python3
"""Rolls over an edge found inside motions (`roll` parts, `crates/objmodel/src/roll/`), against
the ground truth of a simulated dataset (written by `objmodel dataset`).

    python3 bench/rolls.py DATA_DIR [--bin target/release/objmodel] [--scene toss]

For every demonstration of the scene, `objmodel classify --json`; per noise level:
* measurable rolls: truth intervals of topple about an edge turning >= 8.6 deg over >= 5
  frames (as bench/precision.py counts them);
* found: those with a taught roll whose edge is within 5 mm and 3 deg of the rolled edge
  (recall), and those with any roll part (taught or withheld) overlapping them;
* rolls reported / taught, and taught rolls whose edge is within 5 mm and 3 deg of *some*
  edge of the box (precision of the taught rolls, before fusion in the tree);
* error/sigma of the taught edges against the nearest true edge: point (normal to the edge)
  and direction, each as sqrt(chi2_2 / 2) (about 1 when the covariance is honest), median and
  90th percentile, and the share within the 95% chi2_2 bound.

Needs numpy; imports bench/precision.py's box features and line distance.
"""
import argparse
import json
import os
import subprocess
import sys
from collections import defaultdict

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from precision import (MIN_ROLL_FRAMES, MIN_ROLL_TURN, box_features, line_distance,  # noqa: E402
                       roll_frames)

CHI2_2_95 = 5.991


def chi2_normal(cov, d):
    """d^T cov^+ d for a vector d normal to a line (cov of rank 2)."""
    return float(d @ np.linalg.pinv(cov, rcond=1e-10) @ d)


def edge_errors(e, edges):
    """(index of nearest true edge, angle deg, distance m, chi2 point, chi2 direction)."""
    p, u = np.array(e["line"]["point"]), np.array(e["line"]["direction"])
    best = None
    for k, (_, q, v) in enumerate(edges):
        ang, dist = line_distance(p, u, q, v)
        key = ang / 3 + dist / 5e-3
        if best is None or key < best[0]:
            best = (key, k, ang, dist, q, v)
    _, k, ang, dist, q, v = best
    u = u / np.linalg.norm(u)
    v = v / np.linalg.norm(v)
    if u @ v < 0:
        v = -v
    # Point error normal to the learnt line, at its point closest to the origin.
    d = p - q
    d = d - v * (d @ v)
    d = d - u * (d @ u)
    cp = chi2_normal(np.array(e["point_cov"]).reshape(3, 3), d)
    du = v - u
    du = du - u * (du @ u)
    cd = chi2_normal(np.array(e["direction_cov"]).reshape(3, 3), du)
    return k, ang, dist, cp, cd


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("data")
    ap.add_argument("--bin", default="target/release/objmodel")
    ap.add_argument("--scene", default="toss")
    ap.add_argument("--list", action="store_true", help="print every roll and missed roll")
    ap.add_argument("--noise", choices=["given"], help="given: pass each level's true noise "
                    "(the manifest's noise_position / noise_rotation) to classify")
    a = ap.parse_args()
    manifest = json.load(open(os.path.join(a.data, "manifest.json")))
    demos = [d for d in manifest["demos"] if d["scene"] == a.scene]
    stats = defaultdict(lambda: defaultdict(int))
    ratios = defaultdict(lambda: ([], []))
    for d in demos:
        truth = json.load(open(os.path.join(a.data, d["truth"])))
        rate = d.get("rate_hz") or truth.get("rate_hz") or 30.0
        faces, edges = box_features(truth)
        ids = [x[0] for x in edges]
        cmd = [a.bin, "classify", os.path.join(a.data, d["tum"]), "--json"]
        if a.noise == "given":
            # The simulator's noise (zero at `clean`: the learner's floors then stand).
            n = truth["noise"]
            cmd += ["--noise-position", str(max(n["sigma_position"], 5e-5)),
                    "--noise-rotation", str(max(n["sigma_rotation"], 2e-4))]
        out = subprocess.run(cmd, capture_output=True, text=True)
        if out.returncode != 0:
            print(f"{d['name']}: classify failed: {out.stderr.strip()}", file=sys.stderr)
            continue
        c = json.loads(out.stdout)
        rolls = c.get("rolls", [])
        s = stats[d["noise"]]
        s["demos"] += 1
        s["reported"] += len(rolls)
        judged = []
        for r in rolls:
            k, ang, dist, cp, cd = edge_errors(r["edge"], edges)
            ok = ang < 3 and dist < 5e-3
            judged.append((r, ids[k], ok))
            if r["taught"]:
                s["taught"] += 1
                s["taught_true"] += ok
                ratios[d["noise"]][0].append(cp)
                ratios[d["noise"]][1].append(cd)
                if not ok or a.list:
                    print(f"{'WRONG ' if not ok else ''}{d['name']} roll {r['t_start']:.3f}-{r['t_end']:.3f} s "
                          f"turn {np.degrees(r['turn']):.1f} deg: nearest {ids[k]} {ang:.2f} deg "
                          f"{dist * 1e3:.2f} mm, chi2 point {cp:.1f} direction {cd:.1f}")
        for m in truth.get("modes", []):
            frames = roll_frames(m, rate)
            if not (m["mode"] == "topple" and m.get("edge") and m["turn_deg"] >= MIN_ROLL_TURN
                    and frames >= MIN_ROLL_FRAMES):
                continue
            s["measurable"] += 1
            over = [(r, e, ok) for r, e, ok in judged
                    if r["t_start"] <= m["t1"] and r["t_end"] >= m["t0"]]
            if over:
                s["covered"] += 1
            if any(r["taught"] and ok and e == m["edge"]["id"] for r, e, ok in over):
                s["found"] += 1
            elif a.list:
                why = "; ".join(r.get("withheld") or f"taught, nearest {e}" for r, e, ok in over) or "no roll"
                print(f"missed {d['name']} {m['t0']:.3f}-{m['t1']:.3f} s {m['turn_deg']:.1f} deg "
                      f"{frames} frames about {m['edge']['id']}: {why}")
    print("| noise | demos | measurable rolls | found (taught, within 5 mm, 3 deg) | with a roll part | "
          "rolls reported | taught | taught true | error/sigma point: median, p90, within 95% | "
          "direction: median, p90, within 95% |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    order = ["clean", "mocap", "real", "noisy"]
    for noise in sorted(stats, key=lambda n: order.index(n) if n in order else 99):
        s = stats[noise]
        cps, cds = (np.array(x) for x in ratios[noise])

        def summ(x):
            if len(x) == 0:
                return "-"
            r = np.sqrt(x / 2)
            return f"{np.median(r):.2f}, {np.percentile(r, 90):.2f}, {100 * np.mean(x < CHI2_2_95):.0f}%"

        print(f"| {noise} | {s['demos']} | {s['measurable']} | {s['found']} | {s['covered']} | "
              f"{s['reported']} | {s['taught']} | {s['taught_true']}/{s['taught']} | {summ(cps)} | {summ(cds)} |")


if __name__ == "__main__":
    main()
