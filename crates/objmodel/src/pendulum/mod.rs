//! The planar pendulum on an edge's contact sub-manifold (paper Sec. II-B, Fig. 4, Fig. 5):
//! while an object turns about an edge, it is a pendulum with CoM angle φ from the vertical,
//! CoM distance `l_p` from the edge and mass m:
//!
//! ```text
//! I_e ψ̈ = m g l_p sin(ψ - φ),      ψ: the object's tilt about the edge from its resting pose
//! ```
//!
//! (ψ = 0 resting on the face, ψ = φ balanced over the edge). The motion determines φ and
//! `k = m g l_p / I_e` \[1/s²\], i.e. the ratio `I_e/(m l_p) = g/k` \[m\]; `l_p` itself needs an
//! inertia model: for a solid homogeneous box `I_e = (4/3) m l_p²`, so `l_p = (3/4) g/k`.
//!
//! Two estimators:
//! * [`onset`]: the instant a body at rest starts to turn, by two-phase regression (a
//!   change-point model): constant before τ, the linearised toppling motion
//!   `A (sinh(ω (t-τ))/ω - (t-τ))` after; τ and ω by least squares over a fine grid, with the
//!   standard deviation of τ from the profile likelihood's spread.
//!   For an instrumented demonstration φ is the palm's tilt at τ (the paper's method).
//! * [`fit_fall`]: nonlinear least squares (Levenberg-Marquardt on an RK4 integration) of the
//!   equation of motion to ψ(t) over the frames where the object still turns about its edge.
//!
//! Each fit's φ σ is the larger of the least-squares one and the sandwich under errors
//! correlated from frame to frame (`ar1_sandwich`); a free fall's is then checked by the jackknife.

mod ar1_sandwich;
mod jackknife;
mod onset;
mod swing;

pub use jackknife::{jackknife_fall, JACKKNIFE_BLOCKS};
pub use onset::{onset, onset_at_rate, Onset};
pub use swing::{fit_swing, SwingFit};

use serde::{Deserialize, Serialize};

/// Standard gravity \[m/s²\].
pub const G: f64 = 9.806_65;

/// Solve the small normal equations `A x = b` (A symmetric positive definite, n <= 4).
fn solve(a: &[[f64; 4]; 4], b: &[f64; 4], n: usize) -> Option<[f64; 4]> {
    let m = nalgebra::DMatrix::from_fn(n, n, |i, j| a[i][j]);
    let v = nalgebra::DVector::from_fn(n, |i, _| b[i]);
    let x = m.lu().solve(&v)?;
    let mut out = [0.0; 4];
    for i in 0..n {
        out[i] = x[i];
    }
    Some(out)
}

/// Levenberg-Marquardt on `N <= 4` parameters with a forward-difference Jacobian (steps from
/// `steps`), `clamp` keeping parameters in their domain. Returns the parameters, the residual
/// sum of squares and the (undamped) normal matrix JᵀJ at the solution.
fn levenberg_marquardt<const N: usize>(
    p0: [f64; N],
    resid: impl Fn(&[f64; N]) -> Vec<f64>,
    steps: impl Fn(&[f64; N]) -> [f64; N],
    clamp: impl Fn([f64; N]) -> [f64; N],
) -> ([f64; N], f64, [[f64; 4]; 4]) {
    let sse = |r: &[f64]| r.iter().map(|x| x * x).sum::<f64>();
    let mut p = p0;
    let mut r = resid(&p);
    let mut cur = sse(&r);
    let mut jtj = [[0.0; 4]; 4];
    let mut lambda = 1e-3;
    for _ in 0..100 {
        let h = steps(&p);
        let cols: Vec<Vec<f64>> = (0..N)
            .map(|j| {
                let mut q = p;
                q[j] += h[j];
                r.iter()
                    .zip(resid(&q))
                    .map(|(a, b)| (a - b) / h[j])
                    .collect()
            })
            .collect();
        let mut jtr = [0.0; 4];
        jtj = [[0.0; 4]; 4];
        for i in 0..r.len() {
            for a in 0..N {
                jtr[a] += cols[a][i] * r[i];
                for b in 0..N {
                    jtj[a][b] += cols[a][i] * cols[b][i];
                }
            }
        }
        let mut accepted = false;
        for _ in 0..12 {
            let mut damped = jtj;
            for (a, row) in damped.iter_mut().enumerate().take(N) {
                row[a] += lambda * jtj[a][a].max(1e-12);
            }
            let Some(delta) = solve(&damped, &jtr, N) else {
                break;
            };
            let mut q = p;
            for j in 0..N {
                q[j] += delta[j];
            }
            let q = clamp(q);
            let rq = resid(&q);
            let s = sse(&rq);
            if s < cur {
                accepted = (cur - s) / cur.max(1e-300) > 1e-12;
                p = q;
                r = rq;
                cur = s;
                lambda = (lambda / 3.0).max(1e-12);
                break;
            }
            lambda *= 4.0;
        }
        if !accepted {
            break;
        }
    }
    (p, cur, jtj)
}

