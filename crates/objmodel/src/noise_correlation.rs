//! Tracking noise that is correlated from frame to frame, and its long-run size.
//!
//! A tracker that filters its poses (a camera tracking a tag usually does) gives noise whose
//! consecutive frames are correlated. [`crate::noise::estimate`] measures the noise from
//! differences of neighbouring frames, which a filter smooths away, while every statistic over
//! many frames (an edge fitted to a topple, a rest's mean, a change point) varies as white
//! noise of the *long-run* σ, `σ √((1+ρ)/(1−ρ))` for first-order autoregressive noise of
//! marginal σ and lag-one correlation ρ: at ρ 0.5 that is 2.7 times the differences' estimate,
//! and the tests, too strict by that much, split rests into motions and taught edges 8 mm off
//! with a σ of 1 mm.
//!
//! The correlation is measured where the frames hold noise and little else: in windows of
//! [`WINDOW`] consecutive frames, each axis's residuals about a quadratic in time (which takes
//! out a rest's drift, a palm's tilt, a flight's parabola) have a lag-one autocorrelation that
//! depends on ρ alone, `R(ρ)` (negative for white noise: the fit takes out the low
//! frequencies). Windows whose residuals are more than twice the quieter quarter's (an impact,
//! a tag flip, a jerk) are left out; the kept windows' statistic is pooled over the six axes
//! (position and rotation each normalised by its own scale), its standard error is the
//! jackknife's over windows, and ρ is `R⁻¹` of it. A slow creep is a low frequency too, and
//! the quadratic takes it out: the creep of a box down a tilting palm (MuJoCo, 0.3 mm noise)
//! measures ρ ≈ 0, as white noise does. The windows resolve ρ up to [`MAX_RHO`]; beyond, ρ is
//! said to be at least that.

use crate::noise::{NoiseModel, PoseSample};
use crate::se3::so3_log;
use nalgebra::SMatrix;
use serde::{Deserialize, Serialize};

/// Frames per window.
pub const WINDOW: usize = 10;
/// Fewest kept windows for a measurement: 40 frames, which a 30 Hz topple of 3 s holds
/// between its motions (with 6, 13 of the camera set's short topples measured nothing, were
/// tested as white noise, and taught nothing). The learner uses the point estimate; with so
/// few windows [`Correlation::significant`]'s t quantile is large.
pub const MIN_WINDOWS: usize = 4;
/// How many times the quieter quarter's residual scale a window may have and be kept.
const QUIET_FACTOR: f64 = 2.0;
/// Two consecutive frames this many times the stream's median spacing apart, or more, have a
/// frame missing between them (half-way between one spacing and two). The lags are counted in
/// frames, not in time: a filtering tracker correlates consecutive *outputs*, and a camera's
/// stamps jitter (a driver stamps a frame when it arrives: ±25% of a 30 Hz camera's spacing
/// is common) while its frames stay one apart. Until 2026-12-06 a window was kept only where
/// its largest spacing was below 1.5 times its smallest, which a stamp jitter of ±25% fails in
/// nearly every window: the correlation went unmeasured, the tests took the noise as
/// independent, too strict by the long-run factor, and the camera data set with jittered
/// stamps taught 9 edges and 3 faces off the box among its palm topples.
pub const GAP: f64 = 1.5;
/// The largest correlation the windows resolve: the quadratic takes out the low frequencies
/// that tell stronger correlations apart, and `R(ρ)` flattens (−0.036 at 0.7, −0.008 at
/// 0.98, within the statistic's usual standard error of 0.03-0.05), while the long-run σ
/// grows without bound (4 times the independent estimate at 0.7, 66 times at 0.98). A
/// statistic beyond `R(MAX_RHO)` is taken as `MAX_RHO`, and said to be at least that.
pub const MAX_RHO: f64 = 0.7;

type Square = SMatrix<f64, WINDOW, WINDOW>;

