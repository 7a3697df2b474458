//! Rest detection: is the object's pose changing at time t, given the tracking noise?
//!
//! The pose over a window of frames is fitted with a straight line in time, per coordinate:
//! the three coordinates of the accumulated rotation increments `Σ log(q_{k-1}⁻¹ q_k)`
//! (continuous, unlike a rotation vector from a fixed reference, which wraps at π) and the
//! three of the position. Under rest each slope β_j is Gaussian with variance `σ_j² / S_tt`,
//! `S_tt = Σ (t_k - t̄)²`, so `Σ_j β_j² S_tt / σ_j²` is χ²₆; the window moves when that
//! exceeds the χ²₆ quantile at level `alpha`. The slope test uses every frame of the window,
//! so it detects a slow tilt (0.1 rad/s at 0.5° noise and 30 Hz) that a frame-to-frame
//! difference misses.
//!
//! Frame c is *moving* when both the window that ends at c and the window that starts at c
//! (each [`RestDetector::new`]'s `window_s` long) move. A centred window would call the first
//! frames of the rest after a motion "moving" (and the last ones before it), and those are many
//! copies of one pose; with the two one-sided windows, a frame is at rest as soon as the pose is
//! steady on either side of it.
//!
//! The sums over a window are differences of prefix sums: each item held carries the sums over
//! the items before it, so a window's sums are one vector subtraction and a new item one vector
//! addition. The prefix sums restart on a local time and pose origin (re-basing) every
//! [`REBASE_EVERY`] frames (or every window's worth of frames, if more, so that re-basing costs
//! O(1) per frame) so that long files do not lose precision to cancellation: they span a few
//! windows at most.

use super::rest_sums::{terms, Sums, TERMS};
use super::sample::{Sample, SampleRef, SampleSink};
use crate::clean::RawFrame;
use nalgebra::{UnitQuaternion, Vector3};

/// Frames between two re-computations of the prefix sums from scratch (re-basing).
///
/// A window's sums are differences of prefix sums taken about the origin of the last re-basing,
/// so their rounding error grows with the distance from it. The test's denominator
/// `n S_tt - S_t²` (about `w⁴ Δt²/12` for `w` frames `Δt` apart) then carries a relative error
/// of about `12 ε (d/w)³`, with ε = 1.1e-16 and `d` the frames since the origin (at most this
/// many plus the two windows); the slopes' numerators likewise. At 1024 that is 5e-8 for the
/// smallest window the test uses (3 frames) and 2e-10 for 18 frames (0.6 s at 30 Hz): far
/// inside what a χ² test at α = 1e-3 can resolve, whose statistic varies by O(1) from window to
/// window. (Re-basing every 256 frames instead cost 1.3% of `learn`'s samples on 10^6 poses, and
/// gave the same outputs on every file of the regression set.)
pub const REBASE_EVERY: usize = 1024;

/// One item in the detector's window: the sums over the items before it since the last
/// re-basing (see [`Sums`]), whether it is a frame (or an outlier, of which only the index and
/// time are kept), the frame, and its accumulated rotation \[rad\] (with the position, the
/// fitted coordinates).
#[derive(Clone, Copy, Debug)]
struct Slot {
    before: Sums,
    frame: bool,
    f: RawFrame,
    rot: Vector3<f64>,
}

impl Slot {
    const EMPTY: Slot = Slot {
        before: Sums([0.0; TERMS]),
        frame: false,
        f: RawFrame {
            index: 0,
            t: 0.0,
            q: UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(1.0, 0.0, 0.0, 0.0)),
            p: Vector3::new(0.0, 0.0, 0.0),
        },
        rot: Vector3::new(0.0, 0.0, 0.0),
    };

    #[inline(always)]
    fn is_frame(&self) -> bool {
        self.frame
    }

    /// The fitted coordinates: accumulated rotation \[rad\] and position \[m\].
    #[inline(always)]
    fn x(&self) -> [f64; 6] {
        let (r, p) = (&self.rot, &self.f.p);
        [r.x, r.y, r.z, p.x, p.y, p.z]
    }

    /// The item this slot holds.
    #[inline(always)]
    fn sample(&self) -> SampleRef<'_> {
        if self.is_frame() {
            SampleRef::Frame(&self.f)
        } else {
            SampleRef::Outlier(self.f.index, self.f.t)
        }
    }
}

