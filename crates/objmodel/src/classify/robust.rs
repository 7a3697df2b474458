//! The robust method's streaming part: rest detection (its noise warm-up and the windowed test,
//! [`RestTest`]), unless it runs on another thread, feeding the segments ([`Segmenter`]); at
//! the end the segment analysis ([`super::conclusion`]).

use super::conclusion::conclude;
use super::rest_test::RestTest;
use super::sample::Sample;
use super::segments::Segmenter;
use super::{Classification, Config};
use nalgebra::{UnitQuaternion, Vector3};

/// The robust core: the rest front end ([`RestTest`]: noise warm-up, rest detection), unless
/// it runs elsewhere, and the segments and blocks fed by it ([`Segmenter`]).
pub(super) struct RobustMethod {
    /// `None` when the front end was taken to run on another thread.
    pub(super) rest_test: Option<RestTest>,
    pub(super) seg: Segmenter,
}

impl RobustMethod {
    pub(super) fn new(config: &Config) -> Self {
        Self {
            rest_test: Some(RestTest::new(config)),
            seg: Segmenter::new(config),
        }
    }

    /// Push the next item; `down` is the unit "down" in the frame the poses are relative to.
    pub(super) fn push(&mut self, item: Sample, down: Option<Vector3<f64>>) {
        self.seg.down = down;
        let Self { rest_test, seg } = self;
        if let Some(rest_test) = rest_test {
            rest_test.push(item, seg);
        }
    }

    /// [`RobustMethod::push`] for a frame (index, time \[s\], orientation, position \[m\]; `None`
    /// for an outlier, of which only the index and time count) whose accumulated rotation
    /// \[rad\] was taken elsewhere (see [`RestTest::push_frame`]).
    #[inline(always)]
    pub(super) fn push_rotated(
        &mut self,
        index: usize,
        t: f64,
        frame: Option<(&UnitQuaternion<f64>, &Vector3<f64>, &Vector3<f64>)>,
        down: Option<Vector3<f64>>,
    ) {
        self.seg.down = down;
        let Self { rest_test, seg } = self;
        if let Some(rest_test) = rest_test {
            match frame {
                Some((q, p, rot)) => rest_test.push_frame(index, t, q, p, rot, seg),
                None => rest_test.push_outlier(index, t, seg),
            }
        }
    }

    pub(super) fn finish(
        self,
        name: &str,
        instrumented: bool,
        frames: u64,
    ) -> crate::Result<Classification> {
        let Self { rest_test, mut seg } = self;
        if let Some(rest_test) = rest_test {
            rest_test.finish(&mut seg);
        }
        Ok(conclude(seg.finish(), name, instrumented, frames))
    }
}
