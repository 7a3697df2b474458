#!/usr/bin/env python3
"""Precision and recall of the features the learner reports, against the ground truth of a
simulated dataset (written by `objmodel dataset`).

    python3 bench/precision.py DATA_DIR [--bin target/release/objmodel] [--tables box,scene,all]
                               [--learn-args "--support-height 0"]

A learnt edge is true when it is within 5 mm and 3 degrees of an edge of the box, a face when
its normal is within 5 degrees of a face's (sign included when known) and its offset, if known,
within 5 mm. Precision = learnt features that are true / learnt features.

Recall counts the features the demonstrations showed in a mode that can teach them, from the
truth's per-interval `modes`: a face that the box rested on for at least 0.05 s, or slid on
for at least 0.1 s moving 5 mm or turning 3 degrees; an edge it toppled about (the edge on the
support and not slipping) while turning at least 5 degrees. Recall = those features found /
those features. ("box edges/faces found" counts any of the box's 12 edges and 6 faces.)
"measurable rolls" (scene table): the edges rolled over long enough to be measured — one
interval of topple about the edge turning at least 8.6 degrees (what an edge rotation must
turn to locate its edge) over at least 5 frames at the file's rate (what a roll needs to
reject the free flight that a spinning object's few frames can pass for) — found / shown, and
in brackets the number of such rolls.

Tables (Markdown on stdout):
* `box`: per box and noise level, the single-mode scenes of the original dataset (topple,
  instrumented, slide, general, compound) learnt together — the measurement this script made
  before the messy scenes existed;
* `scene`: per scene kind and noise level: each box's demonstrations of that kind learnt
  together (e.g. all tosses of a box at once), summed over the boxes;
* `all`: per box and noise level, every demonstration of the box learnt together.
Then every wrong feature with the demonstrations that support it and the true contact modes
during the learner's segment that taught it.

Needs numpy.
"""
import argparse
import itertools
import json
import os
import subprocess
from collections import Counter, defaultdict

import numpy as np

CLASSIC = {"topple", "instrumented", "slide", "general", "compound"}
MIN_REST = 0.05
MIN_SLIDE_T, MIN_SLIDE_TRAVEL, MIN_SLIDE_TURN = 0.1, 5e-3, 3.0
MIN_TOPPLE_TURN = 5.0
# A roll over an edge long enough to be measured: an interval the truth calls a topple about
# the edge (on the support, not slipping) that turns at least the 8.6 degrees an edge rotation
# must turn to locate its edge (`classify::parts::edge_turns_too_little`) and holds at least
# the learner's `roll::MIN_ROLL_FRAMES` (5, `flight::MIN_FLIGHT_FRAMES`: a flight has 9
# unknowns, and a roll must reject it) frames of the file's frame clock (t = k / rate).
# (Until 2026-12-04 this counted 3 frame intervals, 3-4 frames, which no roll can have.)
MIN_ROLL_TURN, MIN_ROLL_FRAMES = 8.6, 5


def roll_frames(m, rate):
    """Frames of the file's clock (t = k / rate) within the truth interval `m`."""
    return int(np.floor(m["t1"] * rate + 1e-9) - np.ceil(m["t0"] * rate - 1e-9)) + 1


def quat_matrix(q):
    x, y, z, w = q  # the truth files store nalgebra's (i, j, k, w)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def box_features(truth):
    """The box's faces (id, normal, offset) and edges (id, point, direction), tag frame."""
    if truth.get("features"):
        f = truth["features"]
        faces = [(x["id"], np.array(x["normal"]), x["offset"]) for x in f["faces"]]
        edges = [(x["id"], np.array(x["point"]), np.array(x["direction"])) for x in f["edges"]]
        return faces, edges
    # Older truth files: from box_from_tag and the dimensions.
    r = quat_matrix(truth["box_from_tag"]["quaternion"])
    t = np.array(truth["box_from_tag"]["translation"])
    to_tag = lambda p: r.T @ (p - t)
    half = np.array(truth["box_dims"]) / 2
    faces, edges = [], []
    for a in range(3):
        for s in (1, -1):
            n_box = np.zeros(3)
            n_box[a] = s
            n = r.T @ n_box
            faces.append((f"{a}{s:+d}", n, float(n @ to_tag(n_box * half))))
    for a in range(3):
        b, c = [k for k in range(3) if k != a]
        for sb, sc in itertools.product((1, -1), repeat=2):
            p = np.zeros(3)
            p[b], p[c] = sb * half[b], sc * half[c]
            d = np.zeros(3)
            d[a] = 1
            edges.append((f"{b}{sb:+d}/{c}{sc:+d}", to_tag(p), r.T @ d))
    return faces, edges


