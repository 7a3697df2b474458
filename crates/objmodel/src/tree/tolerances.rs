//! The tolerances the tree decides with: the level of the test that matches an observation to
//! a known feature and the systematic errors it allows, when normals are one face, and when
//! pendulum planes fix a point; with the two helpers they are used with.

use nalgebra::{Matrix3, Vector3};

/// Significance level of the test that decides whether an observation is a known feature.
pub const MATCH_ALPHA: f64 = 1e-4;
/// Per-demonstration systematic error \[m\] of an edge's position beyond its propagated noise
/// (pivot micro-slip, rounded edges), used only when matching observations to features.
pub const SYSTEMATIC_POINT_M: f64 = 3e-3;
/// Per-demonstration systematic error \[rad\] of a direction (2°), used only when matching.
pub const SYSTEMATIC_DIRECTION_RAD: f64 = 0.034_906_585_039_886_59;
/// Smallest ratio of the smallest to the largest eigenvalue of `Σ m mᵀ` over the unit normals
/// `m` of the pendulums' CoM planes: below it the planes are too close to parallel to fix a
/// point, and no CoM is reported (the planes' weights do not enter: see `com_from_planes`).
pub const CONDITION_MIN: f64 = 1e-2;
/// Resting-face normals closer than this \[rad\] (20°) are one face, for pendulums: faces of a
/// polyhedron that share an edge differ by far more.
pub const SAME_FACE_RAD: f64 = 0.349_065_850_398_865_9;

/// A 3x3 matrix as rows (how the tree's files keep matrices).
pub(crate) fn rows(m: &Matrix3<f64>) -> [[f64; 3]; 3] {
    [
        [m[(0, 0)], m[(0, 1)], m[(0, 2)]],
        [m[(1, 0)], m[(1, 1)], m[(1, 2)]],
        [m[(2, 0)], m[(2, 1)], m[(2, 2)]],
    ]
}

/// A 3x3 matrix from its rows (the inverse of [`rows`]).
pub(crate) fn matrix(rows: &[[f64; 3]; 3]) -> Matrix3<f64> {
    Matrix3::from_fn(|i, j| rows[i][j])
}

/// The angle \[rad\] between two directions.
pub(crate) fn angle(a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    a.cross(b).norm().atan2(a.dot(b))
}
