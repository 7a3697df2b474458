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
#[derive(Debug)]
pub struct Cleaner {
    threshold_sq: f64,
    var_rot: f64,
    kept_prev: Option<RawFrame>,
    kept: Option<RawFrame>,
    buffer: std::collections::VecDeque<RawFrame>,
}

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

impl Cleaner {
    /// A cleaner for orientation noise `sigma_rotation` \[rad\] per axis, testing at level `alpha`.
    pub fn new(sigma_rotation: f64, alpha: f64) -> Self {
        Self {
            threshold_sq: crate::stats::chi2_threshold(3.0, alpha),
            var_rot: sigma_rotation * sigma_rotation,
            kept_prev: None,
            kept: None,
            buffer: std::collections::VecDeque::with_capacity(4),
        }
    }

    fn is_flip(&self, a: &RawFrame, b: &RawFrame, f: &RawFrame) -> bool {
        // Fast rejection, exact: the residual r from the geodesic point at fraction s obeys
        // r <= |s| d(a,b) + d(a,f) (triangle inequality), so a flip needs both
        // |s| d(a,b) + d(a,f) > d(a,b) and (|s| d(a,b) + d(a,f))² > threshold.
        // The variance factor 1 + s² + (1-s)² is at least 1.5.
        let floor = self.threshold_sq * self.var_rot * 1.5;
        // Cheapest first, without a square root, division or atan2: the squared chord
        // c² = 4|imag(x⁻¹y)|² of the angle θ between x and y (c = 2 sin(θ/2)) bounds θ² from
        // above by u = c² (1 + c²/20)² for c <= 1 (2 asin(c/2) = c + c³/24 + ...), and
        // (|s| √u_ab + √u_af)² <= 2 (s² u_ab + u_af); s = Δt_af / Δt_ab is cleared of its
        // denominator.
        let chord2 = |x: &UnitQuaternion<f64>, y: &UnitQuaternion<f64>| {
            4.0 * (x.quaternion().conjugate() * y.quaternion())
                .imag()
                .norm_squared()
        };
        let (c_ab, c_af) = (chord2(&a.q, &b.q), chord2(&a.q, &f.q));
        if c_ab <= 1.0 && c_af <= 1.0 {
            let u = |c2: f64| c2 * (1.0 + c2 / 20.0) * (1.0 + c2 / 20.0);
            let (t_ab, t_af) = (b.t - a.t, f.t - a.t);
            let d2 = t_ab * t_ab;
            if 2.0 * (t_af * t_af * u(c_ab) + d2 * u(c_af)) <= floor * d2 {
                return false;
            }
        }
        let s = ((f.t - a.t) / (b.t - a.t)).abs();
        let dab = rotation_angle_between(&a.q, &b.q);
        let daf = rotation_angle_between(&a.q, &f.q);
        let bound = s * dab + daf;
        if bound <= dab || bound * bound <= floor {
            return false;
        }
        let (r, k) = residual(a, b, f);
        r * r > self.threshold_sq * self.var_rot * k && r > dab
    }

    fn emit(&mut self, f: RawFrame, outlier: bool, out: &mut impl FnMut(RawFrame, bool)) {
        if !outlier {
            self.kept_prev = self.kept.replace(f);
        }
        out(f, outlier);
    }

    /// Push the next frame; frames are passed to `out` with their verdict once judged.
    pub fn push(&mut self, mut f: RawFrame, out: &mut impl FnMut(RawFrame, bool)) {
        if let Some(last) = self.buffer.back().or(self.kept.as_ref()) {
            f.q = align(f.q, &last.q);
        }
        self.buffer.push_back(f);
        loop {
            match self.kept {
                None if self.buffer.len() >= 3 => {
                    let bad = self.is_flip(&self.buffer[1], &self.buffer[2], &self.buffer[0]);
                    let first = self.buffer.pop_front().unwrap();
                    self.emit(first, bad, out);
                }
                Some(k) if self.buffer.len() >= 2 => {
                    let bad = self.is_flip(&k, &self.buffer[1], &self.buffer[0]);
                    let mut next = self.buffer.pop_front().unwrap();
                    if !bad {
                        next.q = align(next.q, &k.q);
                    }
                    self.emit(next, bad, out);
                }
                _ => break,
            }
        }
    }

    /// Flush the last frames at the end of the stream (the last one is judged by extrapolation
    /// from the two kept frames before it).
    pub fn finish(mut self, out: &mut impl FnMut(RawFrame, bool)) {
        for f in std::mem::take(&mut self.buffer) {
            let bad = match (&self.kept_prev, &self.kept) {
                (Some(a), Some(b)) => self.is_flip(a, b, &f),
                _ => false,
            };
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
        frames[20].q = frames[20].q * UnitQuaternion::from_scaled_axis(Vector3::new(0.7, 0.0, 0.0));
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

    #[test]
    fn rejects_a_flip_on_the_first_and_last_frame() {
        let mut frames: Vec<RawFrame> = (0..10).map(|i| frame(i, 0.01 * i as f64)).collect();
        frames[0].q = frames[0].q * UnitQuaternion::from_scaled_axis(Vector3::new(0.8, 0.0, 0.0));
        frames[9].q = frames[9].q * UnitQuaternion::from_scaled_axis(Vector3::new(-0.8, 0.0, 0.0));
        let out = run(frames);
        let flagged: Vec<usize> = out
            .iter()
            .filter(|(_, o)| *o)
            .map(|(f, _)| f.index)
            .collect();
        assert_eq!(flagged, vec![0, 9]);
    }
}
