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
//! Sums over the windows are kept incrementally, re-based on a local time and pose origin every
//! [`REBASE_EVERY`] frames (or every window's worth of frames, if more, so that re-basing costs
//! O(1) per frame) so that long files do not lose precision to cancellation.

use super::Config;
use crate::clean::RawFrame;
use crate::noise::{self, NoiseModel};
use crate::se3::so3_log;
use nalgebra::Vector3;
use std::collections::VecDeque;

/// Frames between two re-computations of the running sums from scratch.
pub const REBASE_EVERY: usize = 256;

/// An item flowing through the detector: a good frame or a rejected one (kept for ordering).
#[derive(Clone, Copy, Debug)]
pub enum Item {
    /// A frame.
    Frame(RawFrame),
    /// A frame rejected as an outlier (index, time).
    Outlier(usize, f64),
}

/// Window data of one item: time, and for frames (accumulated rotation, position).
#[derive(Clone, Copy, Debug)]
struct Entry {
    t: f64,
    is_frame: bool,
    x: [f64; 6],
    /// The item's terms of the window sums about the current origin (see [`Sums`]), zero for
    /// outliers.
    terms: [f64; TERMS],
}

/// Number of running sums (padded to an even count for two-lane SIMD).
const TERMS: usize = 16;

/// Running least-squares sums of (t, x) over a window, about a local origin: with
/// `dt = t - t₀` and `x = x - x₀`, the terms are `[1, dt, dt², x₀..x₅, dt·x₀..dt·x₅, 0]`, so
/// adding or removing an item is one vector addition.
#[derive(Clone, Copy, Debug)]
struct Sums([f64; TERMS]);

impl Default for Sums {
    fn default() -> Self {
        Sums([0.0; TERMS])
    }
}

/// The terms of a frame at `t, x` about `origin` (see [`Sums`]).
fn terms(t: f64, x: &[f64; 6], origin: &(f64, [f64; 6])) -> [f64; TERMS] {
    let dt = t - origin.0;
    let mut v = [0.0; TERMS];
    v[0] = 1.0;
    v[1] = dt;
    v[2] = dt * dt;
    for j in 0..6 {
        let d = x[j] - origin.1[j];
        v[3 + j] = d;
        v[9 + j] = dt * d;
    }
    v
}

impl Sums {
    #[inline(always)]
    fn add(&mut self, e: &Entry) {
        for (s, v) in self.0.iter_mut().zip(&e.terms) {
            *s += v;
        }
    }

    #[inline(always)]
    fn sub(&mut self, e: &Entry) {
        for (s, v) in self.0.iter_mut().zip(&e.terms) {
            *s -= v;
        }
    }

    /// Whether the χ²₆ statistic of the slope exceeds `threshold` (never with fewer than 3
    /// frames). With `D = n S_tt - S_t²` the slope is `β_j = (n S_tx_j - S_t S_x_j) / D` and
    /// its variance `σ_j² n / D`, so the statistic is `Σ_j (n S_tx_j - S_t S_x_j)² / (σ_j² n D)`,
    /// compared here without a division.
    #[inline(always)]
    fn exceeds(&self, inv_var: &[f64; 6], threshold: f64) -> bool {
        let [n, st, stt, ..] = self.0;
        if n < 2.5 {
            return false;
        }
        let den = n * stt - st * st;
        if den <= 0.0 {
            return false;
        }
        let mut sum = 0.0;
        for j in 0..6 {
            let b = n * self.0[9 + j] - st * self.0[3 + j];
            sum += b * b * inv_var[j];
        }
        sum > threshold * n * den
    }
}

/// Streaming rest detector; emits items in order with a `moving` verdict for frames.
#[derive(Debug)]
pub struct RestDetector {
    window: f64,
    threshold: f64,
    inv_var: [f64; 6],
    /// Window data, and the items themselves (same indices).
    buf: VecDeque<Entry>,
    items: VecDeque<Item>,
    /// Index in `buf` of the next item to judge; `buf[..center]` is the left window's past.
    center: usize,
    /// `buf[center..hi]` is the right window.
    hi: usize,
    left: Sums,
    right: Sums,
    cum_rot: Vector3<f64>,
    last_q: Option<nalgebra::UnitQuaternion<f64>>,
    origin: (f64, [f64; 6]),
    since_rebase: usize,
}

