//! Cleaning a tracked trajectory: quaternion sign continuity, and tracker glitches: tag flips
//! and short runs of wrong poses.
//!
//! * **Sign.** q and -q are one rotation; trackers flip between them. Each kept frame's
//!   quaternion is replaced by the one of the pair closest to the previous kept frame's.
//! * **Glitches.** A planar tag's pose has a mirror solution, which a tracker sometimes reports
//!   for a frame or two: the orientation jumps by tens of degrees and comes back. A camera
//!   tracker misreads a blurred tag, a motion-capture system swaps markers: the position jumps
//!   by centimetres and comes back. Frame k is rejected as an outlier when, for its orientation
//!   or for its position,
//!   1. its residual from the interpolation of its neighbours k-1 and k+1 at its time
//!      (geodesic for the orientation, straight for the position) is significant under the
//!      tracking noise (χ²₃ test at level `alpha`, residual variance `σ² (1 + s² + (1-s)²)` per
//!      axis, `s` the fraction of the way), and
//!   2. that residual is larger than the neighbours' own distance from each other, i.e. the
//!      neighbours agree with each other better than with frame k. Smooth motion, even fast,
//!      never satisfies this (its midpoint residual is at most half the neighbour distance);
//!      a landing impact can, which costs one true frame and nothing else.
//!
//!   The two parts are tested apart (orientation, then position), each as the tag-flip test
//!   was: a flip during a fast slide is still a flip, whatever the position does.
//!
//! The first and last frames have one neighbour; they are tested against a constant-velocity
//! extrapolation from the two frames beside them with the same two conditions.
//!
//! * **Runs.** Frames k .. k+n-1 all wrong alike agree with each other, so each is only part of
//!   the way off the interpolation of its neighbours and condition 2 fails. A frame whose
//!   residual is significant (condition 1) but not larger than the neighbour distance is
//!   therefore held back with the frames after it, and the runs it may start, of 2 to
//!   [`MAX_RUN`] frames, are tested against the interpolation of k-1 and the frame after the
//!   run, shortest first, with the same two conditions: a run is rejected when all its frames
//!   pass. A real change (an impact: the pose jumps and stays) fails it at the frame after.
//!   A longer run is not a glitch this test can tell from motion; it is left to the motion
//!   models' own tests.
//!
//! * **Held poses** ([`held`]): frames that repeat the pose before them exactly, from a tracker
//!   whose noise rules that out, are left out before this test where the config says so.

use crate::se3::{rotation_angle_between, so3_exp, so3_log};
use nalgebra::{UnitQuaternion, Vector3};

pub mod held;
pub use held::HeldPoses;

/// Longest run of consecutive frames rejected together: one fewer than the fewest frames of a
/// free flight ([`crate::flight::MIN_FLIGHT_FRAMES`]), so that no motion the learner can
/// identify (a flight, or a roll, which needs as many) is ever taken for a glitch. A bounce
/// shorter than that, which no model could identify, may be.
pub const MAX_RUN: usize = crate::flight::MIN_FLIGHT_FRAMES - 1;

/// A frame as it flows through cleaning: index in the file, time \[s\], orientation, position \[m\].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RawFrame {
    /// 0-based index of the pose in its file.
    pub index: usize,
    /// Time \[s\].
    pub t: f64,
    /// Orientation (any sign on input; sign-continuous on output).
    pub q: UnitQuaternion<f64>,
    /// Position \[m\].
    pub p: Vector3<f64>,
}

/// Frames held: a run of [`MAX_RUN`] and the frame after it.
const PENDING: usize = MAX_RUN + 1;