/// The correlation of a tracker's noise between consecutive frames, measured.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Correlation {
    /// Lag-one correlation ρ of the noise (first-order autoregressive model), at most
    /// [`MAX_RHO`].
    pub rho: f64,
    /// Whether the statistic was beyond what [`MAX_RHO`] gives: ρ is at least that.
    pub at_least: bool,
    /// Standard error of the pooled statistic that measured it, in its own units.
    pub statistic_se: f64,
    /// How many standard errors the statistic lies above white noise's.
    pub z: f64,
    /// Windows it was measured on.
    pub windows: usize,
    /// The long-run per-axis noise, `σ √((1+ρ)/(1−ρ))`, σ the marginal noise at this ρ.
    pub long_run: NoiseModel,
    /// The per-axis noise the same windows give taken as independent (ρ = 0).
    pub white: NoiseModel,
}

/// The correlated noise of a demonstration's trackers, where the object's is: the learner
/// then tests with the long-run noise of each.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct TrackerCorrelations {
    /// The object's tracker.
    pub object: Correlation,
    /// The palm's tracker, where its own frames are correlated too.
    pub palm: Option<Correlation>,
}

impl Correlation {
    /// Whether the noise is correlated beyond the statistic's sampling error (the learner does
    /// not ask this: `learn::tracker_noise` uses the measured ρ as it is): one-sided at
    /// `alpha`, against Student's t with one fewer degree of freedom than windows, since the
    /// jackknife's standard error is itself estimated from the windows. (Against the normal
    /// quantile, 3.09 at 10⁻³, 120 files of independent noise with motion came close: z = 3.0
    /// with 14 windows, where t's quantile is 3.85.)
    pub fn significant(&self, alpha: f64) -> bool {
        self.rho > 0.0
            && self.z > crate::stats::student_t_quantile(1.0 - alpha, self.windows as f64 - 1.0)
    }

    /// Whether the correlation is beyond what the windows resolve, beyond their sampling error:
    /// the statistic above `R(MAX_RHO)` one-sided at `alpha` (Student's t, as
    /// [`Correlation::significant`]). The long-run σ is then unknown, and larger than
    /// [`Correlation::long_run`] by any factor: frames that a logger interpolates between a
    /// slower tracker's poses (ROS `tf` looked up at 100 Hz over a 30 Hz camera) are such, and
    /// tested with the capped σ a camera data set so resampled taught edges 7.5 mm off the box
    /// and faces 10 mm off. (A tracker's own filter at ρ 0.95 lies within the windows' error of
    /// `R(MAX_RHO)` at 150 frames: capped, not beyond.)
    pub fn beyond_resolution(&self, alpha: f64) -> bool {
        if !self.at_least || self.statistic_se <= 0.0 {
            return false;
        }
        let m = residual_maker();
        let statistic = expected_statistic(&m, 0.0) + self.z * self.statistic_se;
        let beyond = (statistic - expected_statistic(&m, MAX_RHO)) / self.statistic_se;
        beyond > crate::stats::student_t_quantile(1.0 - alpha, self.windows as f64 - 1.0)
    }

    /// Whether the long-run noise exceeds the noise the same windows give as independent by
    /// more than `tolerance` (position \[m\], rotation \[rad\]) in quadrature, in position or
    /// rotation: what a test that adds `tolerance` to the noise would notice. Exact poses
    /// (the contacts' micro-motion is smooth, so correlated) give the floor for both.
    pub fn matters(&self, tolerance: (f64, f64)) -> bool {
        let exceeds =
            |long_run: f64, white: f64, tol: f64| long_run * long_run - white * white > tol * tol;
        exceeds(
            self.long_run.sigma_position,
            self.white.sigma_position,
            tolerance.0,
        ) || exceeds(
            self.long_run.sigma_rotation,
            self.white.sigma_rotation,
            tolerance.1,
        )
    }
}