/// Streaming rest detector; emits items in order with a `moving` verdict for frames.
///
/// The window is a ring buffer of [`Slot`]s with a power-of-two capacity (grown when full),
/// addressed by the items' running numbers masked to the capacity.
#[derive(Debug)]
pub struct RestDetector {
    window: f64,
    threshold: f64,
    inv_var: [f64; 6],
    /// Ring buffer: item number `i` is in `slots[i & mask]`.
    slots: Vec<Slot>,
    mask: usize,
    /// Number of the oldest item held (the left window's past starts here).
    head: usize,
    /// Number of the next item to judge.
    center: usize,
    /// Items `center..hi` are the right window.
    hi: usize,
    /// Number of the next item pushed; items `head..tail` are held.
    tail: usize,
    /// Sums over the items pushed since the last re-basing (the next item's `before`).
    total: Sums,
    origin: (f64, [f64; 6]),
    since_rebase: usize,
}

/// Initial ring capacity (a power of two): a 0.6 s window at 120 Hz holds 145 items.
const INITIAL_CAPACITY: usize = 256;

impl RestDetector {
    /// A detector with windows of `window_s` \[s\], noise sigmas, and level `alpha`.
    pub fn new(window_s: f64, sigma_position: f64, sigma_rotation: f64, alpha: f64) -> Self {
        let vr = 1.0 / (sigma_rotation * sigma_rotation);
        let vp = 1.0 / (sigma_position * sigma_position);
        Self {
            window: window_s + 1e-9,
            threshold: crate::stats::chi2_threshold(6.0, alpha),
            inv_var: [vr, vr, vr, vp, vp, vp],
            slots: vec![Slot::EMPTY; INITIAL_CAPACITY],
            mask: INITIAL_CAPACITY - 1,
            head: 0,
            center: 0,
            hi: 0,
            tail: 0,
            total: Sums::default(),
            origin: (0.0, [0.0; 6]),
            since_rebase: 0,
        }
    }

    #[inline(always)]
    fn slot(&self, i: usize) -> &Slot {
        &self.slots[i & self.mask]
    }

    /// Double the ring's capacity (items keep their numbers).
    #[cold]
    #[inline(never)]
    fn grow(&mut self) {
        let mask = 2 * self.slots.len() - 1;
        let mut slots = vec![Slot::EMPTY; mask + 1];
        for i in self.head..self.tail {
            slots[i & mask] = *self.slot(i);
        }
        self.slots = slots;
        self.mask = mask;
    }

    /// Re-compute the prefix sums of every held item about the centre item.
    #[cold]
    #[inline(never)]
    fn rebase(&mut self) {
        let c = self.slot(self.center);
        let origin = (c.f.t, c.x());
        self.origin = origin;
        let mut acc = Sums::default();
        for i in self.head..self.tail {
            let e = &mut self.slots[i & self.mask];
            e.before = acc;
            if e.frame {
                acc.add(&terms(e.f.t, &e.x(), &origin));
            }
        }
        self.total = acc;
        self.since_rebase = 0;
    }

    /// The sums of the items held before item `i` (since the last re-basing).
    #[inline(always)]
    fn before(&self, i: usize) -> &Sums {
        if i == self.tail {
            &self.total
        } else {
            &self.slot(i).before
        }
    }

    /// The slot for the next item, to be filled by the caller (the ring grows if full).
    #[inline(always)]
    fn next_slot(&mut self) -> &mut Slot {
        if self.tail - self.head == self.slots.len() {
            self.grow();
        }
        &mut self.slots[self.tail & self.mask]
    }

    /// Push the next frame, given by its index, time \[s\], orientation and position \[m\],
    /// with its accumulated rotation `r` \[rad\] (see [`RotationSum`](super::rotation_sum::RotationSum), [`RestDetector::push`]).
    /// The parts are taken by reference and stored field by field, so that they are read
    /// where the caller has them.
    #[inline(always)]
    pub fn push_frame(
        &mut self,
        index: usize,
        t: f64,
        q: &UnitQuaternion<f64>,
        p: &Vector3<f64>,
        r: &Vector3<f64>,
        out: &mut impl SampleSink,
    ) {
        let x = [r.x, r.y, r.z, p.x, p.y, p.z];
        let origin = self.origin;
        // Field by field, in place: a whole `Slot` value would be built aside and copied.
        let total = self.total;
        let slot = self.next_slot();
        slot.before = total;
        slot.frame = true;
        slot.f.index = index;
        slot.f.t = t;
        slot.f.q = *q;
        slot.f.p = *p;
        slot.rot = *r;
        self.total.add(&terms(t, &x, &origin));
        self.tail += 1;
        self.drain(false, out);
    }

    /// Push the next item, a frame rejected as an outlier (see [`RestDetector::push`]).
    #[inline(always)]
    pub fn push_outlier(&mut self, index: usize, t: f64, out: &mut impl SampleSink) {
        let total = self.total;
        let slot = self.next_slot();
        slot.before = total;
        slot.frame = false;
        slot.f.index = index;
        slot.f.t = t;
        slot.rot = Vector3::zeros();
        self.tail += 1;
        self.drain(false, out);
    }

