//! φ's standard deviation when a fit's residuals are serially correlated: the sandwich
//! covariance under first-order autoregressive (AR(1)) errors.
//!
//! The least-squares covariance `(JᵀJ)⁻¹ σ²` counts every sample as independent. A tracker
//! that filters its poses (consecutive frames' errors correlated) or a contact that creeps
//! (the residuals drift for a stretch) leaves fewer independent samples than frames, and the
//! covariance is then too small, by up to `(1+ρ)/(1−ρ)` for errors of lag-one correlation ρ
//! (9 at ρ = 0.8). To first order `φ̂ − φ = Σᵢ aᵢ eᵢ` with `aᵢ = ((JᵀJ)⁻¹ Jᵢ)₀` and `eᵢ` the
//! samples' errors, so under errors of variance σ² and correlation `ρ^|i−j|`
//!
//! `var φ̂ = σ² Σᵢ Σⱼ aᵢ aⱼ ρ^|i−j|`,
//!
//! with σ² and ρ estimated from the fit's residuals (their variance over `n − p`, their
//! lag-one autocorrelation). The nonparametric sandwich of Newey & West (1987), which takes
//! `Σᵢ aᵢ r̂ᵢ` products of the residuals themselves, cannot be used here: the normal equations
//! make `Σᵢ aᵢ r̂ᵢ = 0`, and over the few frames that determine φ (the onset and the early
//! fall) its lag window then takes most of the correlation away (tried: median |error|/σ 1.38
//! at ρ 0.8, where honest is 0.67). The residuals of the whole span estimate ρ instead, most
//! of them from the rest before the onset, where they are the tracker's errors alone.

/// φ's (the first parameter's) standard deviation under AR(1) errors at the least-squares solution `p` of
/// the residuals `resid`, the Jacobian by forward differences of steps `h`. `None` when the
/// samples are too few for the parameters or the normal matrix is singular.
pub(super) fn phi_sigma<const N: usize>(
    resid: &impl Fn(&[f64; N]) -> Vec<f64>,
    p: [f64; N],
    h: [f64; N],
) -> Option<f64> {
    let (_, a, r) = influences(resid, p, h)?;
    let n = r.len();
    let var = r.iter().map(|x| x * x).sum::<f64>() / (n - N) as f64;
    let lag1 = r.windows(2).map(|w| w[0] * w[1]).sum::<f64>();
    let rho = (lag1 / (var * (n - N) as f64)).clamp(0.0, 1.0);
    Some((var * ar1_quadratic_form(&a, rho)).max(0.0).sqrt())
}

/// `((JᵀJ)⁻¹)₀₀`, each sample's weight in φ, `aᵢ = ((JᵀJ)⁻¹ Jᵢ)₀`, and the residuals at `p`
/// (see [`phi_sigma`]).
fn influences<const N: usize>(
    resid: &impl Fn(&[f64; N]) -> Vec<f64>,
    p: [f64; N],
    h: [f64; N],
) -> Option<(f64, Vec<f64>, Vec<f64>)> {
    let r = resid(&p);
    let n = r.len();
    if n < 2 * N + 2 {
        return None;
    }
    let cols: Vec<Vec<f64>> = (0..N)
        .map(|j| {
            let mut q = p;
            q[j] += h[j];
            resid(&q)
                .iter()
                .zip(&r)
                .map(|(b, a)| (b - a) / h[j])
                .collect()
        })
        .collect();
    let jtj = nalgebra::DMatrix::from_fn(N, N, |a, b| {
        (0..n).map(|i| cols[a][i] * cols[b][i]).sum::<f64>()
    });
    let bread = jtj.try_inverse()?;
    let a = (0..n)
        .map(|i| (0..N).map(|j| bread[(0, j)] * cols[j][i]).sum::<f64>())
        .collect();
    Some((bread[(0, 0)], a, r))
}

