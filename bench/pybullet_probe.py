#!/usr/bin/env python3
"""Probe with a third simulator: one box's demonstrations made in PyBullet, learnt together.

MuJoCo (`bench/mujoco_probe.py`, `mujoco_box_set.py`, `mujoco_tosses.py`) has soft contacts
solved as a convex program; Bullet has rigid contacts with a sequential-impulse solver, error
reduction and restitution, its own friction model and integrator. Each box here (random size,
friction, tag pose) is demonstrated as a user would, in one set:

* pushes that topple it: a finger (a sphere driven by a constraint) pushes high on a face
  until the box passes its balance point, from a random one of its 24 axis-aligned poses;
* pushes that slide it: low, on low friction, through or off the face's centre;
* palm tilts (instrumented): the box rests on a plate that tilts about a horizontal axis
  until the box falls over its downhill edge; the plate's pose is written as NAME.palm.tum;
* tosses: thrown onto the table with a spin; it lands, bounces, slides, rolls and stops.

All of a box's demonstrations are learnt into one tree (`objmodel learn *.tum --json`), and
every learnt feature is compared with the box's (`scoring.edge_true` / `face_true`: an
edge within 5 mm and 3°, a face within 5° and, where it has an offset, 5 mm). Prints per box
the features learnt and the wrong ones, and the precision over all boxes.

    PATH=/tmp/venv/bin:$PATH OBJMODEL=target/release/objmodel python3 bench/pybullet_probe.py 4
    LEVEL=mocap ...   (150-250 Hz, 0.1-0.5 mm, 0.05-0.3 deg; default camera: 30 Hz, 1 mm, 0.5 deg)
    SEED=3 ...  (another stream; default 1)    PER_KIND=6 ...  (demonstrations per kind; 5)

Needs numpy, scipy and pybullet (pip install pybullet). Writes into $PROBE_DIR (default
/tmp/objmodel-pybullet). Not a test: the numbers are for reading.
"""
import math
import os
import sys

import numpy as np
import pybullet as pb
from scipy.spatial.transform import Rotation as R

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from probe_common import record, run, settle  # noqa: E402

BIN = os.environ.get("OBJMODEL", "target/release/objmodel")
DIR = os.environ.get("PROBE_DIR", "/tmp/objmodel-pybullet")
LEVEL = os.environ.get("LEVEL", "camera")
DT = 1.0 / 1000.0


class World:
    """A PyBullet world with a table (z = 0) and the box."""

    def __init__(self, half, mu, world_from_box, restitution=0.2):
        self.c = pb.connect(pb.DIRECT)
        pb.setGravity(0, 0, -9.81, physicsClientId=self.c)
        pb.setTimeStep(DT, physicsClientId=self.c)
        pb.setPhysicsEngineParameter(numSolverIterations=100, physicsClientId=self.c)
        plane = pb.createCollisionShape(pb.GEOM_PLANE, physicsClientId=self.c)
        self.table = pb.createMultiBody(0, plane, physicsClientId=self.c)
        shape = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=list(half), physicsClientId=self.c)
        p, q = world_from_box
        self.box = pb.createMultiBody(0.4, shape, basePosition=list(p),
                                      baseOrientation=list(q.as_quat()), physicsClientId=self.c)
        for b in (self.table, self.box):
            pb.changeDynamics(b, -1, lateralFriction=mu, restitution=restitution,
                              spinningFriction=0.001, rollingFriction=0.0,
                              physicsClientId=self.c)

    def driven(self, shape, mass, pos, orn=(0, 0, 0, 1)):
        """A body moved by a constraint (a finger, a palm), and the constraint."""
        b = pb.createMultiBody(mass, shape, basePosition=list(pos), baseOrientation=list(orn),
                               physicsClientId=self.c)
        cid = pb.createConstraint(b, -1, -1, -1, pb.JOINT_FIXED, [0, 0, 0], [0, 0, 0], list(pos),
                                  childFrameOrientation=list(orn), physicsClientId=self.c)
        return b, cid

    def pose(self, body):
        p, q = pb.getBasePositionAndOrientation(body, physicsClientId=self.c)
        return np.array(p), R.from_quat(q)

    def step(self):
        pb.stepSimulation(physicsClientId=self.c)

    def still(self):
        v, w = pb.getBaseVelocity(self.box, physicsClientId=self.c)
        return np.linalg.norm(v) < 2e-3 and np.linalg.norm(w) < 2e-2

    def close(self):
        pb.disconnect(self.c)


