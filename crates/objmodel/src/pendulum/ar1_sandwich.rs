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
//! with σ² and ρ estimated from the fit's residuals. A fit absorbs part of correlated errors
//! (it follows their slow part), so its residuals are smaller and less correlated than the
//! errors. Their expected moments through the residual maker `M` (as
//! [`crate::noise_correlation`] does for its windows) are solved for ρ, then σ² (see
//! [`Linearised::ar1_errors`]). Taken as they were, on 100 falls of 60 frames at 120 Hz and
//! ρ 0.8 (the test below) φ was up to 5.1 σ off (χ² per degree of freedom 0.3-0.8 where it
//! was beyond 3 σ); through `M`, at most 3.6 σ (median 0.56).
//!
//! The nonparametric sandwich of Newey & West (1987), which takes products of the residuals
//! themselves, was tried first and does not work here: the normal equations make
//! `Σᵢ aᵢ r̂ᵢ = 0`, and over the few frames that determine φ (the onset and the early fall)
//! its lag window then takes most of the correlation away (median |error|/σ 1.38 at ρ 0.8,
//! where honest is 0.67).

/// φ's (the first parameter's) standard deviation under AR(1) errors at the least-squares
/// solution `p` of the residuals `resid`, the Jacobian by forward differences of steps `h`.
/// `None` when the samples are too few for the parameters or the normal matrix is singular.
pub(super) fn phi_sigma<const N: usize>(
    resid: &impl Fn(&[f64; N]) -> Vec<f64>,
    p: [f64; N],
    h: [f64; N],
) -> Option<f64> {
    let fit = Linearised::at(resid, p, h)?;
    let (rho, var) = fit.ar1_errors();
    Some(
        (var * ar1_quadratic_form(&fit.phi_weights(), rho))
            .max(0.0)
            .sqrt(),
    )
}

/// Largest error correlation the residuals are solved for: at 1 the errors would be one
/// offset common to every sample, which a fit's residuals cannot show.
const MAX_RHO: f64 = 0.99;

/// A least-squares fit linearised at its solution: the Jacobian `J` (n × p, of the
/// residuals), `B = (JᵀJ)⁻¹` and the residuals.
struct Linearised {
    jacobian: nalgebra::DMatrix<f64>,
    bread: nalgebra::DMatrix<f64>,
    residuals: Vec<f64>,
}

impl Linearised {
    fn at<const N: usize>(
        resid: &impl Fn(&[f64; N]) -> Vec<f64>,
        p: [f64; N],
        h: [f64; N],
    ) -> Option<Self> {
        let residuals = resid(&p);
        let n = residuals.len();
        if n < 2 * N + 2 {
            return None;
        }
        let mut jacobian = nalgebra::DMatrix::zeros(n, N);
        for j in 0..N {
            let mut q = p;
            q[j] += h[j];
            for (i, (b, a)) in resid(&q).iter().zip(&residuals).enumerate() {
                jacobian[(i, j)] = (b - a) / h[j];
            }
        }
        let bread = (jacobian.transpose() * &jacobian).try_inverse()?;
        Some(Self {
            jacobian,
            bread,
            residuals,
        })
    }

    /// Each sample's weight in φ, `aᵢ = (B Jᵢ)₀`.
    fn phi_weights(&self) -> Vec<f64> {
        (&self.jacobian * self.bread.row(0).transpose())
            .iter()
            .copied()
            .collect()
    }

    /// The errors' correlation ρ and variance σ² that the residuals show, through the
    /// residual maker `M = I − J B Jᵀ`: under AR(1) errors `E Σ rᵢ² = σ² tr(MΓM)` and
    /// `E Σ rᵢ rᵢ₊₁ = σ² Σᵢ (MΓM)ᵢ,ᵢ₊₁`, so their ratio depends on ρ alone; it is solved for ρ
    /// (bisection on [0, MAX_RHO]; 0 where the residuals are less correlated than
    /// independent errors leave them), then σ² = Σ rᵢ² / tr(MΓM).
    fn ar1_errors(&self) -> (f64, f64) {
        let r = &self.residuals;
        let sse: f64 = r.iter().map(|x| x * x).sum();
        if sse <= 0.0 {
            return (0.0, 0.0);
        }
        let observed = r.windows(2).map(|w| w[0] * w[1]).sum::<f64>() / sse;
        let ratio = |rho: f64| {
            let (lag1, trace) = self.residual_moments(rho);
            lag1 / trace
        };
        let rho = crate::stats::invert_increasing(ratio, observed, (0.0, MAX_RHO), 50);
        (rho, sse / self.residual_moments(rho).1)
    }

