//! The robust classifier's front end: the noise warm-up, then the [`RestDetector`], and what
//! they pass on ([`VerdictSink`], [`Verdict`]).

use super::rest::RestDetector;
use super::rotation_sum::RotationSum;
use super::sample::{Sample, SampleRef, SampleSink};
use super::Config;
use crate::clean::RawFrame;
use crate::fast::avx2_or_baseline;
use crate::noise::{self, NoiseModel};
use nalgebra::{UnitQuaternion, Vector3};

/// What the rest front end passes on: first the noise model in force (once, before any item),
/// then every item in order with its verdict.
#[derive(Clone, Copy, Debug)]
pub enum Verdict {
    /// The tracking noise, given or estimated from the first frames.
    Noise(NoiseModel),
    /// An item, `moving` or not, with its accumulated rotation \[rad\]: the sum of the logs of
    /// the frame-to-frame rotations since the first frame (zero for outliers).
    Sample(Sample, bool, Vector3<f64>),
}

/// Where the rest front end's output goes, in order: first the noise model in force (once,
/// before any item), then every item with its verdict (see [`Verdict`]).
pub trait VerdictSink {
    /// The tracking noise, given or estimated from the first frames.
    fn noise(&mut self, noise: NoiseModel);
    /// An item, `moving` or not, with its accumulated rotation `rot` \[rad\] (zero for
    /// outliers).
    fn sample(&mut self, item: SampleRef<'_>, moving: bool, rot: &Vector3<f64>);
}

/// A [`VerdictSink`] as the [`RestDetector`]'s [`SampleSink`], its `item` inlined into the
/// detector's loop.
struct ToSampleSink<'a, V>(&'a mut V);

impl<V: VerdictSink> SampleSink for ToSampleSink<'_, V> {
    #[inline(always)]
    fn sample(&mut self, item: SampleRef<'_>, moving: bool, rot: &Vector3<f64>) {
        self.0.sample(item, moving, rot)
    }
}

/// [`VerdictSink`] as owned [`Verdict`] values passed to a closure (to keep them, or to send them
/// to another thread).
pub struct OwnedVerdicts<F>(pub F);

impl<F: FnMut(Verdict)> VerdictSink for OwnedVerdicts<F> {
    fn noise(&mut self, noise: NoiseModel) {
        (self.0)(Verdict::Noise(noise))
    }
    #[inline(always)]
    fn sample(&mut self, item: SampleRef<'_>, moving: bool, rot: &Vector3<f64>) {
        (self.0)(Verdict::Sample(item.to_sample(), moving, *rot))
    }
}

/// The robust classifier's front end: the noise warm-up (the first
/// [`super::RobustConfig::warmup_frames`] items, unless the noise is given) and the
/// [`RestDetector`]. It only looks at the cleaned stream, so it can run on another thread than
/// the segments and blocks that consume its output.
#[derive(Debug)]
pub struct RestTest {
    config: Config,
    /// The accumulated rotation, for items pushed without it ([`RestTest::push`]).
    rotation: RotationSum,
    warm: Vec<(Sample, Vector3<f64>)>,
    noise: Option<NoiseModel>,
    rest: Option<RestDetector>,
}

impl RestTest {
    /// A front end for `config`.
    pub fn new(config: &Config) -> Self {
        Self {
            config: *config,
            rotation: RotationSum::default(),
            warm: Vec::new(),
            noise: config.robust.noise.map(NoiseModel::floored),
            rest: None,
        }
    }

    fn start(&mut self, out: &mut impl VerdictSink) {
        let noise = self.noise.unwrap_or_else(|| {
            let samples: Vec<noise::PoseSample> = self
                .warm
                .iter()
                .filter_map(|(i, _)| match i {
                    Sample::Frame(f) => Some((f.t, f.q, f.p)),
                    Sample::Outlier(..) => None,
                })
                .collect();
            noise::estimate(&samples).unwrap_or(NoiseModel {
                sigma_position: noise::MIN_SIGMA_POSITION_M,
                sigma_rotation: noise::MIN_SIGMA_ROTATION_RAD,
            })
        });
        self.noise = Some(noise);
        out.noise(noise);
        let r = &self.config.robust;
        let mut rest = RestDetector::new(
            r.rest_window_s,
            noise.sigma_position,
            noise.sigma_rotation,
            r.alpha,
        );
        for (item, rot) in std::mem::take(&mut self.warm) {
            rest.push(&item, &rot, &mut ToSampleSink(out));
        }
        self.rest = Some(rest);
    }

