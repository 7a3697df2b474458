//! A slide on the tilting palm, and the friction it shows (issue 19, item 3).
//!
//! An instrumented demonstration whose object, instead of toppling, slides down the palm as
//! the palm tilts. Under Coulomb friction the object rests until the palm's slope θ reaches
//! `atan μ_s` (static friction), then moves down the slope with `ẍ = |g| (sin θ − μ_k cos θ)`
//! (kinetic friction, `μ_k ≤ μ_s`) while it moves, and stops where its speed falls to zero (the
//! hand levelling the palm), to rest until the slope reaches `atan μ_s` again.
//!
//! * The slope θ(t): the angle from the vertical of the support's normal, that normal taken in
//!   the palm frame from the rest before the motion (gravity in the object frame then, turned
//!   into the palm frame: the palm is level at the start, as for an instrumented topple), the
//!   palm's orientation slerped at each object frame and the angles smoothed (local lines over
//!   ±[`SLOPE_SMOOTH_S`]). The frames fitted end at the steepest slope: where the hand turns
//!   the palm back, the palm surface's own acceleration changes the normal force.
//! * x(t): the object's displacement down the slope, in the palm frame, from that rest.
//! * μ_s and μ_k by least squares of x over the rest, the slide and the rest after: the model
//!   integrated from the rest under the measured θ(t) (1 ms steps); golden-section search over
//!   μ_s, each with the best μ_k (a second golden section in `[0, μ_s]`).
//! * μ_s is the friction reported; μ_k is a nuisance parameter of the fit, not reported (in
//!   rapier a slide's deceleration follows no one kinetic coefficient: fitted values of 0-0.18
//!   for a nominal 0.25-0.35).
//! * μ_s's σ: the fit's, from the Hessian of the sum of squares under the residuals' variance
//!   (at least the tracker's position noise), and the slope's reference (the support
//!   normal from `N` rest frames, `σ_r √(2/N)` in θ) and the model tolerance of the slope
//!   where a slide starts ([`SLIDE_TILT_TOLERANCE_RAD`]), carried by `dμ/dθ = 1 + μ²`.
//! * It teaches a friction only if the model explains the motion: the residuals' χ² passes at
//!   1% (under the position noise plus [`SLIDE_TOLERANCE_M`]), no motion at all fails its
//!   test at 10⁻³ (it moved on the palm beyond the noise), and it did not turn on the palm by
//!   more than [`MAX_TURN_RAD`] (a topple, a roll, a carry are not slides).

use super::palm_stream::without_glitches;
use super::regression::smooth;
use super::series::palm_at;
use super::tolerances::{MAX_REST_FRAMES, REST_MARGIN_S};
use crate::classify::Classification;
use crate::noise::NoiseModel;
use crate::recording::Recording;
use crate::stats::golden_min;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// Largest turn of the object on the palm during a slide \[rad\] (5°).
pub const MAX_TURN_RAD: f64 = 0.087_266_462_599_716_48;
/// What the Coulomb model leaves out \[m\] (contact compliance, the palm's own acceleration),
/// added in quadrature to the position noise in the χ² test.
pub const SLIDE_TOLERANCE_M: f64 = 5e-4;
/// Half-width \[s\] of the local lines that smooth the slope: narrower than a topple's
/// ([`super::SMOOTH_S`]), since the hand turns the palm back where the object slid.
pub const SLOPE_SMOOTH_S: f64 = 0.1;
/// How sharply a slide's start is defined \[rad\] (1°), a model tolerance in the slope where
/// the object breaks free, added in quadrature to μ_s's σ (through `dμ/dθ = 1 + μ²`): a
/// compliant contact lets the object creep before it slides (in rapier it starts to move
/// 0.3-0.4° below `atan μ`, and the static-kinetic model then puts its start lower still), and
/// real contacts stick and slip.
pub const SLIDE_TILT_TOLERANCE_RAD: f64 = 0.017_453_292_519_943_295;
/// Integration step of the slide model \[s\].
const STEP_S: f64 = 1e-3;