/// The residual maker of a quadratic in the frame count on [`WINDOW`] consecutive frames (in
/// time, where the frames are evenly spaced):
/// `I − X (XᵀX)⁻¹ Xᵀ`.
fn residual_maker() -> Square {
    let x = SMatrix::<f64, WINDOW, 3>::from_fn(|i, j| {
        (i as f64 - (WINDOW as f64 - 1.0) / 2.0).powi(j as i32)
    });
    let xtx = (x.transpose() * x)
        .try_inverse()
        .expect("a quadratic on distinct times is determined");
    Square::identity() - x * xtx * x.transpose()
}

/// `M Γ(ρ) M` for the residual maker `M` and the correlation matrix `Γ(ρ)_ij = ρ^|i−j|`.
fn residual_covariance(m: &Square, rho: f64) -> Square {
    let gamma = Square::from_fn(|i, j| rho.powi((i as i32 - j as i32).abs()));
    m * gamma * m
}

/// The expected pooled lag-one autocorrelation of the residuals, `R(ρ)`, as the ratio of
/// expectations (what the pooled statistic estimates).
fn expected_statistic(m: &Square, rho: f64) -> f64 {
    let c = residual_covariance(m, rho);
    (0..WINDOW - 1).map(|i| c[(i, i + 1)]).sum::<f64>() / c.trace()
}

/// `R⁻¹(r)` by bisection on ρ in [−0.9, 0.98] (R increases with ρ).
fn rho_of(m: &Square, r: f64) -> f64 {
    crate::stats::invert_increasing(|rho| expected_statistic(m, rho), r, (-0.9, 0.98), 60)
}

/// One window's sums per axis (rotation x, y, z, position x, y, z): of the residuals'
/// lag-one products and of their squares.
#[derive(Clone, Copy, Debug, PartialEq)]
struct WindowSums {
    lagged: [f64; 6],
    squares: [f64; 6],
}

impl WindowSums {
    fn scale(&self, group: usize) -> f64 {
        self.squares[3 * group..3 * group + 3]
            .iter()
            .sum::<f64>()
            .sqrt()
    }
}

/// The window's sums, or `None` where a frame is missing from it (a dropped frame breaks the
/// lags): two consecutive stamps `max_dt` \[s\] or more apart, or not increasing.
fn window_sums(m: &Square, w: &[PoseSample], max_dt: f64) -> Option<WindowSums> {
    if !w.windows(2).all(|p| {
        let dt = p[1].0 - p[0].0;
        dt > 0.0 && dt < max_dt
    }) {
        return None;
    }
    let centre = w[WINDOW / 2].1;
    let mut x = SMatrix::<f64, WINDOW, 6>::zeros();
    for (i, (_, q, p)) in w.iter().enumerate() {
        let r = so3_log(&(centre.inverse() * q));
        for j in 0..3 {
            x[(i, j)] = r[j];
            x[(i, 3 + j)] = p[j];
        }
    }
    let res = m * x;
    let mut sums = WindowSums {
        lagged: [0.0; 6],
        squares: [0.0; 6],
    };
    for j in 0..6 {
        let c = res.column(j);
        sums.squares[j] = c.dot(&c);
        sums.lagged[j] = (0..WINDOW - 1).map(|i| c[i] * c[i + 1]).sum();
    }
    Some(sums)
}

/// The lower quartile of `xs` (non-empty).
fn lower_quartile(xs: &[f64]) -> f64 {
    let mut v = xs.to_vec();
    v.sort_by(f64::total_cmp);
    v[(v.len() - 1) / 4]
}

/// Measure the noise's correlation from consecutive samples (time, orientation, position)
/// of one tracker. `None` with fewer than [`MIN_WINDOWS`] quiet windows without a missing
/// frame ([`GAP`]), or without noise (exact poses).
pub fn measure(samples: &[PoseSample]) -> Option<Correlation> {
    measure_pooled([&NoiseWindows::of(samples)])
}

