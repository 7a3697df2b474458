//! Dynamic models from a classified demonstration: for each topple, the tilt angles over time,
//! the topple onset, φ and the pendulum fit ([`crate::pendulum`]).
//!
//! Angles are measured about the learnt edge, from the vertical, in the plane normal to the
//! edge: ψ_obj(t) is the angle between "up" (against gravity) and the inward normal of the face
//! the object rested on, as the object carries it; for an instrumented demonstration ψ_palm(t)
//! is the same angle for that face carried rigidly by the palm (the palm's tilt), and their
//! difference is the object's rotation relative to the palm. Resting on a level support both
//! are 0; the object balances over its edge at ψ = φ.

mod budget;
mod palm_stream;

use crate::classify::{Classification, Label};
use crate::geometry::angle_about;
use crate::pendulum::{self, FallFit, Onset};
use crate::recording::Recording;
use crate::trajectory::StampedPose;
use budget::Budget;
use nalgebra::{UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

/// Largest relative rotation \[rad\] (15°) kept in the onset window: enough of the start of the
/// topple to fix the change-point model, before the fall stops being polynomial.
pub const ONSET_WINDOW_RAD: f64 = 0.26;
/// Rest before the first moving frame \[s\] included in the onset window.
pub const ONSET_REST_S: f64 = 2.0;
/// Relative rotation \[rad\] (8.6°) up to which the pendulum-on-palm model is fitted (the palm
/// may move fast after that, and the object may leave its edge).
pub const SUPPORT_FIT_RAD: f64 = 0.15;
/// Model tolerance \[rad\] of the pendulum (0.1°), added in quadrature to the tracking noise when
/// fitting a fall: contacts are compliant and edges not perfectly sharp, so a real fall
/// departs from the ideal pendulum by about this much.
pub const PENDULUM_TOLERANCE_RAD: f64 = 0.001_745_329_251_994_329_5;
/// Frames within this angle \[rad\] (2°) of where the object comes to rest are the landing, not
/// the fall.
pub const LANDING_RAD: f64 = 0.034_906_585_039_886_59;
/// Rest frames closer than this \[s\] to the first moving frame are not used as the reference.
pub const REST_MARGIN_S: f64 = 0.3;
/// At most this many rest frames are averaged for the reference.
pub const MAX_REST_FRAMES: usize = 60;
/// Half-width \[s\] of the local linear smoothing of the palm tilt.
pub const SMOOTH_S: f64 = 0.25;
/// Standard deviation \[rad\] of φ uniform on its admissible range (0, π/2) for an object
/// resting on a face: `π / (2√12)` ≈ 0.45 rad. A model fit whose φ is less certain than that
/// tells less than the bounds themselves (a fall of a few frames leaves φ and `k` trading off
/// against the unknown start state); its φ is not used.
pub const PHI_PRIOR_SIGMA_RAD: f64 = std::f64::consts::FRAC_PI_2 / 3.464_101_615_137_754_6;

/// Local linear regression smoothing of `y(t)` with half-width `h` \[s\].
fn smooth(t: &[f64], y: &[f64], h: f64) -> Vec<f64> {
    (0..t.len())
        .map(|i| {
            let lo = t.partition_point(|&x| x < t[i] - h);
            let hi = t.partition_point(|&x| x <= t[i] + h);
            linear_at(&t[lo..hi], &y[lo..hi], t[i], 0.0).map_or(y[i], |r| r.0)
        })
        .collect()
}

/// Angles of one topple over time, for analysis and plots.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct AngleSeries {
    /// Times \[s\].
    pub t: Vec<f64>,
    /// ψ_obj \[rad\].
    pub object: Vec<f64>,
    /// ψ_palm \[rad\] (instrumented), empty otherwise.
    pub palm: Vec<f64>,
}

