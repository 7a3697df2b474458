//! The delete-a-block jackknife of a free fall's φ: the uncertainty the data show, not the
//! one the model assumes.
//!
//! The least-squares covariance `(JᵀJ)⁻¹ σ²` holds when the residuals are independent noise
//! of size σ and the model is linear near the solution. A topple breaks both: a pusher that
//! still drives the first frames, a pivot that slips, a support's compliance, correlated
//! tracking errors; and a fall of a few frames leaves φ, k and the start state trading off
//! so that the linearisation says almost nothing (a fit reported φ to 0.0003° and was 1.1°
//! off). The jackknife refits with each of [`JACKKNIFE_BLOCKS`] contiguous blocks of samples
//! left out in turn; where the model holds, the refits scatter as the noise makes them (the
//! jackknife variance estimates the least-squares one), and where a part of the span does not
//! follow the model, leaving it out moves φ, and the variance shows it (Efron & Stein 1981;
//! Künsch 1989 for blocks of dependent samples).
//!
//! A refit that leaves the admissible range (0 < φ < π/2, k > 0), or a span too short to
//! leave a block out and still determine the parameters, means the data do not determine φ:
//! the sigma is then infinite and no caller uses the φ.

use super::{fall_lm, FallFit};

/// Contiguous blocks left out one at a time.
pub const JACKKNIFE_BLOCKS: usize = 8;

/// Significance level of the test that the blocks' φ scatter more than the least-squares σ
/// allows.
pub const MODEL_ALPHA: f64 = 0.01;

/// Frames a refit keeps beyond the number of parameters, at the least.
const SPARE_FRAMES: usize = 2;

/// The jackknife standard deviation of φ over `n` samples: `refit(w)` redoes the fit with the
/// weights `w` (0 on the left-out block, 1 elsewhere) and returns its φ. `None` when a refit
/// fails or a block cannot be left out.
fn jackknife_sigma(
    n: usize,
    n_params: usize,
    refit: impl Fn(&[f64]) -> Option<f64>,
) -> Option<f64> {
    let g = JACKKNIFE_BLOCKS;
    let block = n.div_ceil(g);
    if n < g || n - block < n_params + SPARE_FRAMES {
        return None;
    }
    let mut phis = Vec::with_capacity(g);
    for b in 0..g {
        let (lo, hi) = (b * n / g, (b + 1) * n / g);
        let w: Vec<f64> = (0..n)
            .map(|i| if (lo..hi).contains(&i) { 0.0 } else { 1.0 })
            .collect();
        phis.push(refit(&w)?);
    }
    let mean = phis.iter().sum::<f64>() / g as f64;
    let ss: f64 = phis.iter().map(|p| (p - mean).powi(2)).sum();
    Some((ss * (g as f64 - 1.0) / g as f64).sqrt())
}

/// `fit` with its φ's sigma: the jackknife's where the blocks scatter beyond what the
/// least-squares sigma allows (a χ² test at [`MODEL_ALPHA`]), the least-squares one otherwise,
/// infinite when the jackknife finds φ undetermined. (The jackknife variance is biased upward,
/// Efron & Stein 1981: used everywhere it made φ's σ on on-model falls about 1.5 times too
/// large.)
fn with_sigma(mut fit: FallFit, jackknife: Option<f64>) -> FallFit {
    let Some(jk) = jackknife else {
        fit.phi_sigma = f64::INFINITY;
        return fit;
    };
    // Where the model holds, (G - 1) jk² / σ² is about χ² with G - 1 degrees of freedom; a
    // larger ratio says the blocks disagree beyond the noise, and the jackknife's σ stands.
    let dof = (JACKKNIFE_BLOCKS - 1) as f64;
    if dof * jk * jk > crate::stats::chi2_threshold(dof, MODEL_ALPHA) * fit.phi_sigma.powi(2) {
        fit.phi_sigma = jk;
    }
    fit
}

/// [`super::fit_fall`]'s `fit` of ψ(t) (the samples it was fitted to) with its φ's sigma
/// checked by the jackknife.
pub fn jackknife_fall(t: &[f64], psi: &[f64], fit: FallFit) -> FallFit {
    let start = [fit.phi, fit.k, fit.start_state[0], fit.start_state[1]];
    let s = jackknife_sigma(t.len(), 4, |w| {
        fall_lm(t, psi, Some(w), start).map(|r| r.0[0])
    });
    with_sigma(fit, s)
}

#[cfg(test)]
mod tests {
    use super::super::{fit_fall, simulate};
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_distr::StandardNormal;

    /// On falls that follow the model, with white noise, the jackknife's sigma is honest: the
    /// median |error|/σ over many falls is near 0.674 and none is beyond 5.
    #[test]
    fn on_model_falls_the_sigma_is_honest() {
        let mut rng = rand::rngs::StdRng::seed_from_u64(3);
        let (phi, k, sigma) = (0.45, 40.0, 2e-3);
        let t: Vec<f64> = (0..30).map(|i| i as f64 / 60.0).collect();
        let mut z = Vec::new();
        for _ in 0..60 {
            let clean = simulate(phi, k, 0.0, phi + 0.05, 0.2, &t);
            let psi: Vec<f64> = clean
                .iter()
                .map(|x| x + sigma * rng.sample::<f64, _>(StandardNormal))
                .collect();
            let fit = fit_fall(&t, &psi, sigma, phi + 0.1).expect("a fit");
            let fit = jackknife_fall(&t, &psi, fit);
            z.push((fit.phi - phi).abs() / fit.phi_sigma);
        }
        let med = crate::stats::median(&mut z.clone()).unwrap();
        let max = z.iter().copied().fold(0.0, f64::max);
        assert!(med > 0.4 && med < 0.9, "median {med}");
        assert!(max < 5.0, "max {max}");
    }

    /// A fall whose first frames are driven (a pusher turning the object at a steady rate
    /// past its balance point before letting go) is not a free pendulum. The driven frames'
    /// misfit is serially correlated, and the fit's σ (with the AR(1) sandwich,
    /// `super::ar1_sandwich`) holds it; the jackknife, given the fit with an overconfident σ
    /// (the least-squares one was below a fifth of the error), finds it too.
    #[test]
    fn a_driven_start_shows_in_the_sigma() {
        let (phi, k) = (0.6, 30.0);
        let t: Vec<f64> = (0..40).map(|i| i as f64 / 60.0).collect();
        // Driven at 0.8 rad/s for the first 12 frames, then free from that state.
        let release = t[12];
        let free = simulate(phi, k, release, phi + 0.02 + 0.8 * release, 0.8, &t[12..]);
        let psi: Vec<f64> = t[..12]
            .iter()
            .map(|x| phi + 0.02 + 0.8 * x)
            .chain(free)
            .collect();
        let sigma = 1e-3;
        let fit = fit_fall(&t, &psi, sigma, phi - 0.1).expect("a fit");
        // The fit's sigma holds the misfit.
        let err = (fit.phi - phi).abs();
        assert!(
            err < 3.0 * fit.phi_sigma,
            "error {err}, sigma {}",
            fit.phi_sigma
        );
        let overconfident = FallFit {
            phi_sigma: err / 10.0,
            ..fit
        };
        let checked = jackknife_fall(&t, &psi, overconfident);
        let err = (checked.phi - phi).abs();
        assert!(
            err < 3.0 * checked.phi_sigma,
            "error {err} against sigma {} (given {})",
            checked.phi_sigma,
            overconfident.phi_sigma
        );
    }
}
