//! Whether an edge's pivot stayed put over a rest and up to a topple's onset: the test that a
//! rest is a valid reference for the topple after it.
//!
//! A rotation about a fixed edge leaves the edge's points where they are: with `X_k` the
//! object's pose in the support's frame (relative to the palm when there is one) and `e` a
//! point of the edge in the object's frame, `q_k = X_k e` is the same for every frame from the
//! rest to the end of the rotation, whatever the object turned. A creep before the topple (a
//! box lagging a tilting palm and creeping 1-3 mm down it in stick-slip steps, on soft
//! contacts) moves `q_k`: the rest's mean pose is then a pose the object left before it
//! tipped, and every frame measured from it has its axis moved by the creep `δ`, by about
//! `δ / (2 sin(θ/2))`.
//!
//! The test scans the sequence `q_k` (the rest's frames, then the frames up to the reference of
//! the topple's onset), projected normal to the edge, for one change of its mean: at every cut
//! the weighted means before and after differ by `d`, and `|d|² / (1/W_before + 1/W_after)` is
//! χ²₂ under a pivot that stayed put; the largest over the cuts is compared with the χ²₂
//! quantile at α divided by the number of cuts (Bonferroni). Each frame's variance is the
//! tracking noise at the edge (`σ_p² + σ_r² |e|²`) and, for a frame turned by θ from the rest,
//! the edge's own error moved by the chord `2 sin(θ/2)`; the onset's frame also carries the
//! settling of a contact as the load moves onto the edge
//! (`classify::frame_model::REFERENCE_SETTLING_M`). The contact's wander during a rotation (the
//! edge tolerance) is not in it: the question is whether a rest is still, and a rest that moves
//! by more than its noise is not one.

use crate::classify::frame_model::REFERENCE_SETTLING_M;
use crate::geometry::Line;
use crate::noise::NoiseModel;
use nalgebra::{Isometry3, Matrix3, Vector3};

/// How far the pivot moved, and the test's statistic against its level.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PivotMove {
    /// Distance \[m\] between the weighted mean pivot positions before and after the cut.
    pub distance_m: f64,
    /// Time \[s\] of the first frame after the cut.
    pub t_cut: f64,
    /// χ²₂ statistic at the cut.
    pub chi2: f64,
    /// The Bonferroni-corrected χ²₂ level it is tested against.
    pub level: f64,
}

