//! A segment's moving-frame sums, sixteen frames at a time: each frame's logarithm and the
//! terms of its block's line and plane statistics, four frames to a step (the per-frame model
//! they compute is `crate::classify`'s [`FrameModel`]; the frame-by-frame reference is in the
//! tests).

use super::avx2_or_baseline;
use super::lanes::{dot, scale, F4, M4, V4};
use super::twist4::Twist4;
use crate::classify::frame_model::{FrameModel, MAX_AXIS_DISTANCE_M};
use crate::geometry::{LineStats, PlaneStats, Sym3};
use crate::screw::moments;
use crate::se3::Twist;
use nalgebra::{UnitQuaternion, Vector3};

/// What a block's moving frames add to its statistics (see [`MovingFrameSums::close`]).
#[derive(Clone, Copy, Debug)]
pub struct MovingStats {
    /// Frames measurably displaced from the segment reference (they vote).
    pub significant: u64,
    /// Their line statistics (the frames with an axis).
    pub line: LineStats,
    /// Their plane statistics.
    pub plane: PlaneStats,
    /// The largest rotation \[rad\] among the frames with an axis, and that frame's twist.
    pub largest: Option<(f64, Twist)>,
}

/// The moving-frame statistics of the last block while it takes frames, handed to the block
/// when it is closed ([`MovingFrameSums::close`]): the sums of the frames added so far, and the
/// frames waiting to be added (see [`MovingFrameSums::push`]), by their poses relative to the
/// segment reference.
#[derive(Clone, Copy, Debug, Default)]
pub struct MovingFrameSums {
    sums: LaneSums,
    pending: usize,
    /// The pending frames by coordinate, four to an [`F4`] (frame `k` is lane `k % 4` of
    /// group `k / 4`), so that a kernel loads them as they are: translations `x, y, z`, and
    /// quaternions `w, x, y, z`.
    pending_t: [[F4; PENDING_GROUPS]; 3],
    pending_q: [[F4; PENDING_GROUPS]; 4],
}

/// Moving frames whose logarithms are taken together (see [`MovingFrameSums::push`]).
const PENDING_FRAMES: usize = 16;
/// Groups of four frames among them.
const PENDING_GROUPS: usize = PENDING_FRAMES / 4;

/// A block's moving-frame statistics in compact form: symmetric matrices by their 6 distinct
/// entries (ordered as [`Sym3`]), and every sum in four lanes, lane `k` over the frames that
/// were in lane `k` of a [`FrameTerms`]. The lanes are added up on closing
/// ([`LaneSums::close`]), so a sum over n frames is rounded as four partial sums and
/// their total, not as one running sum (the same results to about 1e-16 relative).
///
/// The plane sums are kept unweighted (`Σ ω ωᵀ`, `Σ t tᵀ`: the weights 1/σ² are the same for
/// every frame and are applied on closing) and `Σ a u uᵀ` is taken as `Σ ω ωᵀ/D` with
/// `D = θ²/a` (see [`FrameTerms`]), so that `ω ωᵀ` serves both; the axis of the largest
/// rotation is kept as its twist and made a [`crate::geometry::Line`] on closing.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct LaneSums {
    /// Frames measurably displaced from the segment reference.
    significant: u64,
    /// Σ ω ωᵀ \[rad²\] and Σ t tᵀ \[m²\] over those frames.
    sum_ww: [F4; 6],
    sum_tt: [F4; 6],
    /// [`LineStats`]: n, Σ w, Σ w², Σ w r, Σ w r rᵀ, Σ a, Σ a², Σ a u uᵀ, Σ pitch χ², Σ w / c.
    line_n: F4,
    sw: F4,
    sww: F4,
    swr: V4,
    swrr: [F4; 6],
    sa: F4,
    saa: F4,
    sauu: [F4; 6],
    pitch_chi2: F4,
    sw_inv_chord: F4,
    /// Largest rotation \[rad\] among the frames with an axis, and the twist of that frame.
    max_angle: f64,
    max_twist: Option<Twist>,
}

