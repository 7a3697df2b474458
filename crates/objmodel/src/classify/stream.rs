//! The streaming front end: cleaning each tracked stream, forming the palm-relative motion of an
//! instrumented demonstration, and feeding the robust ([`super::blocks`]) or the paper's
//! ([`super::paper`]) back end.

use super::blocks::Core;
use super::front::{Judged, RestFront, ToJudged};
use super::paper::PaperCore;
use super::rest::{Item, RotationSum};
use super::{Classification, Config, Method};
use crate::clean::{Cleaner, RawFrame};
use crate::noise::{self, NoiseModel};
use crate::trajectory::StampedPose;
use nalgebra::{UnitQuaternion, Vector3};
use std::collections::VecDeque;

/// Cleans one stream: noise warm-up, then the tag-flip [`Cleaner`].
struct StreamCleaner {
    warm: Vec<RawFrame>,
    warmup: usize,
    alpha: f64,
    noise: Option<NoiseModel>,
    cleaner: Option<Cleaner>,
}

impl StreamCleaner {
    fn new(config: &Config) -> Self {
        Self {
            warm: Vec::new(),
            warmup: config.robust.warmup_frames.max(3),
            alpha: config.robust.outlier_alpha,
            noise: config.robust.noise,
            cleaner: None,
        }
    }

    fn start(&mut self, out: &mut impl FnMut(RawFrame, bool)) {
        let samples: Vec<noise::PoseSample> = self.warm.iter().map(|f| (f.t, f.q, f.p)).collect();
        let n = self
            .noise
            .or_else(|| noise::estimate(&samples))
            .unwrap_or(NoiseModel {
                sigma_position: 1e-3,
                sigma_rotation: 1e-2,
            });
        let mut c = Cleaner::new(n.floored().sigma_rotation, self.alpha);
        for f in std::mem::take(&mut self.warm) {
            c.push(f, out);
        }
        self.cleaner = Some(c);
    }

    // Inlined with `Cleaner::push`, so that the new frame is handed over in registers: through
    // memory it costs store-forwarding stalls (clean only: 16 -> 12 ns/pose).
    #[inline(always)]
    fn push(&mut self, f: RawFrame, out: &mut impl FnMut(RawFrame, bool)) {
        match &mut self.cleaner {
            Some(c) => c.push(f, out),
            None => {
                self.warm.push(f);
                if self.warm.len() >= self.warmup {
                    self.start(out);
                }
            }
        }
    }

    fn finish(mut self, out: &mut impl FnMut(RawFrame, bool)) {
        if self.cleaner.is_none() {
            self.start(out);
        }
        self.cleaner.take().unwrap().finish(out);
    }
}

/// The object stream's cleaner, detached from its [`Analyzer`] so that it can run on another
/// thread (it is `Send`).
pub struct ObjectCleaner {
    cleaner: StreamCleaner,
    frames: usize,
}

impl ObjectCleaner {
    /// Push the next object pose; judged frames are passed to `out` with their verdict.
    pub fn push(&mut self, p: &StampedPose, out: &mut impl FnMut(RawFrame, bool)) {
        let f = RawFrame {
            index: self.frames,
            t: p.t,
            q: p.pose.rotation,
            p: p.pose.translation.vector,
        };
        self.frames += 1;
        self.cleaner.push(f, out);
    }

    /// Flush the last frames.
    pub fn finish(self, out: &mut impl FnMut(RawFrame, bool)) {
        self.cleaner.finish(out);
    }
}

/// The object stream's cleaner and the accumulated rotation of the frames it keeps
/// ([`RotationSum`]): the part of the robust analysis before rest detection that can run on
/// another thread (it is `Send`). Feed it poses; pass what it emits to
/// [`Analyzer::push_cleaned_rotated`].
pub struct RotatingCleaner {
    cleaner: ObjectCleaner,
    rotation: RotationSum,
}