def push(half, mu, rot, height_frac, offset_frac, topple, rate, rng):
    """A finger pushes the box along +x: world_from_box rows, or None if it did not do as meant."""
    w = World(half, mu, settle(half, rot))
    ext = np.abs(rot.as_matrix()) @ half
    r = 0.008
    finger = pb.createCollisionShape(pb.GEOM_SPHERE, radius=r, physicsClientId=w.c)
    start = np.array([-ext[0] - r - 0.02, offset_frac * ext[1], 2 * ext[2] * height_frac])
    f, cid = w.driven(finger, 0.05, start)
    pb.changeDynamics(f, -1, lateralFriction=0.2, physicsClientId=w.c)
    speed = rng.uniform(0.03, 0.08)
    rest_before, rest_after = rng.uniform(1.0, 1.5), rng.uniform(1.0, 1.5)
    rows, t, t_next, moved, stop_at = [], 0.0, 0.0, 0.0, None
    z0 = w.pose(w.box)[1]
    while t < 20.0:
        if t > rest_before and stop_at is None:
            moved += speed * DT
            pos = start + np.array([moved, 0.0, 0.0])
            pb.changeConstraint(cid, list(pos), maxForce=50, physicsClientId=w.c)
            tilt = math.degrees((w.pose(w.box)[1] * z0.inv()).magnitude())
            if (topple and tilt > 60) or (not topple and moved > 0.12):
                stop_at = t
                # The finger withdraws.
                pb.changeConstraint(cid, list(pos - np.array([0.05, 0, -0.05])), maxForce=50,
                                    physicsClientId=w.c)
        w.step()
        t += DT
        t_next = record(w, rows, t, t_next, rate)
        if stop_at is not None and t > stop_at + 0.5 and w.still():
            rest_after -= DT
            if rest_after < 0:
                break
    w.close()
    tilt = math.degrees((R.from_quat(rows[-1][4:8]) * z0.inv()).magnitude())
    if topple and tilt < 80:
        return None
    if not topple and tilt > 5:
        return None
    return np.array(rows), None


def palm_tilt(half, mu, rot, rate, rng):
    """The box on a plate that tilts until it falls: (box rows, palm rows) or None."""
    w = World(half, mu, settle(half, rot))
    plate_half = [0.15, 0.15, 0.01]
    shape = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=plate_half, physicsClientId=w.c)
    ext = np.abs(rot.as_matrix()) @ half
    lift = 0.25
    # The box sits on the plate, which floats `lift` above the table.
    p, q = settle(half, rot)
    pb.resetBasePositionAndOrientation(w.box, list(p + [0, 0, lift + 0.02]), list(q.as_quat()),
                                       physicsClientId=w.c)
    plate, cid = w.driven(shape, 2.0, [0.0, 0.0, lift + 0.01])
    # A rubber palm: the box tips before it slides (unless it is squat).
    pb.changeDynamics(plate, -1, lateralFriction=1.5, physicsClientId=w.c)
    pb.changeDynamics(w.box, -1, lateralFriction=1.5, physicsClientId=w.c)
    heading = rng.uniform(-math.pi, math.pi)
    axis = np.array([math.cos(heading), math.sin(heading), 0.0])
    rate_tilt = math.radians(rng.uniform(8, 20))
    rest_before = rng.uniform(1.0, 1.5)
    rows, palm_rows, t, t_next, fell_at, rel0 = [], [], 0.0, 0.0, None, None
    while t < 25.0:
        if t > rest_before and fell_at is None:
            ang = rate_tilt * (t - rest_before)
            orn = R.from_rotvec(axis * ang)
            pb.changeConstraint(cid, [0.0, 0.0, lift + 0.01],
                                jointChildFrameOrientation=list(orn.as_quat()), maxForce=500,
                                physicsClientId=w.c)
            rel = w.pose(plate)[1].inv() * w.pose(w.box)[1]
            rel0 = rel if rel0 is None else rel0
            if math.degrees((rel * rel0.inv()).magnitude()) > 40 or ang > math.radians(70):
                fell_at = t
        w.step()
        t += DT
        t_next = record(w, rows, t, t_next, rate, plate, palm_rows)
        if fell_at is not None and t > fell_at + 1.5 and w.still():
            break
    w.close()
    if fell_at is None:
        return None
    return np.array(rows), np.array(palm_rows)


def toss(half, mu, rate, rng):
    """The box thrown onto the table: rows or None."""
    q0 = R.random(random_state=rng.integers(1 << 31))
    p0 = np.array([0.0, 0.0, rng.uniform(0.15, 0.35)])
    w = World(half, mu, (p0, q0), restitution=rng.uniform(0.05, 0.4))
    v = [rng.uniform(0.3, 1.2), rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.8)]
    om = R.random(random_state=rng.integers(1 << 31)).apply([1.0, 0.0, 0.0]) * rng.uniform(3, 15)
    hold = rng.uniform(0.4, 0.8)
    rows, t, t_next, still_since = [], 0.0, 0.0, None
    rest_after = rng.uniform(0.8, 1.5)
    while t < 8.0:
        if t < hold:
            pb.resetBasePositionAndOrientation(w.box, list(p0), list(q0.as_quat()), physicsClientId=w.c)
            pb.resetBaseVelocity(w.box, [0, 0, 0], [0, 0, 0], physicsClientId=w.c)
        elif t < hold + DT * 1.5:
            pb.resetBaseVelocity(w.box, v, list(om), physicsClientId=w.c)
        w.step()
        t += DT
        t_next = record(w, rows, t, t_next, rate)
        if t > hold + 0.3:
            still_since = (still_since if still_since is not None else t) if w.still() else None
            if still_since is not None and t - still_since > rest_after:
                break
    w.close()
    return np.array(rows), None


def main():
    boxes = int(sys.argv[1]) if len(sys.argv) > 1 else 3
    per_kind = int(os.environ.get("PER_KIND", "5"))
    rng = np.random.default_rng(int(os.environ.get("SEED", "1")))
    run(sys.modules[__name__], "PyBullet", boxes, per_kind, rng, LEVEL, BIN, DIR)


if __name__ == "__main__":
    main()
