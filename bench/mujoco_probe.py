#!/usr/bin/env python3
"""Probe with another simulator: box demonstrations from MuJoCo, classified and learnt by objmodel.

The learner was developed on its own kinematic generator and on rapier scenes; this makes
demonstrations with an independent physics engine (MuJoCo: its own contact model, friction
cones and integrator) and checks the learner against their truth. A kinematic finger (a mocap
sphere) pushes a box on a table:

* topple: high push (90% of the box height) on high friction, until the box passes its balance
  point; the truth edge is the far bottom edge;
* straight slide: low push through the face's centre on low friction (the box does not turn);
* turning slide: the same, off the centre line (the box turns while it slides);
* instrumented: the box rests on a palm plate that tilts steadily until the box falls over its
  downhill edge; the palm's pose (small noise, no flips) is written beside it as NAME.palm.tum.

The tracked frame is a tag on the top face (offset and turned, as a real tag is), recorded at
30 Hz (RATE) with tracking noise of 1 mm / 0.5 deg per axis, 3% dropped frames, 5% quaternion sign
flips and 1% single-frame mirror flips (40 deg about the tag's x axis). Prints per kind the
kinds classified right, the learnt edge's direction and offset errors (topples) and the face
normal errors (slides), and the error of the pendulum's CoM angle φ against the homogeneous box's
atan(half length / half height) (topples).

    python3 bench/mujoco_probe.py [N per kind, default 10]
    OBJMODEL=target/release/objmodel python3 bench/mujoco_probe.py 20
    NOISE=0 python3 bench/mujoco_probe.py      (exact poses: what is the physics, what the noise)
    KINDS=instrumented python3 bench/mujoco_probe.py 20    (only some kinds; comma-separated)
    SEED=12 python3 bench/mujoco_probe.py 20    (another random stream; default 11)
    RATE=120 NOISE=0.1 python3 bench/mujoco_probe.py 20    (a motion-capture rate [Hz]; default 30)
    EXACT_TOO=1 ...    (also write the tag's exact poses as NAME.exact.tum, for diagnosis)
    CORRELATION=0.5 ...  (each axis's noise first-order autoregressive with that lag-one
                        correlation, as a filtering tracker's; each frame's variance unchanged;
                        the tag's and the palm's; default 0: the same draws as before)
    NOISE_GIVEN=1 ...  (pass the trackers' noise to the learner: the tag's, and the palm's;
                        NOISE_GIVEN=object: the tag's alone, which the learner takes for both)

Needs numpy, scipy and mujoco (pip install mujoco). Writes into $PROBE_DIR (default
/tmp/objmodel-mujoco). Not a test: the numbers are for reading (see the notes on issue 3).
"""
import json
import math
import os
import subprocess
import sys

import mujoco
import numpy as np
from scipy.spatial.transform import Rotation as R

BIN = os.environ.get("OBJMODEL", "target/release/objmodel")
DIR = os.environ.get("PROBE_DIR", "/tmp/objmodel-mujoco")
DEG = math.pi / 180
RATE = float(os.environ.get("RATE", "30"))
# Tracking noise, as a multiple of 1 mm / 0.5 deg (and of the flip rates): NOISE=0 for exact poses.
NOISE = float(os.environ.get("NOISE", "1"))
# Lag-one correlation of consecutive frames' noise (0: independent).
CORRELATION = float(os.environ.get("CORRELATION", "0"))


def ar_step(previous, draw):
    """The next frame's first-order autoregressive noise from the previous frame's and an
    independent draw, of the draw's variance; the draw itself at CORRELATION 0."""
    return CORRELATION * previous + math.sqrt(1 - CORRELATION**2) * draw


def correlated(draws):
    """First-order autoregressive noise from independent draws (rows are frames), each frame's
    variance that of the draws; the draws themselves at CORRELATION 0."""
    out = np.array(draws, dtype=float)
    for k in range(1, len(out)):
        out[k] = ar_step(out[k - 1], out[k])
    return out


def mjcf(mu, bodies):
    """A MuJoCo model: a floor of friction `mu` under `bodies` (MJCF body elements)."""
    return f"""
<mujoco>
  <option timestep="0.0005" gravity="0 0 -9.81" cone="elliptic"/>
  <worldbody>
    <geom type="plane" size="3 3 0.1" friction="{mu} 0.005 0.0001"/>
    {bodies}
  </worldbody>
</mujoco>"""