/// The friction a slide on the tilting palm shows.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PalmSlide {
    /// The static friction coefficient between the object and the palm: the slope where it
    /// starts to slide is `atan μ`.
    pub mu: f64,
    /// Its standard deviation.
    pub mu_sigma: f64,
    /// The slope where the object starts to slide, `atan μ` \[rad\].
    pub slide_tilt: f64,
    /// The largest slope the palm reached \[rad\].
    pub max_tilt: f64,
    /// How far it slid over the frames fitted (up to the steepest slope) \[m\].
    pub distance_m: f64,
    /// Frames fitted.
    pub frames: usize,
    /// χ² of the fit per degree of freedom.
    pub chi2_per_dof: f64,
}

/// The frames the slide model is fitted to: times \[s\], slope \[rad\], displacement down
/// the slope \[m\]; and the rest frames the slope's reference came from.
struct SlideSeries {
    t: Vec<f64>,
    theta: Vec<f64>,
    x: Vec<f64>,
    rest_frames: usize,
}

/// The friction a slide on the palm shows, if the demonstration `c` (whose frames `recording`
/// kept) is one: instrumented, resting first, and moving on the palm as the model says (and
/// teaching something: see [`Classification::withheld`]); `g` is gravity in the tracking
/// frame.
pub fn measure(recording: &Recording, c: &Classification, g: &Vector3<f64>) -> Option<PalmSlide> {
    // (A demonstration that teaches nothing teaches no friction either.)
    if recording.palm.is_empty() || !c.topples.is_empty() || c.withheld.is_some() {
        return None;
    }
    let first = c.segments.first()?;
    let noise = c.noise?;
    // The rest, the slide and the rest after it (up to the next motion).
    let until = c.segments.get(1).map_or(f64::INFINITY, |s| s.t_start);
    let series = slide_series(recording, c, g, (first.t_start, until), noise)?;
    let (t, theta, x) = (&series.t, &series.theta, &series.x);
    let distance = x.iter().cloned().fold(0.0, f64::max);
    let sigma_x = (noise.sigma_position.powi(2) + SLIDE_TOLERANCE_M.powi(2)).sqrt();
    // The object must have moved on the palm beyond the noise: no motion at all (x = 0) fails
    // its χ² test at 10⁻³.
    let n = t.len();
    let still = x.iter().map(|x| x * x).sum::<f64>() / sigma_x.powi(2);
    if still <= crate::stats::chi2_threshold(n as f64, 1e-3) {
        return None;
    }
    let g = g.norm();
    let sse = |mu_s: f64, mu_k: f64| -> f64 {
        simulate(t, theta, g, mu_s, mu_k)
            .iter()
            .zip(x)
            .map(|(m, o)| (m - o).powi(2))
            .sum()
    };
    let best_kinetic = |mu_s: f64| golden_min(&|mu_k| sse(mu_s, mu_k), 0.0, mu_s, 1e-7);
    let max_tilt = theta.iter().cloned().fold(0.0, f64::max);
    // A palm turned past 80° is not a slope a slide on it can be measured on.
    if max_tilt <= 0.0 || max_tilt >= 80f64.to_radians() {
        return None;
    }
    let mu = golden_min(
        &|mu_s| sse(mu_s, best_kinetic(mu_s)),
        0.0,
        max_tilt.tan(),
        1e-7,
    );
    let mu_k = best_kinetic(mu);
    let dof = n as f64 - 2.0;
    let chi2 = sse(mu, mu_k) / sigma_x.powi(2);
    if chi2 > crate::stats::chi2_threshold(dof, 0.01) {
        return None;
    }
    // The covariance: 2 σ_x² H⁻¹, H the Hessian of the sum of squares (central differences).
    let h = 1e-3;
    let f = |a: f64, b: f64| sse(mu + a, mu_k + b);
    let h_ss = (f(h, 0.0) - 2.0 * f(0.0, 0.0) + f(-h, 0.0)) / (h * h);
    let h_kk = (f(0.0, h) - 2.0 * f(0.0, 0.0) + f(0.0, -h)) / (h * h);
    let h_sk = (f(h, h) - f(h, -h) - f(-h, h) + f(-h, -h)) / (4.0 * h * h);
    let cov = nalgebra::Matrix2::new(h_ss, h_sk, h_sk, h_kk).try_inverse()?;
    let var_x = (sse(mu, mu_k) / dof).max(noise.sigma_position.powi(2));
    let var_s = 2.0 * var_x * cov[(0, 0)];
    if var_s.is_nan() || var_s <= 0.0 {
        return None;
    }
    let rest_frames = series.rest_frames as f64;
    let var_reference = (2.0 * noise.sigma_rotation.powi(2) / rest_frames
        + SLIDE_TILT_TOLERANCE_RAD.powi(2))
        * (1.0 + mu * mu).powi(2);
    Some(PalmSlide {
        mu,
        mu_sigma: (var_s + var_reference).sqrt(),
        slide_tilt: mu.atan(),
        max_tilt,
        distance_m: distance,
        frames: n,
        chi2_per_dof: chi2 / dof,
    })
}

