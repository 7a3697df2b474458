//! What flows from the cleaning to rest detection and on to the methods: a kept frame or the
//! place of a rejected one ([`Sample`]), owned or borrowed, and where a stage passes them on.

use crate::clean::RawFrame;
use nalgebra::Vector3;

/// A frame of the object stream as the methods see it: a good frame or a rejected one (kept for ordering).
#[derive(Clone, Copy, Debug)]
pub enum Sample {
    /// A frame.
    Frame(RawFrame),
    /// A frame rejected as an outlier (index, time).
    Outlier(usize, f64),
}

impl Sample {
    /// The item, borrowed.
    #[inline(always)]
    pub fn as_ref(&self) -> SampleRef<'_> {
        match self {
            Sample::Frame(f) => SampleRef::Frame(f),
            Sample::Outlier(index, t) => SampleRef::Outlier(*index, *t),
        }
    }
}

/// An item as the [`super::rest::RestDetector`] passes it on: a frame is borrowed from the detector's
/// window, so that it is read where it was stored. (A copy assembled on the stack field by
/// field and read back in other widths stalls the CPU on store forwarding: measured as the
/// largest single cost of the robust analysis before this.)
#[derive(Clone, Copy, Debug)]
pub enum SampleRef<'a> {
    /// A frame.
    Frame(&'a RawFrame),
    /// A frame rejected as an outlier (index, time).
    Outlier(usize, f64),
}

impl SampleRef<'_> {
    /// The item, owned.
    pub fn to_sample(self) -> Sample {
        match self {
            SampleRef::Frame(f) => Sample::Frame(*f),
            SampleRef::Outlier(index, t) => Sample::Outlier(index, t),
        }
    }
}

/// Where a [`super::rest::RestDetector`] passes its items, in order, each with its verdict (`moving`, false
/// for outliers) and its accumulated rotation \[rad\] (zero for outliers). Any
/// `FnMut(SampleRef, bool, &Vector3<f64>)` is one; a type of its own can promise that its method
/// is inlined into the detector's loop, which a closure cannot.
pub trait SampleSink {
    /// Take the next judged item.
    fn sample(&mut self, item: SampleRef<'_>, moving: bool, rot: &Vector3<f64>);
}

impl<F: FnMut(SampleRef<'_>, bool, &Vector3<f64>)> SampleSink for F {
    #[inline(always)]
    fn sample(&mut self, item: SampleRef<'_>, moving: bool, rot: &Vector3<f64>) {
        self(item, moving, rot)
    }
}
