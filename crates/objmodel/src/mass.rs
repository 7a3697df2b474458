//! Mass properties of a reconstructed [`Shape`] of uniform density: volume, centroid and the
//! inertia tensor per unit mass about the centroid.
//!
//! The shape is split into tetrahedra, one per triangle of each face's polygon (a fan) and a
//! point inside; each tetrahedron `T` with corners `v₀..v₃` contributes its signed volume
//! `V = v₁₀ · (v₂₀ × v₃₀) / 6`, its first moment `V (Σ vᵢ) / 4` and its second moment
//! `∫_T x xᵀ = V/20 (Σ vᵢ vᵢᵀ + s sᵀ)`, `s = Σ vᵢ` (the exact integral over a tetrahedron);
//! the inertia tensor of a body with second moment `C` (per unit mass, about its centroid) is
//! `tr(C) 1 − C`.

use crate::shape::Shape;
use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

/// Volume, centroid and inertia of a uniform-density shape.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct MassProperties {
    /// Volume \[m³\].
    pub volume: f64,
    /// Centroid (the centre of mass at uniform density) \[m\], object frame.
    pub centroid: Vector3<f64>,
    /// Inertia tensor about the centroid per unit mass \[m²\] (multiply by the mass in kg for
    /// kg m²), object-frame axes.
    pub inertia_per_kg: Matrix3<f64>,
}

/// The mass properties of `shape` at uniform density.
pub fn uniform(shape: &Shape) -> MassProperties {
    let inside = shape.vertices.iter().sum::<Vector3<f64>>() / shape.vertices.len() as f64;
    let (mut volume, mut first, mut second) = (0.0, Vector3::zeros(), Matrix3::zeros());
    for face in &shape.faces {
        let p = &face.polygon;
        for k in 1..p.len().saturating_sub(1) {
            let corners = [
                inside,
                shape.vertices[p[0]],
                shape.vertices[p[k]],
                shape.vertices[p[k + 1]],
            ];
            let v = (corners[1] - corners[0])
                .dot(&(corners[2] - corners[0]).cross(&(corners[3] - corners[0])))
                / 6.0;
            let s: Vector3<f64> = corners.iter().sum();
            volume += v;
            first += s * (v / 4.0);
            second += (corners
                .iter()
                .map(|c| c * c.transpose())
                .sum::<Matrix3<f64>>()
                + s * s.transpose())
                * (v / 20.0);
        }
    }
    let centroid = first / volume;
    let c = second / volume - centroid * centroid.transpose();
    MassProperties {
        volume,
        centroid,
        inertia_per_kg: Matrix3::identity() * c.trace() - c,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shape::{reconstruct, tests_support::box_faces};
    use nalgebra::UnitQuaternion;

    /// A box `a x b x c` anywhere, turned: volume `abc`, centroid its centre, and inertia
    /// `(b² + c²)/12` etc. per kg about its own axes.
    #[test]
    fn a_box_has_the_textbook_inertia() {
        let centre = Vector3::new(0.03, -0.02, 0.11);
        let rotation = UnitQuaternion::from_euler_angles(0.3, -0.5, 1.1);
        let size = Vector3::new(0.2, 0.1, 0.3);
        let shape = reconstruct(&box_faces(centre, &rotation, &size)).unwrap();
        let m = uniform(&shape);
        assert!((m.volume - size.product()).abs() < 1e-12, "{}", m.volume);
        assert!((m.centroid - centre).norm() < 1e-12);
        let [a, b, c] = [size.x, size.y, size.z].map(|x| x * x);
        let expected = rotation.to_rotation_matrix().matrix()
            * Matrix3::from_diagonal(&Vector3::new(b + c, a + c, a + b))
            / 12.0
            * rotation.to_rotation_matrix().matrix().transpose();
        assert!(
            (m.inertia_per_kg - expected).norm() < 1e-12,
            "{}",
            m.inertia_per_kg
        );
    }
}
