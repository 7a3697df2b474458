"""A learnt tree scored against a box's truth, as every probe with another simulator (and
`bench/contactnets.py`, on real tosses) counts it: an edge is true when it is within 5 mm and 3°
of an edge of the box, a face when its normal is within 5° of a face's outward normal and its
offset, if known, within 5 mm (as `bench/precision.py`)."""
import json
import math
import subprocess

import numpy as np


def face_true(f, faces):
    n = np.array(f["normal"])
    for nt, dt in faces:
        c = n @ nt if f.get("sign_known", True) else abs(n @ nt)
        if math.degrees(math.acos(min(1.0, c))) <= 5.0:
            if f.get("offset") is None:
                return True
            d = f["offset"] if n @ nt > 0 else -f["offset"]
            return abs(d - dt) <= 5e-3
    return False


def edge_true(e, edges):
    p, u = np.array(e["point"]), np.array(e["direction"])
    for pt, ut in edges:
        ang = math.degrees(math.atan2(np.linalg.norm(np.cross(u, ut)), abs(u @ ut)))
        off = p - pt
        off -= ut * (off @ ut)
        if ang <= 3.0 and np.linalg.norm(off) <= 5e-3:
            return True
    return False


def learn_and_score(args, out, faces, edges):
    """Run `objmodel learn ... --json` (`args`), keep its tree in `out`, and score it against
    the box: (tree, true edges, true faces, ids of the wrong features), or None (the error
    printed) if it failed."""
    r = subprocess.run(args, capture_output=True, text=True)
    if r.returncode != 0:
        print(r.stderr.strip()[:400])
        return None
    tree = json.loads(r.stdout)
    with open(out, "w") as f:
        f.write(r.stdout)
    et = sum(edge_true(e, edges) for e in tree["edges"])
    ft = sum(face_true(f, faces) for f in tree["faces"])
    wrong = [e["id"] for e in tree["edges"] if not edge_true(e, edges)] + \
            [f["id"] for f in tree["faces"] if not face_true(f, faces)]
    return tree, et, ft, wrong