impl MovingFrameSums {
    /// Take a moving frame, its pose `(t_rel, q_rel)` relative to the segment reference (`m`
    /// the frame model). Frames are added [`PENDING_FRAMES`] at a time, four in each step of
    /// the kernel ([`FrameTerms`], [`LaneSums::add`]): each frame is a long chain of
    /// dependent operations (square roots, divisions, the arc tangent), which four frames then
    /// share (back end 62 → 42 ns a frame on the benchmark file, against frame by frame).
    #[inline]
    pub fn push(&mut self, t_rel: &Vector3<f64>, q_rel: &UnitQuaternion<f64>, m: &FrameModel) {
        let q = q_rel.quaternion();
        self.set_pending(self.pending, [q.w, q.i, q.j, q.k], (*t_rel).into());
        self.pending += 1;
        if self.pending == PENDING_FRAMES {
            self.add_pending(m);
        }
    }

    /// Pending frame `k`: its rotation `(w, x, y, z)` and translation \[m\].
    #[inline(always)]
    fn set_pending(&mut self, k: usize, q: [f64; 4], t: [f64; 3]) {
        let (g, l) = (k / 4, k % 4);
        for (lanes, x) in self.pending_q.iter_mut().zip(q) {
            lanes[g].0[l] = x;
        }
        for (lanes, x) in self.pending_t.iter_mut().zip(t) {
            lanes[g].0[l] = x;
        }
    }

    /// Add the pending frames, four at a time through [`FrameTerms`] into the four lanes of
    /// the sums (in AVX2 code when the processor has it). Missing frames of the last four are
    /// identities, computed and masked out.
    #[inline(never)]
    fn add_pending(&mut self, m: &FrameModel) {
        let n = std::mem::take(&mut self.pending);
        if n == 0 {
            return;
        }
        avx2_or_baseline!(self.add_pending_lanes(n, m));
    }

    #[inline(always)]
    fn add_pending_lanes(&mut self, n: usize, m: &FrameModel) {
        // Identities after the last frame, to fill its group.
        for k in n..n.next_multiple_of(4) {
            self.set_pending(k, [1.0, 0.0, 0.0, 0.0], [0.0; 3]);
        }
        for g in 0..n.div_ceil(4) {
            let first = 4 * g;
            let pad = |k: usize| first + k >= n;
            let (q, t) = (&self.pending_q, &self.pending_t);
            let (qw, qv): (F4, V4) = (q[0][g], [q[1][g], q[2][g], q[3][g]]);
            let t: V4 = [t[0][g], t[1][g], t[2][g]];
            let valid = M4([true, !pad(1), !pad(2), !pad(3)]);
            self.sums.add(&FrameTerms::new(qw, &qv, &t, valid, m));
        }
    }

    /// The statistics of the frames pushed since the last call (`m` the frame model they were
    /// pushed with), if any was significant; start afresh.
    pub fn close(&mut self, m: &FrameModel) -> Option<MovingStats> {
        self.add_pending(m);
        (self.sums.significant > 0).then(|| std::mem::take(&mut self.sums).close(m))
    }
}

impl LaneSums {
    /// Add four moving frames' terms (as [`FrameModel`] describes them), each into its lane.
    #[inline(always)]
    fn add(&mut self, f: &FrameTerms) {
        let o = self;
        let zero = F4::splat(0.0);
        // What a frame adds only when it is displaced, or (`line`) also has an axis: an axis
        // only from a rotation well above the noise, since the axis point's bias is of order
        // (σ_r/θ)² relative, kept below 1% by θ >= 10 σ_r (MIN_AXIS_SNR).
        let sig = f.significant;
        let line = sig & f.axis;
        let add = |acc: &mut F4, mask: M4, x: F4| *acc = *acc + mask.select(x, zero);
        let m = sig.0;
        o.significant += m[0] as u64 + m[1] as u64 + m[2] as u64 + m[3] as u64;
        for i in 0..6 {
            add(&mut o.sum_ww[i], sig, f.ww[i]);
            add(&mut o.sum_tt[i], sig, f.tt[i]);
            add(&mut o.swrr[i], line, f.wrr[i]);
            add(&mut o.sauu[i], line, f.auu[i]);
        }
        for i in 0..3 {
            add(&mut o.swr[i], line, f.wr[i]);
        }
        add(&mut o.line_n, line, F4::splat(1.0));
        add(&mut o.sw, line, f.w);
        add(&mut o.sww, line, f.w * f.w);
        add(&mut o.sa, line, f.a);
        add(&mut o.saa, line, f.a * f.a);
        add(&mut o.pitch_chi2, line, f.pitch_chi2);
        add(&mut o.sw_inv_chord, line, f.w_inv_chord);
        // The largest rotation: the first frame of the largest angle, as frame by frame.
        if (line & f.theta.gt(F4::splat(o.max_angle))).any() {
            for k in 0..4 {
                if line.0[k] && f.theta.0[k] > o.max_angle {
                    o.max_angle = f.theta.0[k];
                    o.max_twist = Some(f.xi.lane(k));
                }
            }
        }
    }