/// Streaming cleaner: push frames in time order, receive `(frame, is_outlier)` a frame or two
/// late (the first frame needs two frames after it, every other frame one; a suspect frame up
/// to [`MAX_RUN`]).
///
/// Layout for speed: once the first frame is kept, each frame is judged as soon as the next one
/// arrives, so the stream needs only one pending frame and the last two kept frames, held in
/// fixed slots (no queue); the common verdict "no glitch" is decided by exact pretests without
/// trigonometry or division (in `verdict`).
#[derive(Debug)]
pub struct Cleaner {
    threshold_sq: f64,
    var_rot: f64,
    var_pos: f64,
    /// `threshold_sq · var_rot · 1.5` \[rad²\]: a squared residual bound at or below it is never
    /// significant (1.5 is the least variance factor, see [`Cleaner::verdict`]).
    floor: f64,
    /// The same for the position \[m²\], less a margin far above rounding (see
    /// [`Cleaner::position_surely_kept`]).
    floor_pos: f64,
    /// `threshold_sq · var_rot · 2` \[rad²\]: a squared jump between consecutive frames at or
    /// below it is not significant (the difference of two frames' noise has twice the
    /// variance), and no run of glitches starts there.
    jump_floor: f64,
    /// The same for the position \[m²\], with the margin of `floor_pos`.
    jump_floor_pos: f64,
    /// The last two kept frames: `kept[latest]` the latest, `kept[latest ^ 1]` the one before
    /// (`kept_count` of them are valid, at most 2).
    kept: [RawFrame; 2],
    latest: usize,
    kept_count: usize,
    /// Frames pushed and not judged yet, oldest first: `pending[..pending_len]`. One once the
    /// first frame is kept (after a push: two, and the older one is judged at once); up to
    /// three before, and up to [`PENDING`] after a suspect frame.
    pending: [RawFrame; PENDING],
    pending_len: usize,
}

/// `q` or `-q`, whichever is closer to `to` (non-negative dot product). Negation is exact.
#[inline(always)]
fn align(q: UnitQuaternion<f64>, to: &UnitQuaternion<f64>) -> UnitQuaternion<f64> {
    if q.quaternion().dot(to.quaternion()) < 0.0 {
        UnitQuaternion::new_unchecked(-q.into_inner())
    } else {
        q
    }
}

/// Rotation residual \[rad\] of `f` from the geodesic through `a` and `b`, evaluated at `f.t`
/// (interpolation or extrapolation), and the factor of its variance over the per-frame one.
fn residual(a: &RawFrame, b: &RawFrame, f: &RawFrame) -> (f64, f64) {
    let s = (f.t - a.t) / (b.t - a.t);
    let d = so3_log(&(a.q.inverse() * b.q));
    let pred = a.q * so3_exp(&(d * s));
    let r = so3_log(&(pred.inverse() * f.q)).norm();
    (r, 1.0 + s * s + (1.0 - s) * (1.0 - s))
}

/// What the glitch test says of a frame, for its orientation or its position, or both.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Verdict {
    Keep,
    Flip,
    /// Significantly off its neighbours' interpolation but not farther than they are apart:
    /// the first of a run of glitches, or a real change; decided with the frames after it.
    Suspect,
}

impl Verdict {
    /// The verdict on a frame of this one (for one part of the pose) and `other` (the other
    /// part): a glitch in either is a glitch.
    fn or(self, other: Verdict) -> Verdict {
        match (self, other) {
            (Verdict::Flip, _) | (_, Verdict::Flip) => Verdict::Flip,
            (Verdict::Suspect, _) | (_, Verdict::Suspect) => Verdict::Suspect,
            _ => Verdict::Keep,
        }
    }
}

/// What the frames after a suspect one say ([`Cleaner::outlier_run`]).
enum Run {
    /// A longer run may still be tested: wait for more frames.
    Wait,
    /// The first this many pending frames are a run of glitches.
    Found(usize),
    /// No run: the suspect frame is kept.
    None,
}

/// A placeholder for an empty slot (never read).
const EMPTY: RawFrame = RawFrame {
    index: 0,
    t: 0.0,
    q: UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(1.0, 0.0, 0.0, 0.0)),
    p: Vector3::new(0.0, 0.0, 0.0),
};

