"""The tilt at which a body that `objmodel export` wrote (MJCF) starts to topple on a tilting palm
in MuJoCo: the same experiment as objmodel-sim's src/onset.rs in rapier (a 40 x 40 cm plate
tilting at 1 deg/s about a horizontal axis through its middle, from 4 deg below the quasi-static
angle, after half a second of settling; the onset is the last tilt at which the body was within
0.1 deg of its settled attitude on the plate, once it has turned 2 deg, or the middle of its
downhill edge has moved 2 mm along the plate: a slide).

    python tilt_onset.py EXPERIMENTS.json

EXPERIMENTS.json: {"models": {"NAME": "PATH.xml", ...},
                   "experiments": [{"model": NAME, "n": [3], "e": [3], "mu": mu,
                                    "phi": rad, "beyond": rad,
                                    "corners": [[3], ...], "com": [3]}, ...]}
(n: outward normal of the face it rests on, e: the direction the tilt carries it, corners and
com: its corners and centre of mass; all in the model's body frame.)
Prints a JSON list, one {"what": "topples" | "slides" | "neither", "tilt_rad": x} per experiment.
"""
import json
import sys

import mujoco
import numpy as np

RATE = np.radians(1.0)
TIPPED = np.radians(2.0)
STILL = np.radians(0.1)
SLID = 2e-3
START_BELOW = np.radians(4.0)
PLATE_HALF = [0.2, 0.2, 0.005]
PIVOT = np.array([0.0, 0.0, 0.3])
DT = 0.001


def quat_of(r):
    q = np.zeros(4)
    mujoco.mju_mat2Quat(q, np.asarray(r, float).reshape(9))
    return q


def rot_y(theta):
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def mat_of(q):
    m = np.zeros(9)
    mujoco.mju_quat2Mat(m, q)
    return m.reshape(3, 3)


def run(path, x):
    n = np.asarray(x["n"], float)
    n /= np.linalg.norm(n)
    e = np.asarray(x["e"], float)
    e = e - n * n.dot(e)
    e /= np.linalg.norm(e)
    corners = np.asarray(x["corners"], float)
    com = np.asarray(x["com"], float)
    # The middle of the downhill edge of the face: it stays put while the body tips about it.
    low = max(n.dot(c) for c in corners)
    face = [c for c in corners if n.dot(c) > low - 1e-6]
    far = max(e.dot(c) for c in face)
    edge = [c for c in face if e.dot(c) > far - 1e-6]
    pivot_point = np.mean(edge, axis=0)
    mu = x["mu"]
    spec = mujoco.MjSpec.from_file(path)
    spec.option.timestep = DT
    # MuJoCo's soft contacts let a body creep down a slope under pyramidal cones; elliptic cones
    # with a high impratio and no-slip iterations hold it as Coulomb friction would (MuJoCo
    # documentation, "Computation: Contact"), for the true box and the learnt one alike.
    spec.option.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
    spec.option.impratio = 10
    spec.option.noslip_iterations = 10
    plate = spec.worldbody.add_body(name="palm", mocap=True, pos=PIVOT)
    plate.add_geom(
        type=mujoco.mjtGeom.mjGEOM_BOX,
        size=PLATE_HALF,
        pos=[0, 0, -PLATE_HALF[2]],
        friction=[mu, 0.005, 0.0001],
    )
    model = spec.compile()
    data = mujoco.MjData(model)
    body = 1  # the object: the first body of the exported file
    palm = model.body("palm").id
    mocap = model.body_mocapid[palm]

    start = max(0.0, x["phi"] - START_BELOW)
    # Body at rest on its face n, e along the palm's x, CoM above the palm's middle.
    frm = np.column_stack([e, np.cross(n, e), n])
    to = np.column_stack([[1, 0, 0], [0, -1, 0], [0, 0, -1]])
    r = to @ frm.T
    lowest = min((r @ c)[2] for c in corners)
    c = r @ com
    palm_from_body_t = np.array([-c[0], -c[1], -lowest + 1e-4])

    def palm_at(theta):
        return rot_y(theta)

    r0 = palm_at(start)
    data.qpos[0:3] = PIVOT + r0 @ palm_from_body_t
    data.qpos[3:7] = quat_of(r0 @ r)
    data.mocap_pos[mocap] = PIVOT
    data.mocap_quat[mocap] = quat_of(r0)
    mujoco.mj_forward(model, data)

    def relative():
        rp = palm_at(theta)
        rb = data.xmat[body].reshape(3, 3)
        rel = rp.T @ rb
        point = data.xpos[body] + rb @ pivot_point
        return rel, rp.T @ (point - PIVOT)

    theta = start
    for _ in range(int(0.5 / DT)):
        mujoco.mj_step(model, data)
    settled, settled_com = relative()
    last_still = theta
    end = x["phi"] + x["beyond"]
    while theta < end:
        theta += RATE * DT
        data.mocap_quat[mocap] = quat_of(palm_at(theta))
        mujoco.mj_step(model, data)
        rel, com_p = relative()
        d = settled.T @ rel
        turned = np.arccos(np.clip((np.trace(d) - 1) / 2, -1, 1))
        moved = np.linalg.norm((com_p - settled_com)[:2])
        if turned <= STILL and moved < SLID / 4:
            last_still = theta
        if turned > TIPPED:
            return {"what": "topples", "tilt_rad": last_still}
        if moved > SLID:
            return {"what": "slides", "tilt_rad": last_still}
        if not np.all(np.isfinite(data.qpos)):
            break
    return {"what": "neither", "tilt_rad": None}


def main():
    job = json.load(open(sys.argv[1]))
    out = [run(job["models"][x["model"]], x) for x in job["experiments"]]
    json.dump(out, sys.stdout)


if __name__ == "__main__":
    main()
