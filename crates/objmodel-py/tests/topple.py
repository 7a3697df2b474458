"""Exact demonstrations in numpy, independent of objmodel: a box toppled over its edges.

A box of half extents ``half`` rests on a level table (z up, gravity -z). A tag (the tracked
object frame) sits on its top face, off centre and turned. A topple: the box rests, is pushed
at a constant rate about a bottom edge up to its tipping angle phi = atan(e / ez) (e the half
extent towards the edge, ez the half height), then falls as a rigid pendulum about that edge
(uniform density: I = m (a^2 + b^2) / 3 about the edge, integrated with small RK4 steps) until
it lands on the adjacent face, and rests again. Everything is known exactly: the edge in the
tag frame, phi, the centre of mass.
"""

import numpy as np

G = 9.81


def rot(axis, angle):
    """Rotation matrix about a unit axis (Rodrigues)."""
    a = np.asarray(axis, float)
    a = a / np.linalg.norm(a)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def iso(r=np.eye(3), p=(0, 0, 0)):
    m = np.eye(4)
    m[:3, :3] = r
    m[:3, 3] = p
    return m


def quat_xyzw(r):
    """Unit quaternion (x, y, z, w) of a rotation matrix, w >= 0 (Shepperd's method)."""
    t = np.trace(r)
    if t > 0:
        s = np.sqrt(t + 1.0) * 2
        q = [(r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s, s / 4]
    else:
        i = int(np.argmax(np.diag(r)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = np.sqrt(1.0 + r[i, i] - r[j, j] - r[k, k]) * 2
        q = [0.0, 0.0, 0.0, (r[k, j] - r[j, k]) / s]
        q[i] = s / 4
        q[j] = (r[j, i] + r[i, j]) / s
        q[k] = (r[k, i] + r[i, k]) / s
    q = np.array(q)
    return q if q[3] >= 0 else -q


def rows_of(times, mats):
    """(N, 8) TUM rows t x y z qx qy qz qw of 4x4 matrices."""
    return np.array([np.r_[t, m[:3, 3], quat_xyzw(m[:3, :3])] for t, m in zip(times, mats)])


class Box:
    """A box with half extents ``half`` and a tag on its top face (``box_from_tag``)."""

    def __init__(self, half=(0.05, 0.035, 0.08), tag_offset=(0.012, -0.007), tag_yaw=0.7):
        self.half = np.asarray(half, float)
        self.box_from_tag = iso(rot((0, 0, 1), tag_yaw), (tag_offset[0], tag_offset[1], self.half[2]))


SIDES = {  # side -> (world axis of the edge line, topple rotation axis, world direction)
    "+x": (1, (0, 1, 0)),
    "-x": (0, (0, -1, 0)),
    "+y": (3, (-1, 0, 0)),
    "-y": (2, (1, 0, 0)),
}


def topple(box, side="+x", world_r0=np.eye(3), rate=100.0, push_speed=0.25, t0=1000.0, yaw=0.3,
           start=(0.3, -0.2)):
    """A topple of ``box`` about its bottom edge on ``side`` of the world (+x, -x, +y, -y),
    starting from the box turned by ``world_r0`` (a rotation that keeps it resting on a face)
    and then by ``yaw`` about z. Returns (times, world_from_tag matrices, truth) with truth a
    dict: ``point``, ``direction`` (the edge in the tag frame), ``phi``, ``com`` (box centre in
    the tag frame)."""
    r0 = rot((0, 0, 1), yaw) @ world_r0
    ext = np.abs(r0) @ box.half  # half extents of the resting box along world x, y, z
    world_from_box0 = iso(r0, (start[0], start[1], ext[2]))
    # The edge and the rotation, in a world frame turned by yaw so that "+x" is the box's.
    ry = rot((0, 0, 1), yaw)
    ext_local = np.abs(world_r0) @ box.half
    _, axis_local = SIDES[side]
    toward = {"+x": (1, 0, 0), "-x": (-1, 0, 0), "+y": (0, 1, 0), "-y": (0, -1, 0)}[side]
    along = ext_local[0] if side[1] == "x" else ext_local[1]
    pivot = np.array([start[0], start[1], 0.0]) + ry @ (np.array(toward, float) * along)
    axis = ry @ np.array(axis_local, float)
    phi = np.arctan2(along, ext_local[2])
    # Push at a constant rate to phi, then a rigid pendulum fall to pi/2, rests around.
    a, b = 2 * along, 2 * ext_local[2]
    l = np.hypot(along, ext_local[2])
    k = G * l / ((a * a + b * b) / 3.0)  # alpha'' = k sin(alpha - phi)
    dt = 1.0 / rate
    angles = [0.0] * int(1.2 * rate)
    alpha = 0.0
    while alpha + push_speed * dt < phi:
        alpha += push_speed * dt
        angles.append(alpha)
    w = push_speed
    sub = 50
    while alpha < np.pi / 2:
        for _ in range(sub):
            h = dt / sub
            f = lambda x: k * np.sin(x - phi)
            k1a, k1w = w, f(alpha)
            k2a, k2w = w + h / 2 * k1w, f(alpha + h / 2 * k1a)
            k3a, k3w = w + h / 2 * k2w, f(alpha + h / 2 * k2a)
            k4a, k4w = w + h * k3w, f(alpha + h * k3a)
            alpha += h / 6 * (k1a + 2 * k2a + 2 * k3a + k4a)
            w += h / 6 * (k1w + 2 * k2w + 2 * k3w + k4w)
        angles.append(min(alpha, np.pi / 2))
    angles += [np.pi / 2] * int(1.5 * rate)
    times = t0 + np.arange(len(angles)) / rate
    mats = []
    for al in angles:
        turn = iso(rot(axis, al))
        at_pivot = iso(np.eye(3), pivot) @ turn @ iso(np.eye(3), -pivot)
        mats.append(at_pivot @ world_from_box0 @ box.box_from_tag)
    tag_from_world = np.linalg.inv(world_from_box0 @ box.box_from_tag)
    point = (tag_from_world @ np.r_[pivot, 1])[:3]
    direction = tag_from_world[:3, :3] @ axis
    com = np.linalg.inv(box.box_from_tag)[:3, 3]
    world_from_box = at_pivot @ world_from_box0
    return times, np.array(mats), {"point": point, "direction": direction, "phi": phi, "com": com,
                                   "world_from_box": world_from_box}


def rolls(box, sides, yaw=0.3, rate=100.0, t0=1000.0):
    """One demonstration of several topples in a row, each from where the last one left the
    box (over ``sides``, e.g. "+x" four times: rolled over once around). Returns (times,
    matrices, truths), the truths' edges in the tag frame at the start."""
    ry = rot((0, 0, 1), yaw)
    r_local, start = np.eye(3), (0.3, -0.2)
    ts, ms, truths = [], [], []
    tag_from_world0 = None
    for side in sides:
        t, m, truth = topple(box, side, r_local, rate=rate, t0=t0, yaw=yaw, start=start)
        if tag_from_world0 is None:
            tag_from_world0 = np.linalg.inv(m[0])
        else:  # the edge in the tag frame is the same at every instant: the tag is rigid
            pass
        ts.append(t)
        ms.append(m)
        truths.append(truth)
        end = truth["world_from_box"]
        r_local = np.round(ry.T @ end[:3, :3])  # axis-aligned, exactly
        start = (end[0, 3], end[1, 3])
        t0 = t[-1] + 1.0 / rate
    return np.concatenate(ts), np.concatenate(ms), truths


def every_face(box, rate=100.0):
    """Six topples that rest the box on every face: over its four bottom edges, then turned
    upside down over two more (so that every face's offset follows from an edge in it)."""
    flip = rot((1, 0, 0), np.pi)
    plan = [(np.eye(3), s) for s in ("+x", "-x", "+y", "-y")] + [(flip, "+x"), (flip, "+y")]
    return [topple(box, side, r0, rate=rate, t0=1000.0 + 100 * i, yaw=0.3 + 0.4 * i)
            for i, (r0, side) in enumerate(plan)]


def line_distance(p, d, q, e):
    """Largest distance of line (q, e) from line (p, d) over |x| < 0.2 m along it, and the
    angle between their directions (sign ignored)."""
    d, e = d / np.linalg.norm(d), e / np.linalg.norm(e)
    ang = np.arccos(min(1.0, abs(float(d @ e))))
    worst = 0.0
    for s in (-0.2, 0.2):
        x = q + s * e
        r = x - p
        worst = max(worst, np.linalg.norm(r - (r @ d) * d))
    return worst, ang
