#!/usr/bin/env python3
"""Precision and recall of the features learnt from all the demonstrations of each box of a
simulated dataset (written by `objmodel dataset`), per noise level: a learnt edge is true when
it is within 5 mm and 3 degrees of an edge of the box, a face when its normal is within 5
degrees of a face's (sign included when known) and its offset, if known, within 5 mm.

    python3 bench/precision.py DATA_DIR [--bin target/release/objmodel]

Needs numpy. Prints a Markdown table.
"""
import argparse
import glob
import itertools
import json
import os
import subprocess

import numpy as np


def quat_matrix(q):
    x, y, z, w = q  # the truth files store nalgebra's (i, j, k, w)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def box_features(truth):
    """The box's faces (normal, offset) and edges (point, direction) in the tag frame."""
    r = quat_matrix(truth["box_from_tag"]["quaternion"])
    t = np.array(truth["box_from_tag"]["translation"])
    # tag_from_box: x_tag = R^T (x_box - t)
    to_tag = lambda p: r.T @ (p - t)
    half = np.array(truth["box_dims"]) / 2
    faces, edges = [], []
    for a in range(3):
        for s in (1, -1):
            n_box = np.zeros(3)
            n_box[a] = s
            n = r.T @ n_box
            p = to_tag(n_box * half)
            faces.append((n, float(n @ p)))
    for a in range(3):
        b, c = [k for k in range(3) if k != a]
        for sb, sc in itertools.product((1, -1), repeat=2):
            p = np.zeros(3)
            p[b], p[c] = sb * half[b], sc * half[c]
            d = np.zeros(3)
            d[a] = 1
            edges.append((to_tag(p), r.T @ d))
    return faces, edges


def line_distance(p, u, q, v):
    u, v = u / np.linalg.norm(u), v / np.linalg.norm(v)
    ang = np.degrees(np.arccos(min(1.0, abs(float(u @ v)))))
    d = p - q
    d = d - v * (d @ v)
    return ang, float(np.linalg.norm(d))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("data")
    ap.add_argument("--bin", default="target/release/objmodel")
    a = ap.parse_args()
    manifest = json.load(open(os.path.join(a.data, "manifest.json")))
    groups = {}
    for d in manifest["demos"]:
        groups.setdefault((d["box"], d["noise"]), []).append(d)
    print("| box | noise | demos | edges true/learnt | faces true/learnt | box edges found | box faces found | wrong features |")
    print("|---|---|---|---|---|---|---|---|")
    totals = np.zeros(4, int)
    for (box, noise), demos in sorted(groups.items()):
        files = [os.path.join(a.data, d["tum"]) for d in demos]
        out = subprocess.run([a.bin, "learn", *files, "--json", "--quiet"], capture_output=True, text=True)
        tree = json.loads(out.stdout)
        truth = json.load(open(os.path.join(a.data, demos[0]["truth"])))
        faces, edges = box_features(truth)
        wrong = []
        true_e, found_e = 0, set()
        for e in tree["edges"]:
            best = min(range(len(edges)), key=lambda k: sum(line_distance(np.array(e["point"]), np.array(e["direction"]), *edges[k])[::-1]))
            ang, dist = line_distance(np.array(e["point"]), np.array(e["direction"]), *edges[best])
            if ang < 3 and dist < 5e-3:
                true_e += 1
                found_e.add(best)
            else:
                wrong.append(f"{e['id']} ({ang:.1f} deg, {dist * 1e3:.1f} mm)")
        true_f, found_f = 0, set()
        for f in tree["faces"]:
            n = np.array(f["normal"])
            ok = False
            for k, (tn, td) in enumerate(faces):
                c = float(n @ tn)
                if not f["sign_known"]:
                    c = abs(c)
                if np.degrees(np.arccos(min(1.0, c))) < 5 and (f["offset"] is None or abs(f["offset"] - td) < 5e-3):
                    ok = True
                    found_f.add(k)
            if ok:
                true_f += 1
            else:
                wrong.append(f"{f['id']} ({f['support'][0]})")
        totals += [true_e, len(tree["edges"]), true_f, len(tree["faces"])]
        print(f"| {box} | {noise} | {len(files)} | {true_e}/{len(tree['edges'])} | {true_f}/{len(tree['faces'])} | {len(found_e)}/12 | {len(found_f)}/6 | {', '.join(wrong) or '-'} |")
    print(f"\nPrecision: edges {totals[0]}/{totals[1]}, faces {totals[2]}/{totals[3]}")


if __name__ == "__main__":
    main()