/// The dynamics of one topple.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ToppleDynamics {
    /// Index of the topple in [`Classification::topples`].
    pub topple: usize,
    /// Outward normal (object frame) of the face the object rested on.
    pub resting_face_normal: Vector3<f64>,
    /// Topple onset relative to the palm (instrumented).
    pub onset: Option<Onset>,
    /// φ as the palm's tilt at the onset (instrumented; the paper's method) \[rad\].
    pub phi_onset: Option<f64>,
    /// Its standard deviation \[rad\].
    pub phi_onset_sigma: Option<f64>,
    /// The pendulum on the tilting palm fitted to the onset and early fall jointly
    /// (instrumented): its φ is the palm tilt at which the object starts to turn.
    pub on_support: Option<FallFit>,
    /// The pendulum fitted to the fall.
    pub fall: Option<FallFit>,
    /// The best φ \[rad\]: from the onset when instrumented, else from the fall.
    pub phi: Option<f64>,
    /// Its standard deviation \[rad\].
    pub phi_sigma: Option<f64>,
    /// The angles.
    pub series: AngleSeries,
}

/// Unwrap an angle series in place (no jumps of more than π between samples).
fn unwrap(v: &mut [f64]) {
    for i in 1..v.len() {
        let d = v[i] - v[i - 1];
        v[i] -= (d / std::f64::consts::TAU).round() * std::f64::consts::TAU;
    }
}

/// The palm orientation at time `t` (slerp between the palm samples around it).
fn palm_at(palm: &[StampedPose], t: f64) -> Option<UnitQuaternion<f64>> {
    let i = palm.partition_point(|p| p.t < t);
    if i < palm.len() && (palm[i].t - t).abs() < 1e-9 {
        return Some(palm[i].pose.rotation);
    }
    if i == 0 || i >= palm.len() {
        return None;
    }
    let (a, b) = (&palm[i - 1], &palm[i]);
    Some(
        a.pose
            .rotation
            .slerp(&b.pose.rotation, (t - a.t) / (b.t - a.t)),
    )
}

/// Least-squares line through (t, y) evaluated at `at`, with its standard error for per-sample
/// noise `sigma`.
fn linear_at(t: &[f64], y: &[f64], at: f64, sigma: f64) -> Option<(f64, f64, f64)> {
    let n = t.len() as f64;
    if n < 2.0 {
        return None;
    }
    let tm = t.iter().sum::<f64>() / n;
    let ym = y.iter().sum::<f64>() / n;
    let stt: f64 = t.iter().map(|x| (x - tm).powi(2)).sum();
    let sty: f64 = t.iter().zip(y).map(|(a, b)| (a - tm) * (b - ym)).sum();
    let slope = if stt > 0.0 { sty / stt } else { 0.0 };
    let value = ym + slope * (at - tm);
    let se = sigma
        * (1.0 / n
            + if stt > 0.0 {
                (at - tm).powi(2) / stt
            } else {
                0.0
            })
        .sqrt();
    Some((value, se, slope))
}

/// Whether a pendulum fit with `params` parameters explains its frames within the noise: its
/// χ² passes at the 1% level (a fall or an onset that is not a free pendulum teaches no φ).
fn passes_with(f: &pendulum::FallFit, params: usize) -> bool {
    let dof = f.frames as f64 - params as f64;
    dof > 0.0 && f.chi2_per_dof <= crate::stats::chi2_threshold(dof, 0.01) / dof
}

