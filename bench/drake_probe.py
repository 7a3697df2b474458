#!/usr/bin/env python3
"""Probe with a fourth simulator: one box's demonstrations made in Drake, learnt together.

Rapier (objmodel's own), MuJoCo (`bench/mujoco_probe.py`, `mujoco_tosses.py`) and Bullet
(`bench/pybullet_probe.py`) each have their own contact. Drake's MultibodyPlant here uses its
discrete SAP solver (a convex, regularised contact problem) with either point contact (a
penetration allowance, `CONTACT=point`, the default) or hydroelastic contact
(`CONTACT=hydroelastic`: a compliant box whose contact is a pressure field over the overlap,
so a box pivots about a patch, not a line). The demonstrations are those of the PyBullet
probe (`probe_common.run`): pushes that topple and that slide the box from a random one of
its 24 axis-aligned poses, palm tilts (instrumented: the plate's pose is NAME.palm.tum) and
tosses, each box's learnt into one tree, every learnt feature checked against the box (an
edge within 5 mm and 3°, a face within 5° and, where it has an offset, 5 mm).

The finger and the plate are free bodies whose pose and velocity the script sets at every
step (a driven body of unlimited force); the box is simulated.

    PYTHONPATH= /tmp/dvenv/bin/python bench/drake_probe.py 4
    LEVEL=mocap ...   (150-250 Hz, 0.1-0.5 mm, 0.05-0.3 deg; default camera: 30 Hz, 1 mm, 0.5 deg)
    CONTACT=hydroelastic ...   SEED=3 ...   PER_KIND=6 ...

Needs numpy, scipy, mujoco (for the shared box and tracker of `mujoco_tosses.py`) and drake
(`pip install drake`). Writes into $PROBE_DIR (default /tmp/objmodel-drake). Not a test: the
numbers are for reading.
"""
import math
import os
import sys

import numpy as np
from pydrake.all import (AddMultibodyPlant, Box, CoulombFriction, DiagramBuilder, HalfSpace,
                         MultibodyPlantConfig, Quaternion, RigidTransform, Simulator,
                         SpatialInertia, SpatialVelocity, Sphere)
from pydrake.geometry import (AddCompliantHydroelasticProperties, AddContactMaterial,
                              AddRigidHydroelasticProperties, ProximityProperties)
from scipy.spatial.transform import Rotation as R

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from probe_common import record, run, settle  # noqa: E402

BIN = os.environ.get("OBJMODEL", "target/release/objmodel")
DIR = os.environ.get("PROBE_DIR", "/tmp/objmodel-drake")
LEVEL = os.environ.get("LEVEL", "camera")
CONTACT = os.environ.get("CONTACT", "point")
DT = 1.0 / 1000.0
# Steps over which `World.still` measures the box's speed.
STILL_STEPS = 50


def transform(p, q):
    """A Drake transform from a position and a scipy rotation."""
    x, y, z, w = q.as_quat()
    return RigidTransform(Quaternion(w, x, y, z), list(p))


def proximity(mu, compliant, resolution=None):
    """Contact properties: friction `mu`, and for hydroelastic contact a compliant (or rigid)
    pressure field; a rigid shape other than the table's half space is meshed at
    `resolution` [m]."""
    props = ProximityProperties()
    AddContactMaterial(friction=CoulombFriction(mu, mu), properties=props)
    if CONTACT == "hydroelastic":
        if compliant:
            AddCompliantHydroelasticProperties(resolution_hint=0.01, hydroelastic_modulus=5e6,
                                               properties=props)
        elif resolution is not None:
            AddRigidHydroelasticProperties(resolution_hint=resolution, properties=props)
        else:
            AddRigidHydroelasticProperties(properties=props)
    return props


