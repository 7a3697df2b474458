//! The statistics of moving frames: each frame's pose relative to its segment's reference,
//! its SE(3) logarithm and what it adds to its block's line and plane sums (see
//! [`super::blocks`]), and the per-frame noise model they are weighted with.

use super::blocks::{
    Block, MAX_AXIS_DISTANCE_M, MIN_AXIS_SNR, REFERENCE_SETTLING_M, REFERENCE_SETTLING_RAD,
};
use crate::geometry::{Line, LineStats, PlaneStats, Sym3};
use crate::noise::NoiseModel;
use crate::se3::Twist;
use nalgebra::{UnitQuaternion, Vector3};

/// The moving-frame statistics of the last block while it takes frames, added to the block
/// when it is closed ([`OpenSums::close_into`]): the sums of the frames added so far, and the
/// frames waiting to be added (see [`OpenSums::push`]), by their poses relative to the
/// segment reference.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct OpenSums {
    sums: MovingSums,
    pending: usize,
    pending_t: [Vector3<f64>; PENDING_FRAMES],
    pending_q: [UnitQuaternion<f64>; PENDING_FRAMES],
}

/// Moving frames whose logarithms are taken together (see [`OpenSums::push`]).
const PENDING_FRAMES: usize = 16;

/// A block's moving-frame statistics in compact form (symmetric matrices by their 6 distinct
/// entries, see [`Sym3`]).
///
/// The plane sums are kept unweighted (`Σ ω ωᵀ`, `Σ t tᵀ`: the weights 1/σ² are the same for
/// every frame and are applied on closing) and `Σ a u uᵀ` is taken as `Σ ω ωᵀ/D` with
/// `D = θ²/a` (see [`MovingSums::add`]), so that `ω ωᵀ` serves both; the axis of the largest
/// rotation is kept as its twist and made a [`Line`] on closing.
#[derive(Clone, Copy, Debug, Default)]
struct MovingSums {
    /// Frames measurably displaced from the segment reference.
    significant: u64,
    /// Σ ω ωᵀ \[rad²\] and Σ t tᵀ \[m²\] over those frames.
    sum_ww: Sym3,
    sum_tt: Sym3,
    /// [`LineStats`]: n, Σ w, Σ w², Σ w r, Σ w r rᵀ, Σ a, Σ a², Σ a u uᵀ, Σ pitch χ², Σ w / c.
    line_n: f64,
    sw: f64,
    sww: f64,
    swr: Vector3<f64>,
    swrr: Sym3,
    sa: f64,
    saa: f64,
    sauu: Sym3,
    pitch_chi2: f64,
    sw_inv_chord: f64,
    /// Largest rotation \[rad\] among the frames with an axis, and the twist of that frame.
    max_angle: f64,
    max_twist: Option<Twist>,
}

impl OpenSums {
    /// Take a moving frame, its pose `(t_rel, q_rel)` relative to the segment reference (`m`
    /// the frame model). Frames are added [`PENDING_FRAMES`] at a time, their logarithms first
    /// and then their statistics ([`MovingSums::add`]), in frame order: each frame is a long
    /// chain of dependent operations (square roots, divisions, the arc tangent), and so the
    /// processor works on several at once (a fifth less time per frame than one by one).
    #[inline]
    pub(super) fn push(
        &mut self,
        t_rel: &Vector3<f64>,
        q_rel: &UnitQuaternion<f64>,
        m: &FrameModel,
    ) {
        let k = self.pending;
        self.pending_t[k] = *t_rel;
        self.pending_q[k] = *q_rel;
        self.pending += 1;
        if self.pending == PENDING_FRAMES {
            self.add_pending(m);
        }
    }

    /// Add the pending frames.
    #[inline(never)]
    fn add_pending(&mut self, m: &FrameModel) {
        let n = std::mem::take(&mut self.pending);
        if n == 0 {
            return;
        }
        let mut xi = [Twist::new(Vector3::zeros(), Vector3::zeros()); PENDING_FRAMES];
        for (x, (q, t)) in xi
            .iter_mut()
            .zip(self.pending_q.iter().zip(&self.pending_t))
            .take(n)
        {
            *x = Twist::log_quat(q, t);
        }
        for (k, x) in xi.iter().enumerate().take(n) {
            self.sums.add(x, &self.pending_t[k], &self.pending_q[k], m);
        }
    }

