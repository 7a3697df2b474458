//! Cleaning a tracked trajectory: quaternion sign continuity and single-frame tag flips.
//!
//! * **Sign.** q and -q are one rotation; trackers flip between them. Each kept frame's
//!   quaternion is replaced by the one of the pair closest to the previous kept frame's.
//! * **Tag flips.** A planar tag's pose has a mirror solution; a tracker sometimes reports it
//!   for one frame, and the orientation jumps by tens of degrees and comes back. Frame k is
//!   rejected as such an outlier when both
//!   1. its rotation residual from the geodesic interpolation of its neighbours k-1 and k+1 is
//!      significant under the tracking noise (χ²₃ test at level `alpha`, residual variance
//!      `σ_r² (1 + s² + (1-s)²)` per axis), and
//!   2. that residual is larger than the rotation between the neighbours themselves, i.e. the
//!      neighbours agree with each other better than with frame k. Smooth motion, even fast,
//!      never satisfies this (its midpoint residual is at most half the neighbour distance);
//!      a landing impact can, which costs one true frame and nothing else.
//!
//! The first and last frames have one neighbour; they are tested against a constant-velocity
//! extrapolation from the two frames beside them with the same two conditions.
//!
//! * **Two flips in a row.** Frames k and k+1 both flipped agree with each other, so each is
//!   only half-way off the geodesic of its neighbours and condition 2 fails. A frame whose
//!   residual is significant (condition 1) but not larger than the neighbour distance is
//!   therefore held back with the next frame, and the pair is tested against the geodesic of
//!   k-1 and k+2 with the same two conditions: both are rejected when both pass. A real change
//!   of orientation (an impact: the orientation jumps and stays) fails it at k+2.

use crate::se3::{rotation_angle_between, so3_exp, so3_log};
use nalgebra::{UnitQuaternion, Vector3};

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

/// Streaming cleaner: push frames in time order, receive `(frame, is_outlier)` a frame or two
/// late (the first frame needs two frames after it, every other frame one).
///
/// Layout for speed: once the first frame is kept, each frame is judged as soon as the next one
/// arrives, so the stream needs only one pending frame and the last two kept frames, held in
/// fixed slots (no queue); the common verdict "no flip" is decided by an exact pretest without
/// trigonometry (in `is_flip`).
#[derive(Debug)]
pub struct Cleaner {
    threshold_sq: f64,
    var_rot: f64,
    /// `threshold_sq · var_rot · 1.5` \[rad²\]: a squared residual bound at or below it is never
    /// significant (1.5 is the least variance factor, see [`Cleaner::is_flip`]).
    floor: f64,
    /// The last two kept frames: `kept[latest]` the latest, `kept[latest ^ 1]` the one before
    /// (`kept_count` of them are valid, at most 2).
    kept: [RawFrame; 2],
    latest: usize,
    kept_count: usize,
    /// Frames pushed and not judged yet, oldest first: `pending[..pending_len]`. One once the
    /// first frame is kept (after a push: two, and the older one is judged at once); up to
    /// three before.
    pending: [RawFrame; 3],
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

/// What the tag-flip test says of a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Verdict {
    Keep,
    Flip,
    /// Significantly off its neighbours' geodesic but not farther than they are apart: one of
    /// two flips in a row, or a real change; decided with the frame after the next.
    Suspect,
}

/// A placeholder for an empty slot (never read).
const EMPTY: RawFrame = RawFrame {
    index: 0,
    t: 0.0,
    q: UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(1.0, 0.0, 0.0, 0.0)),
    p: Vector3::new(0.0, 0.0, 0.0),
};

impl Cleaner {
    /// A cleaner for orientation noise `sigma_rotation` \[rad\] per axis, testing at level `alpha`.
    pub fn new(sigma_rotation: f64, alpha: f64) -> Self {
        let threshold_sq = crate::stats::chi2_threshold(3.0, alpha);
        let var_rot = sigma_rotation * sigma_rotation;
        Self {
            threshold_sq,
            var_rot,
            floor: threshold_sq * var_rot * 1.5,
            kept: [EMPTY; 2],
            latest: 0,
            kept_count: 0,
            pending: [EMPTY; 3],
            pending_len: 0,
        }
    }