impl RotatingCleaner {
    /// Wrap a cleaner taken with [`Analyzer::take_object_cleaner`].
    pub fn new(cleaner: ObjectCleaner) -> Self {
        Self {
            cleaner,
            rotation: RotationSum::default(),
        }
    }

    /// Push the next object pose; judged frames are passed to `out` with their verdict and,
    /// for kept frames, their accumulated rotation \[rad\] (zero for rejected ones).
    #[inline(always)]
    pub fn push(&mut self, p: &StampedPose, out: &mut impl FnMut(RawFrame, bool, Vector3<f64>)) {
        let rotation = &mut self.rotation;
        self.cleaner.push(p, &mut |f, outlier| {
            out(f, outlier, rotated(rotation, &f, outlier))
        });
    }

    /// Flush the last frames.
    pub fn finish(self, out: &mut impl FnMut(RawFrame, bool, Vector3<f64>)) {
        let mut rotation = self.rotation;
        self.cleaner
            .finish(&mut |f, outlier| out(f, outlier, rotated(&mut rotation, &f, outlier)));
    }
}

/// The accumulated rotation at a cleaned frame: zero for a rejected one, which is left out.
#[inline(always)]
fn rotated(rotation: &mut RotationSum, f: &RawFrame, outlier: bool) -> Vector3<f64> {
    if outlier {
        Vector3::zeros()
    } else {
        rotation.next(&f.q)
    }
}

/// The object stream's cleaner *and* the robust classifier's rest front end, detached from
/// their [`Analyzer`] so that they can run on another thread (parsing, cleaning and rest
/// detection there; segments and blocks in [`Analyzer::push_judged`]). For demonstrations
/// without a palm.
pub struct ObjectFront {
    cleaner: ObjectCleaner,
    front: RestFront,
}

impl ObjectFront {
    /// Push the next object pose; what is judged goes to `out`.
    pub fn push(&mut self, p: &StampedPose, out: &mut impl FnMut(Judged)) {
        let front = &mut self.front;
        let mut out = ToJudged(out);
        self.cleaner
            .push(p, &mut |f, outlier| front.push(item(f, outlier), &mut out));
    }

    /// Flush the last frames.
    pub fn finish(self, out: &mut impl FnMut(Judged)) {
        let Self { cleaner, mut front } = self;
        let mut out = ToJudged(out);
        cleaner.finish(&mut |f, outlier| front.push(item(f, outlier), &mut out));
        front.finish(&mut out);
    }
}

/// A cleaned frame as an item for a back end (an outlier keeps only its index and time).
fn item(f: RawFrame, outlier: bool) -> Item {
    if outlier {
        Item::Outlier(f.index, f.t)
    } else {
        Item::Frame(f)
    }
}

/// Pairs object frames with the palm pose at the same time (interpolated between the palm
/// frames around it) and forms `palm_from_object`.
///
/// The support's "down" in the palm frame is taken once, from gravity over the palm's first
/// [`SUPPORT_FRAMES`] frames (the palm is level when a demonstration starts), and held fixed: the object rests on
/// the palm's surface however the palm is tilted later, so that is the direction whose face
/// the object rests on, not the current gravity. It is passed on with every item.
#[derive(Default)]
struct PalmMerger {
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
    fn push_palm(&mut self, f: RawFrame, out: &mut impl FnMut(Item, Option<Vector3<f64>>)) {
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
    fn push_object(
        &mut self,
        f: RawFrame,
        outlier: bool,
        out: &mut impl FnMut(Item, Option<Vector3<f64>>),
    ) {
        self.pending.push_back((f, outlier));
        self.drain(out);
    }

    fn drain(&mut self, out: &mut impl FnMut(Item, Option<Vector3<f64>>)) {
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
                out(Item::Outlier(o.index, o.t));
                continue;
            }
            while self.palm.len() >= 2 && self.palm[1].t <= o.t {
                self.palm.pop_front();
            }
            let Some(a) = self.palm.front().copied() else {
                if self.palm_done {
                    self.pending.pop_front();
                    out(Item::Outlier(o.index, o.t));
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
                None => out(Item::Outlier(o.index, o.t)),
                Some((pq, pp)) => {
                    let inv = pq.inverse();
                    out(Item::Frame(RawFrame {
                        index: o.index,
                        t: o.t,
                        q: inv * o.q,
                        p: inv * (o.p - pp),
                    }))
                }
            }
        }
    }

