//! The frames of a demonstration that the dynamics stage needs, kept while the stream is
//! classified, in bounded memory.
//!
//! The geometry of a demonstration is learnt streaming, in one pass and flat memory; the
//! dynamics ([`crate::dynamics`]) fit angle series over time, which needs the frames. Which
//! frames are topples is only known once the whole stream is classified, so the [`Recorder`]
//! keeps every frame it is handed up to its capacity, and beyond it halves its time resolution
//! (keeps every second kept frame, then takes every second new one, and so on): memory stays at
//! most `capacity` frames per stream whatever the file's length, and a demonstration of up to
//! `capacity` frames (at 250 Hz, [`DEFAULT_CAPACITY`] is four minutes) is analysed at its full
//! rate. Each kept object frame carries its index in the stream, which is what the
//! classification's labels refer to.

use crate::trajectory::StampedPose;
use nalgebra::{UnitQuaternion, Vector3};

/// Frames kept per stream (object, palm) by default: 16 384, 0.8 MiB of object frames. A
/// demonstration of up to 65 s at 250 Hz, 2.3 minutes at 120 Hz or 9 at 30 Hz keeps every
/// frame; a longer one is thinned to no less than half that rate (a 10⁶-frame file to one frame
/// in 64). Twice this capacity cost the 10⁶-pose benchmark 2% more instructions on its busiest
/// thread.
pub const DEFAULT_CAPACITY: usize = 1 << 14;

/// An object frame kept: its index in the stream, its time and its pose (the dynamics use the
/// orientation; the test of whether a rest was on the support, the whole pose).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RecordedFrame {
    /// Index of the frame in the object stream (the classification's labels count these).
    pub index: u64,
    /// Time \[s\].
    pub t: f64,
    /// The orientation of `world_from_object`.
    pub rotation: UnitQuaternion<f64>,
    /// The position of `world_from_object` \[m\].
    pub position: Vector3<f64>,
}

impl RecordedFrame {
    /// The frame as a sample of the noise estimators ([`crate::noise::PoseSample`]).
    pub fn sample(&self) -> crate::noise::PoseSample {
        (self.t, self.rotation, self.position)
    }
}

/// What a [`Recorder`] kept of a demonstration.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Recording {
    /// Object frames, in stream order.
    pub object: Vec<RecordedFrame>,
    /// Palm poses (`world_from_palm`), in time order; empty when not instrumented.
    pub palm: Vec<StampedPose>,
    /// Every how many object frames one was kept (1: all).
    pub object_stride: u64,
    /// Every how many palm poses one was kept (1: all).
    pub palm_stride: u64,
}

impl Recording {
    /// What a recorder of `capacity` frames keeps of an in-memory demonstration: the same as
    /// of its files.
    pub fn of(demo: &crate::Demonstration, capacity: usize) -> Self {
        let mut r = Recorder::new(capacity);
        for (i, p) in (0u64..).zip(&demo.object) {
            r.object(i, p.t, &p.pose.rotation, &p.pose.translation.vector);
        }
        for p in demo.palm.iter().flatten() {
            r.palm(p);
        }
        r.finish()
    }
}

impl Recording {
    /// The kept object frames whose stream index lies in `first..=last` (a part's or a label
    /// run's frames, as far as they were kept).
    pub fn objects_in(&self, first: usize, last: usize) -> &[RecordedFrame] {
        let lo = self.object.partition_point(|f| (f.index as usize) < first);
        let hi = self.object.partition_point(|f| (f.index as usize) <= last);
        &self.object[lo..hi]
    }

    /// The median time \[s\] from one object frame of the stream to the next, over the kept
    /// frames (each gap divided by the stream frames it spans; a record thinned to one frame
    /// in as many as a tracker drops one in, counts the drops in); `None` with no positive
    /// gap.
    pub fn median_frame_interval(&self) -> Option<f64> {
        let mut gaps: Vec<f64> = self
            .object
            .windows(2)
            .filter(|w| w[1].index > w[0].index && w[1].t > w[0].t)
            .map(|w| (w[1].t - w[0].t) / (w[1].index - w[0].index) as f64)
            .collect();
        crate::stats::median(&mut gaps)
    }

