//! Segments: after rest detection, frames are split into motion segments, each with the mean
//! pose of the rest before it as reference (a rest too short, or over which the pose drifted,
//! does not split; a motion too slow for the windowed rest test is found by its drift), and
//! summarised, relative to that reference, into blocks of per-frame statistics
//! ([`super::block`]), with memory bounded independently of the file length.

use super::block::{Block, Phase, MAX_BLOCKS};
use super::frame_model::FrameModel;
use super::rest_stats::RestStats;
use super::rest_test::{Verdict, VerdictSink};
use super::sample::SampleRef;
use super::Config;
use crate::clean::RawFrame;
use crate::fast::moving_sums::MovingFrameSums;
use crate::landing::RestPlace;
use crate::noise::NoiseModel;
use nalgebra::{Matrix3, UnitQuaternion, Vector3};

/// Largest number of motion segments per demonstration; later rests no longer split.
pub const MAX_SEGMENTS: usize = 256;
/// Rest frames between two drift tests of the rest so far (a slow motion is found at most this
/// many frames late).
pub const SLOW_CHECK_FRAMES: u64 = 32;

/// One motion segment as the segmenter keeps it: its reference pose, its time span, "down"
/// and the faces rested on before and after.
pub(super) struct MotionSegment {
    /// The reference pose's inverse rotation, as a quaternion (for the relative rotation) and
    /// as a matrix (for the relative translation, cheaper than rotating by the quaternion).
    pub ref_q_inv: UnitQuaternion<f64>,
    pub ref_r_inv: Matrix3<f64>,
    /// The reference pose's position \[m\].
    pub ref_p: Vector3<f64>,
    pub t_start: f64,
    pub t_end: f64,
    /// Down (unit) in object coordinates at the reference, if gravity is known.
    pub down_ref: Option<Vector3<f64>>,
    /// Number of frames averaged into the reference pose.
    pub n_ref: f64,
    pub rest_before: Option<Vector3<f64>>,
    pub rest_after: Option<Vector3<f64>>,
    /// Frames of those rests.
    pub rest_before_frames: f64,
    pub rest_after_frames: f64,
    /// Where those rests were, if gravity is known.
    pub rest_before_place: Option<RestPlace>,
    pub rest_after_place: Option<RestPlace>,
    /// The orientations (`world_from_object`) over those rests (their mean).
    pub rest_before_rotation: Option<UnitQuaternion<f64>>,
    pub rest_after_rotation: Option<UnitQuaternion<f64>>,
}

/// Segments and blocks: consumes the rest front end's output ([`Verdict`]).
pub(super) struct Segmenter {
    config: Config,
    noise: Option<NoiseModel>,
    model: Option<FrameModel>,
    blocks: Vec<Block>,
    /// The last block's moving-frame statistics, until it is closed.
    open: MovingFrameSums,
    block_size: u64,
    segments: Vec<MotionSegment>,
    rest: RestStats,
    in_motion: bool,
    outliers: u64,
    /// Unit "down" in the frame the poses are relative to, if known.
    pub(super) down: Option<Vector3<f64>>,
    /// The latest part (a quarter to a half) of the current rest, to tell a persistent drift
    /// (a slow motion) from a transient one (contacts settling after a landing).
    recent: RestStats,
    /// In a slow motion (see [`Slow`]).
    slow: Option<Slow>,
}

impl VerdictSink for Segmenter {
    fn noise(&mut self, noise: NoiseModel) {
        self.set_noise(noise)
    }
    #[inline(always)]
    fn sample(&mut self, item: SampleRef<'_>, moving: bool, rot: &Vector3<f64>) {
        Segmenter::sample(self, item, moving, rot)
    }
}

/// A slow motion: a "rest" to the windowed test over which the pose drifted measurably, both
/// over the whole rest and over its latest part. All its frames are treated as moving, in one
/// segment, until a span as long as the one that revealed the motion shows no drift (a real
/// rest: it becomes the current rest) or the stream ends.
#[derive(Clone, Copy, Debug)]
struct Slow {
    /// Duration \[s\] of the span that revealed the slow motion.
    span_s: f64,
    /// Frames since the windowed test last saw motion, or since the last probe.
    probe: RestStats,
}