    /// `(Σᵢ (MΓM)ᵢ,ᵢ₊₁, tr(MΓM))` for `Γᵢⱼ = ρ^|i−j|`: with `G = ΓJ` and `H = J B Jᵀ`,
    /// `MΓM = Γ − J B Gᵀ − G B Jᵀ + J (B JᵀG B) Jᵀ`, and `tr(MΓM) = n − tr(B JᵀG)`.
    fn residual_moments(&self, rho: f64) -> (f64, f64) {
        let j = &self.jacobian;
        let (n, p) = j.shape();
        let mut g = j.clone();
        for c in 0..p {
            let col: Vec<f64> = j.column(c).iter().copied().collect();
            g.set_column(c, &nalgebra::DVector::from_vec(ar1_times(&col, rho)));
        }
        let jtg = j.transpose() * &g;
        let (jb, gb) = (j * &self.bread, &g * &self.bread);
        let jc = j * (&self.bread * &jtg * &self.bread);
        let lag1 = (n - 1) as f64 * rho
            + (0..n - 1)
                .map(|i| {
                    -jb.row(i).dot(&g.row(i + 1)) - gb.row(i).dot(&j.row(i + 1))
                        + jc.row(i).dot(&j.row(i + 1))
                })
                .sum::<f64>();
        (lag1, n as f64 - (&self.bread * jtg).trace())
    }
}

/// `Γ(ρ) x`, `Γᵢⱼ = ρ^|i−j|`: a forward and a backward pass.
fn ar1_times(x: &[f64], rho: f64) -> Vec<f64> {
    let mut forward = Vec::with_capacity(x.len());
    let mut acc = 0.0;
    for &v in x {
        acc = v + rho * acc;
        forward.push(acc);
    }
    let mut out = vec![0.0; x.len()];
    acc = 0.0;
    for i in (0..x.len()).rev() {
        acc = x[i] + rho * acc;
        out[i] = forward[i] + acc - x[i];
    }
    out
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
    use super::super::{
        fit_fall, fit_on_support, jackknife_fall, on_support_residuals, on_support_steps, simulate,
        simulate_on_support,
    };
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
                let p = [fit.phi, fit.k];
                let resid = on_support_residuals(t, &theta, beta);
                let lin = Linearised::at(&resid, p, on_support_steps(&p)).expect("enough samples");
                // The least-squares σ: `sqrt(((JᵀJ)⁻¹)₀₀) σ`, widened by a χ² beyond its dof.
                let chi2 = fit.chi2_per_dof.max(1.0);
                let ls = (lin.bread[(0, 0)] * sigma * sigma * chi2).sqrt();
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

    /// AR(1) noise of correlation ρ: `n` samples of marginal standard deviation `sigma`.
    fn ar1_noise(rng: &mut StdRng, n: usize, rho: f64, sigma: f64) -> Vec<f64> {
        let innovation = Normal::new(0.0, sigma * (1.0 - rho * rho).sqrt()).unwrap();
        let mut e = Normal::new(0.0, sigma).unwrap().sample(rng);
        (0..n)
            .map(|_| {
                let v = e;
                e = rho * e + innovation.sample(rng);
                v
            })
            .collect()
    }

    /// A free fall tracked at 120 Hz with noise correlated at ρ 0.8, fitted as the learner
    /// does (then checked by the jackknife): φ's σ honest, median |error|/σ near 0.67 and none
    /// beyond 5.
    #[test]
    fn a_fall_under_correlated_noise_has_an_honest_phi_sigma() {
        let (phi, k, sigma, rho) = (0.45, 40.0, 2e-3, 0.8);
        let t: Vec<f64> = (0..60).map(|i| i as f64 / 120.0).collect();
        let clean = simulate(phi, k, 0.0, phi + 0.05, 0.2, &t);
        let mut rng = StdRng::seed_from_u64(13);
        let mut z = Vec::new();
        for _ in 0..100 {
            let noise = ar1_noise(&mut rng, t.len(), rho, sigma);
            let psi: Vec<f64> = clean.iter().zip(&noise).map(|(c, e)| c + e).collect();
            let fit = fit_fall(&t, &psi, sigma, phi + 0.1).expect("a fit");
            let fit = jackknife_fall(&t, &psi, fit);
            z.push((fit.phi - phi).abs() / fit.phi_sigma);
        }
        let med = crate::stats::median(&mut z.clone()).unwrap();
        let max = z.iter().copied().fold(0.0, f64::max);
        assert!((0.4..0.95).contains(&med), "median |z| {med}");
        assert!(max < 5.0, "max |z| {max}");
    }

    /// The residual moments against the matrices themselves: `M Γ M` built in full for a
    /// random 30 × 3 Jacobian.
    #[test]
    fn residual_moments_are_those_of_the_residual_maker() {
        use rand::Rng;
        let mut rng = StdRng::seed_from_u64(17);
        let (n, p) = (30, 3);
        let jacobian = nalgebra::DMatrix::from_fn(n, p, |_, _| rng.random_range(-1.0..1.0));
        let bread = (jacobian.transpose() * &jacobian).try_inverse().unwrap();
        let fit = Linearised {
            jacobian: jacobian.clone(),
            bread: bread.clone(),
            residuals: vec![0.0; n],
        };
        for rho in [0.0f64, 0.4, 0.9] {
            let gamma =
                nalgebra::DMatrix::from_fn(n, n, |i, j| rho.powi((i as i32 - j as i32).abs()));
            let m = nalgebra::DMatrix::identity(n, n) - &jacobian * &bread * jacobian.transpose();
            let mgm = &m * gamma * &m;
            let lag1: f64 = (0..n - 1).map(|i| mgm[(i, i + 1)]).sum();
            let (l, t) = fit.residual_moments(rho);
            assert!(
                (l - lag1).abs() < 1e-9 && (t - mgm.trace()).abs() < 1e-9,
                "{rho}"
            );
        }
    }
}