impl RestDetector {
    /// A detector with windows of `window_s` \[s\], noise sigmas, and level `alpha`.
    pub fn new(window_s: f64, sigma_position: f64, sigma_rotation: f64, alpha: f64) -> Self {
        let vr = 1.0 / (sigma_rotation * sigma_rotation);
        let vp = 1.0 / (sigma_position * sigma_position);
        Self {
            window: window_s + 1e-9,
            threshold: crate::stats::chi2_threshold(6.0, alpha),
            inv_var: [vr, vr, vr, vp, vp, vp],
            buf: VecDeque::new(),
            items: VecDeque::new(),
            center: 0,
            hi: 0,
            left: Sums::default(),
            right: Sums::default(),
            cum_rot: Vector3::zeros(),
            last_q: None,
            origin: (0.0, [0.0; 6]),
            since_rebase: 0,
        }
    }

    fn rebase(&mut self) {
        let c = &self.buf[self.center];
        self.origin = (c.t, c.x);
        self.left = Sums::default();
        self.right = Sums::default();
        for e in self.buf.iter_mut().filter(|e| e.is_frame) {
            e.terms = terms(e.t, &e.x, &self.origin);
        }
        for e in self.buf.range(..=self.center) {
            self.left.add(e);
        }
        for e in self.buf.range(self.center..self.hi) {
            self.right.add(e);
        }
        self.since_rebase = 0;
    }

    /// Push the next item; judged items are passed to `out` with `moving` (false for outliers)
    /// and the accumulated rotation \[rad\] (the sum of the logs of the frame-to-frame
    /// rotations since the first frame; zero for outliers).
    pub fn push(&mut self, item: Item, out: &mut impl FnMut(Item, bool, &Vector3<f64>)) {
        let entry = match &item {
            Item::Frame(f) => {
                if let Some(q0) = self.last_q {
                    self.cum_rot += so3_log(&(q0.inverse() * f.q));
                }
                self.last_q = Some(f.q);
                let r = &self.cum_rot;
                let x = [r.x, r.y, r.z, f.p.x, f.p.y, f.p.z];
                Entry {
                    t: f.t,
                    is_frame: true,
                    x,
                    terms: terms(f.t, &x, &self.origin),
                }
            }
            Item::Outlier(_, t) => Entry {
                t: *t,
                is_frame: false,
                x: [0.0; 6],
                terms: [0.0; TERMS],
            },
        };
        self.buf.push_back(entry);
        self.items.push_back(item);
        self.drain(false, out);
    }

    /// Flush the remaining items at the end of the stream.
    pub fn finish(mut self, out: &mut impl FnMut(Item, bool, &Vector3<f64>)) {
        self.drain(true, out);
    }

    fn drain(&mut self, at_end: bool, out: &mut impl FnMut(Item, bool, &Vector3<f64>)) {
        while self.center < self.buf.len() {
            let tc = self.buf[self.center].t;
            // Extend the right window [tc, tc + w].
            while self.hi < self.buf.len() && self.buf[self.hi].t <= tc + self.window {
                self.right.add(&self.buf[self.hi]);
                self.hi += 1;
            }
            if self.hi == self.buf.len() && !at_end {
                return; // The right window is not complete yet.
            }
            // Drop frames older than tc - w from the left window [tc - w, tc].
            while self.center > 0 && self.buf[0].t < tc - self.window {
                let e = self.buf.pop_front().unwrap();
                self.items.pop_front();
                self.left.sub(&e);
                self.center -= 1;
                self.hi -= 1;
            }
            if self.since_rebase == 0 || self.since_rebase >= REBASE_EVERY.max(self.buf.len()) {
                self.rebase();
            } else {
                self.left.add(&self.buf[self.center]);
            }
            self.since_rebase += 1;
            let e = &self.buf[self.center];
            let moving = e.is_frame
                && self.left.exceeds(&self.inv_var, self.threshold)
                && self.right.exceeds(&self.inv_var, self.threshold);
            // The centre leaves the right window (it stays in the left one).
            self.right.sub(e);
            let rot = Vector3::new(e.x[0], e.x[1], e.x[2]);
            out(self.items[self.center], moving, &rot);
            self.center += 1;
        }
    }
}

