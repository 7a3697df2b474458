//! What the crate's unit tests share: deterministic randomness (`rand`'s `StdRng`, seeded), and
//! edge observations drawn with their noise.

use crate::edge::EdgeObservation;
use crate::geometry::Line;
use nalgebra::{Matrix3, Vector3};
use rand::{rngs::StdRng, Rng, SeedableRng};
use rand_distr::{Distribution, Normal};

/// A generator seeded with `seed`.
pub(crate) fn rng(seed: u64) -> StdRng {
    StdRng::seed_from_u64(seed)
}

/// The next pseudo-random number of `r`.
pub(crate) fn next(r: &mut StdRng) -> u64 {
    r.random()
}

/// An observation of the line through `p` along `u`, measured with σ `sigma_p` per axis of
/// its point and `sigma_d` of its direction (and drawn with them).
pub(crate) fn observed_edge(
    demo: &str,
    p: Vector3<f64>,
    u: Vector3<f64>,
    sigma_p: f64,
    sigma_d: f64,
    rng: &mut StdRng,
) -> EdgeObservation {
    let unit = Normal::new(0.0, 1.0).unwrap();
    let normal_plane = Matrix3::identity() - u * u.transpose();
    let dp = normal_plane * Vector3::from_fn(|_, _| unit.sample(rng)) * sigma_p;
    let du = normal_plane * Vector3::from_fn(|_, _| unit.sample(rng)) * sigma_d;
    EdgeObservation {
        demo: demo.to_string(),
        line: Line::through(p + dp, u + du),
        point_cov: normal_plane * sigma_p * sigma_p,
        direction_cov: normal_plane * sigma_d * sigma_d,
        paper_line: None,
        frames: 200,
        max_angle: 0.5,
        chi2_per_dof: 1.0,
        common_point_cov: Matrix3::zeros(),
    }
}
