//! The object's inertia from its pendulums where they determine it, else from its shape at
//! uniform density.
//!
//! A fall about an edge of unit direction `u` determines `ρ = I_e / (m l_p)` \[m\]
//! ([`crate::pendulum`]), `I_e` the moment about the edge; the CoM `c` and the edge give
//! `l_p`, the CoM's distance from the edge line. So the moment about the edge per kg is
//! `ρ l_p`, and, by the parallel-axis theorem, the moment per kg about the parallel axis through
//! the CoM is `q = uᵀ J u = ρ l_p - l_p²`, `J` the inertia tensor per kg about the CoM.
//!
//! One edge direction gives one such quadratic form of `J`, which has six unknowns:
//!
//! * **a box** (the shape is one, [`crate::shape::box_fit`]): its edges have three directions,
//!   its axes. Assuming its principal axes of inertia are its own axes (true at uniform density,
//!   and for any weight inside on its axes), the three principal moments are the mean `q` of the
//!   pendulums about edges along each axis (within [`AXIS_RAD`]); an axis without one takes the
//!   uniform shape's moment about it;
//! * **any other shape**: `J` by least squares from six or more edge directions whose `u uᵀ`
//!   span the symmetric matrices (no assumption on the axes); with fewer, the uniform shape's.
//!
//! A moment `q <= 0` (noise larger than the moment) is not used. A box axis takes the
//! pendulums' moment only when it is known: at least [`MIN_FALLS`] falls, the mean's standard
//! deviation at most [`MAX_RELATIVE_SIGMA`] of it, no larger than the largest squared distance
//! of the shape's corners from the axis (no body inside the shape has more), and the three
//! principal moments obey the triangle inequality; otherwise the axis says why not
//! ([`AxisMoment::not_used`]) and takes the uniform shape's moment. (Measured on the
//! simulated data set: the falls' ratio is within 1-3% at exact poses but biased high, by 10%
//! to 100%, with tracking noise, which these checks catch.) The uniform shape's tensor is
//! about its centroid ([`crate::mass::uniform`]) and taken about the learnt CoM unchanged, as
//! `objmodel-sim` does for a weighted box (the weight is not modelled in its inertia).

mod learnt;

pub use learnt::{AxisMoment, InertiaSource, LearntInertia};

use crate::mass;
use crate::shape::box_fit;
use crate::shape::Shape;
use crate::tree::Tree;
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// Pendulum edges within this angle \[rad\] (10°) of a box axis give its moment.
pub const AXIS_RAD: f64 = 0.174_532_925_199_432_95;

/// A box axis's moment is taken from the pendulums only when at least this many falls give it
/// (one fall says nothing of its own uncertainty) ...
pub const MIN_FALLS: usize = 2;
/// ... and their mean's standard deviation (scatter over √n) is at most this fraction of it.
pub const MAX_RELATIVE_SIGMA: f64 = 0.1;

/// `(edge direction, q)` of every pendulum observation with a fall ratio.
fn moments(tree: &Tree, com: &Vector3<f64>) -> Vec<(Vector3<f64>, f64)> {
    let mut out = Vec::new();
    for e in &tree.edges {
        let u = e.direction;
        let r = com - e.point;
        let l = (r - u * u.dot(&r)).norm();
        // A pendulum the others contradict teaches no inertia either.
        for p in e.pendulums.iter().filter(|p| p.com_conflict.is_none()) {
            for o in &p.observations {
                if let Some(rho) = o.inertia_ratio_m {
                    let q = rho * l - l * l;
                    if q.is_finite() && q > 0.0 {
                        out.push((u, q));
                    }
                }
            }
        }
    }
    out
}

fn rows(m: &Matrix3<f64>) -> [[f64; 3]; 3] {
    std::array::from_fn(|i| std::array::from_fn(|j| m[(i, j)]))
}