/// `Σᵢ Σⱼ aᵢ aⱼ ρ^|i−j|`, in one pass: `Σᵢ aᵢ (aᵢ + 2 cᵢ)` with `cᵢ = Σ_{j<i} aⱼ ρ^{i−j}`
/// carried as `cᵢ = ρ (cᵢ₋₁ + aᵢ₋₁)`.
fn ar1_quadratic_form(a: &[f64], rho: f64) -> f64 {
    let (mut sum, mut carry, mut prev) = (0.0, 0.0, 0.0);
    for &x in a {
        carry = rho * (carry + prev);
        sum += x * (x + 2.0 * carry);
        prev = x;
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::super::{fit_on_support, simulate_on_support};
    use super::*;
    use rand::{rngs::StdRng, SeedableRng};
    use rand_distr::{Distribution, Normal};

    /// The quadratic form against its definition (a double sum), and for equal weights the
    /// variance of a sum of n AR(1) samples, `n (1+ρ)/(1−ρ) − 2ρ(1−ρⁿ)/(1−ρ)²`.
    #[test]
    fn the_quadratic_form_is_the_double_sum() {
        use rand::Rng;
        let mut rng = StdRng::seed_from_u64(5);
        for rho in [0.0f64, 0.3, 0.8, 0.95] {
            let a: Vec<f64> = (0..50).map(|_| rng.random_range(-1.0..1.0)).collect();
            let double: f64 = (0..a.len())
                .flat_map(|i| (0..a.len()).map(move |j| (i, j)))
                .map(|(i, j)| a[i] * a[j] * rho.powi((i as i32 - j as i32).abs()))
                .sum();
            let one_pass = ar1_quadratic_form(&a, rho);
            assert!(
                (one_pass - double).abs() < 1e-9 * double.abs().max(1.0),
                "{rho}"
            );
            let n = 200;
            let sum_var = n as f64 * (1.0 + rho) / (1.0 - rho)
                - 2.0 * rho * (1.0 - rho.powi(n)) / (1.0 - rho).powi(2);
            let ones = ar1_quadratic_form(&vec![1.0; n as usize], rho);
            assert!(
                (ones - sum_var).abs() < 1e-9 * sum_var,
                "{rho}: {ones} vs {sum_var}"
            );
        }
    }

    /// An instrumented topple on a palm tilting at 0.15 rad/s, tracked at 120 Hz with noise
    /// correlated from frame to frame (ρ 0.8) and the fit told the noise's per-frame size:
    /// the least-squares σ of φ is several times too small (median |error|/σ above 1.5), the
    /// fit's φ σ (the larger of it and the sandwich's) is honest: median |error|/σ near 0.67
    /// and none beyond 5. On white noise it stays honest.
    #[test]
    fn correlated_residuals_widen_phi_sigma_to_an_honest_one() {
        let (phi, k, rate, hz) = (0.40, 40.0, 0.15, 120.0);
        let t: Vec<f64> = (0..)
            .map(|i| 1.0 + i as f64 / hz)
            .take_while(|&x| x < 1.0 + (phi + 0.1) / rate)
            .collect();
        let beta: Vec<f64> = t.iter().map(|x| rate * (x - 1.0) + 0.05).collect();
        let clean = simulate_on_support(phi, k, &t, &beta);
        let end = clean.iter().position(|x| *x > 0.15).expect("it falls");
        let (t, beta, clean) = (&t[..=end], &beta[..=end], &clean[..=end]);
        let sigma = 2e-3;
        for rho in [0.0, 0.8] {
            let mut rng = StdRng::seed_from_u64(11);
            let innovation = Normal::new(0.0, sigma * (1.0f64 - rho * rho).sqrt()).unwrap();
            let (mut z, mut z_ls) = (Vec::new(), Vec::new());
            for _ in 0..100 {
                let mut e = Normal::new(0.0, sigma).unwrap().sample(&mut rng);
                let theta: Vec<f64> = clean
                    .iter()
                    .map(|c| {
                        let v = c + e;
                        e = rho * e + innovation.sample(&mut rng);
                        v
                    })
                    .collect();
                let fit = fit_on_support(t, &theta, beta, sigma, phi + 0.02).expect("a fit");
                z.push((fit.phi - phi).abs() / fit.phi_sigma);
                let resid = |p: &[f64; 2]| -> Vec<f64> {
                    simulate_on_support(p[0], p[1], t, beta)
                        .iter()
                        .zip(&theta)
                        .map(|(m, y)| y - m)
                        .collect()
                };
                let (bread, _, r) = influences(&resid, [fit.phi, fit.k], [1e-5, 1e-4 * fit.k])
                    .expect("enough samples");
                // The least-squares σ: `sqrt(((JᵀJ)⁻¹)₀₀) σ`, widened by a χ² beyond its dof.
                let chi2 = fit.chi2_per_dof.max(1.0);
                let ls = (bread * sigma * sigma * chi2).sqrt();
                assert!(!r.is_empty());
                z_ls.push((fit.phi - phi).abs() / ls);
            }
            let med = crate::stats::median(&mut z.clone()).unwrap();
            let max = z.iter().copied().fold(0.0, f64::max);
            assert!((0.4..0.95).contains(&med), "rho {rho}: median |z| {med}");
            assert!(max < 5.0, "rho {rho}: max |z| {max}");
            if rho > 0.0 {
                let med_ls = crate::stats::median(&mut z_ls).unwrap();
                assert!(med_ls > 1.5, "least squares alone: median |z| {med_ls}");
            }
        }
    }
}
