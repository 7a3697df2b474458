#!/usr/bin/env python3
"""Real tosses from another lab: the ContactNets cube (Pfrommer, Halm, Posa, "ContactNets:
Learning discontinuous contact dynamics with smooth, implicit representations", CoRL 2020;
github.com/DAIRLab/contact-nets, BSD-3-Clause), learnt by objmodel and scored against the cube.

570 tosses of one acrylic cube (half-width 52.4 mm) onto a board, tracked with AprilTags at
148 Hz; each file runs from the release (in flight) to a short rest (a tenth of a second). The
processed files (`data/tosses_processed/N.pt`) hold per frame: position (3, in half-widths,
board frame, z up), quaternion (4, real part first), velocity, angular velocity and zeros; the
tracked frame is the cube's centre, axes along its faces. This script reads them without torch
(the files are torch's legacy pickle format), writes them as TUM files in metres
(`box0_real_N.tum`, t = N / 148 s) with the cube's faces and edges in `box0_real.truth.json`,
learns all of them together (`objmodel learn --json`) and scores the tree as
`bench/mujoco_tosses.py` does (an edge within 5 mm and 3° of one of the cube's, a face within 5°
and, with an offset, 5 mm).

    python3 bench/contactnets.py CONTACT_NETS_REPO [OUT_DIR]      (OUT_DIR default /tmp/contactnets)
    EVERY=10 ...        (only tosses 0, 10, 20, ...: how tests/data/contactnets_tosses was made,
                         with toss 334 added by ONLY_TOO=334)
    SUPPORT_HEIGHT=0 ...  (learn with the board's height given, `--support-height 0`: the
                         faces' offsets and the shape)

Needs numpy. The repository: `git clone https://github.com/DAIRLab/contact-nets`. Not a test:
the numbers are for reading (see the notes on issue 20); `crates/objmodel/tests/real_tosses.rs`
holds a subset as a test.
"""
import glob
import itertools
import json
import os
import pickle
import struct
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from scoring import learn_and_score  # noqa: E402

HALF = 0.0524   # the cube's half-width [m] (ContactNets' BLOCK_HALF_WIDTH)
RATE = 148.0    # the tracker's rate [Hz]
BIN = os.environ.get("OBJMODEL", "target/release/objmodel")
STORAGE = {"DoubleStorage": np.float64, "FloatStorage": np.float32}


class _Unpickler(pickle.Unpickler):
    """torch's legacy format without torch: tensors become (storage key, offset, size,
    stride), storages (kind, key)."""

    def find_class(self, module, name):
        if module == "torch._utils" and name == "_rebuild_tensor_v2":
            return lambda storage, offset, size, stride, *rest: (storage, offset, size, stride)
        if module == "torch" and name.endswith("Storage"):
            return name
        if module == "collections" and name == "OrderedDict":
            import collections
            return collections.OrderedDict
        raise pickle.UnpicklingError(f"unexpected {module}.{name}")

    def persistent_load(self, pid):
        _, kind, key, _, _, _ = pid
        return (kind, key)


def load_tensor(path):
    """The one tensor a legacy `torch.save` file holds, as a numpy array."""
    with open(path, "rb") as f:
        for _ in range(3):      # magic number, protocol version, system info
            pickle.load(f)
        (kind, key), offset, size, stride = _Unpickler(f).load()
        keys = pickle.load(f)
        data = {}
        for k in keys:
            n, = struct.unpack("<q", f.read(8))
            dtype = STORAGE[kind]
            data[k] = np.frombuffer(f.read(n * np.dtype(dtype).itemsize), dtype=dtype)
    a = data[key]
    return np.lib.stride_tricks.as_strided(
        a[offset:], shape=size, strides=[s * a.itemsize for s in stride]).copy()


def write_tum(run, path, toss):
    with open(path, "w") as f:
        f.write(f"# ContactNets toss {toss} (github.com/DAIRLab/contact-nets, "
                "data/tosses_processed, BSD-3-Clause): the cube's centre in the board frame, "
                f"{RATE:.0f} Hz, metres\n")
        for i, r in enumerate(run):
            x, y, z = r[0:3] * HALF
            qw, qx, qy, qz = r[3:7]
            f.write(f"{i / RATE:.6f} {x:.6f} {y:.6f} {z:.6f} {qx:.7f} {qy:.7f} {qz:.7f} {qw:.7f}\n")


def cube_truth():
    """The cube's faces (outward normal, offset) and edges (point, direction)."""
    axes = np.eye(3)
    faces = [(s * axes[k], HALF) for k in range(3) for s in (-1.0, 1.0)]
    edges = []
    for k in range(3):
        o = [j for j in range(3) if j != k]
        for s1, s2 in itertools.product((-1.0, 1.0), repeat=2):
            p = np.zeros(3)
            p[o[0]], p[o[1]] = s1 * HALF, s2 * HALF
            edges.append((p, axes[k]))
    return faces, edges


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    src = os.path.join(sys.argv[1], "data", "tosses_processed")
    out = sys.argv[2] if len(sys.argv) > 2 else "/tmp/contactnets"
    every = int(os.environ.get("EVERY", "1"))
    too = {int(x) for x in os.environ.get("ONLY_TOO", "").split(",") if x}
    os.makedirs(out, exist_ok=True)
    tosses = sorted(int(os.path.basename(p)[:-3]) for p in glob.glob(f"{src}/*.pt"))
    tosses = [n for n in tosses if n % every == 0 or n in too]
    paths = []
    for n in tosses:
        run = load_tensor(f"{src}/{n}.pt")[0]
        paths.append(f"{out}/box0_real_{n}.tum")
        write_tum(run, paths[-1], n)
    faces, edges = cube_truth()
    with open(f"{out}/box0_real.truth.json", "w") as f:
        json.dump({"half": [HALF] * 3,
                   "faces": [{"normal": list(n), "offset": d} for n, d in faces],
                   "edges": [{"point": list(p), "direction": list(u)} for p, u in edges]},
                  f, indent=1)
    print(f"{len(paths)} tosses written to {out}")
    given = os.environ.get("SUPPORT_HEIGHT")
    support = ["--support-height", given] if given is not None else []
    s = learn_and_score([BIN, "learn", *paths, *support, "--json"], f"{out}/tree.json", faces, edges)
    if s is None:
        sys.exit(1)
    tree, et, ft, wrong = s
    print(f"edges {et}/{len(tree['edges'])} true (the cube has 12), faces {ft}/{len(tree['faces'])} "
          f"true (of 6), offsets known: {sum(f['offset'] is not None for f in tree['faces'])}, "
          f"centre of mass: {'none' if tree.get('com') is None else tree['com']}")
    for f in tree["faces"]:
        if f["offset"] is not None:
            print(f"  {f['id']}: offset {f['offset'] * 1e3:.2f} mm ±{f['offset_sigma_m'] * 1e3:.2f} "
                  f"(the cube's {HALF * 1e3:.1f} mm)")
    if tree.get("shape"):
        lo, hi = tree["shape"]["extents"]
        print(f"  shape: {len(tree['shape']['vertices'])} vertices, extents "
              f"{[round(x * 1e3, 1) for x in lo]} to {[round(x * 1e3, 1) for x in hi]} mm")
    if wrong:
        print("WRONG:", wrong)
    kinds = {}
    for path in paths:
        r = subprocess.run([BIN, "classify", path, "--json"], capture_output=True, text=True)
        for p in json.loads(r.stdout).get("parts", []) if r.returncode == 0 else []:
            kinds[p["kind"]] = kinds.get(p["kind"], 0) + 1
    print("parts:", kinds)


if __name__ == "__main__":
    main()