def line_distance(p, u, q, v):
    u, v = u / np.linalg.norm(u), v / np.linalg.norm(v)
    ang = np.degrees(np.arccos(min(1.0, abs(float(u @ v)))))
    d = p - q
    d = d - v * (d @ v)
    return ang, float(np.linalg.norm(d))


def match_edge(e, edges):
    """(index of the nearest true edge, angle deg, distance m, true?)"""
    p, u = np.array(e["point"]), np.array(e["direction"])
    scores = [line_distance(p, u, q, v) for _, q, v in edges]
    k = min(range(len(edges)), key=lambda i: scores[i][0] / 3 + scores[i][1] / 5e-3)
    ang, dist = scores[k]
    return k, ang, dist, ang < 3 and dist < 5e-3


def match_face(f, faces):
    """(index of the nearest true face, angle deg, offset error m or None, true?)"""
    n = np.array(f["normal"])
    best = None
    for k, (_, tn, td) in enumerate(faces):
        c = float(n @ tn)
        if not f.get("sign_known", True):
            c = abs(c)
        ang = float(np.degrees(np.arccos(min(1.0, c))))
        off = None if f.get("offset") is None else abs(f["offset"] - td)
        ok = ang < 5 and (off is None or off < 5e-3)
        key = (not ok, ang)
        if best is None or key < best[0]:
            best = (key, (k, ang, off, ok))
    return best[1]


def demonstrated(truths):
    """Ids of the faces and edges the demonstrations showed in a mode that teaches them."""
    faces, edges = set(), set()
    for t in truths:
        for m in t.get("modes", []):
            dur = m["t1"] - m["t0"]
            if m["mode"] == "rest" and m.get("face") and dur >= MIN_REST:
                faces.add(m["face"]["id"])
            if m["mode"] == "slide" and m.get("face") and dur >= MIN_SLIDE_T and (
                m["travel"] >= MIN_SLIDE_TRAVEL or m["turn_deg"] >= MIN_SLIDE_TURN
            ):
                faces.add(m["face"]["id"])
            if m["mode"] == "topple" and m.get("edge") and m["turn_deg"] >= MIN_TOPPLE_TURN:
                edges.add(m["edge"]["id"])
    return faces, edges


def measurable_rolls(truths, rates):
    """Ids of the edges the demonstrations rolled over long enough to be measured (see
    MIN_ROLL_TURN), and how many such rolls there were."""
    edges, n = set(), 0
    for t, rate in zip(truths, rates):
        for m in t.get("modes", []):
            if (m["mode"] == "topple" and m.get("edge") and m["turn_deg"] >= MIN_ROLL_TURN
                    and roll_frames(m, rate) >= MIN_ROLL_FRAMES):
                edges.add(m["edge"]["id"])
                n += 1
    return edges, n