    /// Push the next item, with its accumulated rotation `rot` \[rad\] (of the frames up to it,
    /// see [`RotationSum`](super::rotation_sum::RotationSum); ignored for outliers); judged items are passed to `out` with
    /// `moving` (false for outliers) and that rotation (zero for outliers).
    #[inline(always)]
    pub fn push(&mut self, item: &Sample, rot: &Vector3<f64>, out: &mut impl SampleSink) {
        match item {
            Sample::Frame(f) => self.push_frame(f.index, f.t, &f.q, &f.p, rot, out),
            Sample::Outlier(index, t) => self.push_outlier(*index, *t, out),
        }
    }

    /// Flush the remaining items at the end of the stream.
    pub fn finish(mut self, out: &mut impl SampleSink) {
        self.drain(true, out);
    }

    #[inline(always)]
    fn drain(&mut self, at_end: bool, out: &mut impl SampleSink) {
        while self.center < self.tail {
            let tc = self.slot(self.center).f.t;
            // Extend the right window [tc, tc + w].
            while self.hi < self.tail && self.slot(self.hi).f.t <= tc + self.window {
                self.hi += 1;
            }
            if self.hi == self.tail && !at_end {
                return; // The right window is not complete yet.
            }
            // Drop frames older than tc - w from the left window [tc - w, tc].
            while self.center > self.head && self.slot(self.head).f.t < tc - self.window {
                self.head += 1;
            }
            if self.since_rebase == 0
                || self.since_rebase >= REBASE_EVERY.max(self.tail - self.head)
            {
                self.rebase();
            }
            self.since_rebase += 1;
            let c = self.center;
            let e = self.slot(c);
            let moving = e.is_frame()
                && self
                    .before(c + 1)
                    .minus(self.before(self.head))
                    .exceeds(&self.inv_var, self.threshold)
                && self
                    .before(self.hi)
                    .minus(&e.before)
                    .exceeds(&self.inv_var, self.threshold);
            out.sample(e.sample(), moving, &e.rot);
            self.center += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::classify::rotation_sum::{step_log, RotationSum};
    use std::collections::VecDeque;

    /// An item, comparable: a frame, or an outlier's index and time.
    type Key = Result<RawFrame, (usize, f64)>;

    fn key(i: &Sample) -> Key {
        match *i {
            Sample::Frame(f) => Ok(f),
            Sample::Outlier(index, t) => Err((index, t)),
        }
    }

    /// The detector as first written (queues of window entries and of items, running sums
    /// updated item by item), as a reference for the ring buffer of prefix sums. The sums are
    /// formed in another order, so they agree to rounding, and the verdicts unless a statistic
    /// is within rounding of its threshold (which these data do not have).
    fn reference(d: &RestDetector, items: &[Sample]) -> Vec<(Key, bool, [f64; 3])> {
        let (window, threshold, inv_var) = (d.window, d.threshold, d.inv_var);
        // (t, is_frame, x, terms), and the items.
        let mut buf: VecDeque<(f64, bool, [f64; 6], [f64; TERMS])> = VecDeque::new();
        let mut queued: VecDeque<Sample> = VecDeque::new();
        let (mut center, mut hi, mut since_rebase) = (0, 0, 0);
        let (mut left, mut right) = (Sums::default(), Sums::default());
        let (mut cum_rot, mut last_q) = (Vector3::zeros(), None::<UnitQuaternion<f64>>);
        let mut origin = (0.0, [0.0; 6]);
        let mut out = Vec::new();
        for (k, item) in items.iter().enumerate() {
            let at_end = k + 1 == items.len();
            buf.push_back(match item {
                Sample::Frame(f) => {
                    if let Some(q0) = last_q {
                        cum_rot += step_log(&q0, &f.q);
                    }
                    last_q = Some(f.q);
                    let x = [cum_rot.x, cum_rot.y, cum_rot.z, f.p.x, f.p.y, f.p.z];
                    (f.t, true, x, terms(f.t, &x, &origin))
                }
                Sample::Outlier(_, t) => (*t, false, [0.0; 6], [0.0; TERMS]),
            });
            queued.push_back(*item);
            for end in [false, at_end] {
                while center < buf.len() {
                    let tc = buf[center].0;
                    while hi < buf.len() && buf[hi].0 <= tc + window {
                        right.add(&buf[hi].3);
                        hi += 1;
                    }
                    if hi == buf.len() && !end {
                        break;
                    }
                    while center > 0 && buf[0].0 < tc - window {
                        left = left.minus(&Sums(buf.pop_front().unwrap().3));
                        queued.pop_front();
                        center -= 1;
                        hi -= 1;
                    }
                    if since_rebase == 0 || since_rebase >= REBASE_EVERY.max(buf.len()) {
                        origin = (buf[center].0, buf[center].2);
                        (left, right) = (Sums::default(), Sums::default());
                        for e in buf.iter_mut().filter(|e| e.1) {
                            e.3 = terms(e.0, &e.2, &origin);
                        }
                        buf.range(..=center).for_each(|e| left.add(&e.3));
                        buf.range(center..hi).for_each(|e| right.add(&e.3));
                        since_rebase = 0;
                    } else {
                        left.add(&buf[center].3);
                    }
                    since_rebase += 1;
                    let e = buf[center];
                    let moving = e.1
                        && left.exceeds(&inv_var, threshold)
                        && right.exceeds(&inv_var, threshold);
                    right = right.minus(&Sums(e.3));
                    out.push((key(&queued[center]), moving, [e.2[0], e.2[1], e.2[2]]));
                    center += 1;
                }
            }
        }
        out
    }

    #[test]
    fn matches_the_queue_based_reference() {
        // Rests and motions at random speeds, outliers, gaps in time; windows of 3 to ~600 items
        // (the ring grows).
        let mut seed =
            <rand::rngs::StdRng as rand::SeedableRng>::seed_from_u64(0x2545_f491_4f6c_dd1d);
        let mut rnd = move || rand::Rng::random::<f64>(&mut seed);
        let mut moving_frames = 0;
        for (window, n) in [(0.1, 50), (0.6, 3000), (5.0, 2000), (0.6, 1)] {
            let (mut t, mut w, mut v) = (0.0, Vector3::zeros(), Vector3::zeros());
            let (mut q, mut p) = (UnitQuaternion::identity(), Vector3::zeros());
            let items: Vec<Sample> = (0..n)
                .map(|index| {
                    t += if rnd() < 0.01 { 0.5 } else { 1.0 / 120.0 };
                    if rnd() < 0.01 {
                        let still = rnd() < 0.5;
                        w = Vector3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5)
                            * (!still as u8 as f64);
                        v = w * 0.1;
                    }
                    q *= UnitQuaternion::from_scaled_axis(w / 120.0);
                    p += v / 120.0;
                    let noise = |r: &mut dyn FnMut() -> f64, s: f64| {
                        Vector3::new(r() - 0.5, r() - 0.5, r() - 0.5) * s
                    };
                    if rnd() < 0.05 {
                        return Sample::Outlier(index, t);
                    }
                    Sample::Frame(RawFrame {
                        index,
                        t,
                        q: q * UnitQuaternion::from_scaled_axis(noise(&mut rnd, 0.02)),
                        p: p + noise(&mut rnd, 0.002),
                    })
                })
                .collect();
            let mut d = RestDetector::new(window, 1e-3, 0.0087, 1e-3);
            let expected = reference(&d, &items);
            let mut got = Vec::new();
            let mut keep = |i: SampleRef<'_>, m: bool, r: &Vector3<f64>| {
                got.push((key(&i.to_sample()), m, [r.x, r.y, r.z]));
            };
            let mut rotation = RotationSum::default();
            for i in &items {
                let rot = match i {
                    Sample::Frame(f) => rotation.next(&f.q),
                    Sample::Outlier(..) => Vector3::zeros(),
                };
                d.push(i, &rot, &mut keep);
            }
            d.finish(&mut keep);
            moving_frames += got.iter().filter(|g| g.1).count();
            assert_eq!(got, expected);
        }
        assert!(moving_frames > 1000, "{moving_frames}");
    }