    /// Whether `f` is a tag flip with respect to the geodesic through `a` and `b` (see the
    /// module documentation).
    ///
    /// Fast rejection, exact: the residual r from the geodesic point at fraction s obeys
    /// `r <= |s| d(a,b) + d(a,f)` (triangle inequality), so a flip needs both
    /// `|s| d(a,b) + d(a,f) > d(a,b)` and `(|s| d(a,b) + d(a,f))² > threshold`; the variance
    /// factor `1 + s² + (1-s)²` is at least 1.5. Cheapest first, without a square root,
    /// division or atan2: the squared chord `c² = 4|imag(x⁻¹y)|²` of the angle θ between x and y
    /// (`c = 2 sin(θ/2)`) bounds θ² from above by `u = c² (1 + c²/20)²` for `c <= 1`
    /// (`2 asin(c/2) = c + c³/24 + ...`), and `(|s| √u_ab + √u_af)² <= 2 (s² u_ab + u_af)`;
    /// `s = Δt_af / Δt_ab` is cleared of its denominator.
    #[inline(always)]
    fn is_flip(&self, a: &RawFrame, b: &RawFrame, f: &RawFrame) -> bool {
        self.verdict(a, b, f) == Verdict::Flip
    }

    /// [`Cleaner::is_flip`], telling a suspect frame apart (see [`Verdict::Suspect`]).
    #[inline(always)]
    fn verdict(&self, a: &RawFrame, b: &RawFrame, f: &RawFrame) -> Verdict {
        let chord2 = |x: &UnitQuaternion<f64>, y: &UnitQuaternion<f64>| {
            4.0 * (x.quaternion().conjugate() * y.quaternion())
                .imag()
                .norm_squared()
        };
        let (c_ab, c_af) = (chord2(&a.q, &b.q), chord2(&a.q, &f.q));
        if c_ab <= 1.0 && c_af <= 1.0 {
            // `c2 * 0.05` for `c2 / 20`: a multiplication instead of a division, and the
            // double nearest 0.05 is above it, so `u` stays an upper bound.
            let u = |c2: f64| c2 * (1.0 + c2 * 0.05) * (1.0 + c2 * 0.05);
            let (t_ab, t_af) = (b.t - a.t, f.t - a.t);
            let d2 = t_ab * t_ab;
            if 2.0 * (t_af * t_af * u(c_ab) + d2 * u(c_af)) <= self.floor * d2 {
                return Verdict::Keep;
            }
        }
        self.verdict_exact(a, b, f)
    }

    /// [`Cleaner::is_flip`] past its pretest: the triangle bound with the angles themselves,
    /// then the residual test.
    #[cold]
    #[inline(never)]
    fn verdict_exact(&self, a: &RawFrame, b: &RawFrame, f: &RawFrame) -> Verdict {
        let s = ((f.t - a.t) / (b.t - a.t)).abs();
        let dab = rotation_angle_between(&a.q, &b.q);
        let daf = rotation_angle_between(&a.q, &f.q);
        let bound = s * dab + daf;
        if bound * bound <= self.floor {
            return Verdict::Keep;
        }
        let (r, k) = residual(a, b, f);
        match (r * r > self.threshold_sq * self.var_rot * k, r > dab) {
            (true, true) => Verdict::Flip,
            (true, false) => Verdict::Suspect,
            _ => Verdict::Keep,
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
    /// with the frame after it).
    #[cold]
    #[inline(never)]
    fn hold(&mut self, f: RawFrame) {
        self.pending[1] = f;
        self.pending_len = 2;
    }

    /// [`Cleaner::push`] until the first frame is kept: each frame is judged against the two
    /// after it; and after a suspect frame, the pair of it and the next one against the frames
    /// around them.
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
            let (bad, next) = match self.last_kept() {
                None if self.pending_len >= 3 => (
                    self.is_flip(&self.pending[1], &self.pending[2], &self.pending[0]),
                    self.pending[0],
                ),
                Some(k) if self.pending_len >= 2 => {
                    let bad = match self.verdict(k, &self.pending[1], &self.pending[0]) {
                        Verdict::Keep => false,
                        Verdict::Flip => true,
                        Verdict::Suspect if self.pending_len < 3 => break,
                        Verdict::Suspect => {
                            let (p, f, g) = (self.pending[0], self.pending[1], self.pending[2]);
                            if self.verdict_exact(k, &g, &p) == Verdict::Flip
                                && self.verdict_exact(k, &g, &f) == Verdict::Flip
                            {
                                self.pending[0] = g;
                                self.pending_len = 1;
                                self.emit(p, true, out);
                                self.emit(f, true, out);
                                continue;
                            }
                            false
                        }
                    };
                    let mut next = self.pending[0];
                    if !bad {
                        next.q = align(next.q, &k.q);
                    }
                    (bad, next)
                }
                _ => break,
            };
            self.pending.copy_within(1..self.pending_len, 0);
            self.pending_len -= 1;
            self.emit(next, bad, out);
        }
    }