class Data:
    def __init__(self, root, binary, noise_given=False, learn_args=()):
        self.root, self.bin, self.noise_given = root, binary, noise_given
        self.learn_args = list(learn_args)
        self.manifest = json.load(open(os.path.join(root, "manifest.json")))
        self._truth, self._classify = {}, {}

    def truth(self, d):
        if d["name"] not in self._truth:
            self._truth[d["name"]] = json.load(open(os.path.join(self.root, d["truth"])))
        return self._truth[d["name"]]

    def learn(self, demos):
        args = []
        for d in demos:
            args.append(os.path.join(self.root, d["tum"]))
        if self.noise_given:
            # The simulator's noise, when the demonstrations share one (not the mocap level's
            # per-file noise); zero at `clean`, where the learner's floors then stand.
            noises = {(self.truth(d)["noise"]["sigma_position"], self.truth(d)["noise"]["sigma_rotation"])
                      for d in demos}
            if len(noises) == 1:
                sp, sr = noises.pop()
                args += ["--noise-position", str(max(sp, 5e-5)), "--noise-rotation", str(max(sr, 2e-4))]
        out = subprocess.run([self.bin, "learn", *args, *self.learn_args, "--json", "--quiet"],
                             capture_output=True, text=True)
        if out.returncode != 0:
            raise SystemExit(f"objmodel learn failed on {len(args)} files: {out.stderr.strip()}")
        return json.loads(out.stdout)

    def classify(self, d):
        if d["name"] not in self._classify:
            cmd = [self.bin, "classify", os.path.join(self.root, d["tum"]), "--json"]
            if d.get("palm"):
                cmd += ["--palm", os.path.join(self.root, d["palm"])]
            out = subprocess.run(cmd, capture_output=True, text=True)
            self._classify[d["name"]] = json.loads(out.stdout) if out.returncode == 0 else {"segments": []}
        return self._classify[d["name"]]


def modes_during(truth, t0, t1):
    """Share of [t0, t1] spent in each true mode, as 'mode(contact) 60%'."""
    c = Counter()
    for m in truth.get("modes", []):
        a, b = max(t0, m["t0"]), min(t1, m["t1"])
        if b > a:
            c[f"{m['mode']}({m['contact']})"] += b - a
    if t1 <= t0:
        for m in truth.get("modes", []):
            if m["t0"] <= t0 <= m["t1"]:
                c[f"{m['mode']}({m['contact']})"] += 1
    total = sum(c.values()) or 1
    return ", ".join(f"{k} {100 * v / total:.0f}%" for k, v in c.most_common(3))


def why(data, by_name, feature, is_edge):
    """Where a wrong feature came from: its demos' segments that report it, with the truth."""
    names = feature.get("support", [])
    out = []
    for name in names[:3]:
        d = by_name.get(os.path.splitext(name)[0])
        if d is None:
            continue
        truth = data.truth(d)
        for s in data.classify(d).get("segments", []):
            if is_edge and s.get("edge"):
                ln = s["edge"]["line"]
                ang, dist = line_distance(np.array(ln["point"]), np.array(ln["direction"]),
                                          np.array(feature["point"]), np.array(feature["direction"]))
                if ang < 5 and dist < 0.01:
                    out.append(f"{d['name']} {s['kind']} segment {s['t_start']:.2f}-{s['t_end']:.2f} s: {modes_during(truth, s['t_start'], s['t_end'])}")
            if not is_edge:
                n = np.array(feature["normal"])
                cands = []
                if s.get("face"):
                    cands.append((s["face"]["normal"], s["t_start"], s["t_end"], "slide"))
                for key, t in (("resting_normal_before", s["t_start"]), ("resting_normal_after", s["t_end"])):
                    if s.get(key):
                        cands.append((s[key], t, t, "rest"))
                for nn, a, b, src in cands:
                    if np.degrees(np.arccos(min(1.0, abs(float(n @ np.array(nn)))))) < 5:
                        out.append(f"{d['name']} {src} of {s['kind']} segment at {a:.2f}-{b:.2f} s: {modes_during(truth, a, b)}")
                        break
    return out or [f"supported by {', '.join(names[:3])}"]