impl Cleaner {
    /// A cleaner for tracking noise `sigma_rotation` \[rad\] and `sigma_position` \[m\] per axis,
    /// testing at level `alpha`.
    pub fn new(sigma_rotation: f64, sigma_position: f64, alpha: f64) -> Self {
        let threshold_sq = crate::stats::chi2_threshold(3.0, alpha);
        let var_rot = sigma_rotation * sigma_rotation;
        let var_pos = sigma_position * sigma_position;
        Self {
            threshold_sq,
            var_rot,
            var_pos,
            floor: threshold_sq * var_rot * 1.5,
            floor_pos: threshold_sq * var_pos * 1.5 * (1.0 - 1e-9),
            jump_floor: threshold_sq * var_rot * 2.0,
            jump_floor_pos: threshold_sq * var_pos * 2.0 * (1.0 - 1e-9),
            kept: [EMPTY; 2],
            latest: 0,
            kept_count: 0,
            pending: [EMPTY; PENDING],
            pending_len: 0,
        }
    }

    /// Whether `f` is a glitch with respect to the interpolation of `a` and `b` (see the module
    /// documentation).
    #[inline(always)]
    fn is_flip(&self, a: &RawFrame, b: &RawFrame, f: &RawFrame) -> bool {
        self.verdict(a, b, f) == Verdict::Flip
    }

    /// [`Cleaner::is_flip`], telling a suspect frame apart (see [`Verdict::Suspect`]): exact
    /// pretests first, which keep almost every frame of a stream.
    #[inline(always)]
    fn verdict(&self, a: &RawFrame, b: &RawFrame, f: &RawFrame) -> Verdict {
        if self.rotation_surely_kept(a, b, f) && self.position_surely_kept(a, b, f) {
            return Verdict::Keep;
        }
        self.verdict_exact(a, b, f)
    }

    /// Whether the orientation of `f` is surely kept: not significantly off the geodesic of `a`
    /// and `b`, and its jump from `a` not significant, so that it starts no run either (false:
    /// not known without the exact test).
    ///
    /// Exact: the residual r from the geodesic point at fraction s obeys
    /// `r <= |s| d(a,b) + d(a,f)` (triangle inequality), so a flip needs
    /// `(|s| d(a,b) + d(a,f))² > threshold`; the variance factor `1 + s² + (1-s)²` is at
    /// least 1.5. Without a square root, division or atan2: the squared chord
    /// `c² = 4|imag(x⁻¹y)|²` of the angle θ between x and y (`c = 2 sin(θ/2)`) bounds θ² from
    /// above by `u = c² (1 + c²/20)²` for `c <= 1` (`2 asin(c/2) = c + c³/24 + ...`), and
    /// `(|s| √u_ab + √u_af)² <= 2 (s² u_ab + u_af)`; `s = Δt_af / Δt_ab` is cleared of its
    /// denominator; and the jump's `u_af` bounds its squared angle.
    #[inline(always)]
    fn rotation_surely_kept(&self, a: &RawFrame, b: &RawFrame, f: &RawFrame) -> bool {
        let chord2 = |x: &UnitQuaternion<f64>, y: &UnitQuaternion<f64>| {
            4.0 * (x.quaternion().conjugate() * y.quaternion())
                .imag()
                .norm_squared()
        };
        let (c_ab, c_af) = (chord2(&a.q, &b.q), chord2(&a.q, &f.q));
        if c_ab > 1.0 || c_af > 1.0 {
            return false;
        }
        // `c2 * 0.05` for `c2 / 20`: a multiplication instead of a division, and the double
        // nearest 0.05 is above it, so `u` stays an upper bound.
        let u = |c2: f64| c2 * (1.0 + c2 * 0.05) * (1.0 + c2 * 0.05);
        let (t_ab, t_af) = (b.t - a.t, f.t - a.t);
        let d2 = t_ab * t_ab;
        2.0 * (t_af * t_af * u(c_ab) + d2 * u(c_af)) <= self.floor * d2
            && u(c_af) <= self.jump_floor
    }

    /// Whether the position of `f` is surely kept: not significantly off the line of `a` and
    /// `b` (its residual times `Δt_ab`, no division, against the least significant residual),
    /// and its jump from `a` not significant; each with a relative margin of 1e-9, far above the
    /// rounding by which these differ from [`Cleaner::position_verdict`]'s.
    #[inline(always)]
    fn position_surely_kept(&self, a: &RawFrame, b: &RawFrame, f: &RawFrame) -> bool {
        let (t_ab, t_af) = (b.t - a.t, f.t - a.t);
        let jump = f.p - a.p;
        let e = jump * t_ab - (b.p - a.p) * t_af;
        e.norm_squared() <= self.floor_pos * (t_ab * t_ab)
            && jump.norm_squared() <= self.jump_floor_pos
    }