def scene(half, mu, finger_start, quat=None, height=None):
    """A box on the floor and a finger (a mocap sphere) at `finger_start`; the box turned by
    `quat` (w x y z) with its centre at `height` when given (else upright, `half[2]` high)."""
    hx, hy, hz = half
    turned = "" if quat is None else ' quat="{} {} {} {}"'.format(*quat)
    return mjcf(mu, f"""
    <body name="box" pos="0 0 {hz if height is None else height}"{turned}>
      <freejoint/>
      <geom type="box" size="{hx} {hy} {hz}" mass="0.5" friction="{mu} 0.005 0.0001"/>
    </body>
    <body name="finger" mocap="true" pos="{finger_start[0]} {finger_start[1]} {finger_start[2]}">
      <geom type="sphere" size="0.008" friction="0.1 0.005 0.0001" contype="1" conaffinity="1"/>
    </body>""")


def palm_scene(half, mu):
    """A box resting on a palm plate (mocap, 0.6 m square) 0.3 m above the floor, its sides
    along the plate's, 5 cm uphill of the plate's centre."""
    hx, hy, hz = half
    return mjcf(mu, f"""
    <body name="palm" mocap="true" pos="0 0 0.3">
      <geom type="box" size="0.3 0.3 0.005" friction="{mu} 0.005 0.0001"/>
    </body>
    <body name="box" pos="-0.05 0 {0.305 + hz}">
      <freejoint/>
      <geom type="box" size="{hx} {hy} {hz}" mass="0.5" friction="{mu} 0.005 0.0001"/>
    </body>""")


def run_palm(rng):
    """An instrumented topple: the palm tilts about its y axis at a steady rate until the box
    turns on it (it has passed its balance point), then holds while the box falls.
    Returns (box poses, palm poses, truth, done) as [t x y z qx qy qz qw] rows."""
    half = np.array([rng.uniform(0.025, 0.04), rng.uniform(0.025, 0.04), rng.uniform(0.06, 0.09)])
    hx, hy, hz = half
    m = mujoco.MjModel.from_xml_string(palm_scene(half, 1.5))
    d = mujoco.MjData(m)
    box = m.body("box").id
    rate = rng.uniform(10, 25) * DEG  # tilt rate [rad/s]
    phi = math.atan2(hx, hz)
    rest_before, t, t_next, beta, t_hold = rng.uniform(0.8, 1.5), 0.0, 0.0, 0.0, None
    box_rows, palm_rows = [], []
    while t < 30:
        if t >= rest_before and t_hold is None:
            beta += rate * m.opt.timestep
            # Hold the tilt once the box has turned 10 degrees on the palm (it falls on its own).
            tilt = math.acos(np.clip(d.xmat[box][8], -1.0, 1.0))
            if tilt - beta > 10 * DEG:
                t_hold = t
        if t_hold is not None and t - t_hold > 1.5:
            break
        # Rotation about the palm's y axis by beta: its +x side goes down.
        q = R.from_rotvec([0.0, beta, 0.0])
        d.mocap_quat[0] = np.roll(q.as_quat(), 1)  # (w, x, y, z)
        d.mocap_pos[0] = [0.0, 0.0, 0.3]
        mujoco.mj_step(m, d)
        t += m.opt.timestep
        if t >= t_next:
            w, x, y, z = d.xquat[box]
            box_rows.append([t, *d.xpos[box], x, y, z, w])
            pq = q.as_quat()
            palm_rows.append([t, 0.0, 0.0, 0.3, *pq])
            t_next += 1.0 / RATE
    box_rows, palm_rows = np.array(box_rows), np.array(palm_rows)
    truth = {"kind": "topple", "edge_point": [hx, 0.0, -hz], "edge_direction": [0.0, 1.0, 0.0],
             "face_normal": [0.0, 0.0, -1.0], "phi": phi}
    final_tilt = math.acos(np.clip(R.from_quat(box_rows[-1, 4:8]).as_matrix()[2, 2], -1.0, 1.0))
    return box_rows, palm_rows, truth, final_tilt > 45 * DEG