impl Segmenter {
    pub(super) fn new(config: &Config) -> Self {
        Self {
            config: *config,
            noise: None,
            model: None,
            // All the blocks there can be, at once: growing by doubling copied up to 2 MB
            // and faulted the copies' pages in, on the per-frame path. Pages never used are
            // never touched, so a short file costs no more memory.
            blocks: Vec::with_capacity(MAX_BLOCKS),
            open: MovingFrameSums::default(),
            block_size: 1,
            segments: Vec::new(),
            rest: RestStats::default(),
            in_motion: false,
            outliers: 0,
            down: None,
            recent: RestStats::default(),
            slow: None,
        }
    }

    /// The noise model in force: per-frame variances and thresholds follow from it.
    fn set_noise(&mut self, n: NoiseModel) {
        self.noise = Some(n);
        self.model = Some(FrameModel::new(&n, &self.config.robust));
    }

    /// Take the next output of the rest front end, owned.
    pub(super) fn verdict(&mut self, j: Verdict) {
        match j {
            Verdict::Noise(n) => self.set_noise(n),
            Verdict::Sample(item, moving, rot) => self.sample(item.as_ref(), moving, &rot),
        }
    }

    #[inline(always)]
    fn sample(&mut self, item: SampleRef<'_>, moving: bool, rot: &Vector3<f64>) {
        match item {
            SampleRef::Outlier(index, t) => {
                self.outliers += 1;
                let segment = self.segments.len().checked_sub(1);
                self.block(index, t, Phase::Outlier, segment);
            }
            // A moving frame, or any frame of a slow motion (all of which count as moving): the
            // common cases, inlined into the caller (the rest front end's loop), in its code.
            SampleRef::Frame(f) if moving || self.slow.is_some() => {
                let slow = self.slow.is_some();
                self.moving(f, false);
                if slow {
                    self.probe_slow(f, rot, moving);
                }
            }
            SampleRef::Frame(f) => {
                if self.in_motion {
                    self.in_motion = false;
                    self.rest = RestStats::default();
                    self.recent = RestStats::default();
                } else if f.t - self.rest.t1 > self.config.robust.rest_window_s
                    && self.left_rest_unseen(f)
                {
                    return;
                }
                let min_rest = self.config.robust.min_rest_s;
                self.rest.add(f, rot, min_rest);
                let full = self.rest.t1 - self.rest.t0;
                if self.recent.n() > 0.0 && self.recent.t1 - self.recent.t0 >= 0.5 * full {
                    self.recent = RestStats::default();
                }
                self.recent.add(f, rot, min_rest);
                if self.is_slow_motion() {
                    self.slow = Some(Slow {
                        span_s: full,
                        probe: RestStats::default(),
                    });
                    self.in_motion = false;
                    self.slow_motion_found(f);
                } else {
                    // Rests belong to the segment they follow (None before the first motion).
                    let segment = self.segments.len().checked_sub(1);
                    self.block(f.index, f.t, Phase::Rest, segment);
                }
            }
        }
    }

    /// After a gap in the stream longer than the rest test's window, a frame that the test
    /// calls at rest may not be in the rest before the gap: the windows on either side of the
    /// gap hold only their own side (a tracker that lost the object while it fell, and saw it
    /// again where it landed). Where its pose departs from that rest's mean beyond the noise
    /// and the model tolerance (χ²₆ at the tests' level), the object moved unseen: the frame
    /// is taken as moving (and the frames after it start a new rest), rather than the two
    /// rests being merged into one that teaches a face between them.
    #[cold]
    #[inline(never)]
    fn left_rest_unseen(&mut self, f: &RawFrame) -> bool {
        let m = self.model.unwrap();
        if self.rest.n() == 0.0 || self.rest.departure_chi2(f, &m) <= m.displaced {
            return false;
        }
        self.moving(f, false);
        true
    }

    /// Whether the current rest is a motion too slow for the windowed test: over at least
    /// `min_rest_s` its pose drifted measurably, and so it did over its latest part (at least a
    /// quarter of it), so that the drift is not a transient such as contacts settling. Tested
    /// every [`SLOW_CHECK_FRAMES`] frames.
    fn is_slow_motion(&self) -> bool {
        let (r, recent) = (&self.rest, &self.recent);
        let m = self.model.unwrap();
        let full = r.t1 - r.t0;
        (r.n() as u64).is_multiple_of(SLOW_CHECK_FRAMES)
            && full >= self.config.robust.min_rest_s
            && recent.t1 - recent.t0 >= 0.25 * full
            && r.drift_chi2(&m) > m.displaced
            && recent.drift_chi2(&m) > m.displaced
    }