    /// [`Cleaner::verdict`] past its pretests: the orientation's and the position's verdicts.
    #[cold]
    #[inline(never)]
    fn verdict_exact(&self, a: &RawFrame, b: &RawFrame, f: &RawFrame) -> Verdict {
        self.rotation_verdict(a, b, f)
            .or(self.position_verdict(a, b, f))
    }

    /// The orientation's verdict: the triangle bound with the angles themselves, then the
    /// residual test.
    fn rotation_verdict(&self, a: &RawFrame, b: &RawFrame, f: &RawFrame) -> Verdict {
        let s = ((f.t - a.t) / (b.t - a.t)).abs();
        let dab = rotation_angle_between(&a.q, &b.q);
        let daf = rotation_angle_between(&a.q, &f.q);
        let bound = s * dab + daf;
        // Not significant, and not half-way significant after a significant jump.
        let b2 = bound * bound;
        if b2 <= 0.25 * self.floor || (b2 <= self.floor && daf * daf <= self.jump_floor) {
            return Verdict::Keep;
        }
        let (r, k) = residual(a, b, f);
        self.part_verdict(r * r, self.var_rot * k, dab * dab, daf * daf, self.var_rot)
    }

    /// The position's verdict: the residual from the straight line through `a` and `b` at
    /// `f.t`, and the distance between them.
    fn position_verdict(&self, a: &RawFrame, b: &RawFrame, f: &RawFrame) -> Verdict {
        let s = (f.t - a.t) / (b.t - a.t);
        let d = b.p - a.p;
        let jump = f.p - a.p;
        let r2 = (jump - d * s).norm_squared();
        let k = 1.0 + s * s + (1.0 - s) * (1.0 - s);
        let j2 = jump.norm_squared();
        self.part_verdict(r2, self.var_pos * k, d.norm_squared(), j2, self.var_pos)
    }

    /// The verdict on one part of the pose: from its squared residual `r2` \[rad² or m²\] from
    /// the interpolation of the neighbours, that residual's variance per axis `var_r`, the
    /// squared distance `d2` between the neighbours, the squared jump `j2` from the frame
    /// before, and the per-frame variance `var`.
    ///
    /// A flip: significant and beyond the neighbours' distance. Suspect (the start of a run,
    /// or a real change): significant and within it; or half-way significant after a
    /// significant jump (`j2` against `2 var` per axis), for the first frame of a run of two or
    /// more is only about half-way off the interpolation of the frame before and the next
    /// frame of the run, which is off with it.
    fn part_verdict(&self, r2: f64, var_r: f64, d2: f64, j2: f64, var: f64) -> Verdict {
        let t = self.threshold_sq;
        if r2 > t * var_r {
            if r2 > d2 {
                Verdict::Flip
            } else {
                Verdict::Suspect
            }
        } else if r2 > 0.25 * t * var_r && j2 > 2.0 * t * var {
            Verdict::Suspect
        } else {
            Verdict::Keep
        }
    }

    /// The latest kept frame, if any.
    #[inline(always)]
    fn last_kept(&self) -> Option<&RawFrame> {
        (self.kept_count > 0).then(|| &self.kept[self.latest])
    }

    /// Pass `f` on with its verdict; a kept frame becomes the latest kept one.
    #[inline(always)]
    fn emit(&mut self, f: RawFrame, outlier: bool, out: &mut impl FnMut(RawFrame, bool)) {
        if !outlier {
            self.latest ^= 1;
            self.kept[self.latest] = f;
            self.kept_count = (self.kept_count + 1).min(2);
        }
        out(f, outlier);
    }

