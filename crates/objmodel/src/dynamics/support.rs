//! An instrumented topple on its tilting palm: where the object starts to turn relative to the
//! palm (the onset, and the palm's tilt there: the paper's φ), and the pendulum on the tilting
//! palm fitted to the onset and the early fall jointly.

use super::budget::Budget;
use super::regression::{linear_at, slope, smooth};
use super::series::AngleSeries;
use super::tolerances::{
    passes_with, ONSET_REST_S, ONSET_WINDOW_RAD, PENDULUM_TOLERANCE_RAD, SMOOTH_S, SUPPORT_FIT_RAD,
};
use crate::pendulum::{self, FallFit, Onset};

/// The object's angle relative to the palm's at every sample.
fn relative(series: &AngleSeries) -> Vec<f64> {
    series
        .object
        .iter()
        .zip(&series.palm)
        .map(|(a, b)| a - b)
        .collect()
}

/// The onset relative to the palm, and the palm's tilt there with its standard deviation
/// (`None`s without a palm or an onset); `first_moving` the time of the motion's first frame,
/// `sigma` the rotation noise.
pub(super) fn onset(
    series: &AngleSeries,
    first_moving: f64,
    sigma: f64,
    budget: &Budget,
) -> (Option<Onset>, Option<f64>, Option<f64>) {
    if series.palm.is_empty() {
        return (None, None, None);
    }
    let rel = relative(series);
    let n = series.t.len();
    let start = series
        .t
        .partition_point(|&t| t < first_moving - ONSET_REST_S);
    let end = (start..n)
        .find(|&k| series.t[k] > first_moving && rel[k].abs() > ONSET_WINDOW_RAD)
        .unwrap_or(n);
    let base = rel[start];
    // The rotation from the rest, signed the way the object turns off the palm. Its absolute
    // value folded the rest's noise into a plateau above zero (0.8 σ on average), which the
    // onset model, flat and then rising, can only follow by starting its rise late: the
    // palm's tilt there was 0.1-0.6° high at motion-capture noise (up to 14 σ), 0.4° at
    // camera noise.
    let turn = if rel[end.min(n - 1)] < base {
        -1.0
    } else {
        1.0
    };
    let w: Vec<f64> = rel[start..end].iter().map(|x| (x - base) * turn).collect();
    let Some(free) = pendulum::onset(&series.t[start..end], &w, sigma) else {
        return (None, None, None);
    };
    let palm_sigma = sigma / std::f64::consts::SQRT_2;
    // The palm's tilt at `at` by a straight line through its samples within 0.3 s: the tilt,
    // its standard deviation and the tilt rate.
    let palm_near = |at: f64| {
        let near: Vec<usize> = (0..n)
            .filter(|&k| (series.t[k] - at).abs() <= 0.3)
            .collect();
        let tt: Vec<f64> = near.iter().map(|&k| series.t[k]).collect();
        let yy: Vec<f64> = near.iter().map(|&k| series.palm[k]).collect();
        linear_at(&tt, &yy, at, palm_sigma)
    };
    // The onset again with its amplitude fixed at the palm's tilt rate, which the linearised
    // motion on a support tilting at a constant rate makes it (`pendulum::onset_at_rate`).
    // Free, the amplitude trades against the onset's time: a slow rise from an early start
    // took in a drift of the rest and put the onset up to 2 s early at camera noise (φ 3-7°
    // low). The rate is the palm's over the whole window fitted, as the model has it, and
    // used only when measured (3 σ from zero): a palm that does not tilt has none to fix.
    let window = &series.t[start..end];
    let o = slope(window, &series.palm[start..end], palm_sigma)
        .filter(|&(rate, rate_sigma)| rate.abs() > 3.0 * rate_sigma)
        .and_then(|(rate, _)| pendulum::onset_at_rate(window, &w, sigma, Some(rate.abs())))
        .unwrap_or(free);
    match palm_near(o.t) {
        Some((v, se, slope)) => {
            // The balance angle of a real contact (a compliant support, an edge that is not
            // perfectly sharp) departs from the ideal one by about the pendulum's tolerance,
            // which the fits take per sample; here it is one offset of the whole onset.
            let s = (se * se
                + (slope * o.sigma_t).powi(2)
                + budget.resting_normal()
                + budget.palm_reference()
                + PENDULUM_TOLERANCE_RAD.powi(2))
            .sqrt();
            (Some(o), Some(v), Some(s))
        }
        None => (Some(o), None, None),
    }
}

/// The pendulum on the tilting palm, fitted to the rotation relative to the palm from the rest
/// before (`first_moving`) to the end of the pivot (`last_pivot`), against the smoothed tilt;
/// `None` without a palm or when the fit fails its χ² test.
pub(super) fn on_support(
    series: &AngleSeries,
    first_moving: f64,
    last_pivot: usize,
    onset: Option<Onset>,
    phi_onset: Option<f64>,
    sigma: f64,
    budget: &Budget,
) -> Option<FallFit> {
    if series.palm.is_empty() {
        return None;
    }
    let start = series
        .t
        .partition_point(|&t| t < first_moving - ONSET_REST_S);
    if start > last_pivot {
        return None; // No frame between the rest and the pivot's end.
    }
    let rel = relative(series);
    let base = rel[start];
    let end = (start..=last_pivot)
        .find(|&k| series.t[k] > first_moving && (rel[k] - base).abs() > SUPPORT_FIT_RAD)
        .unwrap_or(last_pivot);
    let tt = &series.t[start..=end];
    let theta: Vec<f64> = rel[start..=end].iter().map(|x| x - base).collect();
    let beta = smooth(&series.t, &series.palm, SMOOTH_S);
    let beta = &beta[start..=end];
    // θ is the object's angle less the palm's (each with noise σ), against the pendulum's
    // tolerance; like the fall, the fit must pass its χ² test.
    let sigma_rel = (2.0 * sigma * sigma + PENDULUM_TOLERANCE_RAD.powi(2)).sqrt();
    let mut fit =
        pendulum::fit_on_support(tt, &theta, beta, sigma_rel, phi_onset.unwrap_or(beta[0]))
            .filter(|f| passes_with(f, 2))?;
    // φ is the palm's tilt where the object starts to turn: its offsets (see `budget`) are one
    // value for every sample.
    let at = onset.map_or(first_moving, |o| o.t);
    fit.phi_sigma = (fit.phi_sigma.powi(2) + budget.palm_tilt_at(&series.t, at)).sqrt();
    Some(fit)
}