/// A fitted pendulum.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct FallFit {
    /// CoM angle from the vertical through the edge, resting on the face \[rad\].
    pub phi: f64,
    /// Standard deviation of phi \[rad\].
    pub phi_sigma: f64,
    /// `k = m g l_p / I_e` \[1/s²\].
    pub k: f64,
    /// Standard deviation of k.
    pub k_sigma: f64,
    /// `I_e / (m l_p) = g / k` \[m\].
    pub inertia_ratio_m: f64,
    /// `l_p` \[m\] under the homogeneous-box inertia model, `(3/4) g / k`.
    pub l_p_homogeneous: f64,
    /// χ² per degree of freedom of the fit.
    pub chi2_per_dof: f64,
    /// Frames used.
    pub frames: usize,
    /// Time span fitted \[s\].
    pub t_start: f64,
    /// End of the fitted span \[s\].
    pub t_end: f64,
    /// The fitted state (ψ, ψ̇) at `t_start` of a free fall (zero for a pendulum on a support,
    /// which starts from rest), where the jackknife's refits start.
    #[serde(skip)]
    pub(crate) start_state: [f64; 2],
}

/// Longest span \[s\] the pendulum fits ([`fit_fall`], [`fit_on_support`]) take. A toppling
/// object falls from its balance point within about a second, and a palm tilts it over within
/// seconds; a longer span is not one topple (or its timestamps are not seconds: nanoseconds
/// made a 4 s demonstration 4·10⁹ "seconds" long), and the fits, which integrate in steps of
/// 2 ms, would take time without bound.
pub const MAX_FIT_SPAN_S: f64 = 60.0;

/// Longest span \[s\] of a free fall that [`fit_fall`] takes. An object released at rest δ₀
/// past its balance point turns δ further in `t ≈ (ln(tan(δ/4) / tan(δ₀/4)) + ln 2) / √k`
/// (`k = m g l_p / I_e`, from `δ̈ = k sin δ`; the `ln 2` is the start from rest): from
/// δ₀ = 10⁻⁶ rad (far below any tracker's noise) to δ = 90°, a homogeneous box
/// (`k = 3g / (4 l_p)`) with its CoM 1 m from the edge falls in 5.5 s, and `t` grows as
/// `√l_p`: 10 s is a fall of an object with `l_p` of 3.3 m. A longer span is not a free fall (a
/// slow push, a turn at a steady pace), and each fit integrates in steps of 2 ms, so its cost
/// grows with the span.
pub const MAX_FALL_S: f64 = 10.0;

/// Integrate `ψ̈ = k sin(ψ - φ)` from `(t0, ψ0, ψ̇0)` and return ψ at the times `t` (sorted,
/// >= t0), with RK4 steps of at most 2 ms.
pub fn simulate(phi: f64, k: f64, t0: f64, psi0: f64, dpsi0: f64, t: &[f64]) -> Vec<f64> {
    let mut out = Vec::with_capacity(t.len());
    integrate(phi, k, t0, psi0, dpsi0, t, |_, x| {
        out.push(x);
        true
    });
    out
}