/// The windows of one tracker's stream that [`measure`] measures on: every [`WINDOW`]
/// consecutive frames without a missing frame ([`GAP`]), as sums of their residuals. Several
/// streams of one tracker pool theirs ([`measure_pooled`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NoiseWindows(Vec<WindowSums>);

impl NoiseWindows {
    /// The windows of consecutive samples (time, orientation, position) of one tracker, from
    /// its first frame on.
    pub fn of(samples: &[PoseSample]) -> Self {
        let m = residual_maker();
        Self(windows(&m, samples, false))
    }

    /// The windows of a tracker's rests (runs of consecutive samples of an object at rest),
    /// each rest's counted back from its last frame: a rest's first frames, right after its
    /// object arrived, hold its settling (98 simulated tosses at 1 mm, 0.5° of white noise:
    /// counted from the rests' first frames, their windows measured a lag-one correlation of
    /// 0.09 and 1.12 mm, 0.54° as independent; from their last, 1.03 mm, 0.50°, no
    /// correlation).
    pub fn of_rests<'a>(rests: impl IntoIterator<Item = &'a [PoseSample]>) -> Self {
        let m = residual_maker();
        Self(
            rests
                .into_iter()
                .flat_map(|r| windows(&m, r, true))
                .collect(),
        )
    }

    /// How many windows.
    pub fn len(&self) -> usize {
        self.0.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// At most `n` of the windows, evenly spread over the stream (every k-th).
    pub fn thinned(self, n: usize) -> Self {
        let k = self.0.len().div_ceil(n.max(1)).max(1);
        Self(self.0.into_iter().step_by(k).collect())
    }
}

/// The sums of the windows of [`WINDOW`] consecutive samples without a missing frame
/// ([`GAP`]), from the first sample on or back from the last.
fn windows(m: &Square, samples: &[PoseSample], from_end: bool) -> Vec<WindowSums> {
    let mut spacings: Vec<f64> = samples
        .windows(2)
        .map(|p| p[1].0 - p[0].0)
        .filter(|dt| *dt > 0.0)
        .collect();
    let Some(median) = crate::stats::median(&mut spacings) else {
        return Vec::new();
    };
    let sums = |w| window_sums(m, w, GAP * median);
    if from_end {
        samples.rchunks_exact(WINDOW).filter_map(sums).collect()
    } else {
        samples.chunks_exact(WINDOW).filter_map(sums).collect()
    }
}

