//! An instrumented demonstration: the object's motion relative to the palm
//! (`palm_from_object`), the support's "down" in the palm frame, and the two streams' clocks
//! ([`Clocks`]).

use super::sample::Sample;
use crate::clean::RawFrame;
use crate::noise::{self, NoiseModel};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};
use std::collections::VecDeque;

/// How the palm's clock relates to the object's, when they come from different sensors (a
/// camera and the robot's joint states) at different rates and with an offset.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Clocks {
    /// Added to the palm's stamps \[s\] to put them on the object's clock: a palm clock
    /// running 4 ms ahead needs -0.004.
    pub palm_time_offset_s: f64,
    /// An object frame whose nearest palm pose is farther than this \[s\] is dropped (and
    /// counted in the warnings); the palm is interpolated at the others' stamps (slerp and
    /// linear). Default [`DEFAULT_MAX_DT_S`].
    pub max_dt_s: f64,
    /// Recognise timestamps in milliseconds, microseconds or nanoseconds in pose files (by
    /// their magnitude and spacing: [`crate::format::detect_time_unit`]) and convert them
    /// to seconds, with a warning.
    pub detect_time_unit: bool,
}

/// Default largest distance \[s\] from an object frame to the nearest palm pose: a palm
/// tracked at 10 Hz or faster has one within it at every object frame.
pub const DEFAULT_MAX_DT_S: f64 = 0.05;

impl Default for Clocks {
    fn default() -> Self {
        Self {
            palm_time_offset_s: 0.0,
            max_dt_s: DEFAULT_MAX_DT_S,
            detect_time_unit: true,
        }
    }
}

/// Where a [`PalmMerger`] passes what it forms: the items, and the noise of the motion
/// relative to a palm slower than the object.
pub(super) trait MergeSink {
    /// The next item, with the support's "down" in the palm frame, if known.
    fn sample(&mut self, item: Sample, down: Option<Vector3<f64>>);
    /// The noise of the relative motion estimated from a slower palm's and the object's
    /// (before any item): a hint, which an estimate from the relative motion may replace.
    fn noise(&mut self, noise: NoiseModel);
    /// The noise of the relative motion propagated from the trackers' given noise (before
    /// any item): the noise in force.
    fn given_noise(&mut self, noise: NoiseModel);
}

/// Frames of each stream from which the [`PalmMerger`] measures its rate and noise.
const RATE_FRAMES: usize = 32;

/// Pairs object frames with the palm pose at the same time (interpolated between the palm
/// frames around it) and forms `palm_from_object`.
///
/// An object frame outside the palm's time range, or whose nearest palm pose is more than
/// [`Clocks::max_dt_s`] away, has no palm pose: it is dropped (not passed on, so neither
/// analysed nor counted as a tracking outlier) and counted for [`PalmMerger::report`].
///
/// A palm slower than the object (say 10 Hz under a 30 Hz object) is interpolated at several
/// object frames between the same two noisy palm poses: the palm's error in those frames is
/// one error, not independent ones, and the motion relative to the palm carries more noise at
/// low frequencies than a noise level estimated from frame to frame says. The per-frame rest
/// test then sees motion where the object rests on the palm (a 10 Hz palm made slides and
/// general segments out of rests). So the merger measures both streams' rates and noise from
/// their first [`RATE_FRAMES`] frames, and when the palm is `k` times slower, gives the
/// relative motion's noise as `σ² = σ_object² + k σ_palm²` ([`MergeSink::noise`]): the
/// noise of a velocity fitted over a window, where the palm contributes `1/k` as many
/// independent poses as the object. A palm as fast as the object or faster gives no hint.
///
/// When the object tracker's noise is given ([`super::RobustConfig::noise`]), the relative
/// motion's is propagated from it and the palm's ([`noise::relative`], with the object's
/// distance from the palm over the same first frames, and the palm's slowness), and is the
/// noise in force ([`MergeSink::given_noise`]). The palm's is `palm_noise` where given, else
/// estimated from its first frames (as every noise not given is), else the object's: a palm
/// posed by the robot's joint encoders is far better than the camera on the object (MuJoCo's
/// palm topples, 0.2 mm and 0.05° against 1 mm and 0.5°: taken as the object's, the edges
/// were 3.2 mm off, median, where they are 1.6 mm with the palm's own). Until 2026-12-04 a
/// given object noise was taken as the relative motion's, which at 2 mm and 1° per tracker
/// with the object 0.1 m from the palm is 60% of it (on the simulator's instrumented
/// demonstrations the rests then showed motion, topples were measured from the wrong rest
/// and 13 of 30 edges came out 6-17 mm off).
///
/// The support's "down" in the palm frame is taken once, from gravity over the palm's first
/// [`SUPPORT_FRAMES`] frames (the palm is level when a demonstration starts), and held fixed:
/// the object rests on the palm's surface however the palm is tilted later, so that is the
/// direction whose face the object rests on, not the current gravity. It is passed on with
/// every item.
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
    max_dt: f64,
    /// The first frames of each stream, for their rates and noise.
    first_object: Vec<RawFrame>,
    first_palm: Vec<RawFrame>,
    /// The object tracker's noise, if given, and the palm's, if given too.
    given: Option<(NoiseModel, Option<NoiseModel>)>,
    /// The relative motion's noise, once settled: propagated from the given noise, or if
    /// none is given and the palm is slower than the object, estimated.
    noise_hint: Option<Option<NoiseModel>>,
    /// First and last palm stamps.
    palm_range: Option<(f64, f64)>,
    /// First and last object stamps.
    object_range: Option<(f64, f64)>,
    /// Object frames passed on with a palm pose.
    paired: u64,
    /// Object frames before the palm's first pose, after its last, and without a palm pose
    /// within `max_dt`.
    before: u64,
    after: u64,
    too_far: u64,
}