    /// In a slow motion, look for a real rest: frames the windowed test calls rest, over a
    /// span as long as the one that revealed the slow motion, without drift.
    #[inline(always)]
    fn probe_slow(&mut self, f: &RawFrame, rot: &Vector3<f64>, moving: bool) {
        let Some(slow) = self.slow.as_mut() else {
            return;
        };
        if moving {
            if slow.probe.n() > 0.0 {
                slow.probe = RestStats::default();
            }
            return;
        }
        slow.probe.add(f, rot, self.config.robust.min_rest_s);
        let p = &slow.probe;
        if p.t1 - p.t0 < slow.span_s || !(p.n() as u64).is_multiple_of(SLOW_CHECK_FRAMES) {
            return;
        }
        let m = self.model.unwrap();
        if p.drift_chi2(&m) <= m.displaced {
            // A real rest: the slow motion is over, and this rest may start a new segment.
            self.rest = slow.probe;
            self.recent = RestStats::default();
            self.in_motion = false;
            self.slow = None;
        } else {
            slow.probe = RestStats::default();
        }
    }

    /// [`Segmenter::moving`] for the frame that reveals a slow motion (once per slow motion; not
    /// inlined, to keep the per-frame loop small).
    #[cold]
    #[inline(never)]
    fn slow_motion_found(&mut self, f: &RawFrame) {
        self.moving(f, true)
    }

    /// A moving frame; `slow_start` when it reveals that the rest before it was a slow motion.
    /// Its pose relative to the segment reference enters its block's statistics (the model:
    /// [`super::frame_model`]) through [`MovingFrameSums::push`].
    ///
    /// Inlined into its caller (the rest front end's loop, in that loop's code); the one
    /// rare caller goes through [`Segmenter::slow_motion_found`].
    #[inline(always)]
    fn moving(&mut self, f: &RawFrame, slow_start: bool) {
        if !self.in_motion {
            self.in_motion = true;
            self.start_motion(f, slow_start);
        }
        let seg_index = self.segments.len() - 1;
        // The block first: nothing computed below is live across its (rare) call.
        self.block(f.index, f.t, Phase::Moving, Some(seg_index));
        let m = self.model.as_ref().unwrap();
        let seg = &mut self.segments[seg_index];
        seg.t_end = f.t;
        let t_rel = seg.ref_r_inv * (f.p - seg.ref_p);
        let q_rel = seg.ref_q_inv * f.q;
        self.open.push(&t_rel, &q_rel, m);
    }

    /// The first moving frame `f` after a rest: a new segment starts after a rest that is long
    /// enough and over which the pose did not drift measurably (a slow motion can pass the
    /// windowed test as rest), and where a slow motion is found (`slow_start`); it starts from
    /// the pose at the slow motion's start.
    #[inline(never)]
    fn start_motion(&mut self, f: &RawFrame, slow_start: bool) {
        let m = self.model.unwrap();
        let long_rest = self.rest.n() > 0.0
            && self.rest.t1 - self.rest.t0 >= self.config.robust.min_rest_s
            && self.rest.drift_chi2(&m) <= m.displaced;
        if !(self.segments.is_empty()
            || ((long_rest || slow_start) && self.segments.len() < MAX_SEGMENTS))
        {
            return;
        }
        // What the first rest's pose is worth where it was held at one frame's pose.
        let worth = |n: f64| match self.config.robust.held_rest_frames {
            Some(k) if self.segments.is_empty() => n.min(k),
            _ => n,
        };
        let start = if slow_start {
            self.rest.start()
        } else {
            self.rest.mean().map(|(q, p)| (q, p, self.rest.n()))
        }
        .map(|(q, p, n)| (q, p, worth(n)));
        let rest_down = start
            .zip(self.down)
            .map(|((q, _, _), d)| (q.inverse() * d).normalize());
        let rest_frames = if rest_down.is_some() {
            worth(self.rest.n())
        } else {
            0.0
        };
        let rest_place = start
            .zip(self.down)
            .map(|((_, p, _), d)| RestPlace::new(&p, &d));
        let rest_rotation = start.filter(|_| rest_down.is_some()).map(|(q, _, _)| q);
        if let Some(prev) = self.segments.last_mut() {
            prev.rest_after = rest_down;
            prev.rest_after_frames = rest_frames;
            prev.rest_after_place = rest_place;
            prev.rest_after_rotation = rest_rotation;
        }
        let (ref_q, ref_p, n_ref) = start.unwrap_or((f.q, f.p, 1.0));
        let down_ref = rest_down.or_else(|| self.down.map(|d| (f.q.inverse() * d).normalize()));
        let ref_q_inv = ref_q.inverse();
        self.segments.push(MotionSegment {
            ref_q_inv,
            ref_r_inv: ref_q_inv.to_rotation_matrix().into_inner(),
            ref_p,
            t_start: f.t,
            t_end: f.t,
            down_ref,
            n_ref: n_ref.max(1.0),
            rest_before: rest_down,
            rest_after: None,
            rest_before_frames: rest_frames,
            rest_after_frames: 0.0,
            rest_before_place: rest_place,
            rest_after_place: None,
            rest_before_rotation: rest_rotation,
            rest_after_rotation: None,
        });
    }