    /// A 64-bit FNV-1a hash (over words), in hex, of `frames` (the object stream's length) and
    /// the bits of every kept frame (index, time, orientation with its sign fixed, position;
    /// palm: time and pose) and of the strides: the same poses give the same fingerprint;
    /// different ones almost surely differ, unless they differ only in frames a thinned
    /// record skipped.
    pub fn fingerprint(&self, frames: u64) -> String {
        self.hash(frames, true)
    }

    /// [`Recording::fingerprint`] as trees written before 2026-12-08 hold it: the object's
    /// positions left out (two streams with bitwise the same times and orientations, which a
    /// tracker's noise never gives but a synthetic generator can, had one fingerprint).
    /// [`crate::tree::Tree::add`] matches a stored demonstration by either.
    pub fn fingerprint_without_positions(&self, frames: u64) -> String {
        self.hash(frames, false)
    }

    /// The hash of [`Recording::fingerprint`], with or without the object's `positions`.
    fn hash(&self, frames: u64, positions: bool) -> String {
        // FNV-1a taking a 64-bit word at a time (not a byte: a tenth of the work, and the
        // words are the data's own).
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        let mut eat = |x: u64| h = (h ^ x).wrapping_mul(0x0000_0100_0000_01b3);
        eat(frames);
        eat(self.object_stride);
        eat(self.palm_stride);
        // A rotation's quaternion with its sign fixed (w >= 0): q and -q are one rotation, and
        // the streams differ in which one they keep (the cleaner makes signs continuous).
        let canonical = |q: &UnitQuaternion<f64>| {
            let c = q.coords;
            if c.w < 0.0 {
                -c
            } else {
                c
            }
        };
        for f in &self.object {
            eat(f.index);
            eat(f.t.to_bits());
            canonical(&f.rotation).iter().for_each(|c| eat(c.to_bits()));
            if positions {
                f.position.iter().for_each(|c| eat(c.to_bits()));
            }
        }
        for p in &self.palm {
            eat(p.t.to_bits());
            canonical(&p.pose.rotation)
                .iter()
                .for_each(|c| eat(c.to_bits()));
            p.pose
                .translation
                .vector
                .iter()
                .for_each(|c| eat(c.to_bits()));
        }
        format!("{h:016x}")
    }
}

/// One stream's bounded, evenly thinned record.
#[derive(Clone, Debug)]
struct Thinned<T> {
    kept: Vec<T>,
    /// A power of two: items whose index is a multiple of it are kept.
    stride: u64,
    capacity: usize,
}

impl<T> Thinned<T> {
    fn new(capacity: usize) -> Self {
        Self {
            // Reserved up to the default capacity at once: growing by doubling copies.
            kept: Vec::with_capacity(capacity.min(DEFAULT_CAPACITY)),
            stride: 1,
            capacity: capacity.max(2),
        }
    }

    /// Whether the item with this index is kept (after thinning, if the record is full).
    #[inline(always)]
    fn wants(&mut self, index: u64, index_of: impl Fn(&T) -> u64) -> bool {
        if index & (self.stride - 1) != 0 {
            return false;
        }
        if self.kept.len() < self.capacity {
            return true;
        }
        self.stride *= 2;
        let stride = self.stride;
        self.kept.retain(|x| index_of(x).is_multiple_of(stride));
        index.is_multiple_of(stride)
    }
}

/// Keeps the frames of one demonstration for its dynamics (see the module's documentation).
#[derive(Clone, Debug)]
pub struct Recorder {
    object: Thinned<RecordedFrame>,
    palm: Thinned<(u64, StampedPose)>,
    palm_count: u64,
}

impl Recorder {
    /// A recorder keeping at most `capacity` frames per stream.
    pub fn new(capacity: usize) -> Self {
        Self {
            object: Thinned::new(capacity),
            palm: Thinned::new(capacity),
            palm_count: 0,
        }
    }

    /// The first object frame index at or after `index` that the recorder would keep now
    /// (callers holding frames in bulk need hand it only those: see [`Recorder::object`]).
    #[inline(always)]
    pub fn next_object_index(&self, index: u64) -> u64 {
        let mask = self.object.stride - 1;
        (index + mask) & !mask
    }

    /// Hand it the object frame `index` of the stream: its time and pose. Frames it would not
    /// keep may be skipped ([`Recorder::next_object_index`]).
    #[inline(always)]
    pub fn object(
        &mut self,
        index: u64,
        t: f64,
        rotation: &UnitQuaternion<f64>,
        position: &Vector3<f64>,
    ) {
        if self.object.wants(index, |f| f.index) {
            self.object.kept.push(RecordedFrame {
                index,
                t,
                rotation: *rotation,
                position: *position,
            });
        }
    }