/// `Σ (y_i - m_i)²` in order over the model values `m_i` that `run` passes to the sampler it is
/// given (e.g. [`integrate`]'s), stopping it (the sampler returns false) once the sum reaches
/// `bound`; the partial sum, `>= bound`, is then returned. A grid search that keeps the
/// smallest sum thus skips most of its candidates' integration with the same winner: a sum of
/// squares only grows.
fn squares_below(
    y: &[f64],
    bound: f64,
    run: impl FnOnce(&mut dyn FnMut(usize, f64) -> bool),
) -> f64 {
    let mut acc = 0.0;
    run(&mut |i, m| {
        let d = y[i] - m;
        acc += d * d;
        acc < bound
    });
    acc
}

/// One classical Runge-Kutta step of `ẍ = a(t, x)` from `(t, x, ẋ = v)` over `h`: the new
/// `(x, v)`.
#[inline(always)]
fn rk4_step(t: f64, x: f64, v: f64, h: f64, a: impl Fn(f64, f64) -> f64) -> (f64, f64) {
    let (k1x, k1v) = (v, a(t, x));
    let (k2x, k2v) = (v + 0.5 * h * k1v, a(t + 0.5 * h, x + 0.5 * h * k1x));
    let (k3x, k3v) = (v + 0.5 * h * k2v, a(t + 0.5 * h, x + 0.5 * h * k2x));
    let (k4x, k4v) = (v + h * k3v, a(t + h, x + h * k3x));
    (
        x + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x),
        v + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v),
    )
}

/// [`simulate`]'s integration, passing `(i, ψ(t_i))` to `sample`, which stops it by returning
/// false.
fn integrate(
    phi: f64,
    k: f64,
    t0: f64,
    psi0: f64,
    dpsi0: f64,
    t: &[f64],
    mut sample: impl FnMut(usize, f64) -> bool,
) {
    let f = |psi: f64| k * (psi - phi).sin();
    let (mut tc, mut x, mut v) = (t0, psi0, dpsi0);
    for (i, &target) in t.iter().enumerate() {
        while tc < target - 1e-12 {
            let h = (target - tc).min(0.002);
            (x, v) = rk4_step(tc, x, v, h, |_, psi| f(psi));
            tc += h;
        }
        if !sample(i, x) {
            return;
        }
    }
}

/// Fit the pendulum to ψ(t) \[rad\] with noise `sigma` \[rad\], starting from the guess `phi0`.
/// Parameters: φ, k, and the state (ψ, ψ̇) at the first sample. Levenberg-Marquardt with a
/// forward-difference Jacobian; covariance from the inverse normal matrix scaled by the
/// residuals' variance (`sigma` holds a model tolerance, so it bounds the errors rather than
/// measuring them). See [`jackknife_fall`] for what the covariance still leaves out.
pub fn fit_fall(t: &[f64], psi: &[f64], sigma: f64, phi0: f64) -> Option<FallFit> {
    let n = t.len();
    if n < 6 || t[n - 1] - t[0] > MAX_FALL_S || uniform_motion_explains(t, psi, sigma) {
        return None;
    }
    let t0 = t[0];
    let dpsi = (psi[2] - psi[0]) / (t[2] - t[0]);
    let mut p = [phi0, 40.0, psi[0], dpsi];
    // Initial (φ, k): a coarse grid, as the problem is far from linear.
    let mut best = (f64::INFINITY, p[0], p[1]);
    for i in -12..=12 {
        let ph = phi0 + 0.025 * i as f64;
        for kk in [
            5.0, 8.0, 12.0, 18.0, 27.0, 40.0, 60.0, 90.0, 135.0, 200.0, 300.0, 450.0,
        ] {
            let s = squares_below(psi, best.0, |sample| {
                integrate(ph, kk, t0, p[2], p[3], t, sample)
            });
            if s < best.0 {
                best = (s, ph, kk);
            }
        }
    }
    p[0] = best.1;
    p[1] = best.2;
    let (p, cur, jtj) = fall_lm(t, psi, None, p)?;
    let mut fit = fit_result(p[0], p[1], cur, &jtj, 4, sigma, Scale::Residuals, t)?;
    fit.start_state = [p[2], p[3]];
    // Serially correlated residuals (see [`fit_on_support`]).
    if let Some(ar1) = ar1_sandwich::phi_sigma(&fall_residuals(t, psi, None), p, fall_steps(&p)) {
        fit.phi_sigma = fit.phi_sigma.max(ar1);
    }
    Some(fit)
}

