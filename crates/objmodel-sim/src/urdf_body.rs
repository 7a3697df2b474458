//! A URDF's first link as a rigid body of objmodel's rapier world: read with `urdf-rs` and built
//! here in f64 (`rapier3d-urdf` builds f32 bodies only). The link frame is the body frame
//! (for `objmodel export`'s files, the object frame); its `<inertial>` gives the mass, the
//! centre of mass and the inertia (turned by the inertial origin's `rpy`); its first
//! `<collision>` the geometry: a `<box>` at its origin, or a `<mesh>` (a Wavefront OBJ, path
//! relative to the URDF's folder) whose vertices' convex hull collides. URDF has no friction:
//! the caller gives it.

use crate::rigid::{Geometry, RigidModel};
use crate::{Result, SimError};
use nalgebra::{Isometry3, Matrix3, Translation3, UnitQuaternion, Vector3};
use std::path::Path;

fn pose(p: &urdf_rs::Pose) -> Isometry3<f64> {
    let [x, y, z] = p.xyz.0;
    let [roll, pitch, yaw] = p.rpy.0;
    Isometry3::from_parts(
        Translation3::new(x, y, z),
        UnitQuaternion::from_euler_angles(roll, pitch, yaw),
    )
}

/// The vertices of a Wavefront OBJ's `v` lines.
fn obj_vertices(path: &Path) -> Result<Vec<Vector3<f64>>> {
    let bad = |m: String| SimError::InvalidSpec(format!("{}: {m}", path.display()));
    let text = std::fs::read_to_string(path).map_err(|e| bad(e.to_string()))?;
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        if words.next() != Some("v") {
            continue;
        }
        let xyz: Vec<f64> = words
            .take(3)
            .map(str::parse)
            .collect::<std::result::Result<_, _>>()
            .map_err(|e| bad(format!("line {}: {e}", i + 1)))?;
        if xyz.len() != 3 || xyz.iter().any(|x| !x.is_finite()) {
            return Err(bad(format!("line {}: a vertex needs three numbers", i + 1)));
        }
        out.push(Vector3::new(xyz[0], xyz[1], xyz[2]));
    }
    if out.len() < 4 {
        return Err(bad(format!(
            "{} vertices; a solid needs at least 4",
            out.len()
        )));
    }
    Ok(out)
}

/// The first link of the URDF file `path` as a rigid body with friction `mu`.
pub fn read(path: &Path, mu: f64) -> Result<RigidModel> {
    let bad = |m: String| SimError::InvalidSpec(format!("{}: {m}", path.display()));
    let robot = urdf_rs::read_file(path).map_err(|e| bad(e.to_string()))?;
    let link = robot.links.first().ok_or_else(|| bad("no link".into()))?;
    let inertial = &link.inertial;
    let i = &inertial.inertia;
    let inertia_frame = Matrix3::new(
        i.ixx, i.ixy, i.ixz, //
        i.ixy, i.iyy, i.iyz, //
        i.ixz, i.iyz, i.izz,
    );
    let at = pose(&inertial.origin);
    let r = at.rotation.to_rotation_matrix();
    let mass = inertial.mass.value;
    if !(mass.is_finite() && mass > 0.0) {
        return Err(bad(format!("link '{}': mass {mass} kg", link.name)));
    }
    let collision = link
        .collision
        .first()
        .ok_or_else(|| bad(format!("link '{}' has no collision geometry", link.name)))?;
    let geometry = match &collision.geometry {
        urdf_rs::Geometry::Box { size } => Geometry::Cuboid {
            body_from_box: pose(&collision.origin),
            half_extents: Vector3::from(size.0) / 2.0,
        },
        urdf_rs::Geometry::Mesh { filename, scale } => {
            let file = path.parent().unwrap_or(Path::new(".")).join(filename);
            let s = Vector3::from(scale.map_or([1.0; 3], |s| s.0));
            let at = pose(&collision.origin);
            let points = obj_vertices(&file)?
                .into_iter()
                .map(|v| (at * nalgebra::Point3::from(v.component_mul(&s))).coords)
                .collect();
            Geometry::Hull { points }
        }
        other => {
            return Err(bad(format!(
                "link '{}': collision geometry {other:?} is not a box or a mesh",
                link.name
            )))
        }
    };
    Ok(RigidModel {
        geometry,
        mass,
        com: at.translation.vector,
        inertia: r.matrix() * inertia_frame * r.matrix().transpose(),
        friction: mu,
    })
}
