//! Cleaning a tracked stream (noise warm-up, then the glitch [`Cleaner`]), and the parts of
//! the robust analysis before the segments that can run on another thread than the
//! [`super::Analyzer`]: the object's cleaner alone ([`ObjectCleaner`]), with the accumulated
//! rotation ([`RotatingCleaner`]), or with rest detection ([`ObjectRestTest`]).

use super::rest_test::{OwnedVerdicts, RestTest, Verdict};
use super::rotation_sum::RotationSum;
use super::sample::Sample;
use super::Config;
use crate::clean::{Cleaner, HeldPoses, RawFrame};
use crate::noise::{self, NoiseModel};
use crate::trajectory::StampedPose;
use nalgebra::Vector3;

/// Cleans one stream: noise warm-up, then the glitch [`Cleaner`]; and, where the config says
/// that exact repeats are a tracker holding its last pose, those left out first
/// ([`HeldPoses`]).
pub(super) struct StreamCleaner {
    glitches: GlitchTest,
    held: Option<HeldPoses>,
}

/// The noise warm-up, then the glitch [`Cleaner`].
struct GlitchTest {
    warm: Vec<RawFrame>,
    warmup: usize,
    alpha: f64,
    noise: Option<NoiseModel>,
    cleaner: Option<Cleaner>,
}

impl StreamCleaner {
    /// The object stream's cleaner.
    pub(super) fn new(config: &Config) -> Self {
        Self {
            glitches: GlitchTest::new(config, config.robust.noise),
            held: config.robust.repeats_are_held.then(HeldPoses::default),
        }
    }

    /// The palm stream's cleaner: with the palm's noise, where given. (Its repeats are kept:
    /// the held-pose check measures the object's tracker.)
    pub(super) fn for_palm(config: &Config) -> Self {
        let noise = config
            .robust
            .noise
            .map(|n| config.robust.palm_noise.unwrap_or(n));
        Self {
            glitches: GlitchTest::new(config, noise),
            held: None,
        }
    }

    #[inline(always)]
    pub(super) fn push(&mut self, f: RawFrame, out: &mut impl FnMut(RawFrame, bool)) {
        match self.held {
            None => self.glitches.push(f, out),
            Some(_) => self.push_past_held(f, out),
        }
    }

    /// [`StreamCleaner::push`] where repeats are held poses: apart from the common case's
    /// loop (inlined there, the second copy of the glitch test cost 8% of `learn`'s wall time
    /// on 10^6 poses).
    #[inline(never)]
    fn push_past_held(&mut self, f: RawFrame, out: &mut impl FnMut(RawFrame, bool)) {
        let Self { glitches, held } = self;
        let held = held.as_mut().expect("held poses looked for");
        if !held.is_repeat(&f) {
            glitches.push(f, &mut |g, outlier| held.emit(g, outlier, out));
        }
    }

    pub(super) fn finish(self, out: &mut impl FnMut(RawFrame, bool)) {
        let Self { glitches, held } = self;
        match held {
            None => glitches.finish(out),
            Some(mut held) => {
                glitches.finish(&mut |g, outlier| held.emit(g, outlier, out));
                held.drain(out);
            }
        }
    }
}

impl GlitchTest {
    fn new(config: &Config, noise: Option<NoiseModel>) -> Self {
        Self {
            warm: Vec::new(),
            warmup: config.robust.warmup_frames.max(3),
            alpha: config.robust.outlier_alpha,
            noise,
            cleaner: None,
        }
    }

    fn start(&mut self, out: &mut impl FnMut(RawFrame, bool)) {
        let samples: Vec<noise::PoseSample> = self.warm.iter().map(|f| (f.t, f.q, f.p)).collect();
        let n = self
            .noise
            .or_else(|| noise::estimate(&samples))
            .unwrap_or(NoiseModel::FALLBACK)
            .floored();
        let mut c = Cleaner::new(n.sigma_rotation, n.sigma_position, self.alpha);
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

/// The object stream's cleaner, detached from its [`super::Analyzer`] so that it can run on another
/// thread (it is `Send`).
pub struct ObjectCleaner {
    pub(super) cleaner: StreamCleaner,
    pub(super) frames: usize,
}

impl ObjectCleaner {
    /// Push the next object pose; judged frames are passed to `out` with their verdict.
    #[inline(always)]
    pub fn push(&mut self, p: &StampedPose, mut out: impl FnMut(RawFrame, bool)) {
        let f = RawFrame {
            index: self.frames,
            t: p.t,
            q: p.pose.rotation,
            p: p.pose.translation.vector,
        };
        self.frames += 1;
        self.cleaner.push(f, &mut out);
    }

    /// Flush the last frames.
    pub fn finish(self, out: &mut impl FnMut(RawFrame, bool)) {
        self.cleaner.finish(out);
    }
}

/// The object stream's cleaner and the accumulated rotation of the frames it keeps
/// ([`RotationSum`]): the part of the robust analysis before rest detection that can run on
/// another thread (it is `Send`). Feed it poses; pass what it emits to
/// `Analyzer::push_cleaned_rotated`.
pub struct RotatingCleaner {
    cleaner: ObjectCleaner,
    rotation: RotationSum,
}

impl RotatingCleaner {
    /// Wrap a cleaner taken with `Analyzer::take_object_cleaner`.
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
        // The closure inlined where the cleaner passes a frame on, in the parsing thread's loop
        // (left to the compiler, it was called apart, in baseline code: 20% of `learn`'s wall
        // time on 10^6 poses).
        self.cleaner.push(
            p,
            #[inline(always)]
            |f, outlier| out(f, outlier, rotated(rotation, &f, outlier)),
        );
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
/// their [`super::Analyzer`] so that they can run on another thread (parsing, cleaning and rest
/// detection there; segments and blocks in `Analyzer::push_verdict`). For demonstrations
/// without a palm.
pub struct ObjectRestTest {
    pub(super) cleaner: ObjectCleaner,
    pub(super) rest_test: RestTest,
}

impl ObjectRestTest {
    /// Push the next object pose; what is judged goes to `out`.
    pub fn push(&mut self, p: &StampedPose, out: &mut impl FnMut(Verdict)) {
        let rest_test = &mut self.rest_test;
        let mut out = OwnedVerdicts(out);
        self.cleaner.push(p, &mut |f, outlier| {
            rest_test.push(sample(f, outlier), &mut out)
        });
    }

    /// Flush the last frames.
    pub fn finish(self, out: &mut impl FnMut(Verdict)) {
        let Self {
            cleaner,
            mut rest_test,
        } = self;
        let mut out = OwnedVerdicts(out);
        cleaner.finish(&mut |f, outlier| rest_test.push(sample(f, outlier), &mut out));
        rest_test.finish(&mut out);
    }
}

/// A cleaned frame as an item for a back end (an outlier keeps only its index and time).
pub(super) fn sample(f: RawFrame, outlier: bool) -> Sample {
    if outlier {
        Sample::Outlier(f.index, f.t)
    } else {
        Sample::Frame(f)
    }
}