    fn finish(&mut self, out: &mut impl FnMut(Item, Option<Vector3<f64>>)) {
        self.palm_done = true;
        self.drain(out);
    }
}

// One per analyzer, on the per-frame path: boxing the large variant would add an indirection
// to every frame for no saving that matters.
#[allow(clippy::large_enum_variant)]
enum Back {
    Robust(Core),
    Paper(PaperCore),
}

impl Back {
    /// Push an item; `down` is the unit "down" in the frame the item's pose is relative to
    /// (constant over a stream once known).
    fn push(&mut self, item: Item, down: Option<Vector3<f64>>) {
        match self {
            Back::Robust(c) => c.push(item, down),
            Back::Paper(p) => p.push(item, down),
        }
    }
}

/// Streaming classifier of one demonstration: push poses in time order (object and palm
/// interleaved, palm first at equal times), then [`Analyzer::finish`].
pub struct Analyzer {
    name: String,
    instrumented: bool,
    down_world: Option<Vector3<f64>>,
    robust: bool,
    object: Option<StreamCleaner>,
    palm: Option<StreamCleaner>,
    merger: PalmMerger,
    back: Back,
    frames: u64,
    palm_frames: u64,
    times: FrameTimes,
}

impl Analyzer {
    /// A classifier for the demonstration `name`; `instrumented` if palm poses will be pushed.
    pub fn new(name: &str, config: &Config, instrumented: bool) -> Self {
        let down_world = config.gravity.and_then(|g| g.try_normalize(1e-12));
        Self {
            name: name.to_string(),
            instrumented,
            down_world,
            robust: config.method == Method::Robust,
            object: Some(StreamCleaner::new(config)),
            palm: instrumented.then(|| StreamCleaner::new(config)),
            merger: PalmMerger {
                down_world,
                ..PalmMerger::default()
            },
            back: match config.method {
                Method::Robust => Back::Robust(Core::new(config)),
                Method::Paper => Back::Paper(PaperCore::new(config)),
            },
            frames: 0,
            palm_frames: 0,
            times: FrameTimes::default(),
        }
    }

    fn raw(&self, index: usize, p: &StampedPose) -> RawFrame {
        RawFrame {
            index,
            t: p.t,
            q: p.pose.rotation,
            p: p.pose.translation.vector,
        }
    }

    /// Push the next object pose (`world_from_object`).
    pub fn push_object(&mut self, p: &StampedPose) {
        let f = self.raw(self.frames as usize, p);
        self.frames += 1;
        self.times.note(p.t);
        let Self {
            object,
            merger,
            back,
            instrumented,
            robust,
            down_world,
            ..
        } = self;
        let down_world = *down_world;
        let mut to_back = |f: RawFrame, outlier: bool| {
            if *instrumented {
                merger.push_object(f, outlier, &mut |i, d| back.push(i, d));
            } else {
                back.push(item(f, outlier), down_world);
            }
        };
        match object {
            Some(c) if *robust => c.push(f, &mut to_back),
            _ => to_back(f, false),
        }
    }

    /// Take the object stream's cleaner, to run it elsewhere (e.g. on the parsing thread):
    /// feed it with [`ObjectCleaner::push`], and pass what it emits to
    /// [`Analyzer::push_cleaned_object`]. `None` for the paper method, which does not clean, or
    /// if already taken.
    pub fn take_object_cleaner(&mut self) -> Option<ObjectCleaner> {
        if !self.robust {
            return None;
        }
        Some(ObjectCleaner {
            cleaner: self.object.take()?,
            frames: 0,
        })
    }

