//! A pendulum swinging about a fixed edge, its balance angle anywhere: the turn of an object
//! about an edge that nothing but gravity turns, seen from any reference angle.
//!
//! [`super::fit_fall`] fits a topple's fall, whose angle ψ is measured from the face it rested
//! on, so that its balance angle φ lies in (0, π/2). A roll inside a motion ([`crate::roll`])
//! has no such reference: its angle is measured from its first frame, and the object may
//! be past its balance point there or reach it later. The equation of motion is the same,
//! `ψ̈ = k sin(ψ − φ)` with `k > 0` (`k = m g l_p / I_e`), with φ free; a turn that it does
//! not explain was driven by something other than gravity (an impact, a push) or was not
//! about a fixed edge.

use super::{fall_residuals, fall_steps, integrate, levenberg_marquardt, squares_below};

/// The least-squares pendulum of a swing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SwingFit {
    /// Balance angle \[rad\], in the reference of the angles fitted.
    pub phi: f64,
    /// `k = m g l_p / I_e` \[1/s²\].
    pub k: f64,
    /// The state (ψ, ψ̇) at the first sample.
    pub state: [f64; 2],
    /// Residual sum of squares \[rad²\].
    pub sse: f64,
}

/// Balance angles \[rad\] of the starting grid, relative to the first angle and in the
/// direction the angle turns: the object may have passed its balance (negative) or reach it
/// later, within a quarter turn either way and a little more.
const GRID_PHI_RAD: [f64; 9] = [-2.0, -1.5, -1.0, -0.6, -0.3, 0.0, 0.3, 0.8, 1.6];

/// Starting `k` \[1/s²\] of the grid: from an object whose centre of mass is a metre from its
/// edge to one a centimetre from it (`k ≈ 3g / (4 l_p)` for a homogeneous box).
const GRID_K: [f64; 7] = [4.0, 10.0, 25.0, 60.0, 150.0, 400.0, 1000.0];

/// Levenberg-Marquardt runs started from the best grid points (the sum of squares has local
/// minima in φ).
const STARTS: usize = 3;

/// Fit `ψ̈ = k sin(ψ − φ)` (`k > 0`, φ free) to the angles `psi` \[rad\] at the times `t`
/// \[s\]: the best of Levenberg-Marquardt runs from the best points of a grid over (φ, k), the
/// state at the first sample started from the first samples' differences. `None` with fewer
/// than five samples (four parameters), over more than [`super::MAX_FALL_S`] or on times that
/// do not increase.
pub fn fit_swing(t: &[f64], psi: &[f64]) -> Option<SwingFit> {
    let n = t.len();
    if n < 5 || psi.len() != n || t[n - 1] - t[0] > super::MAX_FALL_S {
        return None;
    }
    if t.windows(2).any(|w| w[1] <= w[0]) {
        return None;
    }
    let rate = (psi[1] - psi[0]) / (t[1] - t[0]);
    let way = if psi[n - 1] >= psi[0] { 1.0 } else { -1.0 };
    let mut grid: Vec<(f64, f64, f64)> = Vec::new();
    for d in GRID_PHI_RAD {
        let phi = psi[0] + way * d;
        for k in GRID_K {
            let bound = grid.get(STARTS - 1).map_or(f64::INFINITY, |g| g.0);
            let s = squares_below(psi, bound, |sample| {
                integrate(phi, k, t[0], psi[0], rate, t, sample)
            });
            if s < bound {
                grid.push((s, phi, k));
                grid.sort_by(|a, b| a.0.total_cmp(&b.0));
                grid.truncate(STARTS);
            }
        }
    }
    grid.iter()
        .map(|&(_, phi, k)| {
            let (p, sse, _) = levenberg_marquardt(
                [phi, k, psi[0], rate],
                fall_residuals(t, psi, None),
                fall_steps,
                |q| [q[0], q[1].max(1e-3), q[2], q[3]],
            );
            SwingFit {
                phi: p[0],
                k: p[1],
                state: [p[2], p[3]],
                sse,
            }
        })
        .filter(|f| f.sse.is_finite())
        .min_by(|a, b| a.sse.total_cmp(&b.sse))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pendulum::simulate;
    use rand::{rngs::StdRng, Rng, SeedableRng};
    use rand_distr::{Distribution, Normal};

    /// Swings simulated from the model, from any reference angle, balance before or after the
    /// first sample, either way, under noise: the fit's sum of squares is what the noise
    /// leaves (χ² within its 0.1% quantile for 4 parameters; at most 1 of 200 or more beyond it).
    #[test]
    fn a_simulated_swing_is_fitted_to_its_noise() {
        let mut rng = StdRng::seed_from_u64(11);
        let (mut beyond, mut tried) = (0, 0);
        for _ in 0..300 {
            let dt = [1.0 / 30.0, 1.0 / 120.0, 1.0 / 250.0][rng.random_range(0..3)];
            let phi = rng.random_range(-3.0..3.0);
            let k = rng.random_range(20.0..400.0);
            let psi0 = phi + rng.random_range(0.02..0.6) * if rng.random() { 1.0 } else { -1.0 };
            let rate = rng.random_range(-3.0..3.0);
            // Up to 0.4 s, and a roll's turn: at most a quarter turn and a little more.
            let t: Vec<f64> = (0..(0.4 / dt) as usize)
                .map(|i| 0.3 + i as f64 * dt)
                .collect();
            let clean = simulate(phi, k, t[0], psi0, rate, &t);
            let n = clean.iter().take_while(|x| (*x - psi0).abs() < 1.8).count();
            if n < 5 {
                continue;
            }
            let sigma = rng.random_range(1e-3..1e-2);
            let noise = Normal::new(0.0, sigma).unwrap();
            let t = &t[..n];
            let psi: Vec<f64> = clean[..n]
                .iter()
                .map(|x| x + noise.sample(&mut rng))
                .collect();
            tried += 1;
            let f = fit_swing(t, &psi).expect("fitted");
            let chi2 = f.sse / (sigma * sigma);
            if chi2 > crate::stats::chi2_threshold((n - 4) as f64, 1e-3) {
                beyond += 1;
            }
        }
        assert!(tried >= 200, "{tried}");
        assert!(beyond <= 1, "{beyond} of {tried} beyond the 0.1% quantile");
    }

    /// A turn that stops at once, as a face landing on the support stops it, is no pendulum's:
    /// a swing falling faster and faster, then still for its last frames.
    #[test]
    fn a_turn_stopped_by_an_impact_is_not_a_swing() {
        let t: Vec<f64> = (0..10).map(|i| i as f64 / 30.0).collect();
        let mut psi = simulate(-0.2, 120.0, 0.0, 0.0, 1.0, &t);
        let landed = psi[6];
        for x in &mut psi[7..] {
            *x = landed;
        }
        let f = fit_swing(&t, &psi).expect("fitted");
        let sigma: f64 = 0.0087;
        let chi2 = f.sse / (sigma * sigma);
        assert!(chi2 > crate::stats::chi2_threshold(6.0, 1e-3), "χ² {chi2}");
    }
}