    /// The statistics, the lanes added up (`m` the frame model they were taken with).
    fn close(self, m: &FrameModel) -> MovingStats {
        let sym = |x: &[F4; 6]| Sym3([0, 1, 2, 3, 4, 5].map(|i| total(x[i]))).to_matrix();
        MovingStats {
            significant: self.significant,
            plane: PlaneStats {
                n: self.significant as f64,
                sww: sym(&self.sum_ww) * m.w_r,
                stt: sym(&self.sum_tt) * m.w_p,
            },
            line: LineStats {
                n: total(self.line_n),
                sw: total(self.sw),
                sww: total(self.sww),
                swr: Vector3::new(total(self.swr[0]), total(self.swr[1]), total(self.swr[2])),
                swrr: sym(&self.swrr),
                sa: total(self.sa),
                saa: total(self.saa),
                sauu: sym(&self.sauu),
                pitch_chi2: total(self.pitch_chi2),
                sw_inv_chord: total(self.sw_inv_chord),
            },
            largest: self.max_twist.map(|xi| (self.max_angle, xi)),
        }
    }
}

/// The sum of the lanes, `(x₀ + x₁) + (x₂ + x₃)`.
#[inline]
fn total(x: F4) -> f64 {
    let [a, b, c, d] = x.0;
    (a + b) + (c + d)
}

/// What four moving frames add to a block's [`LaneSums`], lane by lane: each frame's
/// logarithm and the terms of its sums, computed together (see [`super::lanes`]) and added one
/// in lanes ([`LaneSums::add`]).
///
/// For a frame with twist `ξ = (v, ω)` and pose `(t, q)` relative to the segment reference,
/// with `θ² = |ω|²` and `g = ω × v = θ² r` (r the axis point), the quantities take three
/// independent divisions and two square roots (the divider is the bottleneck, with the
/// logarithm's):
///
/// * `w = c²/E` with `E = σ_p² + s_p² + (σ_r² + s_r²) d² + tol_p² c²`, taken as
///   `w/θ⁴ = c²/(θ⁴ E)`, `θ⁴ E = θ⁴ (σ_p² + s_p² + tol_p² c²) + (σ_r² + s_r²) θ⁴ d²` and
///   `θ⁴ d² = min(|g|², θ⁴ MAX_AXIS_DISTANCE_M²)`; then `w r = (w/θ⁴) θ² g`,
///   `w r rᵀ = (w/θ⁴) g gᵀ` and `w/c = c θ⁴/(θ⁴ E)`,
/// * `a = θ²/D` with `D = σ_r² + s_r² + tol_r² θ²`, so `a u uᵀ = ω ωᵀ/D`,
/// * `(u·t)² = (ω·t)²/θ²`;
///
/// u and r themselves are only formed for the block's largest rotation.
struct FrameTerms {
    /// The frame is measurably displaced from the reference (it votes).
    significant: M4,
    /// Its rotation is large enough for an axis (θ²/σ_r² above [`FrameModel::axis_chi2`]).
    axis: M4,
    /// `ω ωᵀ`, `t tᵀ` (upper triangles, as [`Sym3`]).
    ww: [F4; 6],
    tt: [F4; 6],
    /// `w`, `w r`, `w r rᵀ`, `a`, `a u uᵀ`, the pitch χ² term, `w/c`, θ.
    w: F4,
    wr: V4,
    wrr: [F4; 6],
    a: F4,
    auu: [F4; 6],
    pitch_chi2: F4,
    w_inv_chord: F4,
    theta: F4,
    /// The twists (for the block's largest rotation).
    xi: Twist4,
}