/// The inertia of the tree's object with shape `shape` and centre of mass `com` (see the
/// module documentation).
pub fn learn(tree: &Tree, shape: &Shape, com: &Vector3<f64>) -> LearntInertia {
    let uniform = mass::uniform(shape).inertia_per_kg;
    let obs = moments(tree, com);
    if let Some(b) = box_fit(shape) {
        let r = b.rotation.to_rotation_matrix();
        let mut axes = Vec::new();
        for k in 0..3 {
            let a: Vector3<f64> = r.matrix().column(k).into();
            let q: Vec<f64> = obs
                .iter()
                .filter(|(u, _)| u.dot(&a).abs() > AXIS_RAD.cos())
                .map(|(_, q)| *q)
                .collect();
            let n = q.len();
            let mean = (n > 0).then(|| q.iter().sum::<f64>() / n as f64);
            let sd = mean.filter(|_| n > 1).map(|mean| {
                (q.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1) as f64 / n as f64)
                    .sqrt()
            });
            // No mass inside the shape is farther from the axis than its farthest corner.
            let reach = shape
                .vertices
                .iter()
                .map(|v| {
                    let r = v - com;
                    (r - a * a.dot(&r)).norm_squared()
                })
                .fold(0.0, f64::max);
            let not_used = match (mean, sd) {
                (None, _) => Some("no fall about an edge along it".to_string()),
                (Some(_), None) => Some(format!(
                    "one fall: its uncertainty is unknown (needs {MIN_FALLS})"
                )),
                (Some(m), Some(sd)) if sd > MAX_RELATIVE_SIGMA * m => Some(format!(
                    "the falls scatter by {:.0}% (more than {:.0}%)",
                    100.0 * sd / m,
                    100.0 * MAX_RELATIVE_SIGMA
                )),
                (Some(m), _) if m > reach => Some(format!(
                    "{:.2} cm² is more than any mass inside the shape can have ({:.2} cm²)",
                    m * 1e4,
                    reach * 1e4
                )),
                _ => None,
            };
            let used = not_used.is_none();
            axes.push(AxisMoment {
                direction: a,
                moment_per_kg: match mean {
                    Some(m) if used => m,
                    _ => (a.transpose() * uniform * a)[0],
                },
                sigma_per_kg: if used { sd } else { None },
                pendulums: n,
                from_pendulums: used,
                pendulum_moment_per_kg: mean,
                not_used,
            });
        }
        // Principal moments of a body obey the triangle inequality: a set that does not is not
        // a body's, and the uniform shape's is used instead.
        let mut m: Vec<f64> = axes.iter().map(|a| a.moment_per_kg).collect();
        m.sort_by(f64::total_cmp);
        if m[0] + m[1] < m[2] * (1.0 - 1e-9) {
            for a in axes.iter_mut().filter(|a| a.from_pendulums) {
                a.from_pendulums = false;
                a.moment_per_kg = (a.direction.transpose() * uniform * a.direction)[0];
                a.sigma_per_kg = None;
                a.not_used = Some("the moments violate the triangle inequality".into());
            }
        }
        let from = axes.iter().filter(|a| a.from_pendulums).count();
        let j: Matrix3<f64> = axes
            .iter()
            .map(|a| a.direction * a.direction.transpose() * a.moment_per_kg)
            .sum();
        let source = match from {
            3 => InertiaSource::Pendulums,
            0 => InertiaSource::UniformDensity,
            _ => InertiaSource::PendulumsAndUniformDensity,
        };
        let why: String = axes
            .iter()
            .filter_map(|a| a.not_used.as_ref())
            .map(|w| format!("; {w}"))
            .collect();
        return LearntInertia {
            per_kg: rows(&j),
            source,
            axes,
            note: format!(
                "a box: principal axes taken as its own; {from} of its 3 principal moments from \
                 the pendulums' falls (I_e/(m l_p) about edges along that axis, parallel axis to \
                 the CoM), {} from the shape at uniform density{}",
                3 - from,
                why
            ),
        };
    }
    // Any other shape: the full tensor when the directions determine it.
    let row = |u: &Vector3<f64>| {
        SVector::<f64, 6>::from([
            u.x * u.x,
            u.y * u.y,
            u.z * u.z,
            2.0 * u.x * u.y,
            2.0 * u.x * u.z,
            2.0 * u.y * u.z,
        ])
    };
    let mut ata = SMatrix::<f64, 6, 6>::zeros();
    let mut atb = SVector::<f64, 6>::zeros();
    for (u, q) in &obs {
        let a = row(u);
        ata += a * a.transpose();
        atb += a * *q;
    }
    let sv = ata.symmetric_eigenvalues();
    if !obs.is_empty() && sv.min() > 1e-3 * sv.max() {
        if let Some(x) = ata.try_inverse().map(|inv| inv * atb) {
            let j = Matrix3::new(x[0], x[3], x[4], x[3], x[1], x[5], x[4], x[5], x[2]);
            if j.symmetric_eigenvalues().min() > 0.0 {
                return LearntInertia {
                    per_kg: rows(&j),
                    source: InertiaSource::Pendulums,
                    axes: Vec::new(),
                    note: format!(
                        "the full tensor by least squares from {} pendulum falls about edges of \
                         six or more independent directions",
                        obs.len()
                    ),
                };
            }
        }
    }
    LearntInertia {
        per_kg: rows(&uniform),
        source: InertiaSource::UniformDensity,
        axes: Vec::new(),
        note: "the shape at uniform density: not a box, and the pendulums' edges have fewer \
               than six independent directions (a general tensor needs six)"
            .to_string(),
    }
}

#[cfg(test)]
mod tests;
