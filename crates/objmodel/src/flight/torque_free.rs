//! A flying object turns freely: no torque acts about its centre of mass.
//!
//! Euler's equations for a rigid body with no torque, in its principal axes, are
//! `I₁ ω̇₁ = (I₂ − I₃) ω₂ ω₃` and cyclically. The principal moments of any rigid body obey the
//! triangle inequality (`|I₂ − I₃| ≤ I₁`: each is a sum of the mass's squared distances to two
//! axes), so `|ω̇ᵢ| ≤ |ωⱼ ωₖ|` and `|ω̇| ≤ |ω|² / √3`, whatever the inertia; in the world frame
//! too (`d(R ω_b)/dt = R ω̇_b`). Between two instants of a flight the angular velocity
//! therefore changes by at most `(1/√3) ∫ |ω|² dt`. A contact does not obey this: a topple's
//! fall starts from rest with the angular acceleration of gravity's torque, and an object
//! that rolls or slides on an edge turns about it however its spin was.
//!
//! The test: the angular velocity of each step between frames (world frame,
//! `log(R_{k+1} R_kᵀ) / Δt`), averaged by time over each third of the window. That average
//! telescopes to the rotation between the third's end frames over its duration `T`, whose
//! per-axis noise is `√2 σ_r / T` for independent rotation errors of `σ_r`. The change `Δ`
//! between thirds `p` and `q` has per-axis variance `σ_Δ² = 2 σ_r² (1/T_p² + 1/T_q²)`, and
//! `2 σ_r² / (T_p T_q)` more when they are adjacent (the frame they share ends one average
//! and starts the other, so its error adds up in their difference). `Δ` can exceed the bound
//! `B` (the sum of `|ω_k|² Δt_k / √3` over the steps from the first third's start to the
//! second's end) only by the noise: `|Δ| ≤ B + |noise|`, so `(|Δ| − B)₊² / σ_Δ²` is at most
//! a χ²₃ variable, a conservative test at any inertia. Three pairs of thirds are tested
//! (first with second, second with third, first with third), each at a third of the level
//! (Bonferroni). The noise inflates `|ω_k|²` and so `B`: the test errs towards calling a
//! motion free.

use super::FlightFrame;
use crate::se3::so3_log;
use nalgebra::{Rotation3, UnitQuaternion, Vector3};

/// The rotation test's statistic: the largest of the three pairs' `(|Δ| − B)₊² / σ_Δ²` (see
/// the module's documentation), for rotation noise `sigma_rotation` \[rad\] per axis; 0 when
/// the window has fewer than three steps (nothing to compare).
pub fn torque_chi2(frames: &[FlightFrame], sigma_rotation: f64) -> f64 {
    let steps: Vec<(Vector3<f64>, f64)> = frames
        .windows(2)
        .filter(|w| w[1].t > w[0].t)
        .map(|w| {
            let dt = w[1].t - w[0].t;
            let step = Rotation3::from_matrix_unchecked(w[1].rotation * w[0].rotation.transpose());
            (
                so3_log(&UnitQuaternion::from_rotation_matrix(&step)) / dt,
                dt,
            )
        })
        .collect();
    let s = steps.len();
    if s < 3 {
        return 0.0;
    }
    let a = s / 3;
    let thirds = [0..a, a..s - a, s - a..s];
    // Each third's mean rate (by time) and duration.
    let means = thirds.clone().map(|r| {
        let t: f64 = steps[r.clone()].iter().map(|(_, dt)| dt).sum();
        let w: Vector3<f64> = steps[r].iter().map(|(w, dt)| w * *dt).sum();
        (w / t, t)
    });
    let var_r = sigma_rotation * sigma_rotation;
    let mut worst = 0.0f64;
    for (p, q) in [(0, 1), (1, 2), (0, 2)] {
        let ((wp, tp), (wq, tq)) = (means[p], means[q]);
        let bound: f64 = steps[thirds[p].start..thirds[q].end]
            .iter()
            .map(|(w, dt)| w.norm_squared() * dt)
            .sum::<f64>()
            / 3f64.sqrt();
        let excess = ((wq - wp).norm() - bound).max(0.0);
        // Adjacent thirds share a frame, which enters both averages with opposite signs.
        let shared = if q == p + 1 { 1.0 / (tp * tq) } else { 0.0 };
        let var = 2.0 * var_r * (1.0 / (tp * tp) + 1.0 / (tq * tq) + shared);
        worst = worst.max(if var > 0.0 {
            excess * excess / var
        } else if excess > 0.0 {
            f64::INFINITY
        } else {
            0.0
        });
    }
    worst
}

#[cfg(test)]
#[path = "torque_free_tests.rs"]
mod tests;