impl FrameTerms {
    /// The terms of four frames, poses `(t, q)` relative to the segment reference (quaternions
    /// by their scalar and vector parts `qw`, `qv`); lanes outside `valid` add nothing.
    #[inline(always)]
    fn new(qw: F4, qv: &V4, t: &V4, valid: M4, m: &FrameModel) -> Self {
        let xi = Twist4::log_quat(qw, qv, t);
        let omega = &xi.omega;
        let theta2 = dot(omega, omega);
        let chi2_r = theta2 * m.inv_var_r;
        let significant = valid & (chi2_r + dot(t, t) * m.inv_var_p).gt(F4::splat(m.displaced));
        let axis = !chi2_r.le(F4::splat(m.axis_chi2));
        // With g = ω × v = θ² r, everything over θ⁴ so that no division waits for another:
        // θ⁴ d² = min(|g|², θ⁴ MAX_AXIS_DISTANCE_M²), θ⁴ E, and w r rᵀ = (w/θ⁴) g gᵀ.
        let g = moments(omega, &xi.v).moment;
        let theta4 = theta2 * theta2;
        let g2 = dot(&g, &g).min(theta4 * (MAX_AXIS_DISTANCE_M * MAX_AXIS_DISTANCE_M));
        // Chord 2 sin(θ/2) = 2 |imag(q)|, from the quaternion (no sine).
        let chord2 = dot(qv, qv) * 4.0;
        // The pose from which the rotation starts is uncertain by the noise and by the
        // contacts settling as the load moves onto the edge (REFERENCE_SETTLING_*); its
        // effect on the axis shrinks as 1/θ. The tolerance adds a constant wander.
        let inv_e4 = 1.0 / (theta4 * (chord2 * m.tol_p2 + m.ref_var_p) + g2 * m.ref_var_r);
        let inv_d = 1.0 / (theta2 * m.tol_r2 + m.ref_var_r);
        let w_4 = chord2 * inv_e4; // w/θ⁴
        let wt = dot(omega, t);
        let gw = scale(&g, w_4);
        let ww = upper(omega, omega);
        Self {
            significant,
            axis,
            ww,
            tt: upper(t, t),
            w: w_4 * theta4,
            wr: scale(&g, w_4 * theta2),
            wrr: upper(&gw, &g),
            a: theta2 * inv_d,
            auu: [
                ww[0] * inv_d,
                ww[1] * inv_d,
                ww[2] * inv_d,
                ww[3] * inv_d,
                ww[4] * inv_d,
                ww[5] * inv_d,
            ],
            pitch_chi2: wt * wt * m.w_p / theta2,
            w_inv_chord: chord2.sqrt() * theta4 * inv_e4,
            theta: theta2.sqrt(),
            xi,
        }
    }
}