    /// Push the next frame; frames are passed to `out` with their verdict once judged.
    #[inline(always)]
    pub fn push(&mut self, mut f: RawFrame, out: &mut impl FnMut(RawFrame, bool)) {
        if self.kept_count == 0 || self.pending_len != 1 {
            return self.push_start(f, out);
        }
        // The common case: the pending frame is judged against the latest kept frame and `f`.
        let k = &self.kept[self.latest];
        f.q = align(f.q, &self.pending[0].q);
        let bad = match self.verdict(k, &f, &self.pending[0]) {
            Verdict::Keep => false,
            Verdict::Flip => true,
            Verdict::Suspect => return self.hold(f),
        };
        let mut next = std::mem::replace(&mut self.pending[0], f);
        if !bad {
            next.q = align(next.q, &k.q);
        }
        self.emit(next, bad, out);
    }

    /// Hold a second pending frame after a suspect one (judged in [`Cleaner::push_start`]
    /// with the frames after it).
    #[cold]
    #[inline(never)]
    fn hold(&mut self, f: RawFrame) {
        self.pending[1] = f;
        self.pending_len = 2;
    }

    /// [`Cleaner::push`] until the first frame is kept: each frame is judged against the two
    /// after it; and after a suspect frame, the runs it may start against the frames around
    /// them.
    #[cold]
    #[inline(never)]
    fn push_start(&mut self, mut f: RawFrame, out: &mut impl FnMut(RawFrame, bool)) {
        let last = match self.pending_len {
            0 => self.last_kept(),
            n => Some(&self.pending[n - 1]),
        };
        if let Some(last) = last {
            f.q = align(f.q, &last.q);
        }
        self.pending[self.pending_len] = f;
        self.pending_len += 1;
        loop {
            let Some(k) = self.last_kept().copied() else {
                if self.pending_len < 3 {
                    break;
                }
                let p = &self.pending;
                let bad = self.is_flip(&p[1], &p[2], &p[0]);
                self.emit_pending(1, bad, None, out);
                continue;
            };
            if self.pending_len < 2 {
                break;
            }
            match self.verdict(&k, &self.pending[1], &self.pending[0]) {
                Verdict::Keep => self.emit_pending(1, false, Some(&k), out),
                Verdict::Flip => self.emit_pending(1, true, None, out),
                Verdict::Suspect => match self.outlier_run(&k) {
                    Run::Wait => break,
                    Run::Found(n) => self.emit_pending(n, true, None, out),
                    Run::None => self.emit_pending(1, false, Some(&k), out),
                },
            }
        }
    }

    /// After a suspect first pending frame: the shortest run of 2 to [`MAX_RUN`] pending
    /// frames from it that are all glitches with respect to the interpolation of the latest
    /// kept frame `k` and the frame after the run.
    fn outlier_run(&self, k: &RawFrame) -> Run {
        for n in 2..=MAX_RUN {
            if self.pending_len <= n {
                return Run::Wait;
            }
            let (run, after) = (&self.pending[..n], &self.pending[n]);
            if run
                .iter()
                .all(|f| self.verdict_exact(k, after, f) == Verdict::Flip)
            {
                return Run::Found(n);
            }
        }
        Run::None
    }

    /// Pass the first `n` pending frames on with verdict `bad` (their quaternions made
    /// continuous with `align_to`'s, where given) and drop them from the pending ones.
    fn emit_pending(
        &mut self,
        n: usize,
        bad: bool,
        align_to: Option<&RawFrame>,
        out: &mut impl FnMut(RawFrame, bool),
    ) {
        for i in 0..n {
            let mut f = self.pending[i];
            if let Some(k) = align_to {
                f.q = align(f.q, &k.q);
            }
            self.emit(f, bad, out);
        }
        self.pending.copy_within(n..self.pending_len, 0);
        self.pending_len -= n;
    }

    /// Flush the last frames at the end of the stream (each judged by extrapolation from the
    /// two kept frames before it).
    pub fn finish(mut self, out: &mut impl FnMut(RawFrame, bool)) {
        for i in 0..self.pending_len {
            let f = self.pending[i];
            let bad = self.kept_count >= 2
                && self.is_flip(&self.kept[self.latest ^ 1], &self.kept[self.latest], &f);
            self.emit(f, bad, out);
        }
    }
}

#[cfg(test)]
mod tests;