    /// Flush the last frames at the end of the stream (the last one is judged by extrapolation
    /// from the two kept frames before it).
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
mod tests {
    use super::*;

    fn frame(i: usize, angle: f64) -> RawFrame {
        RawFrame {
            index: i,
            t: i as f64 / 30.0,
            q: UnitQuaternion::from_scaled_axis(Vector3::new(0.0, angle, 0.0)),
            p: Vector3::zeros(),
        }
    }

    fn run(frames: Vec<RawFrame>) -> Vec<(RawFrame, bool)> {
        let mut c = Cleaner::new(0.0087, 1e-6);
        let mut out = Vec::new();
        for f in frames {
            c.push(f, &mut |f, o| out.push((f, o)));
        }
        c.finish(&mut |f, o| out.push((f, o)));
        out
    }

    #[test]
    fn rejects_single_flips_keeps_fast_motion_and_fixes_signs() {
        let mut frames: Vec<RawFrame> = (0..60)
            .map(|i| frame(i, 0.02 * (i as f64).powi(2) / 10.0))
            .collect();
        // A mirror-like flip at frame 20: 40 degrees about x for one frame.
        frames[20].q *= UnitQuaternion::from_scaled_axis(Vector3::new(0.7, 0.0, 0.0));
        // Sign flips.
        for i in [5usize, 6, 33] {
            frames[i].q = UnitQuaternion::new_unchecked(-frames[i].q.into_inner());
        }
        let out = run(frames);
        assert_eq!(out.len(), 60);
        let flagged: Vec<usize> = out
            .iter()
            .filter(|(_, o)| *o)
            .map(|(f, _)| f.index)
            .collect();
        assert_eq!(flagged, vec![20]);
        for w in out.windows(2) {
            assert!(w[0].0.q.quaternion().dot(w[1].0.q.quaternion()) > 0.0 || w[0].1 || w[1].1);
        }
    }

    /// The cleaner as first written (a queue of frames), as a reference for the slotted one.
    fn reference(frames: &[RawFrame]) -> Vec<(RawFrame, bool)> {
        let c = Cleaner::new(0.0087, 1e-6);
        let (mut kept_prev, mut kept) = (None::<RawFrame>, None::<RawFrame>);
        let mut buffer = std::collections::VecDeque::new();
        let mut out = Vec::new();
        let mut emit =
            |f: RawFrame, bad: bool, kp: &mut Option<RawFrame>, k: &mut Option<RawFrame>| {
                if !bad {
                    *kp = k.replace(f);
                }
                out.push((f, bad));
            };
        for &f in frames {
            let mut f = f;
            if let Some(last) = buffer.back().or(kept.as_ref()) {
                f.q = align(f.q, &last.q);
            }
            buffer.push_back(f);
            loop {
                match kept {
                    None if buffer.len() >= 3 => {
                        let bad = c.is_flip(&buffer[1], &buffer[2], &buffer[0]);
                        let first = buffer.pop_front().unwrap();
                        emit(first, bad, &mut kept_prev, &mut kept);
                    }
                    Some(k) if buffer.len() >= 2 => {
                        let bad = match c.verdict(&k, &buffer[1], &buffer[0]) {
                            Verdict::Keep => false,
                            Verdict::Flip => true,
                            Verdict::Suspect if buffer.len() < 3 => break,
                            Verdict::Suspect => {
                                let pair =
                                    [0, 1].map(|i| c.verdict_exact(&k, &buffer[2], &buffer[i]));
                                if pair == [Verdict::Flip; 2] {
                                    for _ in 0..2 {
                                        let f = buffer.pop_front().unwrap();
                                        emit(f, true, &mut kept_prev, &mut kept);
                                    }
                                    continue;
                                }
                                false
                            }
                        };
                        let mut next = buffer.pop_front().unwrap();
                        if !bad {
                            next.q = align(next.q, &k.q);
                        }
                        emit(next, bad, &mut kept_prev, &mut kept);
                    }
                    _ => break,
                }
            }
        }
        for f in buffer {
            let bad = match (&kept_prev, &kept) {
                (Some(a), Some(b)) => c.is_flip(a, b, &f),
                _ => false,
            };
            emit(f, bad, &mut kept_prev, &mut kept);
        }
        out
    }