    /// Add the sums to `b` (the block they were taken for; `m` the frame model they were
    /// taken with) and start afresh.
    pub(super) fn close_into(&mut self, b: &mut Block, m: &FrameModel) {
        self.add_pending(m);
        if self.sums.significant > 0 {
            std::mem::take(&mut self.sums).close_into(b, m);
        }
    }
}

impl MovingSums {
    /// Add a moving frame with twist `xi` and pose `(t_rel, q_rel)` relative to the segment
    /// reference, as [`Segmenter::moving`] describes.
    ///
    /// Its quantities are computed with three independent divisions and two square roots (the
    /// divider is the bottleneck, with the logarithm's), and with `g = ω × v = θ² r`:
    ///
    /// * `w = c²/E` with `E = σ_p² + s_p² + (σ_r² + s_r²) d² + tol_p² c²`, taken as
    ///   `w/θ⁴ = c²/(θ⁴ E)`, `θ⁴ E = θ⁴ (σ_p² + s_p² + tol_p² c²) + (σ_r² + s_r²) θ⁴ d²` and
    ///   `θ⁴ d² = min(|g|², θ⁴ MAX_AXIS_DISTANCE_M²)`; then `w r = (w/θ⁴) θ² g`,
    ///   `w r rᵀ = (w/θ⁴) g gᵀ` and `w/c = c θ⁴/(θ⁴ E)`,
    /// * `a = θ²/D` with `D = σ_r² + s_r² + tol_r² θ²`, so `a u uᵀ = ω ωᵀ/D`,
    /// * `(u·t)² = (ω·t)²/θ²`;
    ///
    /// u and r themselves are only formed for the block's largest rotation.
    #[inline(always)]
    fn add(
        &mut self,
        xi: &Twist,
        t_rel: &Vector3<f64>,
        q_rel: &UnitQuaternion<f64>,
        m: &FrameModel,
    ) {
        let omega = xi.omega;
        let theta2 = omega.norm_squared();
        let chi2_r = theta2 * m.inv_var_r;
        let significant = chi2_r + t_rel.norm_squared() * m.inv_var_p > m.displaced;
        if !significant {
            return;
        }
        let o = self;
        o.significant += 1;
        let ww = Sym3::square(&omega);
        o.sum_ww.add(&ww);
        o.sum_tt.add_product(t_rel, t_rel);
        // An axis only from a rotation well above the noise: the axis point's bias is of
        // order (σ_r/θ)² relative, kept below 1% by θ >= 10 σ_r (MIN_AXIS_SNR).
        if chi2_r <= m.axis_chi2 {
            return;
        }
        // With g = ω × v = θ² r, everything over θ⁴ so that no division waits for another:
        // θ⁴ d² = min(|g|², θ⁴ MAX_AXIS_DISTANCE_M²), θ⁴ E, and w r rᵀ = (w/θ⁴) g gᵀ.
        let g = omega.cross(&xi.v);
        let theta4 = theta2 * theta2;
        let g2 = g
            .norm_squared()
            .min(MAX_AXIS_DISTANCE_M * MAX_AXIS_DISTANCE_M * theta4);
        // Chord 2 sin(θ/2) = 2 |imag(q_rel)|, from the quaternion (no sine).
        let chord2 = 4.0 * q_rel.quaternion().imag().norm_squared();
        // The pose from which the rotation starts is uncertain by the noise and by the
        // contacts settling as the load moves onto the edge (REFERENCE_SETTLING_*); its
        // effect on the axis shrinks as 1/θ. The tolerance adds a constant wander.
        let inv_e4 = 1.0 / (theta4 * (m.ref_var_p + m.tol_p2 * chord2) + m.ref_var_r * g2);
        let inv_d = 1.0 / (m.ref_var_r + m.tol_r2 * theta2);
        let w_4 = chord2 * inv_e4; // w/θ⁴
        let w = w_4 * theta4;
        let a = theta2 * inv_d;
        let wt = omega.dot(t_rel);
        o.line_n += 1.0;
        o.sw += w;
        o.sww += w * w;
        o.swr += g * (w_4 * theta2);
        o.swrr.add_product(&(g * w_4), &g);
        o.sa += a;
        o.saa += a * a;
        o.sauu.add_scaled(&ww, inv_d);
        o.pitch_chi2 += wt * wt * m.w_p / theta2;
        o.sw_inv_chord += chord2.sqrt() * theta4 * inv_e4;
        let theta = theta2.sqrt();
        if theta > o.max_angle {
            o.max_angle = theta;
            o.max_twist = Some(*xi);
        }
    }

