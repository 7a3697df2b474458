//! The shape as a box: when the learnt polyhedron is one (three pairs of opposite, mutually
//! orthogonal faces and eight corners), its centre, axes and size, which a box geometry needs
//! (the export's geometry, the uniform-density inertia).

use super::Shape;
use nalgebra::{Matrix3, UnitQuaternion, Vector3};

/// Faces of a box are pairwise parallel or orthogonal within this angle \[rad\] (1°).
pub const BOX_ANGLE_RAD: f64 = 0.017_453_292_519_943_295;

/// The shape as a box: what a box geometry needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoxFit {
    /// Its centre \[m\], object frame.
    pub centre: Vector3<f64>,
    /// `object_from_box`: the box's axes in the object frame.
    pub rotation: UnitQuaternion<f64>,
    /// Half its size along its own axes \[m\].
    pub half_extents: Vector3<f64>,
}

/// The shape as a box, when its six faces are three pairs of opposite, mutually orthogonal
/// faces (within [`BOX_ANGLE_RAD`]) and it has eight corners.
pub fn box_fit(shape: &Shape) -> Option<BoxFit> {
    if shape.faces.len() != 6 || shape.vertices.len() != 8 {
        return None;
    }
    let cos_tol = BOX_ANGLE_RAD.cos();
    let mut axes: Vec<(Vector3<f64>, f64, f64)> = Vec::new(); // (normal, offset, opposite offset)
    let mut used = [false; 6];
    for i in 0..6 {
        if used[i] {
            continue;
        }
        let fi = &shape.faces[i];
        let j =
            (i + 1..6).find(|&j| !used[j] && fi.normal.dot(&shape.faces[j].normal) < -cos_tol)?;
        used[i] = true;
        used[j] = true;
        axes.push((fi.normal, fi.offset, shape.faces[j].offset));
    }
    let sin_tol = BOX_ANGLE_RAD.sin();
    if axes.len() != 3 || (0..3).any(|a| axes[a].0.dot(&axes[(a + 1) % 3].0).abs() > sin_tol) {
        return None;
    }
    // A right-handed frame from the three normals, made orthonormal.
    let x = axes[0].0;
    let z = x.cross(&axes[1].0).normalize();
    let y = z.cross(&x);
    let rotation = UnitQuaternion::from_matrix(&Matrix3::from_columns(&[x, y, z]));
    let centre = shape.vertices.iter().sum::<Vector3<f64>>() / 8.0;
    let half = |n: &Vector3<f64>| {
        shape
            .vertices
            .iter()
            .map(|v| n.dot(&(v - centre)).abs())
            .fold(0.0, f64::max)
    };
    Some(BoxFit {
        centre,
        rotation,
        half_extents: Vector3::new(half(&x), half(&y), half(&z)),
    })
}
