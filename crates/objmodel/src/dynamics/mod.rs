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
mod fall;
mod palm_slide;
mod palm_stream;
mod regression;
mod series;
mod support;
mod tolerances;

use crate::classify::{Classification, Label};
use crate::noise::NoiseModel;
use crate::pendulum::{FallFit, Onset};
use crate::recording::Recording;
use budget::Budget;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

pub use palm_slide::{measure as palm_slide, PalmSlide};
pub use series::AngleSeries;
pub use tolerances::{
    LANDING_RAD, MAX_REST_FRAMES, ONSET_REST_S, ONSET_WINDOW_RAD, PENDULUM_TOLERANCE_RAD,
    PHI_PRIOR_SIGMA_RAD, REST_MARGIN_S, SMOOTH_S, SUPPORT_FIT_RAD,
};

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

/// Analyse the dynamics of every topple of `c` (the classification of the demonstration whose
/// frames `recording` kept), with gravity `gravity` in the tracking frame.
pub fn analyse(
    recording: &Recording,
    c: &Classification,
    gravity: &Vector3<f64>,
) -> Vec<ToppleDynamics> {
    let up = -gravity.normalize();
    let noise = c.noise.unwrap_or(NoiseModel::FALLBACK);
    let sigma = noise.sigma_rotation;
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
    let palm = palm_stream::without_glitches(&recording.palm, noise);
    let palm = (!palm.is_empty()).then_some(&palm[..]);
    let mut out = Vec::new();
    for (ti, top) in c.topples.iter().enumerate() {
        let Some(n) = top.resting_normal_before else {
            continue;
        };
        let u = top.edge.line.direction;
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
        let palm_ref = palm
            .and_then(|palm| series::palm_reference(palm, frames, &outlier, first_moving, &n, &u));
        let (series, idx) = series::angles(frames, &outlier, palm_ref.as_ref(), &u, &n, &up);
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
        let first_pivot = (0..idx.len())
            .find(|&k| in_topple(idx[k]))
            .unwrap_or(last_pivot);
        // The palm's start that led to this topple comes after the topple before it (a
        // recording may hold several, the object put back on the palm between them).
        let after = c.topples[..ti]
            .iter()
            .flat_map(|t| t.segments.iter().map(|&i| c.segments[i].t_end))
            .fold(f64::NEG_INFINITY, f64::max);
        let palm_onset = support::onset(&series, first_moving, after, sigma, &budget);
        let (onset_r, phi_onset, phi_onset_sigma) =
            (palm_onset.onset, palm_onset.phi, palm_onset.phi_sigma);
        let fall = fall::fit(
            &series,
            first_pivot,
            last_pivot,
            onset_r,
            phi_onset,
            sigma,
            &budget,
        );
        let on_support = support::on_support(
            &series,
            first_moving,
            last_pivot,
            &palm_onset,
            sigma,
            &budget,
        );
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