    /// Take the object stream's cleaner and rest front end, to run them elsewhere (e.g. on the
    /// parsing thread): feed them with [`ObjectFront::push`] and pass what they emit to
    /// [`Analyzer::push_judged`]. `None` for the paper method, for an instrumented
    /// demonstration (its palm merge comes before the rest test), or if already taken.
    pub fn take_object_front(&mut self) -> Option<ObjectFront> {
        let Back::Robust(core) = &mut self.back else {
            return None;
        };
        if self.instrumented || self.object.is_none() || core.front.is_none() {
            return None;
        }
        core.seg.down = self.down_world;
        Some(ObjectFront {
            cleaner: ObjectCleaner {
                cleaner: self.object.take()?,
                frames: 0,
            },
            front: core.front.take()?,
        })
    }

    /// Take what an [`ObjectFront`] emits.
    pub fn push_judged(&mut self, j: Judged) {
        if let Judged::Item(i, _, _) = &j {
            self.frames += 1;
            self.times.note(match i {
                Item::Frame(f) => f.t,
                Item::Outlier(_, t) => *t,
            });
        }
        if let Back::Robust(core) = &mut self.back {
            core.seg.judged(j);
        }
    }

    /// Push an object frame judged by an [`ObjectCleaner`], given by parts: index, time \[s\],
    /// and for a kept frame its orientation, position \[m\] and accumulated rotation \[rad\]
    /// taken by a [`RotationSum`] over the kept frames (see [`RotatingCleaner`]); `None` for a
    /// rejected one. The parts are read where the caller has them: a frame copied together on
    /// the stack and read back in other widths stalls on store forwarding. For the robust
    /// method without a palm; otherwise the same as [`Analyzer::push_cleaned_object`].
    #[inline(always)]
    pub fn push_cleaned_rotated(
        &mut self,
        index: usize,
        t: f64,
        frame: Option<(&UnitQuaternion<f64>, &Vector3<f64>, &Vector3<f64>)>,
    ) {
        match &mut self.back {
            Back::Robust(core) if !self.instrumented => {
                self.frames += 1;
                self.times.note(t);
                core.push_rotated(index, t, frame, self.down_world);
            }
            _ => {
                let f = match frame {
                    Some((q, p, _)) => RawFrame {
                        index,
                        t,
                        q: *q,
                        p: *p,
                    },
                    None => RawFrame {
                        index,
                        t,
                        q: UnitQuaternion::identity(),
                        p: Vector3::zeros(),
                    },
                };
                self.push_cleaned_object(f, frame.is_none())
            }
        }
    }

    /// Push an object frame judged by an [`ObjectCleaner`] (`outlier` = rejected).
    pub fn push_cleaned_object(&mut self, f: RawFrame, outlier: bool) {
        self.frames += 1;
        self.times.note(f.t);
        if self.instrumented {
            let back = &mut self.back;
            self.merger
                .push_object(f, outlier, &mut |i, d| back.push(i, d));
        } else {
            self.back.push(item(f, outlier), self.down_world);
        }
    }

    /// Push the next palm pose (`world_from_palm`).
    pub fn push_palm(&mut self, p: &StampedPose) {
        let f = self.raw(self.palm_frames as usize, p);
        self.palm_frames += 1;
        let Self {
            palm,
            merger,
            back,
            robust,
            ..
        } = self;
        let mut to_merger = |f: RawFrame, outlier: bool| {
            if !outlier {
                merger.push_palm(f, &mut |i, d| back.push(i, d));
            }
        };
        match palm {
            Some(c) if *robust => c.push(f, &mut to_merger),
            _ => to_merger(f, false),
        }
    }