    #[test]
    fn matches_the_queue_based_reference() {
        // Random walks with flips (single, consecutive, at the ends) and sign changes.
        let mut seed =
            <rand::rngs::StdRng as rand::SeedableRng>::seed_from_u64(0x9e37_79b9_7f4a_7c15);
        let mut rnd = move || rand::Rng::random::<f64>(&mut seed);
        let mut flagged = 0;
        for n in [1usize, 2, 3, 4, 5, 8, 40, 200] {
            for _ in 0..50 {
                let mut angle = Vector3::zeros();
                let frames: Vec<RawFrame> = (0..n)
                    .map(|i| {
                        angle += Vector3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5) * 0.05;
                        let mut f = frame(i, 0.0);
                        f.q = UnitQuaternion::from_scaled_axis(angle);
                        if rnd() < 0.15 {
                            f.q *= UnitQuaternion::from_scaled_axis(Vector3::new(0.8, 0.0, 0.0));
                        }
                        if rnd() < 0.3 {
                            f.q = UnitQuaternion::new_unchecked(-f.q.into_inner());
                        }
                        f
                    })
                    .collect();
                let out = run(frames.clone());
                flagged += out.iter().filter(|(_, o)| *o).count();
                assert_eq!(out, reference(&frames));
            }
        }
        assert!(flagged > 500, "{flagged}");
    }

    #[test]
    fn rejects_two_flips_in_a_row_and_keeps_a_real_jump() {
        // A slow turn with frames 20 and 21 both flipped (the same mirror solution, 40° about
        // x), and frames 50-51 flipped by different amounts.
        let mut frames: Vec<RawFrame> = (0..80).map(|i| frame(i, 0.01 * i as f64)).collect();
        for (i, a) in [(20, 0.7), (21, 0.7), (50, 0.6), (51, 0.75)] {
            frames[i].q *= UnitQuaternion::from_scaled_axis(Vector3::new(a, 0.0, 0.0));
        }
        let out = run(frames.clone());
        let flagged: Vec<usize> = out
            .iter()
            .filter(|(_, o)| *o)
            .map(|(f, _)| f.index)
            .collect();
        assert_eq!(flagged, vec![20, 21, 50, 51]);
        assert_eq!(out, reference(&frames));
        // An impact: the orientation jumps by 40° at frame 30 and stays: nothing is rejected
        // (the first frame after the jump costs nothing either).
        let jump: Vec<RawFrame> = (0..60)
            .map(|i| {
                let mut f = frame(i, 0.01 * i as f64);
                if i >= 30 {
                    f.q *= UnitQuaternion::from_scaled_axis(Vector3::new(0.7, 0.0, 0.0));
                }
                f
            })
            .collect();
        let out = run(jump.clone());
        assert!(
            out.iter().all(|(_, o)| !o),
            "{:?}",
            out.iter().filter(|x| x.1).count()
        );
        assert_eq!(out, reference(&jump));
    }

    #[test]
    fn rejects_a_flip_on_the_first_and_last_frame() {
        let mut frames: Vec<RawFrame> = (0..10).map(|i| frame(i, 0.01 * i as f64)).collect();
        frames[0].q *= UnitQuaternion::from_scaled_axis(Vector3::new(0.8, 0.0, 0.0));
        frames[9].q *= UnitQuaternion::from_scaled_axis(Vector3::new(-0.8, 0.0, 0.0));
        let out = run(frames);
        let flagged: Vec<usize> = out
            .iter()
            .filter(|(_, o)| *o)
            .map(|(f, _)| f.index)
            .collect();
        assert_eq!(flagged, vec![0, 9]);
    }
}