/// What the rest front end passes on: first the noise model in force (once, before any item),
/// then every item in order with its verdict.
#[derive(Clone, Copy, Debug)]
pub enum Judged {
    /// The tracking noise, given or estimated from the first frames.
    Noise(NoiseModel),
    /// An item, `moving` or not, with its accumulated rotation (see [`RestDetector::push`]).
    Item(Item, bool, Vector3<f64>),
}

/// The robust classifier's front end: the noise warm-up (the first
/// [`super::RobustConfig::warmup_frames`] items, unless the noise is given) and the
/// [`RestDetector`]. It only looks at the cleaned stream, so it can run on another thread than
/// the segments and blocks that consume its output.
#[derive(Debug)]
pub struct RestFront {
    config: Config,
    warm: Vec<Item>,
    noise: Option<NoiseModel>,
    rest: Option<RestDetector>,
}

impl RestFront {
    /// A front end for `config`.
    pub fn new(config: &Config) -> Self {
        Self {
            config: *config,
            warm: Vec::new(),
            noise: config.robust.noise.map(NoiseModel::floored),
            rest: None,
        }
    }

    fn start(&mut self, out: &mut impl FnMut(Judged)) {
        let noise = self.noise.unwrap_or_else(|| {
            let samples: Vec<noise::PoseSample> = self
                .warm
                .iter()
                .filter_map(|i| match i {
                    Item::Frame(f) => Some((f.t, f.q, f.p)),
                    Item::Outlier(..) => None,
                })
                .collect();
            noise::estimate(&samples).unwrap_or(NoiseModel {
                sigma_position: noise::MIN_SIGMA_POSITION_M,
                sigma_rotation: noise::MIN_SIGMA_ROTATION_RAD,
            })
        });
        self.noise = Some(noise);
        out(Judged::Noise(noise));
        let r = &self.config.robust;
        let mut rest = RestDetector::new(
            r.rest_window_s,
            noise.sigma_position,
            noise.sigma_rotation,
            r.alpha,
        );
        for item in std::mem::take(&mut self.warm) {
            rest.push(item, &mut |i, m, r| out(Judged::Item(i, m, *r)));
        }
        self.rest = Some(rest);
    }

    /// Push the next item; what is judged goes to `out`.
    pub fn push(&mut self, item: Item, out: &mut impl FnMut(Judged)) {
        match self.rest.as_mut() {
            Some(rest) => rest.push(item, &mut |i, m, r| out(Judged::Item(i, m, *r))),
            None => {
                self.warm.push(item);
                if self.warm.len() >= self.config.robust.warmup_frames.max(3) {
                    self.start(out);
                }
            }
        }
    }

    /// Flush the remaining items at the end of the stream.
    pub fn finish(mut self, out: &mut impl FnMut(Judged)) {
        if self.rest.is_none() {
            self.start(out);
        }
        if let Some(rest) = self.rest.take() {
            rest.finish(&mut |i, m, r| out(Judged::Item(i, m, *r)));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::UnitQuaternion;

    #[test]
    fn detects_a_slow_tilt_between_rests() {
        // 1 s rest, 2 s tilt at 0.1 rad/s, 1 s rest, exact data with 0.5 deg / 1 mm noise model.
        let mut d = RestDetector::new(0.6, 1e-3, 0.0087, 1e-3);
        let mut verdicts = Vec::new();
        for k in 0..120 {
            let t = k as f64 / 30.0;
            let angle = 0.1 * (t - 1.0).clamp(0.0, 2.0);
            let f = RawFrame {
                index: k,
                t,
                q: UnitQuaternion::from_scaled_axis(Vector3::new(angle, 0.0, 0.0)),
                p: Vector3::zeros(),
            };
            d.push(Item::Frame(f), &mut |i, m, _| verdicts.push((i, m)));
        }
        d.finish(&mut |i, m, _| verdicts.push((i, m)));
        assert_eq!(verdicts.len(), 120);
        let moving: Vec<bool> = verdicts.iter().map(|v| v.1).collect();
        assert!(moving[..20].iter().all(|m| !m), "{moving:?}");
        assert!(moving[40..80].iter().all(|m| *m), "{moving:?}");
        assert!(moving[100..].iter().all(|m| !m), "{moving:?}");
    }
}