    /// Hand it the next palm pose.
    #[inline]
    pub fn palm(&mut self, p: &StampedPose) {
        let index = self.palm_count;
        self.palm_count += 1;
        if self.palm.wants(index, |x| x.0) {
            self.palm.kept.push((index, *p));
        }
    }

    /// What was kept.
    pub fn finish(self) -> Recording {
        Recording {
            object: self.object.kept,
            palm: self.palm.kept.into_iter().map(|(_, p)| p).collect(),
            object_stride: self.object.stride,
            palm_stride: self.palm.stride,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Isometry3;
    use proptest::prelude::*;

    fn frames(n: u64, capacity: usize) -> Recording {
        let mut r = Recorder::new(capacity);
        for i in 0..n {
            let t = i as f64 * 0.01;
            r.object(i, t, &UnitQuaternion::identity(), &Vector3::zeros());
            r.palm(&StampedPose::new(t, Isometry3::identity()));
        }
        r.finish()
    }

    #[test]
    fn the_frame_interval_is_the_streams_whatever_the_stride_and_the_drops() {
        // 10 ms frames, all kept or one in 8, with one gap of a dropped frame in twenty.
        for capacity in [5000, 300] {
            let mut r = Recorder::new(capacity);
            let mut t = 0.0;
            for i in 0..2000u64 {
                t += if i % 20 == 7 { 0.02 } else { 0.01 };
                r.object(i, t, &UnitQuaternion::identity(), &Vector3::zeros());
            }
            let r = r.finish();
            let dt = r.median_frame_interval().unwrap();
            assert!(
                (dt - 0.01).abs() < 1e-12,
                "{dt} at stride {}",
                r.object_stride
            );
        }
        assert_eq!(frames(1, 10).median_frame_interval(), None);
    }

    proptest! {
        /// Whatever the length, the record holds at most `capacity` frames, evenly spaced at
        /// a power-of-two stride starting at frame 0, and at least half the capacity once it
        /// has thinned: nothing is lost but resolution.
        #[test]
        fn bounded_and_evenly_thinned(n in 0u64..5000, capacity in 2usize..300) {
            let r = frames(n, capacity);
            prop_assert!(r.object.len() <= capacity);
            prop_assert!(r.palm.len() <= capacity);
            prop_assert!(r.object_stride.is_power_of_two());
            let expected: Vec<u64> = (0..n).step_by(r.object_stride as usize).collect();
            let got: Vec<u64> = r.object.iter().map(|f| f.index).collect();
            prop_assert_eq!(got, expected);
            prop_assert_eq!(r.palm.len(), r.object.len());
            if r.object_stride > 1 {
                prop_assert!(2 * r.object.len() >= capacity);
            } else {
                prop_assert_eq!(r.object.len() as u64, n);
            }
        }
    }

    proptest! {
        /// Handing only the frames [`Recorder::next_object_index`] names keeps the same record
        /// as handing every frame.
        #[test]
        fn skipping_what_it_would_not_keep_changes_nothing(
            n in 0u64..3000,
            capacity in 2usize..200,
            chunk in 1u64..500,
        ) {
            let every = frames(n, capacity);
            let mut r = Recorder::new(capacity);
            let mut first = 0;
            while first < n {
                let end = (first + chunk).min(n);
                let mut i = r.next_object_index(first);
                while i < end {
                    let t = i as f64 * 0.01;
                    r.object(i, t, &UnitQuaternion::identity(), &Vector3::zeros());
                    i = r.next_object_index(i + 1);
                }
                first = end;
            }
            let skipped = r.finish();
            prop_assert_eq!(&skipped.object, &every.object);
            prop_assert_eq!(skipped.object_stride, every.object_stride);
        }
    }

    #[test]
    fn keeps_the_pose_it_is_handed() {
        let q = UnitQuaternion::from_euler_angles(0.1, -0.2, 0.3);
        let mut r = Recorder::new(8);
        r.object(0, 4.5, &q, &Vector3::new(0.1, 0.2, 0.3));
        let rec = r.finish();
        assert_eq!(rec.object[0].t, 4.5);
        assert_eq!(rec.object[0].rotation, q);
        assert_eq!(rec.object[0].position, Vector3::new(0.1, 0.2, 0.3));
    }
}