def run(kind, rng):
    """One demonstration: (times, world_from_box poses as (N, 7) [x y z qx qy qz qw], truth)."""
    half = np.array([rng.uniform(0.03, 0.05), rng.uniform(0.03, 0.05), rng.uniform(0.06, 0.1)])
    hx, hy, hz = half
    topple = kind == "topple"
    mu = 0.9 if topple else 0.25
    height = (1.8 if topple else 0.3) * hz
    lateral = rng.uniform(0.3, 0.6) * hy * rng.choice([-1, 1]) if kind == "turning-slide" else 0.0
    start = np.array([-hx - 0.03, lateral, height])
    m = mujoco.MjModel.from_xml_string(scene(half, mu, start))
    d = mujoco.MjData(m)
    speed = rng.uniform(0.05, 0.12)
    phi = math.atan2(hx, hz)  # balance angle about the far bottom edge
    box = m.body("box").id
    rest_before, rest_after = rng.uniform(0.8, 1.5), 1.5
    slide_len = rng.uniform(0.08, 0.15)

    def pushed_enough(d, pushed):
        tilt = math.acos(np.clip(d.xmat[box][8], -1.0, 1.0))  # box z from vertical
        return (topple and tilt > phi + 8 * DEG) or (not topple and pushed > slide_len + 0.03)

    samples = finger_push(m, d, box, start, speed, rest_before, rest_after, pushed_enough)
    poses = np.array(samples)
    # Truth in the box frame: the far bottom edge (topple), the bottom face (slides).
    truth = {"kind": "topple" if topple else "slide",
             "edge_point": [hx, 0.0, -hz], "edge_direction": [0.0, 1.0, 0.0],
             "face_normal": [0.0, 0.0, -1.0], "phi": phi}
    # Did it do what was scripted? (A topple that fell back, a slide that toppled: skip.)
    final_tilt = math.acos(np.clip(R.from_quat(poses[-1, 4:8]).as_matrix()[2, 2], -1.0, 1.0))
    done = (final_tilt > 60 * DEG) if topple else (final_tilt < 5 * DEG)
    return poses, truth, done


def finger_push(m, d, box, start, speed, rest_before, rest_after, pushed_enough):
    """The finger's script in the scene `m` (state `d`, the box's body id `box`, the finger at
    `start`): rest `rest_before` s, push along +x at `speed` until `pushed_enough(d, pushed)`
    (the scene's state and how far the finger went), retract upwards and back for 0.6 s, rest
    `rest_after` s. Returns the box's poses at RATE, rows [t x y z qx qy qz qw] (at most 30 s)."""
    samples, t_next, t, state, t_state = [], 0.0, 0.0, "rest", 0.0
    pos = start.copy()
    while True:
        if state == "rest" and t >= rest_before:
            state, t_state = "push", t
        elif state == "push":
            pos[0] += speed * m.opt.timestep
            if pushed_enough(d, pos[0] - start[0]):
                state, t_state = "retract", t
        elif state == "retract":
            pos[0] -= 0.1 * m.opt.timestep
            pos[2] += 0.2 * m.opt.timestep
            if t - t_state > 0.6:
                state, t_state = "after", t
        elif state == "after" and t - t_state > rest_after:
            break
        d.mocap_pos[0] = pos
        mujoco.mj_step(m, d)
        t += m.opt.timestep
        if t >= t_next:
            w, x, y, z = d.xquat[box]
            samples.append([t, *d.xpos[box], x, y, z, w])
            t_next += 1.0 / RATE
        if t > 30:
            break
    return samples


def tag_track(poses, rng):
    """The tag's poses (on the top face, offset and turned), with tracking noise."""
    box_from_tag_t = np.array([rng.uniform(-0.01, 0.01), rng.uniform(-0.01, 0.01), 0.0])
    box_from_tag_r = R.from_euler("z", rng.uniform(-180, 180), degrees=True)
    tag = []
    for row in poses:
        wb_r = R.from_quat(row[4:8])
        tag.append([row[0], *(row[1:4] + wb_r.apply(box_from_tag_t)),
                    *(wb_r * box_from_tag_r).as_quat()])
    return track(tag, rng), box_from_tag_t, box_from_tag_r


