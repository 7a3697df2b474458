//! An instrumented demonstration: the object's motion relative to the palm
//! (`palm_from_object`), and the support's "down" in the palm frame.

use super::sample::Sample;
use crate::clean::RawFrame;
use nalgebra::Vector3;
use std::collections::VecDeque;

/// Pairs object frames with the palm pose at the same time (interpolated between the palm
/// frames around it) and forms `palm_from_object`.
///
/// The support's "down" in the palm frame is taken once, from gravity over the palm's first
/// [`SUPPORT_FRAMES`] frames (the palm is level when a demonstration starts), and held fixed: the object rests on
/// the palm's surface however the palm is tilted later, so that is the direction whose face
/// the object rests on, not the current gravity. It is passed on with every item.
#[derive(Default)]
pub(super) struct PalmMerger {
    palm: VecDeque<RawFrame>,
    pending: VecDeque<(RawFrame, bool)>,
    palm_done: bool,
    /// Gravity in the world frame, if known.
    down_world: Option<Vector3<f64>>,
    support_down: Option<Option<Vector3<f64>>>,
    support_sum: Vector3<f64>,
    support_n: usize,
}

/// Palm frames averaged for the support's "down" in the palm frame (0.5 s at 30 Hz): one frame
/// would carry its 0.5° orientation noise into every resting-face normal and tilt angle.
const SUPPORT_FRAMES: usize = 15;

impl PalmMerger {
    /// A merger; `down_world` is gravity in the world frame, if known.
    pub(super) fn new(down_world: Option<Vector3<f64>>) -> Self {
        Self {
            down_world,
            ..Self::default()
        }
    }

    pub(super) fn push_palm(
        &mut self,
        f: RawFrame,
        out: &mut impl FnMut(Sample, Option<Vector3<f64>>),
    ) {
        if self.support_down.is_none() {
            match self.down_world {
                None => self.support_down = Some(None),
                Some(d) => {
                    self.support_sum += f.q.inverse() * d;
                    self.support_n += 1;
                    if self.support_n >= SUPPORT_FRAMES {
                        self.support_down = Some(self.support_sum.try_normalize(1e-12));
                    }
                }
            }
        }
        self.palm.push_back(f);
        self.drain(out);
    }

    /// Queue an object frame (or an object outlier, kept in order).
    pub(super) fn push_object(
        &mut self,
        f: RawFrame,
        outlier: bool,
        out: &mut impl FnMut(Sample, Option<Vector3<f64>>),
    ) {
        self.pending.push_back((f, outlier));
        self.drain(out);
    }

    fn drain(&mut self, out: &mut impl FnMut(Sample, Option<Vector3<f64>>)) {
        if self.support_down.is_none() {
            if !self.palm_done {
                return; // Still averaging the support direction.
            }
            self.support_down = Some(self.support_sum.try_normalize(1e-12));
        }
        let down = self.support_down.flatten();
        let mut out = |i| out(i, down);
        while let Some((o, outlier)) = self.pending.front().copied() {
            if outlier {
                self.pending.pop_front();
                out(Sample::Outlier(o.index, o.t));
                continue;
            }
            while self.palm.len() >= 2 && self.palm[1].t <= o.t {
                self.palm.pop_front();
            }
            let Some(a) = self.palm.front().copied() else {
                if self.palm_done {
                    self.pending.pop_front();
                    out(Sample::Outlier(o.index, o.t));
                    continue;
                }
                return;
            };
            let palm = if a.t == o.t {
                Some((a.q, a.p))
            } else if a.t > o.t {
                None // Before the palm's first frame.
            } else if let Some(b) = self.palm.get(1) {
                let s = (o.t - a.t) / (b.t - a.t);
                Some((a.q.slerp(&b.q, s), a.p * (1.0 - s) + b.p * s))
            } else if self.palm_done {
                None // After the palm's last frame.
            } else {
                return; // Wait for the next palm frame.
            };
            self.pending.pop_front();
            match palm {
                None => out(Sample::Outlier(o.index, o.t)),
                Some((pq, pp)) => {
                    let inv = pq.inverse();
                    out(Sample::Frame(RawFrame {
                        index: o.index,
                        t: o.t,
                        q: inv * o.q,
                        p: inv * (o.p - pp),
                    }))
                }
            }
        }
    }

    pub(super) fn finish(&mut self, out: &mut impl FnMut(Sample, Option<Vector3<f64>>)) {
        self.palm_done = true;
        self.drain(out);
    }
}