/// Levenberg-Marquardt of the free fall from `p` = (φ, k, ψ₀, ψ̇₀), the state at `t[0]`, with
/// the samples weighted by `w` (all 1 when `None`); `None` when the solution is not a
/// pendulum about an edge of a resting object (0 < φ < π/2, k > 0).
pub(crate) fn fall_lm(
    t: &[f64],
    psi: &[f64],
    w: Option<&[f64]>,
    p: [f64; 4],
) -> Option<([f64; 4], f64, [[f64; 4]; 4])> {
    let (p, cur, jtj) = levenberg_marquardt(p, fall_residuals(t, psi, w), fall_steps, |q| {
        [q[0], q[1].max(1e-3), q[2], q[3]]
    });
    (p[0] > 0.0 && p[0] < std::f64::consts::FRAC_PI_2 && p[1] > 0.0).then_some((p, cur, jtj))
}

/// The free fall's residuals ψᵢ − model at the parameters (φ, k, ψ₀, ψ̇₀), weighted by `w`.
fn fall_residuals<'a>(
    t: &'a [f64],
    psi: &'a [f64],
    w: Option<&'a [f64]>,
) -> impl Fn(&[f64; 4]) -> Vec<f64> + 'a {
    move |p: &[f64; 4]| {
        let m = simulate(p[0], p[1], t[0], p[2], p[3], t);
        m.iter()
            .zip(psi)
            .enumerate()
            .map(|(i, (a, b))| (b - a) * w.map_or(1.0, |w| w[i]))
            .collect()
    }
}

/// The free fall's forward-difference steps at the parameters `p`.
fn fall_steps(p: &[f64; 4]) -> [f64; 4] {
    [1e-6, 1e-4 * p[1].max(1.0), 1e-6, 1e-5]
}

/// Significance level of the test that a fall is not uniform motion ([`fit_fall`]).
pub const UNIFORM_MOTION_ALPHA: f64 = 0.01;

/// Whether a uniform motion (ψ linear in t) explains ψ(t) within the noise `sigma`: the χ² of
/// the least-squares line (n - 2 degrees of freedom) is within its `1 - UNIFORM_MOTION_ALPHA`
/// quantile. Such a window shows no angular acceleration, so it cannot determine a pendulum:
/// `k sin(ψ - φ) ≈ 0` holds for any φ with k small enough, and a fit would report one anyway.
fn uniform_motion_explains(t: &[f64], psi: &[f64], sigma: f64) -> bool {
    let n = t.len() as f64;
    let (tm, ym) = (t.iter().sum::<f64>() / n, psi.iter().sum::<f64>() / n);
    let stt: f64 = t.iter().map(|x| (x - tm).powi(2)).sum();
    let sty: f64 = t.iter().zip(psi).map(|(a, b)| (a - tm) * (b - ym)).sum();
    let slope = if stt > 0.0 { sty / stt } else { 0.0 };
    let sse: f64 = t
        .iter()
        .zip(psi)
        .map(|(x, y)| (y - ym - slope * (x - tm)).powi(2))
        .sum();
    sse / (sigma * sigma) <= crate::stats::chi2_threshold(n - 2.0, UNIFORM_MOTION_ALPHA)
}