def track(tag_poses, rng):
    """A tracker's view of the tag's exact poses (rows t x y z qx qy qz qw): dropped frames,
    noise (correlated as CORRELATION says), single-frame mirror flips, quaternion sign flips."""
    out = []
    state = None
    for row in tag_poses:
        if rng.random() < 0.03:
            continue  # dropped frame
        p = np.array(row[1:4])
        r = R.from_quat(row[4:8])
        draw = np.concatenate([rng.normal(scale=1e-3 * NOISE, size=3),
                               rng.normal(scale=0.5 * DEG * NOISE, size=3)])
        # (A dropped frame's noise is not drawn: the correlation is between tracked frames.)
        state = draw if state is None else ar_step(state, draw)
        p = p + state[:3]
        r = r * R.from_rotvec(state[3:])
        if rng.random() < 0.01 * NOISE:
            r = r * R.from_rotvec([40 * DEG, 0, 0])  # mirror solution for one frame
        q = r.as_quat()
        if rng.random() < 0.05:
            q = -q
        out.append([row[0], *p, *q])
    return np.array(out)


def truth_kind_topple(kind):
    return kind in ("topple", "instrumented")


def outward(truth):
    """The unit outward bisector of the two box faces that meet at the truth edge (box frame)."""
    p, u = np.array(truth["edge_point"]), np.array(truth["edge_direction"])
    s = np.sign(p - u * (p @ u))
    return s / np.linalg.norm(s)


def write(path, a):
    with open(path, "w") as f:
        f.write("# timestamp tx ty tz qx qy qz qw  (MuJoCo probe)\n")
        for r in a:
            f.write("%.6f " % r[0] + " ".join("%.9f" % x for x in r[1:]) + "\n")