    /// Use `noise` instead of estimating it from the first items, unless the noise is given
    /// or the test has started (the noise relative to a slower palm: see `super::palm`).
    pub(crate) fn hint_noise(&mut self, noise: NoiseModel) {
        if self.rest.is_none() && self.noise.is_none() {
            self.noise = Some(noise);
        }
    }

    /// Use `noise`, given or not, unless the test has started (the noise relative to the
    /// palm, propagated from the trackers' given noise: see `super::palm`).
    pub(crate) fn set_noise(&mut self, noise: NoiseModel) {
        if self.rest.is_none() {
            self.noise = Some(noise.floored());
        }
    }

    /// Push the next item; what is judged goes to `out`.
    pub fn push(&mut self, item: Sample, out: &mut impl VerdictSink) {
        match item {
            Sample::Frame(f) => {
                let rot = self.rotation.next(&f.q);
                self.push_frame(f.index, f.t, &f.q, &f.p, &rot, out)
            }
            Sample::Outlier(index, t) => self.push_outlier(index, t, out),
        }
    }

    /// Push the next frame (index, time \[s\], orientation, position \[m\]) with its
    /// accumulated rotation \[rad\], taken elsewhere (with a [`RotationSum`] over the frames,
    /// outliers left out); what is judged goes to `out`. The parts are read where the caller
    /// has them (see [`SampleRef`]).
    // The work is not inlined into the caller's loop (measured faster: register pressure),
    // only the choice of code.
    #[inline(always)]
    pub fn push_frame(
        &mut self,
        index: usize,
        t: f64,
        q: &UnitQuaternion<f64>,
        p: &Vector3<f64>,
        rot: &Vector3<f64>,
        out: &mut impl VerdictSink,
    ) {
        // Compiled for AVX2 where the processor has it, with what it inlines: the rest test
        // and the consumer's per-frame code.
        avx2_or_baseline!(#[inline(never)] fn(
            this: &mut RestTest = self,
            index: usize = index,
            t: f64 = t,
            q: &UnitQuaternion<f64> = q,
            p: &Vector3<f64> = p,
            rot: &Vector3<f64> = rot,
            out: &mut impl VerdictSink = out,
        ) {
            this.push_frame_with(index, t, q, p, rot, out)
        })
    }

    #[inline(always)]
    fn push_frame_with(
        &mut self,
        index: usize,
        t: f64,
        q: &UnitQuaternion<f64>,
        p: &Vector3<f64>,
        rot: &Vector3<f64>,
        out: &mut impl VerdictSink,
    ) {
        match self.rest.as_mut() {
            Some(rest) => rest.push_frame(index, t, q, p, rot, &mut ToSampleSink(out)),
            None => {
                let f = RawFrame {
                    index,
                    t,
                    q: *q,
                    p: *p,
                };
                self.warm_up(Sample::Frame(f), rot, out)
            }
        }
    }

    /// Push the next item, a frame rejected as an outlier (index, time \[s\]); what is judged
    /// goes to `out`.
    pub fn push_outlier(&mut self, index: usize, t: f64, out: &mut impl VerdictSink) {
        match self.rest.as_mut() {
            Some(rest) => rest.push_outlier(index, t, &mut ToSampleSink(out)),
            None => self.warm_up(Sample::Outlier(index, t), &Vector3::zeros(), out),
        }
    }

    /// Keep an item of the warm-up; start the detector when there are enough.
    #[cold]
    fn warm_up(&mut self, item: Sample, rot: &Vector3<f64>, out: &mut impl VerdictSink) {
        self.warm.push((item, *rot));
        if self.warm.len() >= self.config.robust.warmup_frames.max(3) {
            self.start(out);
        }
    }

    /// Flush the remaining items at the end of the stream.
    pub fn finish(mut self, out: &mut impl VerdictSink) {
        if self.rest.is_none() {
            self.start(out);
        }
        if let Some(rest) = self.rest.take() {
            rest.finish(&mut ToSampleSink(out));
        }
    }
}