/// How a fit's covariance takes the size of its errors.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Scale {
    /// `σ` is the samples' noise: covariance `(JᵀJ)⁻¹ σ²`, inflated by the reduced χ² when the
    /// fit is worse than the noise.
    Noise,
    /// `σ` is only a bound on the errors (it holds a model tolerance): covariance
    /// `(JᵀJ)⁻¹ s²` with `s² = SSE/(n - p)`, the errors' size the residuals show.
    Residuals,
}

/// The [`FallFit`] of a least-squares solution with φ and k its first two of `n_params`
/// parameters, its covariance scaled as `scale` says.
#[allow(clippy::too_many_arguments)]
fn fit_result(
    phi: f64,
    k: f64,
    sse: f64,
    jtj: &[[f64; 4]; 4],
    n_params: usize,
    sigma: f64,
    scale: Scale,
    t: &[f64],
) -> Option<FallFit> {
    let n = t.len();
    let var = sigma * sigma;
    let chi2 = sse / var / (n as f64 - n_params as f64).max(1.0);
    let m = nalgebra::DMatrix::from_fn(n_params, n_params, |i, j| jtj[i][j]);
    let factor = match scale {
        Scale::Noise => chi2.max(1.0),
        Scale::Residuals => chi2,
    };
    let cov = m.try_inverse()? * var * factor;
    Some(FallFit {
        phi,
        phi_sigma: cov[(0, 0)].max(0.0).sqrt(),
        k,
        k_sigma: cov[(1, 1)].max(0.0).sqrt(),
        inertia_ratio_m: G / k,
        l_p_homogeneous: 0.75 * G / k,
        chi2_per_dof: chi2,
        frames: n,
        t_start: t[0],
        t_end: t[n - 1],
        start_state: [0.0; 2],
    })
}

/// The rotation relative to a tilting support predicted by the pendulum: zero while the
/// support's tilt `beta` (smoothed, at the sample times) is below φ; from the first crossing
/// on, `θ̈ = k sin(θ + β(t) - φ)` from rest, with β interpolated linearly between samples.
pub fn simulate_on_support(phi: f64, k: f64, t: &[f64], beta: &[f64]) -> Vec<f64> {
    let mut out = Vec::with_capacity(t.len());
    integrate_on_support(phi, k, t, beta, |_, x| {
        out.push(x);
        true
    });
    out
}

/// [`simulate_on_support`]'s integration, passing `(i, θ(t_i))` to `sample`, which stops it
/// by returning false.
fn integrate_on_support(
    phi: f64,
    k: f64,
    t: &[f64],
    beta: &[f64],
    mut sample: impl FnMut(usize, f64) -> bool,
) {
    let c = (1..t.len()).find(|&i| beta[i] >= phi).unwrap_or(t.len());
    for i in 0..c {
        if !sample(i, 0.0) {
            return;
        }
    }
    if c == t.len() {
        return;
    }
    // Crossing time by linear interpolation.
    let s = ((phi - beta[c - 1]) / (beta[c] - beta[c - 1])).clamp(0.0, 1.0);
    let mut tc = t[c - 1] + s * (t[c] - t[c - 1]);
    let (mut x, mut v) = (0.0, 0.0);
    let beta_at = |tt: f64, i: usize| {
        let i = i.clamp(1, t.len() - 1);
        let w = ((tt - t[i - 1]) / (t[i] - t[i - 1])).clamp(0.0, 1.0);
        beta[i - 1] + w * (beta[i] - beta[i - 1])
    };
    for (i, &ti) in t.iter().enumerate().skip(c) {
        while tc < ti - 1e-12 {
            let h = (ti - tc).min(0.002);
            (x, v) = rk4_step(tc, x, v, h, |tt, xx| k * (xx + beta_at(tt, i) - phi).sin());
            tc += h;
        }
        if !sample(i, x) {
            return;
        }
    }
}