/// Slope and displacement at every kept frame that is not an outlier and has a palm pose,
/// from the rest before `t_moving` on; `None` without enough rest, or if the object turned on
/// the palm.
fn slide_series(
    recording: &Recording,
    c: &Classification,
    g: &Vector3<f64>,
    (t_moving, until): (f64, f64),
    noise: NoiseModel,
) -> Option<SlideSeries> {
    let sigma_rotation = noise.sigma_rotation;
    let frames = &recording.object;
    let outlier = c.is_outlier();
    let palm = without_glitches(&recording.palm, noise);
    let down = g.normalize();
    // The rest before the motion: the support normal (up) and the object's place, palm frame.
    let (mut up_sum, mut place_sum, mut turn_ref, mut rest) =
        (Vector3::zeros(), Vector3::zeros(), None, 0usize);
    let kept: Vec<(usize, nalgebra::UnitQuaternion<f64>)> = frames
        .iter()
        .enumerate()
        .filter(|(_, f)| !outlier(f.index))
        .filter_map(|(i, f)| palm_at(&palm, f.t).map(|q| (i, q)))
        .collect();
    for &(i, qp) in &kept {
        let f = &frames[i];
        if f.t >= t_moving - REST_MARGIN_S || rest >= MAX_REST_FRAMES {
            continue;
        }
        let p = palm_position_at(&palm, f.t)?;
        up_sum += qp.inverse() * -down;
        place_sum += qp.inverse() * (f.position - p);
        turn_ref.get_or_insert(qp.inverse() * f.rotation);
        rest += 1;
    }
    if rest < 5 {
        return None;
    }
    let up_palm = up_sum.normalize();
    let place = place_sum / rest as f64;
    let turn_ref = turn_ref?;
    let (mut t, mut theta, mut shift) = (Vec::new(), Vec::new(), Vec::new());
    let first_rest_t = kept.iter().map(|&(i, _)| frames[i].t).next()?;
    for &(i, qp) in &kept {
        let f = &frames[i];
        if f.t < first_rest_t || f.t >= until {
            continue;
        }
        let palm_from_object = qp.inverse() * f.rotation;
        if palm_from_object.angle_to(&turn_ref) > MAX_TURN_RAD + 5.0 * sigma_rotation {
            return None;
        }
        let p = palm_position_at(&palm, f.t)?;
        t.push(f.t);
        theta.push((qp * up_palm).angle(&-down));
        shift.push(qp.inverse() * (f.position - p) - place);
    }
    let theta = smooth(&t, &theta, SLOPE_SMOOTH_S);
    // Up to the steepest slope: a hand that turns the palm back changes its rate abruptly, and
    // the palm surface's own acceleration then changes the normal force (it may even drop
    // away from the object) that the model takes as `m g cos θ`.
    let peak = theta
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(b.1))?
        .0;
    let (t, theta, shift) = (
        t[..=peak].to_vec(),
        theta[..=peak].to_vec(),
        &shift[..=peak],
    );
    // Down the slope, in the palm frame: gravity's part along the support, where the palm is
    // steepest (the slide's direction).
    let qp = palm_at(&palm, t[peak])?;
    let g_palm = qp.inverse() * down;
    let downhill = (g_palm - up_palm * up_palm.dot(&g_palm)).try_normalize(1e-9)?;
    let x = shift.iter().map(|s| s.dot(&downhill)).collect();
    Some(SlideSeries {
        t,
        theta,
        x,
        rest_frames: rest,
    })
}

