//! The predicted pendulums' uncertainty, and the observed ones beside them.
//!
//! A predicted pendulum depends on the edge line, which is the intersection of its resting face
//! `(n₁, d₁)` and landing face `(n₂, d₂)`, and on the CoM `c`: the line's direction is
//! `u = n₁ × n₂`, its point `p` solves `n₁ᵀp = d₁, n₂ᵀp = d₂, uᵀp = 0`, then φ and `l_p` as in
//! the [parent module](super). Their standard deviations are propagated to first order
//! (Jacobian by central differences) from the CoM's covariance, each face's offset sigma and its
//! normal's sigma per axis (an inferred face carries its larger sigma). The inputs are taken as
//! independent: an inferred face's offset, which comes from the CoM, is in truth correlated with
//! it (left out).

use super::{ObservedPendulum, PredictedPendulum};
use crate::geometry::normal_axes;
use crate::shape::{Shape, ShapeFace};
use crate::tree::{Tree, SAME_FACE_RAD};
use nalgebra::{Matrix3, Vector3};

/// An observed edge is a predicted one when within this distance \[m\] of its line (and parallel
/// within 10°, on the same resting face).
pub const EDGE_MATCH_M: f64 = 0.015;

/// (φ, l_p) of the edge between faces `(n1, d1)` and `(n2, d2)` for the CoM `c`, the edge
/// direction turned towards `u0`.
fn phi_lp(
    c: &Vector3<f64>,
    n1: &Vector3<f64>,
    d1: f64,
    n2: &Vector3<f64>,
    d2: f64,
    u0: &Vector3<f64>,
) -> (f64, f64) {
    let (n1, n2) = (n1.normalize(), n2.normalize());
    let mut u = n1.cross(&n2).normalize();
    if u.dot(u0) < 0.0 {
        u = -u;
    }
    let a = Matrix3::from_rows(&[n1.transpose(), n2.transpose(), u.transpose()]);
    let p = a
        .try_inverse()
        .map_or(Vector3::zeros(), |inv| inv * Vector3::new(d1, d2, 0.0));
    let r = c - p;
    let r = r - u * u.dot(&r);
    let w = u.cross(&n1);
    (r.dot(&w).atan2(-r.dot(&n1)), r.norm())
}

/// Standard deviations of (φ, l_p) of the pendulum `p` of `shape`, for the CoM `com` with
/// covariance `com_cov`.
pub fn sigmas(
    p: &PredictedPendulum,
    f1: &ShapeFace,
    f2: &ShapeFace,
    com: &Vector3<f64>,
    com_cov: &Matrix3<f64>,
) -> (f64, f64) {
    let u0 = p.edge_direction;
    let f = |c: &Vector3<f64>, n1: &Vector3<f64>, d1: f64, n2: &Vector3<f64>, d2: f64| {
        let (phi, l) = phi_lp(c, n1, d1, n2, d2, &u0);
        Vector3::new(phi, l, 0.0)
    };
    let (n1, d1, n2, d2) = (f1.normal, f1.offset, f2.normal, f2.offset);
    let diff = |plus: Vector3<f64>, minus: Vector3<f64>, h: f64| (plus - minus) / (2.0 * h);
    let mut cov = Matrix3::<f64>::zeros();
    // The CoM: a full covariance.
    let h = 1e-6;
    let jc = Matrix3::from_columns(&[0, 1, 2].map(|k| {
        let e = Vector3::ith(k, h);
        diff(
            f(&(com + e), &n1, d1, &n2, d2),
            f(&(com - e), &n1, d1, &n2, d2),
            h,
        )
    }));
    cov += jc * com_cov * jc.transpose();
    // Offsets and normals: independent.
    let mut add = |g: Vector3<f64>, sigma: f64| cov += g * g.transpose() * sigma * sigma;
    add(
        diff(
            f(com, &n1, d1 + h, &n2, d2),
            f(com, &n1, d1 - h, &n2, d2),
            h,
        ),
        f1.offset_sigma_m,
    );
    add(
        diff(
            f(com, &n1, d1, &n2, d2 + h),
            f(com, &n1, d1, &n2, d2 - h),
            h,
        ),
        f2.offset_sigma_m,
    );
    for a in normal_axes(&n1) {
        let g = diff(
            f(com, &(n1 + a * h), d1, &n2, d2),
            f(com, &(n1 - a * h), d1, &n2, d2),
            h,
        );
        add(g, f1.normal_sigma_rad);
    }
    for a in normal_axes(&n2) {
        let g = diff(
            f(com, &n1, d1, &(n2 + a * h), d2),
            f(com, &n1, d1, &(n2 - a * h), d2),
            h,
        );
        add(g, f2.normal_sigma_rad);
    }
    (cov[(0, 0)].sqrt(), cov[(1, 1)].sqrt())
}

/// [`super::pendulums`] with their standard deviations, for the CoM `com` with covariance
/// `com_cov` \[m²\].
pub fn uncertain(
    shape: &Shape,
    com: &Vector3<f64>,
    com_cov: &Matrix3<f64>,
) -> Vec<PredictedPendulum> {
    let mut out = super::pendulums(shape, com);
    for p in &mut out {
        let face = |id: &str| shape.faces.iter().find(|f| f.id == id);
        let (Some(f1), Some(f2)) = (face(&p.resting_face), face(&p.landing_face)) else {
            continue;
        };
        let (s_phi, s_l) = sigmas(p, f1, f2, com, com_cov);
        p.phi_sigma = Some(s_phi);
        p.l_p_sigma = Some(s_l);
    }
    out
}

/// Put each pendulum the tree observed beside the prediction of its (resting face, edge): same
/// resting face (within [`SAME_FACE_RAD`]), parallel edge (10°), within [`EDGE_MATCH_M`].
pub fn observed_beside(tree: &Tree, predicted: &mut [PredictedPendulum]) {
    let parallel = 10f64.to_radians().cos();
    for e in &tree.edges {
        for obs in &e.pendulums {
            let Some(phi) = obs.phi else { continue };
            let distance = |q: &PredictedPendulum| {
                let r = e.point - q.edge_point;
                (r - q.edge_direction * q.edge_direction.dot(&r)).norm()
            };
            let best = predicted
                .iter_mut()
                .filter(|q| {
                    crate::tree::angle(&q.resting_normal, &obs.resting_face_normal) < SAME_FACE_RAD
                })
                .filter(|q| q.edge_direction.dot(&e.direction).abs() > parallel)
                .filter(|q| distance(q) < EDGE_MATCH_M)
                .min_by(|a, b| distance(a).total_cmp(&distance(b)));
            if let Some(q) = best {
                let var = obs.phi_sigma.unwrap_or(0.0).powi(2) + q.phi_sigma.unwrap_or(0.0).powi(2);
                q.observed = Some(ObservedPendulum {
                    edge: e.id.clone(),
                    phi,
                    phi_sigma: obs.phi_sigma,
                    l_p: obs.l_p,
                    phi_z: (var > 0.0).then(|| (phi - q.phi) / var.sqrt()),
                    contradicted: obs.com_conflict.is_some(),
                });
            }
        }
    }
}

#[cfg(test)]
#[path = "sigma_tests.rs"]
mod tests;