    /// Put a frame in a block: the current block if it has the frame's phase and segment and
    /// room left, else a new one; the block's range is extended to the frame (a moving frame's
    /// statistics go to [`Segmenter::open`]).
    #[inline]
    fn block(&mut self, index: usize, t: f64, phase: Phase, segment: Option<usize>) {
        let fits = self.blocks.last().is_some_and(|b| {
            b.phase == phase && b.segment == segment && b.frames < self.block_size
        });
        if !fits {
            self.new_block(index, t, phase, segment);
        }
        let b = self.blocks.last_mut().unwrap();
        b.last = index;
        b.t1 = t;
        b.frames += 1;
    }

    /// Close the last block and start a new one (compacting first if there are
    /// [`MAX_BLOCKS`]).
    #[inline(never)]
    fn new_block(&mut self, index: usize, t: f64, phase: Phase, segment: Option<usize>) {
        self.close_block();
        if self.blocks.len() >= MAX_BLOCKS {
            self.compact();
        }
        self.blocks.push(Block::new(index, t, phase, segment));
    }

    /// Add the open statistics to the last block.
    fn close_block(&mut self) {
        if let (Some(b), Some(m)) = (self.blocks.last_mut(), &self.model) {
            if let Some(s) = self.open.close(m) {
                b.add_moving(&s);
            }
        }
    }

    /// Merge adjacent pairs of blocks and double the block size: first pairs of one phase and
    /// segment; if that does not free a quarter of the blocks (phases alternate), any pairs of
    /// one segment. Blocks of different segments (different references) are never merged.
    fn compact(&mut self) {
        self.block_size *= 2;
        for same_phase in [true, false] {
            // In place: block `read` (and its mergeable successor) becomes block `write`.
            let blocks = &mut self.blocks;
            let (mut read, mut write) = (0, 0);
            while read < blocks.len() {
                let mut b = blocks[read];
                read += 1;
                if let Some(n) = blocks.get(read) {
                    if (!same_phase || n.phase == b.phase) && n.segment == b.segment {
                        b.merge(n);
                        read += 1;
                    }
                }
                blocks[write] = b;
                write += 1;
            }
            blocks.truncate(write);
            if self.blocks.len() <= MAX_BLOCKS * 3 / 4 {
                break;
            }
        }
    }

    /// Close the last block and the last segment: what the segment analysis takes.
    pub(super) fn finish(mut self) -> Segmented {
        self.close_block();
        if !self.in_motion {
            let rest_down = self.rest.down(self.down);
            let mean = self.rest.mean();
            let rest_place = mean
                .zip(self.down)
                .map(|((_, p), d)| RestPlace::new(&p, &d));
            let rest_rotation = mean.filter(|_| rest_down.is_some()).map(|(q, _)| q);
            if let Some(prev) = self.segments.last_mut() {
                prev.rest_after = rest_down;
                prev.rest_after_place = rest_place;
                prev.rest_after_rotation = rest_rotation;
                prev.rest_after_frames = if rest_down.is_some() {
                    self.rest.n()
                } else {
                    0.0
                };
            }
        }
        Segmented {
            config: self.config,
            noise: self.noise,
            segments: self.segments,
            blocks: self.blocks,
            outliers: self.outliers,
        }
    }
}

/// A demonstration split into motion segments and summarised in blocks, for the segment
/// analysis ([`super::conclusion::conclude`]).
pub(super) struct Segmented {
    /// The configuration.
    pub config: Config,
    /// The noise in force (given or estimated).
    pub noise: Option<NoiseModel>,
    /// The segments.
    pub segments: Vec<MotionSegment>,
    /// The blocks of all segments, in time order.
    pub blocks: Vec<Block>,
    /// Frames rejected as outliers.
    pub outliers: u64,
}
