"""MuJoCo on the same scenes as objmodel-sim's speed example, for a side-by-side comparison.

    pip install mujoco && python3 crates/objmodel-sim/bench/mujoco_compare.py

Scene 1 (instrumented topple): a 0.1 x 0.1 x 0.2 m, 0.6 kg box (friction 0.9) on a 40 x 40 cm
plate (a mocap body) tilting at 1 deg/s about a horizontal axis on its top surface; the onset
is found exactly as objmodel-sim does (box tilt relative to the plate 2e-4 rad above its value
1.5 s before it exceeds 2 deg). Analytic onset: phi = atan(0.05/0.1) = 26.565 deg.
Scene 2 (rest): the same box resting on a table for 10 s; drift.
Both at 960 Hz steps, as objmodel-sim.
"""
import math
import time

import mujoco
import numpy as np

BOX = (0.05, 0.05, 0.10)
XML = """
<mujoco>
  <option timestep="{dt}" gravity="0 0 -9.81" cone="{cone}" impratio="{impratio}"/>
  <worldbody>
    {floor}
    <body name="plate" mocap="true" pos="0 0 0.25">
      <geom type="box" size="0.2 0.2 0.005" pos="0 0 -0.005" friction="0.9 0.005 0.0001" solref="{solref}"/>
    </body>
    <body name="box" pos="0 0 {z0}">
      <freejoint/>
      <geom type="box" size="{hx} {hy} {hz}" mass="0.6" friction="0.9 0.005 0.0001" solref="{solref}"/>
    </body>
  </worldbody>
</mujoco>
"""


def model(on_plate, cone="pyramidal", impratio=1, solref="0.02 1"):
    floor = "" if on_plate else '<geom type="plane" size="1 1 0.1" friction="0.9 0.005 0.0001" solref="%s"/>' % solref
    z0 = 0.25 + BOX[2] if on_plate else BOX[2]
    xml = XML.format(dt=1 / 960, cone=cone, impratio=impratio, floor=floor, z0=z0,
                     hx=BOX[0], hy=BOX[1], hz=BOX[2], solref=solref)
    m = mujoco.MjModel.from_xml_string(xml)
    return m, mujoco.MjData(m)


def quat_axis(axis, angle):
    s = math.sin(angle / 2)
    return np.array([math.cos(angle / 2), axis[0] * s, axis[1] * s, axis[2] * s])


def tilt_scene(**kw):
    m, d = model(True, **kw)
    mujoco.mj_forward(m, d)
    plate_id = m.body("plate").mocapid[0]
    rate = math.radians(1.0)
    theta, t = 0.0, 0.0
    tilts, box_tilts, times = [], [], []
    t0 = time.perf_counter()
    steps = 0
    while True:
        if t > 1.0:
            theta += rate * m.opt.timestep
        # tilt about the y axis through the plate's top-surface centre (0, 0, 0.25): +x goes down
        d.mocap_quat[plate_id] = quat_axis((0, 1, 0), theta)
        mujoco.mj_step(m, d)
        steps += 1
        t += m.opt.timestep
        rp = np.zeros(9)
        mujoco.mju_quat2Mat(rp, d.mocap_quat[plate_id])
        rb = d.xmat[m.body("box").id]
        rp, rb = rp.reshape(3, 3), rb.reshape(3, 3)
        n_box_in_plate = rp.T @ rb @ np.array([0, 0, -1.0])
        bt = math.acos(max(-1.0, min(1.0, -n_box_in_plate[2])))
        times.append(t)
        tilts.append(theta)
        box_tilts.append(bt)
        if bt > math.radians(20) or theta > math.radians(60):
            break
    wall = time.perf_counter() - t0
    box_tilts = np.array(box_tilts)
    sure = int(np.argmax(box_tilts > math.radians(2)))
    i_base = int(np.searchsorted(times, times[sure] - 1.5))
    base = box_tilts[i_base]
    onset = i_base
    for i in range(sure, i_base, -1):
        if box_tilts[i] <= base + 2e-4:
            onset = i
            break
    return math.degrees(tilts[onset]), t / wall, steps / wall


def rest_scene(**kw):
    m, d = model(False, **kw)
    mujoco.mj_step(m, d, 480)
    p0 = d.xpos[m.body("box").id].copy()
    t0 = time.perf_counter()
    mujoco.mj_step(m, d, 9600)
    wall = time.perf_counter() - t0
    return np.linalg.norm(d.xpos[m.body("box").id] - p0), 10.0 / wall


if __name__ == "__main__":
    phi = math.degrees(math.atan2(0.05, 0.10))
    print("MuJoCo", mujoco.__version__, "- 960 Hz steps, one thread")
    print("| settings | palm tilt at onset [deg] | error [deg] | tilt scene sim s / wall s (Python loop) | rest drift 10 s [m] | rest sim s / wall s (mj_step n) |")
    print("|---|---|---|---|---|---|")
    for label, kw in [("defaults (pyramidal, solref 0.02)", {}),
                      ("elliptic cone, impratio 10, solref 0.005", dict(cone="elliptic", impratio=10, solref="0.005 1"))]:
        onset, sps, _ = tilt_scene(**kw)
        drift, rsps = rest_scene(**kw)
        print(f"| {label} | {onset:.3f} | {onset - phi:+.3f} | {sps:.0f} | {drift:.1e} | {rsps:.0f} |")