/// The upper triangle of `y xᵀ` (entries `y_i x_j`, i ≤ j), lane by lane, ordered as [`Sym3`].
#[inline(always)]
fn upper(y: &V4, x: &V4) -> [F4; 6] {
    [
        y[0] * x[0],
        y[0] * x[1],
        y[0] * x[2],
        y[1] * x[1],
        y[1] * x[2],
        y[2] * x[2],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::noise::NoiseModel;

    /// The frame-by-frame sums, as one running sum each (the original of [`FrameTerms`] and
    /// [`LaneSums::add`]).
    #[derive(Default)]
    struct Reference {
        significant: u64,
        sum_ww: Sym3,
        sum_tt: Sym3,
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
        max_angle: f64,
        max_twist: Option<Twist>,
    }

    fn add_one(
        o: &mut Reference,
        t_rel: &Vector3<f64>,
        q_rel: &UnitQuaternion<f64>,
        m: &FrameModel,
    ) {
        let xi = Twist::log_quat(q_rel, t_rel);
        let omega = xi.omega;
        let theta2 = omega.norm_squared();
        let chi2_r = theta2 * m.inv_var_r;
        if chi2_r + t_rel.norm_squared() * m.inv_var_p <= m.displaced {
            return;
        }
        o.significant += 1;
        let ww = Sym3::square(&omega);
        o.sum_ww.add(&ww);
        o.sum_tt.add_product(t_rel, t_rel);
        if chi2_r <= m.axis_chi2 {
            return;
        }
        let g = omega.cross(&xi.v);
        let theta4 = theta2 * theta2;
        let g2 = g
            .norm_squared()
            .min(MAX_AXIS_DISTANCE_M * MAX_AXIS_DISTANCE_M * theta4);
        let chord2 = 4.0 * q_rel.quaternion().imag().norm_squared();
        let inv_e4 = 1.0 / (theta4 * (m.ref_var_p + m.tol_p2 * chord2) + m.ref_var_r * g2);
        let inv_d = 1.0 / (m.ref_var_r + m.tol_r2 * theta2);
        let w_4 = chord2 * inv_e4;
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
            o.max_twist = Some(xi);
        }
    }

    #[test]
    fn four_lanes_give_the_frame_by_frame_sums() {
        let m = FrameModel::new(
            &NoiseModel {
                sigma_position: 1e-3,
                sigma_rotation: 8.7e-3,
            },
            &crate::classify::RobustConfig::default(),
        );
        let mut state =
            <rand::rngs::StdRng as rand::SeedableRng>::seed_from_u64(0x0123_4567_89ab_cdef);
        // Runs of 1 to 40 frames (all remainders of 16 and 4): still, barely moving, small and
        // large rotations about random lines, both quaternion signs. Sums agree to rounding
        // (they are added in another order), the rest bit for bit.
        for run in 1..=40 {
            let (mut open, mut reference) = (MovingFrameSums::default(), Reference::default());
            for _ in 0..run {
                let mut r = || rand::Rng::random::<f64>(&mut state);
                let scale = [0.0, 1e-3, 0.05, 0.5, 2.5][(r() * 5.0) as usize];
                let axis = Vector3::new(r() - 0.5, r() - 0.5, r() - 0.5);
                let mut q = UnitQuaternion::from_scaled_axis(axis * scale);
                if r() < 0.3 {
                    q = UnitQuaternion::new_unchecked(-q.into_inner());
                }
                let t = Vector3::new(r() - 0.5, r() - 0.5, r() - 0.5) * (0.2 * scale);
                open.push(&t, &q, &m);
                add_one(&mut reference, &t, &q, &m);
            }
            // The portable build of the kernel (SSE2 or scalar) against the dispatched one
            // (AVX2 where the processor has it): the same operations, the same bits.
            let mut portable = open;
            let n = std::mem::take(&mut portable.pending);
            portable.add_pending_lanes(n, &m);
            open.add_pending(&m);
            assert_eq!(portable.sums, open.sums);
            assert!(reference.significant > 0 && reference.line_n > 0.0 || run < 8);
            // Rounding bound of a sum of n terms in any order: n ε Σ|terms|, with Σ|terms|
            // bounded through Cauchy-Schwarz by the diagonal sums for the mixed-sign entries
            // (Σ|x_i x_j| <= √(Σx_i² Σx_j²)).
            let o = &open.sums;
            let bound = |scale: f64| run as f64 * f64::EPSILON * scale;
            let close = |a: F4, b: f64, scale: f64| {
                let a = total(a);
                assert!((a - b).abs() <= bound(scale), "run of {run}: {a} vs {b}");
            };
            let diag = [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)];
            let sym = |a: &[F4; 6], b: &Sym3| {
                let d = [b.0[0], b.0[3], b.0[5]];
                for (e, &(i, j)) in diag.iter().enumerate() {
                    close(a[e], b.0[e], (d[i] * d[j]).sqrt());
                }
            };
            assert_eq!(o.significant, reference.significant);
            assert_eq!(total(o.line_n), reference.line_n);
            sym(&o.sum_ww, &reference.sum_ww);
            sym(&o.sum_tt, &reference.sum_tt);
            sym(&o.swrr, &reference.swrr);
            sym(&o.sauu, &reference.sauu);
            // Σ|w r_i| <= √(Σw Σ w r_i²).
            let rr = [
                reference.swrr.0[0],
                reference.swrr.0[3],
                reference.swrr.0[5],
            ];
            for (i, r) in rr.iter().enumerate() {
                close(o.swr[i], reference.swr[i], (reference.sw * r).sqrt());
            }
            // Sums of positive terms.
            for (a, b) in [
                (o.sw, reference.sw),
                (o.sww, reference.sww),
                (o.sa, reference.sa),
                (o.saa, reference.saa),
                (o.pitch_chi2, reference.pitch_chi2),
                (o.sw_inv_chord, reference.sw_inv_chord),
            ] {
                close(a, b, b);
            }
            // The largest rotation is picked, not summed: the same frame, bit for bit.
            assert_eq!(o.max_angle, reference.max_angle);
            assert_eq!(o.max_twist, reference.max_twist);
        }
    }
}
