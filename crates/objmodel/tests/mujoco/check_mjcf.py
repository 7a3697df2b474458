"""Load an MJCF that `objmodel export` wrote in MuJoCo and check it against what the learner
said: the first body has a free joint, its mass and centre of mass are the expected ones, its
geometry is the expected box; then, on a floor, resting on each of its faces in turn, it stays
put for two seconds.

    python check_mjcf.py MODEL.xml EXPECTED.json

EXPECTED.json: {"mass": kg, "com": [x, y, z], "box_half": [hx, hy, hz] | null,
                "faces": [[nx, ny, nz], ...]}  (outward normals, object frame)
Exits 0 when every check passes, 1 with the failures on stderr otherwise.
"""
import json
import sys

import mujoco
import numpy as np


def quat_down(n):
    """The rotation (w, x, y, z) taking the unit vector n to -z."""
    n = np.asarray(n, float) / np.linalg.norm(n)
    target = np.array([0.0, 0.0, -1.0])
    axis = np.cross(n, target)
    s, c = np.linalg.norm(axis), float(np.dot(n, target))
    if s < 1e-12:
        return np.array([1.0, 0, 0, 0]) if c > 0 else np.array([0.0, 1, 0, 0])
    angle = np.arctan2(s, c)
    axis /= s
    return np.concatenate([[np.cos(angle / 2)], np.sin(angle / 2) * axis])


def main():
    model_path, expected_path = sys.argv[1], sys.argv[2]
    want = json.load(open(expected_path))
    failures = []
    model = mujoco.MjModel.from_xml_path(model_path)
    body = 1  # the first body after the world
    if model.body_jntnum[body] != 1 or model.jnt_type[model.body_jntadr[body]] != mujoco.mjtJoint.mjJNT_FREE:
        failures.append("the first body has no free joint")
    if abs(model.body_mass[body] - want["mass"]) > 1e-9 * max(1.0, want["mass"]):
        failures.append(f"mass {model.body_mass[body]} != {want['mass']}")
    com = model.body_ipos[body]
    if np.linalg.norm(com - np.array(want["com"])) > 1e-9:
        failures.append(f"centre of mass {com} != {want['com']}")
    if want["box_half"] is not None:
        g = model.body_geomadr[body]
        if model.geom_type[g] != mujoco.mjtGeom.mjGEOM_BOX:
            failures.append("the geometry is not a box")
        if np.linalg.norm(np.sort(model.geom_size[g]) - np.sort(want["box_half"])) > 1e-9:
            failures.append(f"box half sizes {model.geom_size[g]} != {want['box_half']}")

    # Resting on each face on a floor: it must stay where it was put.
    spec = mujoco.MjSpec.from_file(model_path)
    spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_PLANE, size=[2, 2, 0.1])
    floor_model = spec.compile()
    for n in want["faces"]:
        data = mujoco.MjData(floor_model)
        q = quat_down(n)
        data.qpos[3:7] = q
        mujoco.mj_forward(floor_model, data)
        # Lift it so that its lowest point touches the floor.
        lowest = min(
            (data.geom_xpos[i] - 0)[2]
            - (np.abs(data.geom_xmat[i].reshape(3, 3)) @ floor_model.geom_size[i])[2]
            for i in range(floor_model.ngeom)
            if floor_model.geom_bodyid[i] == body and floor_model.geom_type[i] == mujoco.mjtGeom.mjGEOM_BOX
        ) if want["box_half"] is not None else None
        if lowest is None:
            break
        data.qpos[2] = -lowest + 1e-4
        mujoco.mj_forward(floor_model, data)
        start_pos = data.xpos[body].copy()
        start_quat = data.xquat[body].copy()
        while data.time < 2.0:
            mujoco.mj_step(floor_model, data)
        moved = np.linalg.norm(data.xpos[body][:2] - start_pos[:2])
        dq = abs(float(np.dot(data.xquat[body], start_quat)))
        turned = 2 * np.degrees(np.arccos(min(1.0, dq)))
        if moved > 2e-3 or turned > 1.0:
            failures.append(f"resting on the face {n}: moved {moved * 1e3:.2f} mm, turned {turned:.2f} deg")
    if failures:
        print("\n".join(failures), file=sys.stderr)
        sys.exit(1)
    print(f"ok: mass {model.body_mass[body]}, com {com}, {len(want['faces'])} faces stable")


if __name__ == "__main__":
    main()