/// The pivot's test over `frames` (time, the object's pose in the support's frame), the last
/// of which is the onset's reference: `Some` when the edge point moved (see the module
/// documentation), with where and by how much; `None` when it stayed put within the noise or
/// the frames are too few to tell.
pub fn pivot_moved(
    frames: &[(f64, Isometry3<f64>)],
    line: &Line,
    point_cov: &Matrix3<f64>,
    noise: &NoiseModel,
    alpha: f64,
) -> Option<PivotMove> {
    let (first, last) = (frames.first()?, frames.last()?);
    if frames.len() < 3 {
        return None;
    }
    let e = line.point;
    // The edge's direction in the support's frame, and two directions normal to it.
    let w = last.1.rotation * line.direction;
    let a = w
        .cross(&Vector3::x())
        .try_normalize(1e-6)
        .unwrap_or_else(|| {
            w.cross(&Vector3::y())
                .try_normalize(1e-6)
                .unwrap_or(Vector3::z())
        });
    let b = w.cross(&a);
    let var_noise = noise.sigma_position.powi(2) + (noise.sigma_rotation * e.norm()).powi(2);
    let var_edge = point_cov.trace() / 2.0;
    let q0 = first.1.rotation;
    let items: Vec<(f64, [f64; 2], f64)> = frames
        .iter()
        .enumerate()
        .map(|(k, (t, x))| {
            let q = x * nalgebra::Point3::from(e);
            let chord = 2.0 * (0.5 * (q0.inverse() * x.rotation).angle()).sin();
            let settling = if k + 1 == frames.len() {
                REFERENCE_SETTLING_M.powi(2)
            } else {
                0.0
            };
            let var = var_noise + chord * chord * var_edge + settling;
            (*t, [q.coords.dot(&a), q.coords.dot(&b)], 1.0 / var)
        })
        .collect();
    let total = items.iter().fold((0.0, [0.0; 2]), |(sw, s), (_, y, wt)| {
        (sw + wt, [s[0] + wt * y[0], s[1] + wt * y[1]])
    });
    let cuts = items.len() - 1;
    let level = crate::stats::chi2_threshold(2.0, alpha / cuts as f64);
    let mut before = (0.0, [0.0; 2]);
    let mut best: Option<PivotMove> = None;
    for k in 0..cuts {
        let (_, y, wt) = items[k];
        before = (
            before.0 + wt,
            [before.1[0] + wt * y[0], before.1[1] + wt * y[1]],
        );
        let wa = total.0 - before.0;
        let d = [
            before.1[0] / before.0 - (total.1[0] - before.1[0]) / wa,
            before.1[1] / before.0 - (total.1[1] - before.1[1]) / wa,
        ];
        let d2 = d[0] * d[0] + d[1] * d[1];
        let chi2 = d2 / (1.0 / before.0 + 1.0 / wa);
        if best.is_none_or(|m| chi2 > m.chi2) {
            best = Some(PivotMove {
                distance_m: d2.sqrt(),
                t_cut: items[k + 1].0,
                chi2,
                level,
            });
        }
    }
    best.filter(|m| m.chi2 > m.level && last.0 > first.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Translation3, UnitQuaternion};

    /// Poses of a box turning about the edge through (0.03, 0, -0.05) along y by `theta[k]`,
    /// its edge point moved by `slip[k]` along x.
    fn poses(theta: &[f64], slip: &[f64]) -> Vec<(f64, Isometry3<f64>)> {
        let e = Vector3::new(0.03, 0.0, -0.05);
        theta
            .iter()
            .zip(slip)
            .enumerate()
            .map(|(k, (&th, &s))| {
                let r = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), th);
                // x e = e + slip: t = e + slip - R e.
                let t = e + Vector3::new(s, 0.0, 0.0) - r * e;
                (
                    k as f64 / 30.0,
                    Isometry3::from_parts(Translation3::from(t), r),
                )
            })
            .collect()
    }

    fn edge() -> Line {
        Line::through(Vector3::new(0.03, 0.0, -0.05), Vector3::y())
    }

    const NOISE: NoiseModel = NoiseModel {
        sigma_position: 1e-4,
        sigma_rotation: 1e-3,
    };

    #[test]
    fn a_rotation_about_the_edge_leaves_the_pivot_put() {
        // Still for 40 frames, then the onset turned by 5°: the pivot did not move.
        let mut theta = vec![0.0; 40];
        theta.push(5f64.to_radians());
        let slip = vec![0.0; 41];
        let cov = Matrix3::identity() * 1e-6;
        assert!(pivot_moved(&poses(&theta, &slip), &edge(), &cov, &NOISE, 1e-3).is_none());
    }

    #[test]
    fn a_creep_during_the_rest_moves_the_pivot() {
        // The edge point creeps 0.6 mm in steps over the "rest" (each step within a rest
        // window's noise), then the onset.
        let theta = vec![0.0; 41];
        let slip: Vec<f64> = (0..41).map(|k| 2e-4 * (k / 12) as f64).collect();
        let cov = Matrix3::identity() * 1e-6;
        let m = pivot_moved(&poses(&theta, &slip), &edge(), &cov, &NOISE, 1e-3)
            .expect("a 0.6 mm creep at 0.1 mm noise");
        assert!(m.distance_m > 2e-4 && m.distance_m < 6e-4, "{m:?}");
        assert!(m.chi2 > m.level);
    }

    #[test]
    fn the_edge_error_counts_for_a_turned_onset() {
        // The onset turned 20° from the rest, and the edge used is 3 mm off the true one
        // (its covariance says so): the apparent move is the edge's error, not a creep.
        let mut theta = vec![0.0; 40];
        theta.push(20f64.to_radians());
        let slip = vec![0.0; 41];
        let off = Line::through(Vector3::new(0.03, 0.0, -0.047), Vector3::y());
        let honest = Matrix3::identity() * (3e-3f64).powi(2);
        assert!(pivot_moved(&poses(&theta, &slip), &off, &honest, &NOISE, 1e-3).is_none());
        let overconfident = Matrix3::identity() * 1e-10;
        assert!(pivot_moved(&poses(&theta, &slip), &off, &overconfident, &NOISE, 1e-3).is_some());
    }
}
