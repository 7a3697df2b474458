//! Rest detection: is the object's pose changing at time t, given the tracking noise?
//!
//! For each frame c, the pose over the window `|t - t_c| <= w/2` is fitted with a straight line
//! in time, per coordinate: the three coordinates of the accumulated rotation increments
//! `Σ log(q_{k-1}⁻¹ q_k)` (continuous, unlike a rotation vector from a fixed reference, which
//! wraps at π) and the three of the position. Under rest, each slope β_j is Gaussian with
//! variance `σ_j² / S_tt`, `S_tt = Σ (t_k - t̄)²`, so `Σ_j β_j² S_tt / σ_j²` is χ²₆; the frame is
//! moving when that exceeds the χ²₆ quantile at level `alpha`. The slope test uses every frame of
//! the window, so it detects a slow tilt (0.1 rad/s at 0.5° noise and 30 Hz) that a
//! frame-to-frame difference misses.
//!
//! Sums over the window are kept incrementally, re-based on a local time and pose origin every
//! [`REBASE_EVERY`] frames so that long files do not lose precision to cancellation.

use crate::clean::RawFrame;
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

#[derive(Clone, Copy, Debug)]
struct Entry {
    item: Item,
    /// (accumulated rotation, position), for frames.
    x: [f64; 6],
}

/// Streaming rest detector; emits items in order with a `moving` verdict for frames.
#[derive(Debug)]
pub struct RestDetector {
    half: f64,
    threshold: f64,
    inv_var: [f64; 6],
    buf: VecDeque<Entry>,
    /// Index in `buf` of the next frame to judge.
    center: usize,
    /// `buf[lo..hi]` are the frames (and outliers) in the current window.
    hi: usize,
    cum_rot: Vector3<f64>,
    last_q: Option<nalgebra::UnitQuaternion<f64>>,
    origin: (f64, [f64; 6]),
    sums: Sums,
    since_rebase: usize,
}

#[derive(Clone, Copy, Debug, Default)]
struct Sums {
    n: f64,
    st: f64,
    stt: f64,
    sx: [f64; 6],
    stx: [f64; 6],
}

impl RestDetector {
    /// A detector with window width `window_s` [s], noise sigmas, and level `alpha`.
    pub fn new(window_s: f64, sigma_position: f64, sigma_rotation: f64, alpha: f64) -> Self {
        let vr = 1.0 / (sigma_rotation * sigma_rotation);
        let vp = 1.0 / (sigma_position * sigma_position);
        Self {
            half: 0.5 * window_s + 1e-9,
            threshold: crate::stats::chi2_threshold(6.0, alpha),
            inv_var: [vr, vr, vr, vp, vp, vp],
            buf: VecDeque::new(),
            center: 0,
            hi: 0,
            cum_rot: Vector3::zeros(),
            last_q: None,
            origin: (0.0, [0.0; 6]),
            sums: Sums::default(),
            since_rebase: 0,
        }
    }

    fn time(e: &Entry) -> f64 {
        match e.item {
            Item::Frame(f) => f.t,
            Item::Outlier(_, t) => t,
        }
    }

    fn add(&mut self, i: usize, sign: f64) {
        let e = self.buf[i];
        if let Item::Frame(_) = e.item {
            let dt = Self::time(&e) - self.origin.0;
            let s = &mut self.sums;
            s.n += sign;
            s.st += sign * dt;
            s.stt += sign * dt * dt;
            for j in 0..6 {
                let x = e.x[j] - self.origin.1[j];
                s.sx[j] += sign * x;
                s.stx[j] += sign * dt * x;
            }
        }
    }

    fn rebase(&mut self) {
        let c = self.buf[self.center];
        self.origin = (Self::time(&c), c.x);
        self.sums = Sums::default();
        for i in 0..self.hi {
            self.add(i, 1.0);
        }
        self.since_rebase = 0;
    }

    /// Push the next item; judged items are passed to `out` with `moving` (false for outliers).
    pub fn push(&mut self, item: Item, out: &mut impl FnMut(Item, bool)) {
        let mut x = [0.0; 6];
        if let Item::Frame(f) = &item {
            if let Some(q0) = self.last_q {
                self.cum_rot += so3_log(&(q0.inverse() * f.q));
            }
            self.last_q = Some(f.q);
            x = [self.cum_rot.x, self.cum_rot.y, self.cum_rot.z, f.p.x, f.p.y, f.p.z];
        }
        self.buf.push_back(Entry { item, x });
        self.drain(false, out);
    }

    /// Flush the remaining items at the end of the stream.
    pub fn finish(mut self, out: &mut impl FnMut(Item, bool)) {
        self.drain(true, out);
    }

    fn drain(&mut self, at_end: bool, out: &mut impl FnMut(Item, bool)) {
        while self.center < self.buf.len() {
            let tc = Self::time(&self.buf[self.center]);
            // Extend the window to the right.
            while self.hi < self.buf.len() && Self::time(&self.buf[self.hi]) <= tc + self.half {
                self.add(self.hi, 1.0);
                self.hi += 1;
            }
            if self.hi == self.buf.len() && !at_end {
                return; // The window is not complete yet.
            }
            // Shrink it on the left.
            while self.center > 0 && Self::time(&self.buf[0]) < tc - self.half {
                self.add(0, -1.0);
                self.buf.pop_front();
                self.center -= 1;
                self.hi -= 1;
            }
            if self.since_rebase == 0 || self.since_rebase >= REBASE_EVERY {
                self.rebase();
            }
            self.since_rebase += 1;
            let e = self.buf[self.center];
            let moving = matches!(e.item, Item::Frame(_)) && self.statistic() > self.threshold;
            out(e.item, moving);
            self.center += 1;
        }
    }

    /// χ²₆ statistic of the slope over the current window (0 with fewer than 3 frames).
    fn statistic(&self) -> f64 {
        let s = &self.sums;
        if s.n < 3.0 {
            return 0.0;
        }
        let den = s.n * s.stt - s.st * s.st;
        if den <= 0.0 {
            return 0.0;
        }
        let stt_c = den / s.n; // Σ (t - t̄)²
        let mut chi2 = 0.0;
        for j in 0..6 {
            let beta = (s.n * s.stx[j] - s.st * s.sx[j]) / den;
            chi2 += beta * beta * stt_c * self.inv_var[j];
        }
        chi2
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
            let f = RawFrame { index: k, t, q: UnitQuaternion::from_scaled_axis(Vector3::new(angle, 0.0, 0.0)), p: Vector3::zeros(), down: None };
            d.push(Item::Frame(f), &mut |i, m| verdicts.push((i, m)));
        }
        d.finish(&mut |i, m| verdicts.push((i, m)));
        assert_eq!(verdicts.len(), 120);
        let moving: Vec<bool> = verdicts.iter().map(|v| v.1).collect();
        assert!(moving[..20].iter().all(|m| !m), "{moving:?}");
        assert!(moving[40..80].iter().all(|m| *m), "{moving:?}");
        assert!(moving[100..].iter().all(|m| !m), "{moving:?}");
    }
}