def score(data, demos):
    """Learn `demos` together; score the tree against the first demo's box."""
    tree = data.learn(demos)
    truths = [data.truth(d) for d in demos]
    faces, edges = box_features(truths[0])
    shown_f, shown_e = demonstrated(truths)
    rolled, n_rolls = measurable_rolls(truths, [d.get("rate_hz") or truths[i].get("rate_hz") or 30.0
                                                for i, d in enumerate(demos)])
    r = dict(demos=len(demos), edges=len(tree["edges"]), faces=len(tree["faces"]),
             true_e=0, true_f=0, found_e=set(), found_f=set(), wrong=[],
             shown_e=shown_e, shown_f=shown_f, rolled=rolled, n_rolls=n_rolls)
    for e in tree["edges"]:
        k, ang, dist, ok = match_edge(e, edges)
        if ok:
            r["true_e"] += 1
            r["found_e"].add(edges[k][0])
        else:
            r["wrong"].append((e, True, f"edge {e['id']} ({ang:.1f} deg, {dist * 1e3:.1f} mm from {edges[k][0]})"))
    for f in tree["faces"]:
        k, ang, off, ok = match_face(f, faces)
        if ok:
            r["true_f"] += 1
            r["found_f"].add(faces[k][0])
        else:
            off_s = "-" if off is None else f"{off * 1e3:.1f} mm"
            r["wrong"].append((f, False, f"face {f['id']} ({ang:.1f} deg, offset {off_s} from {faces[k][0]}; evidence {f.get('evidence')})"))
        if off is not None and f.get("offset_sigma_m"):
            OFFSET_Z.append(off / f["offset_sigma_m"])
    return r


# |offset error| / its σ of every face that matched a face of the box with an offset (all
# tables), for the summary at the end.
OFFSET_Z = []