class World:
    """A Drake world with a table (z = 0), the box and any driven bodies (a finger, a palm)."""

    def __init__(self, half, mu, world_from_box, driven=(), box_mu=None):
        b = DiagramBuilder()
        model = "hydroelastic_with_fallback" if CONTACT == "hydroelastic" else "point"
        plant, _ = AddMultibodyPlant(MultibodyPlantConfig(
            time_step=DT, contact_model=model, discrete_contact_approximation="sap"), b)
        self.plant = plant
        self.box = plant.AddRigidBody("box", SpatialInertia.SolidBoxWithMass(0.4, *(2 * half)))
        plant.RegisterCollisionGeometry(self.box, RigidTransform(), Box(*(2 * half)), "box",
                                        proximity(box_mu or mu, True))
        plant.RegisterCollisionGeometry(plant.world_body(), HalfSpace.MakePose([0, 0, 1], [0, 0, 0]),
                                        HalfSpace(), "table", proximity(mu, False))
        self.driven = []
        for k, (shape, mass, mu_d) in enumerate(driven):
            inertia = (SpatialInertia.SolidSphereWithMass(mass, shape.radius())
                       if isinstance(shape, Sphere)
                       else SpatialInertia.SolidBoxWithMass(mass, shape.width(), shape.depth(), shape.height()))
            body = plant.AddRigidBody(f"driven{k}", inertia)
            plant.RegisterCollisionGeometry(body, RigidTransform(), shape, f"driven{k}",
                                            proximity(mu_d, False, resolution=0.005))
            self.driven.append(body)
        plant.Finalize()
        self.sim = Simulator(b.Build())
        self.ctx = plant.GetMyMutableContextFromRoot(self.sim.get_mutable_context())
        self.t = 0.0
        self.history = []
        plant.SetFreeBodyPose(self.ctx, self.box, transform(*world_from_box))

    def set(self, body, p, q, v=(0, 0, 0), w=(0, 0, 0)):
        """Put `body` at (p, q) with velocity v and angular velocity w (world frame)."""
        self.plant.SetFreeBodyPose(self.ctx, body, transform(p, q))
        self.plant.SetFreeBodySpatialVelocity(self.ctx, body, SpatialVelocity(w=list(w), v=list(v)))

    def pose(self, body):
        x = self.plant.EvalBodyPoseInWorld(self.ctx, body)
        w, qx, qy, qz = x.rotation().ToQuaternion().wxyz()
        return np.array(x.translation()), R.from_quat([qx, qy, qz, w])

    def step(self):
        self.t += DT
        self.sim.AdvanceTo(self.t)
        self.history.append(self.pose(self.box))
        del self.history[:-STILL_STEPS]

    def still(self):
        """Whether the box moved slower than 2 mm/s and 0.02 rad/s over the last
        `STILL_STEPS` steps (SAP's contact velocities jitter from step to step at rest)."""
        if len(self.history) < STILL_STEPS:
            return False
        (p0, q0), (p1, q1) = self.history[0], self.history[-1]
        span = DT * (STILL_STEPS - 1)
        return (np.linalg.norm(p1 - p0) < 2e-3 * span
                and (q1 * q0.inv()).magnitude() < 2e-2 * span)


def push(half, mu, rot, height_frac, offset_frac, topple, rate, rng):
    """A finger pushes the box along +x: (rows, None), or None if it did not do as meant."""
    r = 0.008
    w = World(half, mu, settle(half, rot), driven=[(Sphere(r), 5.0, 0.2)])
    finger = w.driven[0]
    ext = np.abs(rot.as_matrix()) @ half
    start = np.array([-ext[0] - r - 0.02, offset_frac * ext[1], 2 * ext[2] * height_frac])
    speed = rng.uniform(0.03, 0.08)
    rest_before, rest_after = rng.uniform(1.0, 1.5), rng.uniform(1.0, 1.5)
    rows, t, t_next, moved, stop_at = [], 0.0, 0.0, 0.0, None
    z0 = w.pose(w.box)[1]
    pos, vel = start, np.zeros(3)
    while t < 20.0:
        if t > rest_before and stop_at is None:
            moved += speed * DT
            pos, vel = start + np.array([moved, 0.0, 0.0]), np.array([speed, 0.0, 0.0])
            tilt = math.degrees((w.pose(w.box)[1] * z0.inv()).magnitude())
            if (topple and tilt > 60) or (not topple and moved > 0.12):
                stop_at = t
                # The finger withdraws.
                pos, vel = pos - np.array([0.05, 0, -0.05]), np.zeros(3)
        w.set(finger, pos, R.identity(), vel)
        w.step()
        t += DT
        t_next = record(w, rows, t, t_next, rate)
        if stop_at is not None and t > stop_at + 0.5 and w.still():
            rest_after -= DT
            if rest_after < 0:
                break
    turn = R.from_quat(rows[-1][4:8]) * z0.inv()
    # A slide may turn about the vertical (a push off the centre spins the box); it must not
    # tip: its up axis stays within 5 degrees.
    tip = math.degrees(math.acos(min(1.0, turn.apply([0.0, 0.0, 1.0])[2])))
    if os.environ.get("DEBUG"):
        print("push", topple, "turn", math.degrees(turn.magnitude()), "tip", tip, "t", t)
    if topple and math.degrees(turn.magnitude()) < 80:
        return None
    if not topple and tip > 5:
        return None
    return np.array(rows), None