/// [`measure`] on the windows of several streams of one tracker together: its quiet windows
/// are those of all of them.
pub fn measure_pooled<'a>(
    streams: impl IntoIterator<Item = &'a NoiseWindows>,
) -> Option<Correlation> {
    let m = residual_maker();
    let all: Vec<WindowSums> = streams
        .into_iter()
        .flat_map(|w| w.0.iter().copied())
        .collect();
    if all.len() < MIN_WINDOWS {
        return None;
    }
    let limits: Vec<f64> = (0..2)
        .map(|g| QUIET_FACTOR * lower_quartile(&all.iter().map(|s| s.scale(g)).collect::<Vec<_>>()))
        .collect();
    let kept: Vec<&WindowSums> = all
        .iter()
        .filter(|s| (0..2).all(|g| s.scale(g) <= limits[g]))
        .collect();
    if kept.len() < MIN_WINDOWS {
        return None;
    }
    // Each group (rotation, position) normalised by its total, so that metres and radians
    // pool; a group without noise (exact poses) does not count.
    let totals: Vec<f64> = (0..2)
        .map(|g| kept.iter().map(|s| s.scale(g).powi(2)).sum::<f64>())
        .collect();
    let weight = |g: usize| {
        if totals[g] > 0.0 {
            1.0 / totals[g]
        } else {
            0.0
        }
    };
    if weight(0) == 0.0 && weight(1) == 0.0 {
        return None;
    }
    let contributions: Vec<(f64, f64)> = kept
        .iter()
        .map(|s| {
            (0..6).fold((0.0, 0.0), |(n, d), j| {
                let w = weight(j / 3);
                (n + w * s.lagged[j], d + w * s.squares[j])
            })
        })
        .collect();
    let (num, den) = contributions
        .iter()
        .fold((0.0, 0.0), |(a, b), c| (a + c.0, b + c.1));
    let statistic = num / den;
    // Jackknife over windows.
    let n = contributions.len() as f64;
    let leave_one_out: Vec<f64> = contributions
        .iter()
        .map(|c| (num - c.0) / (den - c.1))
        .collect();
    let mean = leave_one_out.iter().sum::<f64>() / n;
    let se = ((n - 1.0) / n
        * leave_one_out
            .iter()
            .map(|v| (v - mean).powi(2))
            .sum::<f64>())
    .sqrt();
    let rho = rho_of(&m, statistic).clamp(0.0, MAX_RHO);
    let at_least = statistic > expected_statistic(&m, MAX_RHO);
    // Marginal per-axis variance: each axis's residual squares hold σ² tr(M Γ(ρ) M).
    let marginal =
        |g: usize, rho: f64| (totals[g] / (3.0 * n * residual_covariance(&m, rho).trace())).sqrt();
    let inflation = ((1.0 + rho) / (1.0 - rho)).sqrt();
    let long_run = |g: usize| marginal(g, rho) * inflation;
    Some(Correlation {
        rho,
        at_least,
        statistic_se: se,
        z: if se > 0.0 {
            (statistic - expected_statistic(&m, 0.0)) / se
        } else {
            0.0
        },
        windows: kept.len(),
        long_run: NoiseModel {
            sigma_rotation: long_run(0),
            sigma_position: long_run(1),
        }
        .floored(),
        white: NoiseModel {
            sigma_rotation: marginal(0, 0.0),
            sigma_position: marginal(1, 0.0),
        }
        .floored(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{UnitQuaternion, Vector3};
    use rand::{rngs::StdRng, SeedableRng};
    use rand_distr::{Distribution, Normal};

    /// `n` frames at 30 Hz of a box at rest (or turning at `omega` rad/s about z, drifting at
    /// `v` m/s along x), with AR(1) noise of marginal σ (1 mm, 0.5°) and correlation `rho`.
    fn frames(n: usize, rho: f64, omega: f64, v: f64, seed: u64) -> Vec<PoseSample> {
        let mut rng = StdRng::seed_from_u64(seed);
        let unit = Normal::new(0.0, 1.0).unwrap();
        let (sp, sr) = (1e-3, 0.5f64.to_radians());
        let innovation = (1.0 - rho * rho).sqrt();
        let mut e = [0.0; 6];
        for x in &mut e {
            *x = unit.sample(&mut rng);
        }
        (0..n)
            .map(|k| {
                for x in &mut e {
                    *x = rho * *x + innovation * unit.sample(&mut rng);
                }
                let t = k as f64 / 30.0;
                let q = UnitQuaternion::from_scaled_axis(Vector3::z() * omega * t)
                    * UnitQuaternion::from_scaled_axis(Vector3::new(e[0], e[1], e[2]) * sr);
                let p = Vector3::new(0.1 + v * t, 0.2, 0.05) + Vector3::new(e[3], e[4], e[5]) * sp;
                (t, q, p)
            })
            .collect()
    }

    #[test]
    fn white_noise_is_not_correlated() {
        let mut false_alarms = 0;
        let mut rhos = vec![];
        for seed in 0..200 {
            let c = measure(&frames(150, 0.0, 0.0, 0.0, seed)).unwrap();
            rhos.push(c.rho);
            false_alarms += c.significant(1e-2) as usize;
        }
        // At alpha 1%: on 200 white demonstrations, about 2 false alarms (Poisson, 99.9%: <= 8).
        assert!(false_alarms <= 8, "{false_alarms} of 200");
        let median = crate::stats::median(&mut rhos).unwrap();
        assert!(median < 0.05, "median rho {median}");
    }

    #[test]
    fn correlated_noise_is_found_with_its_long_run_sigma() {
        for rho in [0.3, 0.5, 0.7] {
            let (mut found, mut rhos, mut ratios) = (0, vec![], vec![]);
            for seed in 0..100 {
                let c = measure(&frames(150, rho, 0.0, 0.0, 100 + seed)).unwrap();
                found += c.significant(1e-3) as usize;
                rhos.push(c.rho);
                let truth = 1e-3 * ((1.0 + rho) / (1.0 - rho)).sqrt();
                ratios.push(c.long_run.sigma_position / truth);
            }
            let rho_hat = crate::stats::median(&mut rhos).unwrap();
            let ratio = crate::stats::median(&mut ratios).unwrap();
            assert!((rho_hat - rho).abs() < 0.08, "rho {rho}: median {rho_hat}");
            assert!(
                (ratio - 1.0).abs() < 0.15,
                "rho {rho}: long-run ratio {ratio}"
            );
            if rho >= 0.5 {
                assert!(found >= 90, "rho {rho}: found in {found} of 100");
            }
        }
    }

    #[test]
    fn a_correlation_beyond_what_windows_resolve_is_capped() {
        // At 0.95 the windows cannot tell it from 0.7: rho is taken as MAX_RHO, said to be
        // "at least", and the long-run sigma is not blown up by the flat end of R.
        let (mut capped, mut ratios) = (0, vec![]);
        for seed in 0..50 {
            let c = measure(&frames(150, 0.95, 0.0, 0.0, 500 + seed)).unwrap();
            assert!(c.rho <= MAX_RHO);
            capped += c.at_least as usize;
            ratios.push(c.long_run.sigma_position / c.white.sigma_position);
        }
        assert!(capped >= 25, "{capped} of 50 at the cap");
        let worst = ratios.iter().cloned().fold(0.0, f64::max);
        assert!(worst < 4.5, "long-run / independent up to {worst}");
    }

    #[test]
    fn smooth_motion_and_a_drift_are_not_correlation() {
        let mut alarms = 0;
        for seed in 0..100 {
            // A turn at 30 deg/s and a slide at 2 cm/s, white noise.
            let c = measure(&frames(150, 0.0, 0.5, 0.02, 300 + seed)).unwrap();
            alarms += c.significant(1e-3) as usize;
        }
        assert!(alarms <= 3, "{alarms} of 100");
    }

    #[test]
    fn the_statistic_of_white_noise_is_the_fits_negative_correlation() {
        let m = residual_maker();
        // The residual maker is a projection, and the inverse recovers rho.
        assert!(((m * m) - m).norm() < 1e-12);
        for rho in [0.0, 0.3, 0.6, 0.9] {
            let r = expected_statistic(&m, rho);
            assert!((rho_of(&m, r) - rho).abs() < 1e-9);
        }
        assert!(expected_statistic(&m, 0.0) < -0.2);
    }

    #[test]
    fn a_smooth_micro_motion_is_correlated_but_does_not_matter() {
        // Exact poses of a box whose contact complies by micrometres (a slow wobble): its
        // residuals are strongly correlated, but long-run and independent noise are both at
        // the floors, far within the model tolerance.
        let base = Vector3::new(0.1, 0.2, 0.05);
        let wobble: Vec<PoseSample> = frames(200, 0.9, 0.0, 0.0, 4)
            .into_iter()
            .map(|(t, q, p)| {
                (
                    t,
                    UnitQuaternion::from_scaled_axis(q.scaled_axis() * 1e-3),
                    base + (p - base) * 1e-3,
                )
            })
            .collect();
        let c = measure(&wobble).unwrap();
        assert!(c.rho > 0.5, "{c:?}");
        assert!(!c.matters((3e-4, 0.5f64.to_radians())), "{c:?}");
        // Correlated camera noise does matter.
        let camera = measure(&frames(150, 0.5, 0.0, 0.0, 5)).unwrap();
        assert!(camera.matters((3e-4, 0.5f64.to_radians())), "{camera:?}");
    }

    #[test]
    fn interpolated_frames_are_beyond_resolution_a_filter_is_not() {
        // A 30 Hz tracker's poses, looked up at 100 Hz by linear interpolation (as ROS tf
        // does): beyond what the windows resolve. AR(1) noise at 0.95, at the cap: not beyond.
        let (mut beyond, mut filtered) = (0, 0);
        for seed in 0..50 {
            let slow = frames(60, 0.0, 0.0, 0.0, 1000 + seed);
            let mut fast = vec![];
            let mut t = 0.0;
            while t < slow[slow.len() - 1].0 {
                let k = slow.iter().rposition(|s| s.0 <= t).unwrap();
                let (a, b) = (&slow[k], &slow[k + 1]);
                let s = (t - a.0) / (b.0 - a.0);
                fast.push((t, a.1.slerp(&b.1, s), a.2 * (1.0 - s) + b.2 * s));
                t += 0.01;
            }
            let c = measure(&fast).unwrap();
            beyond += c.beyond_resolution(1e-3) as usize;
            let f = measure(&frames(150, 0.95, 0.0, 0.0, 1100 + seed)).unwrap();
            filtered += f.beyond_resolution(1e-3) as usize;
        }
        assert!(beyond >= 48, "interpolated: beyond in {beyond} of 50");
        assert!(filtered <= 2, "AR(0.95): beyond in {filtered} of 50");
    }

    #[test]
    fn jittered_stamps_still_measure_the_correlation() {
        // A camera driver's stamps, each moved by up to a quarter of the spacing (order kept):
        // the frames are still one apart, and the correlation is measured as without jitter.
        let (mut found, mut rhos) = (0, vec![]);
        for seed in 0..100 {
            let mut rng = StdRng::seed_from_u64(900 + seed);
            let jitter = rand_distr::Uniform::new(-0.25 / 30.0, 0.25 / 30.0).unwrap();
            let f: Vec<PoseSample> = frames(150, 0.5, 0.0, 0.0, 700 + seed)
                .into_iter()
                .map(|(t, q, p)| (t + jitter.sample(&mut rng), q, p))
                .collect();
            let c = measure(&f).expect("jittered windows are measured");
            found += c.significant(1e-3) as usize;
            rhos.push(c.rho);
        }
        let rho_hat = crate::stats::median(&mut rhos).unwrap();
        assert!((rho_hat - 0.5).abs() < 0.08, "median {rho_hat}");
        assert!(found >= 90, "found in {found} of 100");
    }

    #[test]
    fn a_window_with_a_dropped_frame_is_left_out() {
        // Every tenth frame dropped: each window of ten kept frames spans a missing one.
        let f: Vec<PoseSample> = frames(200, 0.5, 0.0, 0.0, 6)
            .into_iter()
            .enumerate()
            .filter(|(k, _)| k % 10 != 5)
            .map(|(_, s)| s)
            .collect();
        assert!(measure(&f).is_none());
        // The same frames with none dropped are measured.
        assert!(measure(&frames(200, 0.5, 0.0, 0.0, 6)).is_some());
    }

    #[test]
    fn too_few_frames_or_exact_poses_measure_nothing() {
        assert!(measure(&frames(39, 0.5, 0.0, 0.0, 1)).is_none());
        assert!(measure(&frames(40, 0.5, 0.0, 0.0, 1)).is_some());
        let exact: Vec<PoseSample> = (0..100)
            .map(|k| {
                (
                    k as f64 / 30.0,
                    UnitQuaternion::identity(),
                    Vector3::zeros(),
                )
            })
            .collect();
        assert!(measure(&exact).is_none());
    }
}