/// Palm frames averaged for the support's "down" in the palm frame (0.5 s at 30 Hz): one frame
/// would carry its 0.5° orientation noise into every resting-face normal and tilt angle.
pub(crate) const SUPPORT_FRAMES: usize = 15;

impl PalmMerger {
    /// A merger; `down_world` is gravity in the world frame, if known; `given`, the object
    /// tracker's noise, if given, and the palm's, if given too.
    pub(super) fn new(
        down_world: Option<Vector3<f64>>,
        clocks: &Clocks,
        given: Option<(NoiseModel, Option<NoiseModel>)>,
    ) -> Self {
        Self {
            down_world,
            given,
            max_dt: clocks.max_dt_s,
            ..Self::default()
        }
    }

    pub(super) fn push_palm(&mut self, f: RawFrame, out: &mut impl MergeSink) {
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
        self.palm_range = Some(match self.palm_range {
            None => (f.t, f.t),
            Some((a, _)) => (a, f.t),
        });
        if self.first_palm.len() < RATE_FRAMES {
            self.first_palm.push(f);
        }
        self.palm.push_back(f);
        self.drain(out);
    }

    /// Queue an object frame (or an object outlier, kept in order).
    pub(super) fn push_object(&mut self, f: RawFrame, outlier: bool, out: &mut impl MergeSink) {
        self.object_range = Some(match self.object_range {
            None => (f.t, f.t),
            Some((a, b)) => (a.min(f.t), b.max(f.t)),
        });
        if self.first_object.len() < RATE_FRAMES && !outlier {
            self.first_object.push(f);
        }
        self.pending.push_back((f, outlier));
        self.drain(out);
    }

    /// Whether the noise of the motion relative to the palm is settled (see the type's
    /// documentation): once both streams' first [`RATE_FRAMES`] frames are in, or at the end.
    /// When settled the first time, a slower palm's noise goes to `out`, before any item.
    fn settle_noise(&mut self, out: &mut impl MergeSink) -> bool {
        if self.noise_hint.is_some() {
            return true;
        }
        let full = self.first_object.len() >= RATE_FRAMES && self.first_palm.len() >= RATE_FRAMES;
        if !full && !self.palm_done {
            return false;
        }
        match self.given {
            Some((object, palm)) => {
                let n = given_relative_noise(object, palm, &self.first_object, &self.first_palm);
                self.noise_hint = Some(Some(n));
                out.given_noise(n);
            }
            None => {
                let hint = slow_palm_noise(&self.first_object, &self.first_palm);
                self.noise_hint = Some(hint);
                if let Some(n) = hint {
                    out.noise(n);
                }
            }
        }
        true
    }