def palm_tilt(half, mu, rot, rate, rng):
    """The box on a plate that tilts until it falls: (box rows, palm rows) or None."""
    plate_half = np.array([0.15, 0.15, 0.01])
    lift = 0.25
    p, q = settle(half, rot)
    # A rubber palm: the box tips before it slides (unless it is squat).
    w = World(half, mu, (p + [0, 0, lift + 0.02], q), driven=[(Box(*(2 * plate_half)), 2.0, 1.5)],
              box_mu=1.5)
    plate = w.driven[0]
    centre = np.array([0.0, 0.0, lift + 0.01])
    heading = rng.uniform(-math.pi, math.pi)
    axis = np.array([math.cos(heading), math.sin(heading), 0.0])
    rate_tilt = math.radians(rng.uniform(8, 20))
    rest_before = rng.uniform(1.0, 1.5)
    rows, palm_rows, t, t_next, fell_at, rel0 = [], [], 0.0, 0.0, None, None
    orn, spin = R.identity(), np.zeros(3)
    while t < 25.0:
        if t > rest_before and fell_at is None:
            ang = rate_tilt * (t - rest_before)
            orn, spin = R.from_rotvec(axis * ang), axis * rate_tilt
            rel = w.pose(plate)[1].inv() * w.pose(w.box)[1]
            rel0 = rel if rel0 is None else rel0
            if math.degrees((rel * rel0.inv()).magnitude()) > 40 or ang > math.radians(70):
                fell_at = t
                spin = np.zeros(3)
        w.set(plate, centre, orn, np.zeros(3), spin)
        w.step()
        t += DT
        t_next = record(w, rows, t, t_next, rate, plate, palm_rows)
        if fell_at is not None and t > fell_at + 1.5 and w.still():
            break
    if fell_at is None:
        return None
    return np.array(rows), np.array(palm_rows)


def toss(half, mu, rate, rng):
    """The box thrown onto the table: (rows, None)."""
    q0 = R.random(random_state=rng.integers(1 << 31))
    p0 = np.array([0.0, 0.0, rng.uniform(0.15, 0.35)])
    w = World(half, mu, (p0, q0))
    v = [rng.uniform(0.3, 1.2), rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.8)]
    om = R.random(random_state=rng.integers(1 << 31)).apply([1.0, 0.0, 0.0]) * rng.uniform(3, 15)
    hold = rng.uniform(0.4, 0.8)
    rows, t, t_next, still_since = [], 0.0, 0.0, None
    rest_after = rng.uniform(0.8, 1.5)
    while t < 8.0:
        if t < hold:
            w.set(w.box, p0, q0)
        elif t < hold + DT * 1.5:
            w.set(w.box, w.pose(w.box)[0], w.pose(w.box)[1], v, om)
        w.step()
        t += DT
        t_next = record(w, rows, t, t_next, rate)
        if t > hold + 0.3:
            still_since = (still_since if still_since is not None else t) if w.still() else None
            if still_since is not None and t - still_since > rest_after:
                break
    return np.array(rows), None


def main():
    boxes = int(sys.argv[1]) if len(sys.argv) > 1 else 3
    per_kind = int(os.environ.get("PER_KIND", "5"))
    rng = np.random.default_rng(int(os.environ.get("SEED", "1")))
    run(sys.modules[__name__], f"Drake {CONTACT}", boxes, per_kind, rng, LEVEL, BIN, DIR)


if __name__ == "__main__":
    main()