/// The palm's position at `t` (linear between its samples).
fn palm_position_at(palm: &[crate::trajectory::StampedPose], t: f64) -> Option<Vector3<f64>> {
    let i = palm.partition_point(|p| p.t < t);
    if i < palm.len() && (palm[i].t - t).abs() < 1e-9 {
        return Some(palm[i].pose.translation.vector);
    }
    if i == 0 || i >= palm.len() {
        return None;
    }
    let (a, b) = (&palm[i - 1], &palm[i]);
    let w = (t - a.t) / (b.t - a.t);
    Some(a.pose.translation.vector * (1.0 - w) + b.pose.translation.vector * w)
}

/// The displacement down the slope at the times `t` of the Coulomb slide with static and
/// kinetic friction `mu_s`, `mu_k` under the slope `theta(t)` (linear between samples), from
/// rest at `t[0]`; `g` = |g|.
fn simulate(t: &[f64], theta: &[f64], g: f64, mu_s: f64, mu_k: f64) -> Vec<f64> {
    let mut out = Vec::with_capacity(t.len());
    let (mut x, mut v, mut moving) = (0.0, 0.0, false);
    out.push(0.0);
    for k in 1..t.len() {
        let (t0, t1) = (t[k - 1], t[k]);
        let steps = ((t1 - t0) / STEP_S).ceil().max(1.0) as usize;
        let dt = (t1 - t0) / steps as f64;
        for s in 0..steps {
            let w = (s as f64 + 0.5) / steps as f64;
            let th = theta[k - 1] * (1.0 - w) + theta[k] * w;
            moving = moving || th.sin() > mu_s * th.cos();
            if moving {
                v += g * (th.sin() - mu_k * th.cos()) * dt;
                if v <= 0.0 {
                    (v, moving) = (0.0, false);
                }
                x += v * dt;
            }
        }
        out.push(x);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The model itself: on a slope rising at a constant rate, the object stays until the
    /// slope is atan μ, then accelerates as `g (sin θ − μ cos θ)`; and the fit of its own
    /// output gives μ back.
    #[test]
    fn the_coulomb_slide_starts_at_atan_mu_and_is_fitted_back() {
        let rate = 4f64.to_radians();
        let t: Vec<f64> = (0..300).map(|k| k as f64 / 60.0).collect();
        let theta: Vec<f64> = t.iter().map(|t| rate * t).collect();
        let (g, mu) = (9.81, 0.3);
        let x = simulate(&t, &theta, g, mu, mu);
        let onset = mu.atan() / rate;
        for (ti, xi) in t.iter().zip(&x) {
            if *ti < onset - 0.02 {
                assert_eq!(*xi, 0.0, "moved at {ti} before the onset {onset}");
            }
        }
        // Just after the onset: x ≈ g (1 + μ²) cos θ₀ rate τ³ / 6 (the drive grows linearly).
        let tau = 0.5;
        let k = t.iter().position(|&ti| ti >= onset + tau).unwrap();
        let tau = t[k] - onset;
        let expected = g * (1.0 + mu * mu) * mu.atan().cos() * rate * tau.powi(3) / 6.0;
        assert!(
            (x[k] - expected).abs() < 0.03 * expected,
            "{} vs {expected}",
            x[k]
        );
        let sse = |m: f64| -> f64 {
            simulate(&t, &theta, g, m, m)
                .iter()
                .zip(&x)
                .map(|(a, b)| (a - b).powi(2))
                .sum()
        };
        // Searched up to the steepest slope's tangent (beyond it nothing moves: the sum of
        // squares is flat there), as `measure` does.
        let fitted = golden_min(&sse, 0.0, theta[theta.len() - 1].tan(), 1e-8);
        assert!((fitted - mu).abs() < 1e-5, "{fitted}");
    }

    /// Levelled again, the object stops and stays: the slope below atan μ holds it.
    #[test]
    fn a_slide_stops_when_the_palm_is_levelled() {
        let t: Vec<f64> = (0..600).map(|k| k as f64 / 60.0).collect();
        let up = 0.4f64;
        let theta: Vec<f64> = t
            .iter()
            .map(|&t| {
                if t < 5.0 {
                    up * t / 5.0
                } else {
                    (up - (t - 5.0)).max(0.0)
                }
            })
            .collect();
        let x = simulate(&t, &theta, 9.81, 0.3, 0.25);
        let last = *x.last().unwrap();
        assert!(last > 0.0);
        let k = t.iter().position(|&ti| ti >= 6.0).unwrap();
        assert!(x[k..].iter().all(|&xi| xi == last));
    }
}