/// φ and k from an instrumented topple: the object's rotation relative to the palm, `theta`
/// \[rad\] (zero at rest), against the palm's tilt `beta` \[rad\] (smoothed), both at times `t`,
/// with noise `sigma` \[rad\] on theta. The object starts to turn exactly when the tilt reaches
/// φ, so φ is fixed by the whole onset and the early fall jointly, not by a threshold. Grid
/// search around `phi0`, then Levenberg-Marquardt on (φ, k).
pub fn fit_on_support(
    t: &[f64],
    theta: &[f64],
    beta: &[f64],
    sigma: f64,
    phi0: f64,
) -> Option<FallFit> {
    let n = t.len();
    if n < 8 || t[n - 1] - t[0] > MAX_FIT_SPAN_S {
        return None;
    }
    let mut best = (f64::INFINITY, [phi0, 40.0]);
    for i in -40..=40 {
        let ph = phi0 + 0.002 * i as f64;
        for kk in [
            5.0, 8.0, 12.0, 18.0, 27.0, 40.0, 60.0, 90.0, 135.0, 200.0, 300.0,
        ] {
            let s = squares_below(theta, best.0, |sample| {
                integrate_on_support(ph, kk, t, beta, sample)
            });
            if s < best.0 {
                best = (s, [ph, kk]);
            }
        }
    }
    let resid = on_support_residuals(t, theta, beta);
    let (p, cur, jtj) =
        levenberg_marquardt(best.1, &resid, on_support_steps, |q| [q[0], q[1].max(1e-3)]);
    if !(p[0] > 0.0 && p[0] < std::f64::consts::FRAC_PI_2) {
        return None;
    }
    let mut fit = fit_result(p[0], p[1], cur, &jtj, 2, sigma, Scale::Noise, t)?;
    // Errors correlated from frame to frame (a filtering tracker, a creeping contact) are not
    // in the least-squares covariance: where the sandwich under AR(1) errors shows more, it
    // stands.
    if let Some(ar1) = ar1_sandwich::phi_sigma(&resid, p, on_support_steps(&p)) {
        fit.phi_sigma = fit.phi_sigma.max(ar1);
    }
    Some(fit)
}

/// The pendulum on a support's residuals θᵢ − model at the parameters (φ, k).
fn on_support_residuals<'a>(
    t: &'a [f64],
    theta: &'a [f64],
    beta: &'a [f64],
) -> impl Fn(&[f64; 2]) -> Vec<f64> + 'a {
    move |p: &[f64; 2]| {
        simulate_on_support(p[0], p[1], t, beta)
            .iter()
            .zip(theta)
            .map(|(m, y)| y - m)
            .collect()
    }
}

