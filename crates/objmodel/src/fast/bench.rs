//! A doorway for the benchmark examples (`examples/analyze_bench.rs`, `clean_bench.rs`,
//! `front_dump.rs`, `main_bench.rs`) to the stages of the robust analysis that the parsing
//! thread splits apart, so that each can be timed alone. Hidden from the documentation, and not
//! an API: it changes with the implementation.

pub use crate::classify::cleaning::{ObjectCleaner, ObjectRestTest, RotatingCleaner};
pub use crate::classify::rest_test::Verdict;
pub use crate::classify::rotation_sum::RotationSum;
pub use crate::classify::sample::Sample;
use crate::classify::Analyzer;
use crate::clean::RawFrame;
use nalgebra::{UnitQuaternion, Vector3};

/// The [`Analyzer`]'s entry points for the stages split off onto the parsing thread.
pub trait AnalyzerStages {
    /// Take the object stream's cleaner, to run it elsewhere: feed it with
    /// [`ObjectCleaner::push`], and pass what it emits to
    /// [`AnalyzerStages::push_cleaned_object`]. `None` for the paper method, which does not
    /// clean, or if already taken.
    fn take_object_cleaner(&mut self) -> Option<ObjectCleaner>;
    /// Take the object stream's cleaner and rest test, to run them elsewhere: feed them with
    /// [`ObjectRestTest::push`] and pass what they emit to [`AnalyzerStages::push_verdict`].
    /// `None` for the paper method, for an instrumented demonstration, or if already taken.
    fn take_object_rest_test(&mut self) -> Option<ObjectRestTest>;
    /// Take what an [`ObjectRestTest`] emits.
    fn push_verdict(&mut self, v: Verdict);
    /// Push an object frame judged by a [`RotatingCleaner`], by parts: index, time \[s\], and
    /// for a kept frame its orientation, position \[m\] and accumulated rotation \[rad\];
    /// `None` for a rejected one.
    fn push_cleaned_rotated(
        &mut self,
        index: usize,
        t: f64,
        frame: Option<(&UnitQuaternion<f64>, &Vector3<f64>, &Vector3<f64>)>,
    );
    /// Push an object frame judged by an [`ObjectCleaner`] (`outlier` = rejected).
    fn push_cleaned_object(&mut self, f: RawFrame, outlier: bool);
}

impl AnalyzerStages for Analyzer {
    fn take_object_cleaner(&mut self) -> Option<ObjectCleaner> {
        Analyzer::take_object_cleaner(self)
    }
    fn take_object_rest_test(&mut self) -> Option<ObjectRestTest> {
        Analyzer::take_object_rest_test(self)
    }
    fn push_verdict(&mut self, v: Verdict) {
        Analyzer::push_verdict(self, v)
    }
    #[inline(always)]
    fn push_cleaned_rotated(
        &mut self,
        index: usize,
        t: f64,
        frame: Option<(&UnitQuaternion<f64>, &Vector3<f64>, &Vector3<f64>)>,
    ) {
        Analyzer::push_cleaned_rotated(self, index, t, frame)
    }
    fn push_cleaned_object(&mut self, f: RawFrame, outlier: bool) {
        Analyzer::push_cleaned_object(self, f, outlier)
    }
}
