//! Held poses: frames that repeat the pose of the frame before them exactly.
//!
//! A tracker that loses the object often goes on publishing its last pose at new stamps (a
//! tf re-broadcast, a motion-capture stream's "hold last value", a logger that samples the
//! latest message at a fixed rate). Those frames are not measurements: while the object
//! turned over its edge, they show it still, tilted, where it never rested. A tracker with
//! noise never repeats a pose to the last digit, so where the learner has measured the
//! noise at rest (`learn/held_poses.rs` decides, [`crate::classify::RobustConfig`]'s
//! `repeats_are_held`), the repeats are left out as glitches are. An exact tracker (a
//! simulator's) repeats its poses wherever the object is still, and its repeats are kept.

use super::RawFrame;
use nalgebra::{UnitQuaternion, Vector3};
use std::collections::VecDeque;

/// Whether the pose (`q`, `p`) repeats (`q0`, `p0`) exactly: the same position, bit for bit,
/// and the same orientation up to the quaternion's sign.
#[inline(always)]
pub fn repeats(
    q: &UnitQuaternion<f64>,
    p: &Vector3<f64>,
    q0: &UnitQuaternion<f64>,
    p0: &Vector3<f64>,
) -> bool {
    p == p0 && (q.coords == q0.coords || q.coords == -q0.coords)
}

/// Takes the repeats out of a stream before the glitch test and passes them on as rejected
/// frames, in stream order, among the frames the test judges (it passes them on late, in
/// order). Frames pass through [`HeldPoses::is_repeat`]; what the test emits, through
/// [`HeldPoses::emit`]; at the end, [`HeldPoses::drain`].
#[derive(Debug, Default)]
pub struct HeldPoses {
    /// The last frame that was not a repeat.
    last: Option<(UnitQuaternion<f64>, Vector3<f64>)>,
    /// Repeats not passed on yet, by index.
    held: VecDeque<RawFrame>,
}

impl HeldPoses {
    /// Whether `f` repeats the frame before it: then it is kept back, to be passed on as
    /// rejected; otherwise it is the new last frame.
    pub fn is_repeat(&mut self, f: &RawFrame) -> bool {
        if let Some((q0, p0)) = &self.last {
            if repeats(&f.q, &f.p, q0, p0) {
                self.held.push_back(*f);
                return true;
            }
        }
        self.last = Some((f.q, f.p));
        false
    }

    /// Pass `f` on with its verdict, after the repeats that came before it.
    pub fn emit(&mut self, f: RawFrame, outlier: bool, out: &mut impl FnMut(RawFrame, bool)) {
        while self.held.front().is_some_and(|h| h.index < f.index) {
            let h = self.held.pop_front().expect("a held frame");
            out(h, true);
        }
        out(f, outlier);
    }

    /// Pass on the repeats left at the end of the stream.
    pub fn drain(mut self, out: &mut impl FnMut(RawFrame, bool)) {
        for h in self.held.drain(..) {
            out(h, true);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(index: usize, x: f64) -> RawFrame {
        RawFrame {
            index,
            t: index as f64,
            q: UnitQuaternion::from_scaled_axis(Vector3::new(0.0, 0.0, x)),
            p: Vector3::new(x, 0.0, 0.0),
        }
    }

    #[test]
    fn repeats_are_exact_and_sign_blind() {
        let f = frame(0, 0.3);
        let minus = UnitQuaternion::new_unchecked(-f.q.into_inner());
        assert!(repeats(&f.q, &f.p, &f.q, &f.p));
        assert!(repeats(&minus, &f.p, &f.q, &f.p));
        let nudged = Vector3::new(f64::from_bits(f.p.x.to_bits() + 1), 0.0, 0.0);
        assert!(!repeats(&f.q, &nudged, &f.q, &f.p));
        let turned = UnitQuaternion::from_scaled_axis(Vector3::new(0.0, 0.0, 0.3 + 1e-15));
        assert!(!repeats(&turned, &f.p, &f.q, &f.p));
    }

    /// Repeats come out rejected, every frame once, in stream order, whatever the delay of
    /// the stage between `is_repeat` and `emit` (here: frames passed on up to three late).
    #[test]
    fn repeats_come_out_rejected_in_order() {
        let xs = [0.0, 0.1, 0.1, 0.1, 0.2, 0.3, 0.3, 0.4, 0.4, 0.4, 0.4];
        let mut held = HeldPoses::default();
        let mut out = Vec::new();
        let mut late: VecDeque<RawFrame> = VecDeque::new();
        for (i, &x) in xs.iter().enumerate() {
            let f = frame(i, x);
            if held.is_repeat(&f) {
                continue;
            }
            late.push_back(f);
            if late.len() > 3 {
                let g = late.pop_front().unwrap();
                held.emit(g, false, &mut |f, o| out.push((f.index, o)));
            }
        }
        for g in late {
            held.emit(g, false, &mut |f, o| out.push((f.index, o)));
        }
        held.drain(&mut |f, o| out.push((f.index, o)));
        let indices: Vec<usize> = out.iter().map(|o| o.0).collect();
        assert_eq!(indices, (0..xs.len()).collect::<Vec<_>>());
        let rejected: Vec<usize> = out.iter().filter(|o| o.1).map(|o| o.0).collect();
        assert_eq!(rejected, vec![2, 3, 6, 8, 9, 10]);
    }
}
