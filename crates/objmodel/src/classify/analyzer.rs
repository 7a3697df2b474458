//! The streaming driver: [`Analyzer`] takes a demonstration's poses in time order, cleans each
//! stream, forms the palm-relative motion of an instrumented demonstration, and feeds the robust
//! ([`super::robust`]) or the paper's ([`super::paper`]) method.

use super::cleaning::{sample, ObjectCleaner, ObjectRestTest, StreamCleaner};
use super::palm::{MergeSink, PalmMerger};
use super::paper::PaperMethod;
use super::rest_test::Verdict;
use super::robust::RobustMethod;
use super::sample::Sample;
use super::{Classification, Config, Method};
use crate::clean::RawFrame;
use crate::trajectory::StampedPose;
use nalgebra::{UnitQuaternion, Vector3};

// One per analyzer, on the per-frame path: boxing the large variant would add an indirection
// to every frame for no saving that matters.
#[allow(clippy::large_enum_variant)]
enum Classifier {
    Robust(RobustMethod),
    Paper(PaperMethod),
}

impl MergeSink for Classifier {
    fn sample(&mut self, item: Sample, down: Option<Vector3<f64>>) {
        self.push(item, down)
    }

    fn noise(&mut self, noise: crate::noise::NoiseModel) {
        if let Classifier::Robust(core) = self {
            if let Some(t) = core.rest_test.as_mut() {
                t.hint_noise(noise);
            }
        }
    }

    fn given_noise(&mut self, noise: crate::noise::NoiseModel) {
        if let Classifier::Robust(core) = self {
            if let Some(t) = core.rest_test.as_mut() {
                t.set_noise(noise);
            }
        }
    }
}

impl Classifier {
    /// Push an item; `down` is the unit "down" in the frame the item's pose is relative to
    /// (constant over a stream once known).
    fn push(&mut self, item: Sample, down: Option<Vector3<f64>>) {
        match self {
            Classifier::Robust(c) => c.push(item, down),
            Classifier::Paper(p) => p.push(item, down),
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
    back: Classifier,
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
            palm: instrumented.then(|| StreamCleaner::for_palm(config)),
            merger: PalmMerger::new(
                down_world,
                &config.clocks,
                config.robust.noise.map(|n| (n, config.robust.palm_noise)),
            ),
            back: match config.method {
                Method::Robust => Classifier::Robust(RobustMethod::new(config)),
                Method::Paper => Classifier::Paper(PaperMethod::new(config)),
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
                merger.push_object(f, outlier, &mut *back);
            } else {
                back.push(sample(f, outlier), down_world);
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
    pub(crate) fn take_object_cleaner(&mut self) -> Option<ObjectCleaner> {
        if !self.robust {
            return None;
        }
        Some(ObjectCleaner {
            cleaner: self.object.take()?,
            frames: 0,
        })
    }

    /// Take the object stream's cleaner and rest front end, to run them elsewhere (e.g. on the
    /// parsing thread): feed them with [`ObjectRestTest::push`] and pass what they emit to
    /// [`Analyzer::push_verdict`]. `None` for the paper method, for an instrumented
    /// demonstration (its palm merge comes before the rest test), or if already taken.
    pub(crate) fn take_object_rest_test(&mut self) -> Option<ObjectRestTest> {
        let Classifier::Robust(core) = &mut self.back else {
            return None;
        };
        if self.instrumented || self.object.is_none() || core.rest_test.is_none() {
            return None;
        }
        core.seg.down = self.down_world;
        Some(ObjectRestTest {
            cleaner: ObjectCleaner {
                cleaner: self.object.take()?,
                frames: 0,
            },
            rest_test: core.rest_test.take()?,
        })
    }

    /// Take what an [`ObjectRestTest`] emits.
    pub(crate) fn push_verdict(&mut self, j: Verdict) {
        if let Verdict::Sample(i, _, _) = &j {
            self.frames += 1;
            self.times.note(match i {
                Sample::Frame(f) => f.t,
                Sample::Outlier(_, t) => *t,
            });
        }
        if let Classifier::Robust(core) = &mut self.back {
            core.seg.verdict(j);
        }
    }

    /// Push an object frame judged by an [`ObjectCleaner`], given by parts: index, time \[s\],
    /// and for a kept frame its orientation, position \[m\] and accumulated rotation \[rad\]
    /// taken by a [`RotationSum`](super::rotation_sum::RotationSum) over the kept frames (see
    /// [`RotatingCleaner`](super::cleaning::RotatingCleaner)); `None` for a
    /// rejected one. The parts are read where the caller has them: a frame copied together on
    /// the stack and read back in other widths stalls on store forwarding. For the robust
    /// method without a palm; otherwise the same as [`Analyzer::push_cleaned_object`].
    #[inline(always)]
    pub(crate) fn push_cleaned_rotated(
        &mut self,
        index: usize,
        t: f64,
        frame: Option<(&UnitQuaternion<f64>, &Vector3<f64>, &Vector3<f64>)>,
    ) {
        match &mut self.back {
            Classifier::Robust(core) if !self.instrumented => {
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
    pub(crate) fn push_cleaned_object(&mut self, f: RawFrame, outlier: bool) {
        self.frames += 1;
        self.times.note(f.t);
        if self.instrumented {
            self.merger.push_object(f, outlier, &mut self.back);
        } else {
            self.back.push(sample(f, outlier), self.down_world);
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
                merger.push_palm(f, &mut *back);
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
                        merger.push_palm(f, &mut back);
                    }
                });
            }
            object.into_iter().for_each(|o| {
                o.finish(&mut |f, outlier| {
                    if instrumented {
                        merger.push_object(f, outlier, &mut back);
                    } else {
                        back.push(sample(f, outlier), down_world);
                    }
                })
            });
        }
        let mut clock_warnings = Vec::new();
        if instrumented {
            merger.finish(&mut back);
            clock_warnings = merger.report().map_err(crate::Error::Data)?;
        }
        let mut c = match back {
            Classifier::Robust(c) => c.finish(&name, instrumented, frames),
            Classifier::Paper(p) => p.finish(&name, instrumented, frames),
        }?;
        c.warnings.extend(clock_warnings);
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