    fn drain(&mut self, out: &mut impl MergeSink) {
        if !self.settle_noise(out) {
            return; // Still measuring the streams' rates and noise.
        }
        let max_dt = self.max_dt;
        if self.support_down.is_none() {
            if !self.palm_done {
                return; // Still averaging the support direction.
            }
            self.support_down = Some(self.support_sum.try_normalize(1e-12));
        }
        let down = self.support_down.flatten();
        let mut out = |i| out.sample(i, down);
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
                    self.after += 1; // No palm pose at all, or only after it.
                    continue;
                }
                return;
            };
            let palm = if a.t == o.t {
                Ok((a.q, a.p))
            } else if a.t > o.t {
                Err(&mut self.before)
            } else if let Some(b) = self.palm.get(1) {
                if (o.t - a.t).min(b.t - o.t) > max_dt {
                    Err(&mut self.too_far)
                } else {
                    let s = (o.t - a.t) / (b.t - a.t);
                    Ok((a.q.slerp(&b.q, s), a.p * (1.0 - s) + b.p * s))
                }
            } else if self.palm_done {
                Err(&mut self.after)
            } else {
                return; // Wait for the next palm frame.
            };
            self.pending.pop_front();
            match palm {
                Err(count) => *count += 1,
                Ok((pq, pp)) => {
                    self.paired += 1;
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

    pub(super) fn finish(&mut self, out: &mut impl MergeSink) {
        self.palm_done = true;
        self.drain(out);
    }
}

impl PalmMerger {
    /// After [`PalmMerger::finish`]: warnings about the object frames dropped for want of a
    /// palm pose, or an error when no object frame had one (the two streams do not overlap
    /// in time, or never within `max_dt`).
    pub(super) fn report(&self) -> Result<Vec<String>, String> {
        let (Some((o0, o1)), Some((p0, p1))) = (self.object_range, self.palm_range) else {
            return Ok(vec![]);
        };
        let outside = self.before + self.after;
        let ranges =
            format!("object {o0:.3}..{o1:.3} s, palm {p0:.3}..{p1:.3} s on the object's clock");
        if self.paired == 0 && outside + self.too_far > 0 {
            if self.too_far == 0 || o1 < p0 || p1 < o0 {
                return Err(format!(
                    "the object's and the palm's stamps do not overlap in time ({ranges}): \
                     their clocks differ (by about {:.3} s between their middles); give the \
                     palm's offset with --palm-time-offset S (added to the palm's stamps), or \
                     convert the stamps to seconds",
                    0.5 * ((o0 + o1) - (p0 + p1))
                ));
            }
            return Err(format!(
                "no object frame has a palm pose within {} s (--max-dt) ({ranges})",
                self.max_dt
            ));
        }
        let mut w = Vec::new();
        let total = self.paired + outside + self.too_far;
        if outside > 0 {
            w.push(format!(
                "the object's and the palm's stamps overlap only in part ({ranges}): {outside} \
                 of {total} object frames lie outside the palm's time range and were dropped \
                 (not analysed; not tag flips)"
            ));
        }
        if self.too_far > 0 {
            w.push(format!(
                "{} of {total} object frames have no palm pose within {} s (--max-dt) and were \
                 dropped",
                self.too_far, self.max_dt
            ));
        }
        Ok(w)
    }
}

/// Median interval \[s\] between consecutive frames.
fn median_interval(frames: &[RawFrame]) -> Option<f64> {
    let mut dt: Vec<f64> = frames.windows(2).map(|w| w[1].t - w[0].t).collect();
    dt.sort_by(f64::total_cmp);
    dt.get(dt.len() / 2).copied().filter(|d| *d > 0.0)
}

/// How many times slower the palm is than the object (1 when as fast or faster, or unknown).
fn palm_slower(object: &[RawFrame], palm: &[RawFrame]) -> f64 {
    match (median_interval(palm), median_interval(object)) {
        (Some(p), Some(o)) => (p / o).max(1.0),
        _ => 1.0,
    }
}

/// The object's median distance \[m\] from the palm's origin over the first frames (each
/// object frame with the palm frame nearest in time); 0 without frames.
fn lever_m(object: &[RawFrame], palm: &[RawFrame]) -> f64 {
    let mut d: Vec<f64> = object
        .iter()
        .filter_map(|o| {
            let p = palm
                .iter()
                .min_by(|a, b| (a.t - o.t).abs().total_cmp(&(b.t - o.t).abs()))?;
            Some((p.q.inverse() * (o.p - p.p)).norm())
        })
        .collect();
    d.sort_by(f64::total_cmp);
    d.get(d.len() / 2).copied().unwrap_or(0.0)
}

/// The noise of the motion relative to the palm from the object tracker's given noise and
/// the palm's (given, else estimated from its first frames, else the object's)
/// ([`noise::relative`]), at the first frames' lever and the palm's slowness.
fn given_relative_noise(
    object_noise: NoiseModel,
    palm_noise: Option<NoiseModel>,
    object: &[RawFrame],
    palm: &[RawFrame],
) -> NoiseModel {
    let palm_noise = palm_noise
        .or_else(|| {
            let s: Vec<noise::PoseSample> = palm.iter().map(|f| (f.t, f.q, f.p)).collect();
            noise::estimate(&s)
        })
        .unwrap_or(object_noise);
    noise::relative(
        object_noise.floored(),
        palm_noise,
        lever_m(object, palm),
        palm_slower(object, palm),
    )
    .floored()
}

/// The noise of the motion relative to a palm `k` times slower than the object (each
/// stream's noise estimated from its first frames, combined by [`noise::relative`]), if the
/// palm is slower by more than half; `None` otherwise.
fn slow_palm_noise(object: &[RawFrame], palm: &[RawFrame]) -> Option<NoiseModel> {
    let k = palm_slower(object, palm);
    if k < 1.5 {
        return None;
    }
    let est = |f: &[RawFrame]| {
        let s: Vec<noise::PoseSample> = f.iter().map(|f| (f.t, f.q, f.p)).collect();
        noise::estimate(&s)
    };
    let (o, p) = (est(object)?, est(palm)?);
    Some(noise::relative(o, p, lever_m(object, palm), k).floored())
}
