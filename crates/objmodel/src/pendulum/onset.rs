//! The onset of a topple: the instant a body at rest starts to turn, by two-phase regression
//! (a change-point model) on its rotation, constant before τ and the linearised toppling
//! motion after (see [`onset`]). For an instrumented demonstration the palm's tilt at τ is φ
//! (the paper's method).

use super::solve;
use serde::{Deserialize, Serialize};

/// A detected topple onset.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Onset {
    /// Onset time \[s\].
    pub t: f64,
    /// Standard deviation of the onset time \[s\].
    pub sigma_t: f64,
    /// χ² per degree of freedom of the two-phase fit.
    pub chi2_per_dof: f64,
}

/// Shape of the rotation after the onset, `s = t - τ` \[s\]: linearising the equation of motion
/// about the balance point, with the support still tilting at a constant rate, gives
/// `θ̈ = ω² (θ + β̇ s)`, whose solution from rest is `θ = β̇ (sinh(ω s)/ω - s)`: cubic at
/// first (`β̇ ω² s³/6`), then exponential. `ω = sqrt(k)` \[rad/s\].
fn onset_shape(s: f64, omega: f64) -> f64 {
    if s <= 0.0 {
        0.0
    } else {
        let x = omega * s;
        if x < 1e-3 {
            omega * omega * s * s * s / 6.0
        } else {
            x.sinh() / omega - s
        }
    }
}

/// Residual sum of squares of the two-phase model with the change at `tau`:
/// `θ = θ₀` for t < τ, `θ = θ₀ + A·shape(t - τ, ω)` after; θ₀ and A by linear least squares,
/// or θ₀ alone with `A = rate` when the rate is given.
fn two_phase_sse(t: &[f64], theta: &[f64], tau: f64, omega: f64, rate: Option<f64>) -> Option<f64> {
    if let Some(rate) = rate {
        // The amplitude known: θ₀ alone by least squares.
        let model = |ti: f64| rate * onset_shape(ti - tau, omega);
        let th0 = t
            .iter()
            .zip(theta)
            .map(|(&ti, &yi)| yi - model(ti))
            .sum::<f64>()
            / t.len() as f64;
        return Some(
            t.iter()
                .zip(theta)
                .map(|(&ti, &yi)| (yi - th0 - model(ti)).powi(2))
                .sum(),
        );
    }
    let mut a = [[0.0; 4]; 4];
    let mut b = [0.0; 4];
    for (&ti, &yi) in t.iter().zip(theta) {
        let x = [1.0, onset_shape(ti - tau, omega), 0.0, 0.0];
        for i in 0..2 {
            b[i] += x[i] * yi;
            for j in 0..2 {
                a[i][j] += x[i] * x[j];
            }
        }
    }
    let c = solve(&a, &b, 2)?;
    Some(
        t.iter()
            .zip(theta)
            .map(|(&ti, &yi)| {
                let r = yi - (c[0] + c[1] * onset_shape(ti - tau, omega));
                r * r
            })
            .sum(),
    )
}

/// Rates ω \[rad/s\] tried by the onset model: boxes of a few cm to half a metre.
const ONSET_OMEGAS: [f64; 10] = [2.0, 3.0, 4.5, 6.0, 8.0, 10.0, 13.0, 17.0, 22.0, 30.0];

/// The onset of rotation in `theta(t)` \[rad\], a series that is constant (at rest) and then
/// grows, with per-sample noise `sigma` \[rad\]. The series should run from some rest before the
/// onset to a moderate angle after it (the caller cuts it, e.g. at 15°). `None` if too short.
pub fn onset(t: &[f64], theta: &[f64], sigma: f64) -> Option<Onset> {
    onset_at_rate(t, theta, sigma, None)
}