/// The pendulum on a support's forward-difference steps at the parameters `p`.
fn on_support_steps(p: &[f64; 2]) -> [f64; 2] {
    [1e-5, 1e-4 * p[1]]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounded_sums_of_squares_decide_as_the_full_ones() {
        let t: Vec<f64> = (0..40).map(|i| i as f64 / 30.0).collect();
        let psi = simulate(0.4, 40.0, 0.0, 0.45, 0.3, &t);
        let beta: Vec<f64> = t.iter().map(|x| 0.3 * x).collect();
        let theta = simulate_on_support(0.2, 30.0, &t, &beta);
        for (phi, k) in [(0.3, 20.0), (0.4, 40.0), (0.5, 90.0), (0.1, 5.0)] {
            let full: f64 = simulate(phi, k, 0.0, 0.45, 0.3, &t)
                .iter()
                .zip(&psi)
                .map(|(m, y)| (y - m) * (y - m))
                .sum();
            let support: f64 = simulate_on_support(phi / 2.0, k, &t, &beta)
                .iter()
                .zip(&theta)
                .map(|(m, y)| (y - m) * (y - m))
                .sum();
            // Unbounded: the same sum, bit for bit.
            let sse_below = |bound: f64| {
                squares_below(&psi, bound, |s| integrate(phi, k, 0.0, 0.45, 0.3, &t, s))
            };
            let on_support_below = |bound: f64| {
                squares_below(&theta, bound, |s| {
                    integrate_on_support(phi / 2.0, k, &t, &beta, s)
                })
            };
            let unbounded = sse_below(f64::INFINITY);
            assert_eq!(unbounded.to_bits(), full.to_bits());
            let on = on_support_below(f64::INFINITY);
            assert_eq!(on.to_bits(), support.to_bits());
            // Bounded: below the bound exactly when the full sum is.
            for bound in [full * 0.5, full, full * 2.0 + 1e-12] {
                let b = sse_below(bound);
                assert_eq!(b < bound, full < bound, "{phi} {k} {bound}");
            }
            for bound in [support * 0.5, support * 2.0 + 1e-12] {
                let b = on_support_below(bound);
                assert_eq!(b < bound, support < bound);
            }
        }
    }

    #[test]
    fn spans_longer_than_a_topple_are_not_fitted() {
        // A fall sampled at 30 Hz, stamped in nanoseconds: refused at once (integrating it in
        // 2 ms steps would not end), while the same fall in seconds is fitted.
        let (phi, k) = (0.4, 40.0);
        let t: Vec<f64> = (0..30).map(|i| i as f64 / 30.0).collect();
        let psi = simulate(phi, k, 0.0, phi + 0.05, 0.3, &t);
        assert!(fit_fall(&t, &psi, 1e-3, phi).is_some());
        let t_ns: Vec<f64> = t.iter().map(|x| x * 1e9).collect();
        assert!(fit_fall(&t_ns, &psi, 1e-3, phi).is_none());
        let beta: Vec<f64> = t.iter().map(|x| 0.5 * x).collect();
        assert!(fit_on_support(&t_ns, &psi, &beta, 1e-3, phi).is_none());
    }

    /// A window that a straight line explains within the noise determines no pendulum; the
    /// same window bent by a real fall, at the same noise, does.
    #[test]
    fn uniform_motion_is_not_a_fall() {
        use rand::{rngs::StdRng, SeedableRng};
        use rand_distr::{Distribution, Normal};
        let sigma = 0.01;
        let noise = Normal::new(0.0, sigma).unwrap();
        let mut rng = StdRng::seed_from_u64(3);
        let t: Vec<f64> = (0..15).map(|i| i as f64 / 30.0).collect();
        let line: Vec<f64> = t
            .iter()
            .map(|x| 0.5 + 0.2 * x + noise.sample(&mut rng))
            .collect();
        assert!(uniform_motion_explains(&t, &line, sigma));
        assert!(fit_fall(&t, &line, sigma, 0.4).is_none());
        let fall: Vec<f64> = simulate(0.45, 40.0, 0.0, 0.5, 0.2, &t)
            .iter()
            .map(|y| y + noise.sample(&mut rng))
            .collect();
        assert!(!uniform_motion_explains(&t, &fall, sigma));
        assert!(fit_fall(&t, &fall, sigma, 0.4).is_some());
    }

    /// The bound on a fall's duration is what its documentation derives: a homogeneous box
    /// with its CoM 3.2 m from the edge, released 10⁻⁶ rad past balance, turns 90° in just
    /// under MAX_FALL_S (integrated, not from the closed form).
    #[test]
    fn the_longest_fall_fits_in_max_fall_s() {
        let k = 3.0 * G / (4.0 * 3.2);
        let t: Vec<f64> = (0..=1000).map(|i| i as f64 * MAX_FALL_S / 1000.0).collect();
        let psi = simulate(0.0, k, 0.0, 1e-6, 0.0, &t);
        let at = t[psi.partition_point(|&p| p < std::f64::consts::FRAC_PI_2)];
        assert!(at < MAX_FALL_S && at > 0.9 * MAX_FALL_S, "{at} s");
    }

    #[test]
    fn fall_fit_recovers_phi_and_k() {
        let (phi, k) = (0.45, 55.0);
        let t: Vec<f64> = (0..20).map(|i| i as f64 / 30.0).collect();
        let psi = simulate(phi, k, 0.0, phi + 0.05, 0.3, &t);
        let f = fit_fall(&t, &psi, 1e-4, phi + 0.2).unwrap();
        assert!((f.phi - phi).abs() < 1e-4, "{f:?}");
        assert!((f.k - k).abs() < 0.05, "{f:?}");
    }
}