/// Analyse the dynamics of every topple of `c` (the classification of the demonstration whose
/// frames `recording` kept), with gravity `gravity` in the tracking frame.
pub fn analyse(
    recording: &Recording,
    c: &Classification,
    gravity: &Vector3<f64>,
) -> Vec<ToppleDynamics> {
    let up = -gravity.normalize();
    let sigma = c.noise.map_or(0.01, |n| n.sigma_rotation);
    let frames = &recording.object;
    // Frames the classifier rejected as outliers, and the topple-labelled frames, per kept frame.
    let mut outlier = vec![false; frames.len()];
    let mut topple_label = vec![None; frames.len()];
    for r in &c.labels {
        let lo = frames.partition_point(|f| f.index < r.first as u64);
        let hi = frames.partition_point(|f| f.index <= r.last as u64);
        for k in lo..hi {
            match r.label {
                Label::Outlier => outlier[k] = true,
                Label::Topple => topple_label[k] = r.segment,
                _ => {}
            }
        }
    }
    let palm = palm_stream::without_flips(&recording.palm, sigma);
    let palm = (!palm.is_empty()).then_some(&palm);
    let mut out = Vec::new();
    for (ti, top) in c.topples.iter().enumerate() {
        let Some(n) = top.resting_normal_before else {
            continue;
        };
        let u = top.edge.line.direction;
        // The face normal and edge in the palm frame, averaged over the rest before the motion
        // (one frame would put its orientation noise into every tilt angle).
        let first_moving = c.segments[top.segments[0]].t_start;
        let budget = Budget {
            sigma_object: sigma,
            sigma_palm: sigma,
            reference_frames: frames
                .iter()
                .enumerate()
                .filter(|(i, f)| !outlier[*i] && f.t < first_moving - REST_MARGIN_S)
                .take(MAX_REST_FRAMES)
                .count(),
        };
        let palm_ref = palm.and_then(|palm| {
            let (mut n_sum, mut u_sum) = (Vector3::zeros(), Vector3::zeros());
            let rest = frames
                .iter()
                .enumerate()
                .filter(|(i, f)| !outlier[*i] && f.t < first_moving - REST_MARGIN_S);
            for (_, f) in rest.take(MAX_REST_FRAMES) {
                if let Some(qp) = palm_at(palm, f.t) {
                    let palm_from_object = qp.inverse() * f.rotation;
                    n_sum += palm_from_object * n;
                    u_sum += palm_from_object * u;
                }
            }
            if n_sum == Vector3::zeros() {
                let first = frames.iter().enumerate().find(|(i, _)| !outlier[*i])?.1;
                let qp = palm_at(palm, first.t)?;
                let palm_from_object = qp.inverse() * first.rotation;
                return Some((palm, palm_from_object * n, palm_from_object * u));
            }
            Some((palm, n_sum.normalize(), u_sum.normalize()))
        });
        let mut series = AngleSeries::default();
        let mut idx = Vec::new();
        for (i, p) in frames.iter().enumerate() {
            if outlier[i] {
                continue;
            }
            let r = p.rotation;
            let obj = angle_about(&(r * u), &up, &(r * -n));
            let palm = match &palm_ref {
                Some((palm, n_p, u_p)) => match palm_at(palm, p.t) {
                    Some(qp) => Some(angle_about(&(qp * u_p), &up, &(qp * -n_p))),
                    None => continue,
                },
                None => None,
            };
            series.t.push(p.t);
            series.object.push(obj);
            series.palm.extend(palm);
            idx.push(i);
        }
        unwrap(&mut series.object);
        unwrap(&mut series.palm);
        let in_topple = |i: usize| topple_label[i].is_some_and(|s| top.segments.contains(&s));
        let Some(last_labelled) = (0..idx.len()).rev().find(|&k| in_topple(idx[k])) else {
            continue;
        };
        // The fall ends where the object lands: drop the frames within LANDING_RAD of the final
        // angle (the impact stops the pendulum; the windowed labels may still include it).
        let final_angle = series.object[last_labelled];
        let last_pivot = (0..=last_labelled)
            .rev()
            .find(|&k| (series.object[k] - final_angle).abs() > LANDING_RAD)
            .unwrap_or(last_labelled);

        // Onset and φ from the palm (instrumented).
        let (mut onset_r, mut phi_onset, mut phi_onset_sigma) = (None, None, None);
        if !series.palm.is_empty() {
            let rel: Vec<f64> = series
                .object
                .iter()
                .zip(&series.palm)
                .map(|(a, b)| a - b)
                .collect();
            let start = series
                .t
                .partition_point(|&t| t < first_moving - ONSET_REST_S);
            let end = (start..idx.len())
                .find(|&k| series.t[k] > first_moving && rel[k].abs() > ONSET_WINDOW_RAD)
                .unwrap_or(idx.len());
            let base = rel[start];
            let w: Vec<f64> = rel[start..end].iter().map(|x| (x - base).abs()).collect();
            if let Some(o) = pendulum::onset(&series.t[start..end], &w, sigma) {
                let near: Vec<usize> = (0..idx.len())
                    .filter(|&k| (series.t[k] - o.t).abs() <= 0.3)
                    .collect();
                let tt: Vec<f64> = near.iter().map(|&k| series.t[k]).collect();
                let yy: Vec<f64> = near.iter().map(|&k| series.palm[k]).collect();
                let palm_sigma = sigma / std::f64::consts::SQRT_2;
                if let Some((v, se, slope)) = linear_at(&tt, &yy, o.t, palm_sigma) {
                    phi_onset = Some(v);
                    phi_onset_sigma = Some(
                        (se * se
                            + (slope * o.sigma_t).powi(2)
                            + budget.resting_normal()
                            + budget.palm_reference())
                        .sqrt(),
                    );
                }
                onset_r = Some(o);
            }
        }

        // The fall: from the onset (instrumented) or the earliest start consistent with a free
        // pendulum (direct: before it, the pusher drives the object), to the last pivot frame.
        let sigma_fit = (sigma * sigma + PENDULUM_TOLERANCE_RAD * PENDULUM_TOLERANCE_RAD).sqrt();
        let fit_from = |k0: usize, phi0: f64| {
            pendulum::fit_fall(
                &series.t[k0..=last_pivot],
                &series.object[k0..=last_pivot],
                sigma_fit,
                phi0,
            )
        };
        // A fall that is not a free pendulum within the noise teaches no φ.
        let passes = |f: &pendulum::FallFit| passes_with(f, 4);
        let fall = match onset_r {
            Some(o) => {
                let k0 = series.t.partition_point(|&t| t < o.t);
                (k0 + 6 <= last_pivot)
                    .then(|| fit_from(k0, phi_onset.unwrap_or(series.object[k0])))
                    .flatten()
                    .filter(passes)
            }
            None => {
                let first_pivot = (0..idx.len())
                    .find(|&k| in_topple(idx[k]))
                    .unwrap_or(last_pivot);
                // Scanning the start back from the end of the pivot: the earliest start whose fit
                // passes the χ² test and lies past that fit's own balance point (ψ >= φ). Before
                // balance a pusher may still be driving the object at a steady rate, and a free
                // pendulum fitted through those frames lowers φ (by 0.6° on exact rapier pushes,
                // 3° at 1 mm / 0.5° noise; in MuJoCo 19 of 20 low); past it the object falls
                // away from the pusher.
                let mut best = None;
                let mut k0 = last_pivot.saturating_sub(6);
                while k0 >= first_pivot && k0 + 6 <= last_pivot {
                    match fit_from(k0, series.object[k0]) {
                        Some(f) if passes(&f) && best.is_some() && series.object[k0] < f.phi => {
                            break
                        }
                        Some(f) if passes(&f) => best = Some(f),
                        _ if best.is_some() => break,
                        _ => {}
                    }
                    if k0 == 0 {
                        break;
                    }
                    k0 -= 1;
                }
                best
            }
        };
        // Its φ's sigma as the data show it (the jackknife; see `pendulum::jackknife`), and
        // the resting normal's error that is common to every sample (see `budget`).
        let fall = fall.map(|f| {
            let k0 = series.t.partition_point(|&t| t < f.t_start);
            let mut f = pendulum::jackknife_fall(
                &series.t[k0..=last_pivot],
                &series.object[k0..=last_pivot],
                f,
            );
            f.phi_sigma = (f.phi_sigma.powi(2) + budget.resting_normal()).sqrt();
            f
        });
        // Instrumented: the pendulum on the tilting palm, fitted to the rotation relative to
        // the palm from the rest before to the end of the pivot, against the smoothed tilt.
        let on_support = (!series.palm.is_empty())
            .then(|| {
                let start = series
                    .t
                    .partition_point(|&t| t < first_moving - ONSET_REST_S);
                if start > last_pivot {
                    return None; // No frame between the rest and the pivot's end.
                }
                let rel: Vec<f64> = series
                    .object
                    .iter()
                    .zip(&series.palm)
                    .map(|(a, b)| a - b)
                    .collect();
                let base = rel[start];
                let end = (start..=last_pivot)
                    .find(|&k| {
                        series.t[k] > first_moving && (rel[k] - base).abs() > SUPPORT_FIT_RAD
                    })
                    .unwrap_or(last_pivot);
                let tt = &series.t[start..=end];
                let theta: Vec<f64> = rel[start..=end].iter().map(|x| x - base).collect();
                let beta = smooth(&series.t, &series.palm, SMOOTH_S);
                let beta = &beta[start..=end];
                // θ is the object's angle less the palm's (each with noise σ), against the
                // pendulum's tolerance; like the fall, the fit must pass its χ² test.
                let sigma_rel = (2.0 * sigma * sigma + PENDULUM_TOLERANCE_RAD.powi(2)).sqrt();
                let mut fit = pendulum::fit_on_support(
                    tt,
                    &theta,
                    beta,
                    sigma_rel,
                    phi_onset.unwrap_or(beta[0]),
                )
                .filter(|f| passes_with(f, 2))?;
                // φ is the palm's tilt where the object starts to turn: its offsets (see
                // `budget`) are one value for every sample.
                let at = onset_r.map_or(first_moving, |o| o.t);
                fit.phi_sigma = (fit.phi_sigma.powi(2) + budget.palm_tilt_at(&series.t, at)).sqrt();
                Some(fit)
            })
            .flatten();
        // The best φ: the inverse-variance weighted mean of the model fits that exist and
        // determine φ better than its bounds do (the pendulum on the palm and the free fall),
        // else the palm tilt at the onset. Both fits share the resting normal's offset (see
        // `budget`), which averaging does not reduce; and fits that disagree beyond their
        // sigmas widen the mean's by the Birge ratio √(χ²/(N-1)).
        let fits: Vec<(f64, f64)> = [on_support, fall]
            .iter()
            .flatten()
            .filter(|f| f.phi_sigma > 0.0 && f.phi_sigma < PHI_PRIOR_SIGMA_RAD)
            .map(|f| (f.phi, f.phi_sigma))
            .collect();
        let (phi, phi_sigma) = if !fits.is_empty() {
            let common = budget.resting_normal();
            let var = |s: f64| (s * s - common).max(s * s * 1e-6);
            let w: f64 = fits.iter().map(|(_, s)| 1.0 / var(*s)).sum();
            let mean = fits.iter().map(|(p, s)| p / var(*s)).sum::<f64>() / w;
            let chi2: f64 = fits.iter().map(|(p, s)| (p - mean).powi(2) / var(*s)).sum();
            let birge = if fits.len() > 1 {
                (chi2 / (fits.len() - 1) as f64).max(1.0)
            } else {
                1.0
            };
            (Some(mean), Some((birge / w + common).sqrt()))
        } else {
            (phi_onset, phi_onset_sigma)
        };
        out.push(ToppleDynamics {
            topple: ti,
            resting_face_normal: n,
            onset: onset_r,
            phi_onset,
            phi_onset_sigma,
            on_support,
            fall,
            phi,
            phi_sigma,
            series,
        });
    }
    out
}
