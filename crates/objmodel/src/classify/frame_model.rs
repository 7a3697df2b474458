//! The per-frame model of the robust method: a moving frame's motion relative to its
//! segment's reference pose, its screw, and the noise model its statistics are weighted with.
//!
//! Relative to the segment reference `(R_ref, p_ref)` the frame is `q_rel = q_ref⁻¹ q`,
//! `t = R_refᵀ (p - p_ref)`, with twist `(v, ω) = log(q_rel, t)` and θ² = |ω|². It is
//! significant (it votes) when `θ²/σ_r² + |t|²/σ_p²` exceeds the χ²₆ level; then it enters the
//! plane statistics, and, when `θ²/σ_r²` also exceeds [`FrameModel::axis_chi2`], the line
//! statistics with its screw axis: direction `u = ω/θ`, point `r = ω × v / θ²` (closest to the
//! origin), chord `c² = (2 sin(θ/2))² = 4|imag(q_rel)|²`, weights
//!
//! * point: `w = 1/σ²_point`, `σ²_point = (σ_p² + s_p² + (σ_r² + s_r²) d²)/c² + tol_p²`,
//!   with `d = min(|r|, MAX_AXIS_DISTANCE_M)` and `s_p`, `s_r` the reference settling,
//! * direction: `a = 1/σ²_dir`, `σ²_dir = (σ_r² + s_r²)/θ² + tol_r²`,
//! * pitch χ²: `(u·t)²/(σ_p² + tol_p²)`.
//!
//! (The sums of these terms over a block's frames are taken sixteen frames at a time, in the
//! crate's speed code, which computes them as stated.)

use super::RobustConfig;
use crate::noise::NoiseModel;

/// Smallest rotation, in units of the rotation noise σ_r, from which a frame's screw axis is
/// used: the axis estimate's bias is of order (σ_r/θ)² relative, 1% at 10 σ_r.
pub const MIN_AXIS_SNR: f64 = 10.0;
/// How far \[m\] a resting object's contact settles when it starts to turn onto an edge (the
/// load concentrates on the edge; rigid-body simulators and real compliant contacts both show
/// about 0.1 mm): an uncertainty of the reference pose, whose effect on the axis shrinks as 1/θ.
pub const REFERENCE_SETTLING_M: f64 = 1e-4;
/// The same for orientation \[rad\] (0.2°).
pub const REFERENCE_SETTLING_RAD: f64 = 3.5e-3;
/// Upper bound \[m\] on the axis distance used in the axis-point variance (beyond the palm the
/// frame cannot be a topple anyway; this keeps far-away axes from underflowing the weight).
pub const MAX_AXIS_DISTANCE_M: f64 = 10.0;

/// Per-frame variances and the χ² levels, shared by the block statistics; with the derived
/// weights (inverse variances) the per-frame work uses, so that it multiplies instead of
/// dividing.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FrameModel {
    /// Position noise variance σ_p² \[m²\].
    pub(crate) var_p: f64,
    /// Rotation noise variance σ_r² \[rad²\].
    pub(crate) var_r: f64,
    /// Squared model tolerances \[m²\], \[rad²\].
    pub(crate) tol_p2: f64,
    pub(crate) tol_r2: f64,
    /// χ²₆ level of a pose displaced from the reference.
    pub(crate) displaced: f64,
    /// 1/σ_p² \[1/m²\] and 1/σ_r² \[1/rad²\] (significance test).
    pub(crate) inv_var_p: f64,
    pub(crate) inv_var_r: f64,
    /// 1/(σ_p² + tol_p²) \[1/m²\] and 1/(σ_r² + tol_r²) \[1/rad²\]: plane weights, pitch χ².
    pub(crate) w_p: f64,
    pub(crate) w_r: f64,
    /// Smallest θ²/σ_r² from which a frame's screw axis is used: the larger of the χ²₃ level
    /// of a rotation and [`MIN_AXIS_SNR`]².
    pub(crate) axis_chi2: f64,
    /// Variances of the reference pose, noise plus settling: σ_p² + s_p² \[m²\],
    /// σ_r² + s_r² \[rad²\] (see [`REFERENCE_SETTLING_M`], [`REFERENCE_SETTLING_RAD`]).
    pub(crate) ref_var_p: f64,
    pub(crate) ref_var_r: f64,
}

impl FrameModel {
    pub(crate) fn new(n: &NoiseModel, r: &RobustConfig) -> Self {
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