    /// Add the sums to `b` (the block they were taken for; `m` the frame model they were
    /// taken with).
    fn close_into(self, b: &mut Block, m: &FrameModel) {
        b.significant += self.significant;
        b.plane.merge(&PlaneStats {
            n: self.significant as f64,
            sww: self.sum_ww.to_matrix() * m.w_r,
            stt: self.sum_tt.to_matrix() * m.w_p,
        });
        b.line.merge(&LineStats {
            n: self.line_n,
            sw: self.sw,
            sww: self.sww,
            swr: self.swr,
            swrr: self.swrr.to_matrix(),
            sa: self.sa,
            saa: self.saa,
            sauu: self.sauu.to_matrix(),
            pitch_chi2: self.pitch_chi2,
            sw_inv_chord: self.sw_inv_chord,
        });
        if let Some(xi) = self.max_twist.filter(|_| self.max_angle > b.max_angle) {
            let theta = self.max_angle;
            b.max_angle = theta;
            // The screw axis: r = ω × v / θ² is its point closest to the origin (r ⊥ u).
            let line = Line {
                point: xi.omega.cross(&xi.v) * (1.0 / (theta * theta)),
                direction: xi.omega / theta,
            };
            b.max_line = Some((line, xi.omega));
        }
    }
}

/// Per-frame variances and the χ² levels, shared by the block statistics; with the derived
/// weights (inverse variances) the per-frame work uses, so that it multiplies instead of
/// dividing.
#[derive(Clone, Copy, Debug)]
pub(super) struct FrameModel {
    /// Position noise variance σ_p² \[m²\].
    pub(super) var_p: f64,
    /// Rotation noise variance σ_r² \[rad²\].
    pub(super) var_r: f64,
    /// Squared model tolerances \[m²\], \[rad²\].
    pub(super) tol_p2: f64,
    pub(super) tol_r2: f64,
    /// χ²₆ level of a pose displaced from the reference.
    pub(super) displaced: f64,
    /// 1/σ_p² \[1/m²\] and 1/σ_r² \[1/rad²\] (significance test).
    pub(super) inv_var_p: f64,
    pub(super) inv_var_r: f64,
    /// 1/(σ_p² + tol_p²) \[1/m²\] and 1/(σ_r² + tol_r²) \[1/rad²\]: plane weights, pitch χ².
    pub(super) w_p: f64,
    pub(super) w_r: f64,
    /// Smallest θ²/σ_r² from which a frame's screw axis is used: the larger of the χ²₃ level
    /// of a rotation and [`MIN_AXIS_SNR`]².
    pub(super) axis_chi2: f64,
    /// Variances of the reference pose, noise plus settling: σ_p² + s_p² \[m²\],
    /// σ_r² + s_r² \[rad²\] (see [`REFERENCE_SETTLING_M`], [`REFERENCE_SETTLING_RAD`]).
    pub(super) ref_var_p: f64,
    pub(super) ref_var_r: f64,
}

impl FrameModel {
    pub(super) fn new(n: &NoiseModel, r: &super::RobustConfig) -> Self {
        let var_p = n.sigma_position.powi(2);
        let var_r = n.sigma_rotation.powi(2);
        let tol_p2 = r.edge_tolerance_m.powi(2);
        let tol_r2 = r.edge_tolerance_rad.powi(2);
        let rotated = crate::stats::chi2_threshold(3.0, r.alpha);
        Self {
            var_p,
            var_r,
            tol_p2,
            tol_r2,
            displaced: crate::stats::chi2_threshold(6.0, r.alpha),
            inv_var_p: 1.0 / var_p,
            inv_var_r: 1.0 / var_r,
            w_p: 1.0 / (var_p + tol_p2),
            w_r: 1.0 / (var_r + tol_r2),
            axis_chi2: rotated.max(MIN_AXIS_SNR * MIN_AXIS_SNR),
            ref_var_p: var_p + REFERENCE_SETTLING_M * REFERENCE_SETTLING_M,
            ref_var_r: var_r + REFERENCE_SETTLING_RAD * REFERENCE_SETTLING_RAD,
        }
    }
}