def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 10
    os.makedirs(DIR, exist_ok=True)
    rng = np.random.default_rng(int(os.environ.get("SEED", "11")))
    kinds = os.environ.get("KINDS", "topple,instrumented,straight-slide,turning-slide").split(",")
    for kind in kinds:
        ok, total, skipped, edge_errs, face_errs, phi_errs, withheld = 0, 0, 0, [], [], [], 0
        phi_zs = []
        while total < n:
            palm = None
            if kind == "instrumented":
                poses, palm, truth, done = run_palm(rng)
            else:
                poses, truth, done = run(kind, rng)
            if not done:
                skipped += 1
                if skipped > 3 * n:
                    break
                continue
            total += 1
            track, bt_t, bt_r = tag_track(poses, rng)
            path = f"{DIR}/{kind}_{total}.tum"
            write(path, track)
            if os.environ.get("EXACT_TOO"):
                # The tag's exact poses beside the tracked ones, for diagnosis (no random draws).
                exact = [[row[0], *(row[1:4] + R.from_quat(row[4:8]).apply(bt_t)),
                          *(R.from_quat(row[4:8]) * bt_r).as_quat()] for row in poses]
                write(path[:-4] + ".exact.tum", exact)
            if palm is not None:
                # The palm's pose from the arm's kinematics: small noise, no tag flips.
                noisy = palm.copy()
                noisy[:, 1:4] += correlated(rng.normal(scale=2e-4 * NOISE, size=(len(palm), 3)))
                noisy[:, 4:8] = (R.from_quat(palm[:, 4:8]) * R.from_rotvec(correlated(
                    rng.normal(scale=0.05 * DEG * NOISE, size=(len(palm), 3))))).as_quat()
                write(path[:-4] + ".palm.tum", noisy)
            # Truth in the tag frame: tag_from_box = (box_from_tag)^-1.
            to_tag = lambda x: bt_r.inv().apply(np.array(x) - bt_t)
            with open(path[:-4] + ".truth.json", "w") as f:
                json.dump({"kind": truth["kind"],
                           "edge": {"point": list(to_tag(truth["edge_point"])),
                                    "direction": list(bt_r.inv().apply(truth["edge_direction"])),
                                    # The outward bisector of the two faces that meet there.
                                    "outward": list(bt_r.inv().apply(outward(truth)))},
                           "face_normal": list(bt_r.inv().apply(truth["face_normal"])),
                           "phi": truth["phi"]}, f)
            given = []
            if os.environ.get("NOISE_GIVEN"):
                given = ["--noise-position", str(1e-3 * NOISE), "--noise-rotation", str(0.5 * DEG * NOISE)]
                if palm is not None and os.environ["NOISE_GIVEN"] != "object":
                    given += ["--palm-noise-position", str(2e-4 * NOISE),
                              "--palm-noise-rotation", str(0.05 * DEG * NOISE)]
            r = subprocess.run([BIN, "classify", path, "--json", *given], capture_output=True, text=True)
            if r.returncode != 0:
                print(f"{path}: exit {r.returncode}: {r.stderr.strip()[:200]}")
                continue
            c = json.loads(r.stdout)
            ok += c["kind"] == truth["kind"]
            if truth["kind"] == "topple" and c["kind"] == "topple":
                r = subprocess.run([BIN, "learn", path, "--json", *given], capture_output=True, text=True)
                edges = json.loads(r.stdout)["edges"] if r.returncode == 0 else []
                if edges:
                    e = edges[0]
                    pends = [pd for pd in e.get("pendulums", []) if pd.get("phi") is not None]
                    phis = [pd["phi"] for pd in pends]
                    if phis:
                        phi_errs.append(abs(phis[0] - truth["phi"]) / DEG)
                        if pends[0].get("phi_sigma"):
                            phi_zs.append(abs(phis[0] - truth["phi"]) / pends[0]["phi_sigma"])
                        if os.environ.get("VERBOSE"):
                            print(f"  {path}: phi {phis[0] / DEG:.2f} deg, truth {truth['phi'] / DEG:.2f}")
                    u = bt_r.inv().apply(truth["edge_direction"])
                    p = to_tag(truth["edge_point"])
                    d = np.array(e["direction"])
                    ang = math.degrees(math.atan2(np.linalg.norm(np.cross(d, u)), abs(d @ u)))
                    off = np.array(e["point"]) - p
                    edge_errs.append((ang, np.linalg.norm(off - u * (off @ u)) * 1e3,
                                      e.get("sigma_point_m", float("nan")) * 1e3))
                    if os.environ.get("VERBOSE"):
                        print(f"  {path}: edge {edge_errs[-1][0]:.2f} deg, {edge_errs[-1][1]:.2f} mm"
                              f" (sigma {edge_errs[-1][2]:.2f} mm)")
                else:
                    withheld += 1
                    if os.environ.get("VERBOSE"):
                        print(f"  {path}: no edge learnt")
            if truth["kind"] == "slide" and c["kind"] == "slide":
                faces = [s["face"] for s in c["segments"] if s.get("face")]
                if faces:
                    nt = bt_r.inv().apply(truth["face_normal"])
                    face_errs.append(min(math.degrees(math.acos(np.clip(np.dot(f["normal"], nt), -1, 1)))
                                         for f in faces))
        row = {"classified right": f"{ok}/{total}", "skipped (did not do as scripted)": skipped}
        if edge_errs:
            e = np.array(edge_errs)
            row["edge (median, max)"] = "%.2f°/%.1f mm, %.2f°/%.1f mm" % (
                np.median(e[:, 0]), np.median(e[:, 1]), e[:, 0].max(), e[:, 1].max())
            row["edges within 2 mm"] = f"{int((e[:, 1] <= 2.0).sum())}/{len(e)}"
            # Offset error in units of the stated point sigma (an honest sigma keeps it small).
            row["edge offset / sigma (median, max)"] = "%.1f, %.1f" % (
                np.median(e[:, 1] / e[:, 2]), (e[:, 1] / e[:, 2]).max())
        if truth_kind_topple(kind):
            row["topples with no edge learnt"] = withheld
        if phi_errs:
            row["phi (median, max)"] = "%.2f°, %.2f°" % (np.median(phi_errs), max(phi_errs))
            row["phis learnt"] = len(phi_errs)
        if phi_zs:
            row["phi error / sigma (median, max)"] = "%.1f, %.1f" % (np.median(phi_zs), max(phi_zs))
        if face_errs:
            row["face normal (median, max)"] = "%.2f°, %.2f°" % (np.median(face_errs), max(face_errs))
        print(kind, json.dumps(row, ensure_ascii=False), flush=True)


if __name__ == "__main__":
    main()
