//! An instrumented topple on its tilting palm: where the object starts to turn relative to the
//! palm (the onset, and the palm's tilt there: the paper's φ), and the pendulum on the tilting
//! palm fitted to the onset and the early fall jointly. Both read φ off the palm, so both carry
//! how far the object lags the palm: measured where the palm starts to tilt
//! ([`lag_variance`]).

use super::budget::Budget;
use super::regression::{linear_at, slope, smooth};
use super::series::AngleSeries;
use super::tolerances::{
    passes_with, MIN_ONSET_FRAMES, ONSET_REST_S, ONSET_WINDOW_RAD, PALM_SETTLE_S, PALM_START_RAD,
    PENDULUM_TOLERANCE_RAD, SMOOTH_S, SUPPORT_FIT_RAD,
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

/// The mean of `v` (NaN when empty).
fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

/// What the palm tells of a topple's start: the onset relative to the palm, the palm's tilt
/// there (the paper's φ) with its standard deviation, and what the pendulum on the palm takes
/// from the same window.
pub(super) struct PalmOnset {
    /// The onset (`None` without a palm, or where the onset model finds none).
    pub onset: Option<Onset>,
    /// The palm's tilt at the onset \[rad\].
    pub phi: Option<f64>,
    /// Its standard deviation \[rad\].
    pub phi_sigma: Option<f64>,
    /// The onset window's first sample ([`onset_window`]).
    window_start: usize,
    /// The variance \[rad²\] the object's lag behind the palm adds to a φ read off the palm
    /// ([`lag_variance`]; 0 where the palm's start or the onset is not seen).
    lag: f64,
}

/// The onset relative to the palm and the palm's tilt there ([`PalmOnset`]); `first_moving`
/// the time of the motion's first frame, `after` \[s\] a time the palm's start (see
/// [`onset_window`]) comes after, `sigma` the rotation noise.
pub(super) fn onset(
    series: &AngleSeries,
    first_moving: f64,
    after: f64,
    sigma: f64,
    budget: &Budget,
) -> PalmOnset {
    let mut out = PalmOnset {
        onset: None,
        phi: None,
        phi_sigma: None,
        window_start: 0,
        lag: 0.0,
    };
    if series.palm.is_empty() {
        return out;
    }
    let rel = relative(series);
    let n = series.t.len();
    let OnsetWindow { start, end, palm } = onset_window(series, &rel, first_moving, after, sigma);
    out.window_start = start;
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
        return out;
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
    // The object's lag behind the palm, measured where the palm starts: the same contact (or
    // latency) that delays its start delays the onset's.
    out.lag = palm.map_or(0.0, |p| {
        lag_variance(series, &rel, p.rest, start, o.t, sigma)
    });
    out.onset = Some(o);
    if let Some((v, se, slope)) = palm_near(o.t) {
        // The balance angle of a real contact (a compliant support, an edge that is not
        // perfectly sharp) departs from the ideal one by about the pendulum's tolerance, which
        // the fits take per sample; here it is one offset of the whole onset.
        let var = se * se
            + (slope * o.sigma_t).powi(2)
            + budget.resting_normal()
            + budget.palm_reference()
            + PENDULUM_TOLERANCE_RAD.powi(2)
            + out.lag;
        out.phi = Some(v);
        out.phi_sigma = Some(var.sqrt());
    }
    out
}

/// The samples the onset is sought in, `start..end`, and where the palm starts to tilt after
/// a rest, if it does before `end`.
struct OnsetWindow {
    start: usize,
    end: usize,
    palm: Option<PalmStart>,
}

/// Where the palm starts to tilt ([`palm_start`]).
struct PalmStart {
    /// The first sample off the palm's rest.
    at: usize,
    /// The rest's samples, up to [`PALM_SETTLE_S`] before `at`.
    rest: std::ops::Range<usize>,
}

/// From [`ONSET_REST_S`] before the motion's first frame (`first_moving`) to where the object
/// has turned [`ONSET_WINDOW_RAD`] off the palm (`rel`). Where the palm starts to tilt after a
/// rest ([`palm_start`]), the object lags it by a step (a compliant contact, or a latency
/// between the trackers) that the onset model, flat and then rising, cannot follow, and the
/// rest before is not the steady tilt whose rate the model takes: the window then starts
/// [`PALM_SETTLE_S`] after the palm's start, where that is later and leaves samples to fit.
/// The palm's start is sought from the first sample after `after` \[s\] (the end of the
/// topple before, if any).
fn onset_window(
    series: &AngleSeries,
    rel: &[f64],
    first_moving: f64,
    after: f64,
    sigma: f64,
) -> OnsetWindow {
    let n = series.t.len();
    let start = series
        .t
        .partition_point(|&t| t < first_moving - ONSET_REST_S);
    let end = (start..n)
        .find(|&k| series.t[k] > first_moving && rel[k].abs() > ONSET_WINDOW_RAD)
        .unwrap_or(n);
    let from = series.t.partition_point(|&t| t <= after);
    let palm = palm_start(series, from, end, sigma / std::f64::consts::SQRT_2);
    let start = palm
        .as_ref()
        .map(|p| {
            series
                .t
                .partition_point(|&t| t < series.t[p.at] + PALM_SETTLE_S)
        })
        .filter(|&s| s > start && end >= s + 2 * MIN_ONSET_FRAMES)
        .unwrap_or(start);
    OnsetWindow { start, end, palm }
}

/// The first sample of `series` in `from..end` where the palm has left the tilt it had at
/// `from` by more than its noise allows (5 σ of one sample, `palm_sigma`, and at least
/// [`PALM_START_RAD`]), after a rest: `None` where it does not leave it, or where it was
/// already tilting (its samples up to [`PALM_SETTLE_S`] before show a slope, 3 σ from zero:
/// a slow tilt stays within the threshold for a while), or where that rest has fewer than
/// [`MIN_ONSET_FRAMES`] samples.
fn palm_start(series: &AngleSeries, from: usize, end: usize, palm_sigma: f64) -> Option<PalmStart> {
    let (t, palm) = (&series.t, &series.palm);
    let threshold = (5.0 * palm_sigma).max(PALM_START_RAD);
    let k = (from..end).find(|&k| (palm[k] - palm[from]).abs() > threshold)?;
    let rest = from..from + t[from..k].partition_point(|&x| x <= t[k] - PALM_SETTLE_S);
    if rest.len() < MIN_ONSET_FRAMES {
        return None;
    }
    let (rate, rate_sigma) = slope(&t[rest.clone()], &palm[rest.clone()], palm_sigma)?;
    (rate.abs() <= 3.0 * rate_sigma).then_some(PalmStart { at: k, rest })
}

/// The variance \[rad²\] that the object's lag behind a palm starting to tilt adds to φ at the
/// onset: the mean of the angle relative to the palm (`rel`) over the steady tilt (from
/// `steady`, the window's start, to the onset at `onset_t`) less its mean over the palm's
/// rest before it started (`rest`, [`PalmStart::rest`]), squared, less that difference's own
/// noise variance (`sigma` per sample) so that a lag hidden in the noise adds nothing on
/// average; 0 where either part has fewer than [`MIN_ONSET_FRAMES`] samples.
///
/// A tracker latency `d` between palm and object shifts the angle relative to the palm by
/// `β̇ d` while the palm tilts, and the palm's tilt read at the onset by the same; a compliant
/// contact lags the palm's start and leans before the onset (MuJoCo's soft box on a palm
/// tilting at 4-24°/s: steps of 0.4-0.9°, onsets 0.1-0.9° late; rapier's rigid contact: none).
fn lag_variance(
    series: &AngleSeries,
    rel: &[f64],
    rest: std::ops::Range<usize>,
    steady: usize,
    onset_t: f64,
    sigma: f64,
) -> f64 {
    let rest = &rel[rest];
    let steady: Vec<f64> = (steady..rel.len())
        .take_while(|&k| series.t[k] < onset_t)
        .map(|k| rel[k])
        .collect();
    if rest.len() < MIN_ONSET_FRAMES || steady.len() < MIN_ONSET_FRAMES {
        return 0.0;
    }
    let d = mean(&steady) - mean(rest);
    let noise = sigma * sigma * (1.0 / rest.len() as f64 + 1.0 / steady.len() as f64);
    (d * d - noise).max(0.0)
}

/// The pendulum on the tilting palm, fitted to the rotation relative to the palm from the
/// onset's window (from the rest before `first_moving`, or from the palm's steady tilt: see
/// [`onset_window`]) to the end of the pivot (`last_pivot`), against the smoothed tilt; `None`
/// without a palm or when the fit fails its χ² test. Its φ, like the onset's, carries the
/// object's lag behind the palm ([`lag_variance`]).
pub(super) fn on_support(
    series: &AngleSeries,
    first_moving: f64,
    last_pivot: usize,
    palm: &PalmOnset,
    sigma: f64,
    budget: &Budget,
) -> Option<FallFit> {
    if series.palm.is_empty() {
        return None;
    }
    let start = palm.window_start;
    if start > last_pivot {
        return None; // No frame between the rest and the pivot's end.
    }
    let rel = relative(series);
    // The model's zero is the object at rest on the palm: the mean of the angle relative to the
    // palm before the onset (one sample put its noise into every θ).
    let before: Vec<f64> = (start..=last_pivot)
        .take_while(|&k| palm.onset.is_some_and(|o| series.t[k] < o.t))
        .map(|k| rel[k])
        .collect();
    let base = if before.len() >= MIN_ONSET_FRAMES {
        mean(&before)
    } else {
        rel[start]
    };
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
        pendulum::fit_on_support(tt, &theta, beta, sigma_rel, palm.phi.unwrap_or(beta[0]))
            .filter(|f| passes_with(f, 2))?;
    // φ is the palm's tilt where the object starts to turn: its offsets (see `budget`) are one
    // value for every sample.
    let at = palm.onset.map_or(first_moving, |o| o.t);
    fit.phi_sigma = (fit.phi_sigma.powi(2) + budget.palm_tilt_at(&series.t, at) + palm.lag).sqrt();
    Some(fit)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{rngs::StdRng, SeedableRng};
    use rand_distr::{Distribution, Normal};

    /// 100 Hz for 3 s: the palm at rest until `palm_from` \[s\], then tilting at 0.2 rad/s.
    fn palm_series(palm_from: f64) -> AngleSeries {
        let t: Vec<f64> = (0..300).map(|k| k as f64 / 100.0).collect();
        let palm = t.iter().map(|&x| 0.2 * (x - palm_from).max(0.0)).collect();
        AngleSeries {
            object: vec![0.0; t.len()],
            t,
            palm,
        }
    }

    /// A palm that starts from rest is found where it first leaves the rest by the threshold;
    /// one that tilts from the first sample on, or starts too soon to show a rest, is not.
    #[test]
    fn a_palm_start_is_found_after_a_rest_only() {
        let s = palm_series(1.0);
        let k = palm_start(&s, 0, s.t.len(), 1e-4)
            .expect("the palm starts at 1 s")
            .at;
        // The threshold (0.2°) is crossed 17.5 ms after the start, at the next sample.
        assert!((s.t[k] - 1.02).abs() < 1e-9, "{}", s.t[k]);
        assert!(palm_start(&palm_series(0.0), 0, 300, 1e-4).is_none());
        assert!(palm_start(&palm_series(-1.0), 0, 300, 1e-4).is_none());
        // 0.1 s of rest: fewer than MIN_ONSET_FRAMES samples before the settling time.
        assert!(palm_start(&palm_series(0.1), 0, 300, 1e-4).is_none());
        // Noisier than the whole tilt before the window's end: no start.
        assert!(palm_start(&s, 0, 110, 0.01).is_none());
    }

    /// A recording with two tilts (the palm tilts at 0.5 s, rests from 0.8 s, tilts again at
    /// 1.6 s): sought after the first topple's end, the start is the second tilt's.
    #[test]
    fn the_palm_start_is_sought_after_the_topple_before() {
        let t: Vec<f64> = (0..300).map(|k| k as f64 / 100.0).collect();
        let palm = t
            .iter()
            .map(|&x| 0.2 * ((x.min(0.8) - 0.5).max(0.0) + (x - 1.6).max(0.0)))
            .collect();
        let s = AngleSeries {
            object: vec![0.0; t.len()],
            t,
            palm,
        };
        let k = palm_start(&s, 0, 300, 1e-4).unwrap().at;
        assert!((s.t[k] - 0.52).abs() < 1e-9, "{}", s.t[k]);
        let from = s.t.partition_point(|&x| x <= 0.9);
        let k = palm_start(&s, from, 300, 1e-4).unwrap().at;
        assert!((s.t[k] - 1.62).abs() < 1e-9, "{}", s.t[k]);
    }

    /// The lag variance is the step's square where the angle relative to the palm steps when
    /// the palm starts (exact samples), and close to nothing where it does not: the noise's
    /// own share is taken off, so over many noisy series without a step its mean stays a
    /// fraction of the difference's noise variance, while a step of 3 of those σ is measured
    /// within 20%.
    #[test]
    fn the_lag_is_the_step_at_the_palm_start_less_its_noise() {
        let s = palm_series(1.0);
        let palm = palm_start(&s, 0, s.t.len(), 1e-4).unwrap();
        let k = palm.at;
        let steady = s.t.partition_point(|&t| t < s.t[k] + PALM_SETTLE_S);
        let onset_t = 2.5;
        let step =
            |d: f64| -> Vec<f64> { s.t.iter().map(|&t| if t > 1.0 { d } else { 0.0 }).collect() };
        let exact = lag_variance(&s, &step(0.01), palm.rest.clone(), steady, onset_t, 1e-6);
        assert!((exact - 1e-4).abs() < 1e-9, "{exact}");
        let sigma = 0.005;
        let n_rest = s.t.iter().filter(|&&t| t <= s.t[k] - PALM_SETTLE_S).count();
        assert_eq!(palm.rest, 0..n_rest);
        let n_steady = (steady..s.t.len())
            .take_while(|&i| s.t[i] < onset_t)
            .count();
        let var_d = sigma * sigma * (1.0 / n_rest as f64 + 1.0 / n_steady as f64);
        let noise = Normal::new(0.0, sigma).unwrap();
        let mean_over = |d: f64| {
            let mut rng = StdRng::seed_from_u64(5);
            (0..400)
                .map(|_| {
                    let rel: Vec<f64> =
                        step(d).iter().map(|x| x + noise.sample(&mut rng)).collect();
                    lag_variance(&s, &rel, palm.rest.clone(), steady, onset_t, sigma)
                })
                .sum::<f64>()
                / 400.0
        };
        let none = mean_over(0.0);
        assert!(none < 0.5 * var_d, "no step: {none} against {var_d}");
        let d = 3.0 * var_d.sqrt();
        let some = mean_over(d);
        assert!(
            (some / (d * d) - 1.0).abs() < 0.2,
            "{some} against {}",
            d * d
        );
    }
}