    /// Finish the stream and classify.
    pub fn finish(self) -> crate::Result<Classification> {
        let Self {
            name,
            instrumented,
            object,
            palm,
            mut merger,
            mut back,
            frames,
            robust,
            down_world,
            times,
            ..
        } = self;
        if frames == 0 {
            return Err(crate::Error::Data(
                "no poses: the file is empty or has only comments".to_string(),
            ));
        }
        if robust {
            if let Some(p) = palm {
                p.finish(&mut |f, outlier| {
                    if !outlier {
                        merger.push_palm(f, &mut |i, d| back.push(i, d));
                    }
                });
            }
            object.into_iter().for_each(|o| {
                o.finish(&mut |f, outlier| {
                    if instrumented {
                        merger.push_object(f, outlier, &mut |i, d| back.push(i, d));
                    } else {
                        back.push(item(f, outlier), down_world);
                    }
                })
            });
        }
        if instrumented {
            merger.finish(&mut |i, d| back.push(i, d));
        }
        let mut c = match back {
            Back::Robust(c) => c.finish(&name, instrumented, frames),
            Back::Paper(p) => p.finish(&name, instrumented, frames),
        }?;
        c.warnings.extend(times.warning());
        Ok(c)
    }
}

/// Frame intervals at the start of the object stream whose median [`FrameTimes`] checks.
pub const TIME_CHECK_INTERVALS: usize = 63;
/// Longest plausible median interval \[s\] between a pose tracker's frames (1 Hz). Beyond it
/// the timestamps are most likely not seconds (milliseconds, nanoseconds).
pub const MAX_MEDIAN_FRAME_INTERVAL_S: f64 = 1.0;
/// Shortest plausible median interval \[s\] between a pose tracker's frames (10 kHz).
pub const MIN_MEDIAN_FRAME_INTERVAL_S: f64 = 1e-4;

/// The intervals between the first object frames, to check that the timestamps are seconds:
/// every time-based test (rest windows, the slow-motion probe, velocities) assumes they are,
/// and a file stamped in milliseconds or nanoseconds is otherwise read without complaint.
#[derive(Default)]
struct FrameTimes {
    last: Option<f64>,
    intervals: Vec<f64>,
}

impl FrameTimes {
    /// Note the next frame's time \[s\] (a no-op once enough intervals are kept).
    #[inline(always)]
    fn note(&mut self, t: f64) {
        if self.intervals.len() < TIME_CHECK_INTERVALS {
            if let Some(last) = self.last {
                self.intervals.push(t - last);
            }
            self.last = Some(t);
        }
    }

    /// A warning if the median interval is outside the plausible range.
    fn warning(mut self) -> Option<String> {
        if self.intervals.is_empty() {
            return None;
        }
        self.intervals.sort_by(f64::total_cmp);
        let dt = self.intervals[self.intervals.len() / 2];
        if (MIN_MEDIAN_FRAME_INTERVAL_S..=MAX_MEDIAN_FRAME_INTERVAL_S).contains(&dt) {
            return None;
        }
        Some(format!(
            "the first frames are {dt:.4e} s apart (median), {:.4e} Hz: timestamps must be in \
             seconds (TUM), and every time-based test assumes so; convert milliseconds or \
             nanoseconds first",
            1.0 / dt
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::classify::Config;
    use nalgebra::{Isometry3, Translation3};

    /// A box at rest, then sliding 0.1 m along x in 1 s, then at rest, at 30 Hz, with the
    /// timestamps multiplied by `unit` (1 for seconds).
    fn warnings(unit: f64) -> Vec<String> {
        let mut a = Analyzer::new("t", &Config::default(), false);
        for k in 0..150 {
            let t = k as f64 / 30.0;
            let x = 0.1 * ((t - 2.0).clamp(0.0, 1.0));
            let pose =
                Isometry3::from_parts(Translation3::new(x, 0.0, 0.0), UnitQuaternion::identity());
            a.push_object(&StampedPose {
                t: 1.7e9 * unit + t * unit,
                pose,
            });
        }
        a.finish().unwrap().warnings
    }

    #[test]
    fn timestamps_not_in_seconds_are_warned_about() {
        assert!(warnings(1.0).is_empty(), "{:?}", warnings(1.0));
        for unit in [1e3, 1e9, 1e-6] {
            let w = warnings(unit);
            assert_eq!(w.len(), 1, "unit {unit}: {w:?}");
            assert!(w[0].contains("seconds"), "{}", w[0]);
        }
    }
}