    #[test]
    fn detects_a_slow_tilt_between_rests() {
        // 1 s rest, 2 s tilt at 0.1 rad/s, 1 s rest, exact data with 0.5 deg / 1 mm noise model.
        let mut d = RestDetector::new(0.6, 1e-3, 0.0087, 1e-3);
        let mut verdicts = Vec::new();
        let mut rotation = RotationSum::default();
        for k in 0..120 {
            let t = k as f64 / 30.0;
            let angle = 0.1 * (t - 1.0).clamp(0.0, 2.0);
            let f = RawFrame {
                index: k,
                t,
                q: UnitQuaternion::from_scaled_axis(Vector3::new(angle, 0.0, 0.0)),
                p: Vector3::zeros(),
            };
            let rot = rotation.next(&f.q);
            d.push(
                &Sample::Frame(f),
                &rot,
                &mut |i: SampleRef<'_>, m, _: &Vector3<f64>| verdicts.push((i.to_sample(), m)),
            );
        }
        d.finish(&mut |i: SampleRef<'_>, m, _: &Vector3<f64>| verdicts.push((i.to_sample(), m)));
        assert_eq!(verdicts.len(), 120);
        let moving: Vec<bool> = verdicts.iter().map(|v| v.1).collect();
        assert!(moving[..20].iter().all(|m| !m), "{moving:?}");
        assert!(moving[40..80].iter().all(|m| *m), "{moving:?}");
        assert!(moving[100..].iter().all(|m| !m), "{moving:?}");
    }
}