def pct(a, b):
    return "-" if b == 0 else f"{100 * a / b:.0f}%"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("data")
    ap.add_argument("--bin", default="target/release/objmodel")
    ap.add_argument("--tables", default="box,scene,all", help="comma list of box, scene, all")
    ap.add_argument("--why", type=int, default=40, help="wrong features to explain (0: none)")
    ap.add_argument("--noise", choices=["given"], help="given: pass the simulator's noise to "
                    "learn where the demonstrations learnt together share one (not at mocap)")
    ap.add_argument("--learn-args", default="", help="more options for every `objmodel learn`, "
                    "e.g. \"--support-height 0\" (the table's top in objmodel's scenes)")
    a = ap.parse_args()
    data = Data(a.data, a.bin, a.noise == "given", a.learn_args.split())
    demos = data.manifest["demos"]
    by_name = {d["name"]: d for d in demos}
    tables = a.tables.split(",")
    wrong_all = []

    def by(key, keep):
        g = defaultdict(list)
        for d in demos:
            if keep(d):
                g[key(d)].append(d)
        return g

    if "box" in tables:
        print("### Per box and noise: the single-mode scenes (topple, instrumented, slide, general, compound) learnt together\n")
        print("| box | noise | demos | edges true/learnt | faces true/learnt | box edges found | box faces found | wrong features |")
        print("|---|---|---|---|---|---|---|---|")
        totals = defaultdict(lambda: np.zeros(4, int))
        for (box, noise), ds in sorted(by(lambda d: (d["box"], d["noise"]), lambda d: d["scene"] in CLASSIC).items()):
            r = score(data, ds)
            totals["camera (clean, real, noisy)" if noise != "mocap" else "mocap"] += [r["true_e"], r["edges"], r["true_f"], r["faces"]]
            print(f"| {box} | {noise} | {r['demos']} | {r['true_e']}/{r['edges']} | {r['true_f']}/{r['faces']} | {len(r['found_e'])}/12 | {len(r['found_f'])}/6 | {', '.join(w[2] for w in r['wrong']) or '-'} |")
            wrong_all += [(f"{box} {noise} single-mode", w) for w in r["wrong"]]
        print()
        for k, v in sorted(totals.items()):
            print(f"Precision, {k}: edges {v[0]}/{v[1]}, faces {v[2]}/{v[3]}")
        print()

    if "scene" in tables:
        print("### Per scene kind and noise: each box's demonstrations of the kind learnt together, summed over boxes\n")
        print("| scene | noise | demos | edges true/learnt | faces true/learnt | precision | shown edges found | shown faces found | recall | measurable rolls: edges found (rolls) | wrong features |")
        print("|---|---|---|---|---|---|---|---|---|---|---|")
        groups = by(lambda d: (d["scene"], d["noise"], d["box"]), lambda d: True)
        cells = defaultdict(list)
        for (scene, noise, box), ds in groups.items():
            cells[(scene, noise)].append((box, ds))
        order = {k: i for i, k in enumerate(["topple", "instrumented", "slide", "general", "compound", "topple_slide", "toss", "session"])}
        norder = {k: i for i, k in enumerate(["clean", "mocap", "real", "noisy"])}
        for (scene, noise), items in sorted(cells.items(), key=lambda kv: (order.get(kv[0][0], 99), norder.get(kv[0][1], 99))):
            t = Counter()
            wrong = []
            for box, ds in sorted(items):
                r = score(data, ds)
                t.update(dict(demos=r["demos"], te=r["true_e"], e=r["edges"], tf=r["true_f"], f=r["faces"],
                              se=len(r["shown_e"]), sf=len(r["shown_f"]),
                              fe=len(r["shown_e"] & r["found_e"]), ff=len(r["shown_f"] & r["found_f"]),
                              re=len(r["rolled"]), rf=len(r["rolled"] & r["found_e"]), rn=r["n_rolls"]))
                wrong += [w[2] for w in r["wrong"]]
                wrong_all += [(f"{box} {noise} {scene}", w) for w in r["wrong"]]
            kinds = Counter("edge" if w.startswith("edge") else "face" for w in wrong)
            wsum = ", ".join(f"{v} {k}s" for k, v in kinds.items()) or "-"
            print(f"| {scene} | {noise} | {t['demos']} | {t['te']}/{t['e']} | {t['tf']}/{t['f']} | {pct(t['te'] + t['tf'], t['e'] + t['f'])} | {t['fe']}/{t['se']} | {t['ff']}/{t['sf']} | {pct(t['fe'] + t['ff'], t['se'] + t['sf'])} | {t['rf']}/{t['re']} ({t['rn']}) | {wsum} |")
        print()

    if "all" in tables:
        print("### Per box and noise: every demonstration of the box learnt together\n")
        print("| box | noise | demos | edges true/learnt | faces true/learnt | precision | shown edges found | shown faces found | recall |")
        print("|---|---|---|---|---|---|---|---|---|")
        for (box, noise), ds in sorted(by(lambda d: (d["box"], d["noise"]), lambda d: True).items()):
            r = score(data, ds)
            fe, ff = len(r["shown_e"] & r["found_e"]), len(r["shown_f"] & r["found_f"])
            print(f"| {box} | {noise} | {r['demos']} | {r['true_e']}/{r['edges']} | {r['true_f']}/{r['faces']} | {pct(r['true_e'] + r['true_f'], r['edges'] + r['faces'])} | {fe}/{len(r['shown_e'])} | {ff}/{len(r['shown_f'])} | {pct(fe + ff, len(r['shown_e']) + len(r['shown_f']))} |")
            wrong_all += [(f"{box} {noise} all", w) for w in r["wrong"]]
        print()

    if OFFSET_Z:
        z = np.array(OFFSET_Z)
        print(f"Face offsets learnt (nearest face of the box, every table): {len(z)}; "
              f"|error|/sigma median {np.median(z):.2f} (honest 0.67), max {z.max():.1f}, "
              f"above 5: {(z > 5).sum()}\n")

    if a.why and wrong_all:
        print(f"### Wrong features and where they came from (first {a.why})\n")
        for group, (feat, is_edge, text) in wrong_all[: a.why]:
            print(f"* {group}: {text}")
            for line in why(data, by_name, feat, is_edge):
                print(f"  * {line}")


if __name__ == "__main__":
    main()