/// [`onset`] with the amplitude `A` known: in the linearised motion it is the support's tilt
/// rate `β̇` \[rad/s\] (`rate`), and with it fixed the onset's time is no longer traded
/// against the amplitude: a slow rise from an early start, of an amplitude far below the
/// tilt rate, cannot take in a drift of the rest before the onset.
pub fn onset_at_rate(t: &[f64], theta: &[f64], sigma: f64, rate: Option<f64>) -> Option<Onset> {
    let n = t.len();
    if n < 6 || theta.len() != n {
        return None;
    }
    // Grid over [t_1, t_{n-3}] at a tenth of the median frame interval.
    let dt = {
        let mut d: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
        crate::stats::median(&mut d)?
    };
    let (lo, hi) = (t[1], t[n - 3]);
    let step = dt / 10.0;
    let mut best = (f64::INFINITY, lo);
    let mut profile = Vec::new();
    let mut tau = lo;
    while tau <= hi {
        // Profile over ω: the best shape for this τ, on the grid and then between its
        // neighbours (log ω by golden section). The grid alone cannot follow ω as τ moves,
        // so the profile rose too fast away from its minimum and σ_τ came out too small.
        let sse_at = |w: f64| two_phase_sse(t, theta, tau, w, rate).unwrap_or(f64::INFINITY);
        let grid: Vec<f64> = ONSET_OMEGAS.iter().map(|&w| sse_at(w)).collect();
        let i = (0..grid.len()).fold(0, |b, i| if grid[i] < grid[b] { i } else { b });
        let (a, b) = (
            ONSET_OMEGAS[i.saturating_sub(1)],
            ONSET_OMEGAS[(i + 1).min(grid.len() - 1)],
        );
        let log_w = crate::stats::golden_min(&|x: f64| sse_at(x.exp()), a.ln(), b.ln(), 1e-3);
        let s = grid[i].min(sse_at(log_w.exp()));
        if s.is_finite() {
            profile.push((tau, s));
            if s < best.0 {
                best = (s, tau);
            }
        }
        tau += step;
    }
    let (sse, tau) = best;
    if !sse.is_finite() {
        return None;
    }
    // The profile likelihood's spread about the best τ: weights exp(-Δχ²/2) over the grid.
    // Near the onset the rise is cubic, so the likelihood is far from Gaussian in τ (a long
    // tail towards the late side, where the rise is still below the noise), and the interval
    // where Δχ² <= 1 covered the truth half the time, not 68%.
    let var = sigma * sigma;
    let (mut w_sum, mut w_dev) = (0.0, 0.0);
    for &(t, s) in &profile {
        let w = (-(s - sse) / var / 2.0).exp();
        w_sum += w;
        w_dev += w * (t - tau).powi(2);
    }
    let spread = (w_dev / w_sum).sqrt();
    Some(Onset {
        t: tau,
        sigma_t: spread.max(step / 12f64.sqrt()),
        // θ₀, A, τ, ω fitted; A not when the rate is given.
        chi2_per_dof: sse / var / (n as f64 - if rate.is_some() { 3.0 } else { 4.0 }),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn onset_of_a_toppling_start_is_found_to_a_fraction_of_a_frame() {
        let tau = 1.2345;
        let t: Vec<f64> = (0..90).map(|k| k as f64 / 30.0).collect();
        let theta: Vec<f64> = t.iter().map(|&x| 0.1 * onset_shape(x - tau, 8.0)).collect();
        let o = onset(&t, &theta, 1e-4).unwrap();
        assert!((o.t - tau).abs() < 0.01, "{o:?}");
    }

    /// With the amplitude fixed at the tilt rate that generated it, the onset's time is
    /// unbiased and its σ honest: over many noisy onsets of a box tilted at 0.15 rad/s,
    /// mean error/σ near 0 and rms near 1; and the error no larger than the free fit's.
    #[test]
    fn onset_at_the_tilt_rate_is_unbiased_with_an_honest_sigma() {
        use rand::{rngs::StdRng, SeedableRng};
        use rand_distr::{Distribution, Normal};
        let (tau, omega, rate, sigma) = (1.0123, 8.0, 0.15, 5e-3);
        let noise = Normal::new(0.0, sigma).unwrap();
        // From a second of rest to 15° past the onset, as the caller cuts it.
        let t: Vec<f64> = (0..)
            .map(|k| k as f64 / 30.0)
            .take_while(|&x| rate * onset_shape(x - tau, omega) < 0.26)
            .collect();
        let (mut z_rate, mut err_rate, mut err_free) = (Vec::new(), Vec::new(), Vec::new());
        for seed in 0..200 {
            let mut rng = StdRng::seed_from_u64(seed);
            let theta: Vec<f64> = t
                .iter()
                .map(|&x| rate * onset_shape(x - tau, omega) + noise.sample(&mut rng))
                .collect();
            let o = onset_at_rate(&t, &theta, sigma, Some(rate)).unwrap();
            z_rate.push((o.t - tau) / o.sigma_t);
            err_rate.push(o.t - tau);
            err_free.push(onset(&t, &theta, sigma).unwrap().t - tau);
        }
        let mean = |z: &[f64]| z.iter().sum::<f64>() / z.len() as f64;
        let rms = |z: &[f64]| (z.iter().map(|x| x * x).sum::<f64>() / z.len() as f64).sqrt();
        let (m, r) = (mean(&z_rate), rms(&z_rate));
        assert!(
            m.abs() < 0.25 && (0.8..1.25).contains(&r),
            "mean {m}, rms {r}"
        );
        let (e, e_free) = (rms(&err_rate), rms(&err_free));
        assert!(e <= e_free, "rms error {e} s, free {e_free} s");
    }
}
