//! Blocks: the sufficient statistics ([`LineStats`], [`PlaneStats`]) of a run of consecutive
//! frames of one phase and segment. While a file has fewer than [`MAX_BLOCKS`] frames every
//! block is one frame, so per-frame labels are exact; beyond that, adjacent blocks of the same
//! phase and segment are merged in pairs (and new blocks take twice as many frames), so labels
//! become per block of 2, 4, ... frames and memory stays flat.

use super::{Label, LabelRun};
use crate::fast::moving_sums::MovingStats;
use crate::geometry::{Line, LineStats, PlaneStats};
use crate::screw::moments;
use nalgebra::Vector3;

/// Largest number of blocks kept per demonstration.
pub const MAX_BLOCKS: usize = 1 << 12;
/// What a block's frames are.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Phase {
    Rest,
    Outlier,
    Moving,
}

/// Sufficient statistics of a run of consecutive frames of one phase and segment.
#[derive(Clone, Copy, Debug)]
pub(super) struct Block {
    pub first: usize,
    pub last: usize,
    pub t0: f64,
    pub t1: f64,
    pub frames: u64,
    pub phase: Phase,
    pub segment: Option<usize>,
    /// Frames measurably displaced from the segment reference (they vote).
    pub significant: u64,
    pub line: LineStats,
    pub plane: PlaneStats,
    /// Largest rotation in the block and the screw axis at that frame.
    pub max_angle: f64,
    pub max_line: Option<(Line, Vector3<f64>)>,
    pub label: Label,
}

impl Block {
    pub(super) fn new(index: usize, t: f64, phase: Phase, segment: Option<usize>) -> Self {
        Self {
            first: index,
            last: index,
            t0: t,
            t1: t,
            frames: 0,
            phase,
            segment,
            significant: 0,
            line: LineStats::default(),
            plane: PlaneStats::default(),
            max_angle: 0.0,
            max_line: None,
            label: match phase {
                Phase::Rest => Label::Rest,
                Phase::Outlier => Label::Outlier,
                Phase::Moving => Label::Still,
            },
        }
    }

    /// Add the statistics of the block's moving frames.
    pub(super) fn add_moving(&mut self, s: &MovingStats) {
        self.significant += s.significant;
        self.plane.merge(&s.plane);
        self.line.merge(&s.line);
        if let Some((theta, xi)) = s.largest.filter(|(theta, _)| *theta > self.max_angle) {
            self.max_angle = theta;
            // The screw axis: r = ω × v / θ² is its point closest to the origin (r ⊥ u).
            let m = moments(&xi.omega.into(), &xi.v.into());
            let line = Line {
                point: Vector3::from(m.moment) * (1.0 / (theta * theta)),
                direction: xi.omega / theta,
            };
            self.max_line = Some((line, xi.omega));
        }
    }

    pub(super) fn merge(&mut self, o: &Block) {
        // A mixed block takes the phase that carries the most information.
        let rank = |p: Phase| match p {
            Phase::Moving => 2,
            Phase::Rest => 1,
            Phase::Outlier => 0,
        };
        if rank(o.phase) > rank(self.phase) {
            self.phase = o.phase;
            self.label = o.label;
        }
        self.last = o.last;
        self.t1 = o.t1;
        self.frames += o.frames;
        self.significant += o.significant;
        self.line.merge(&o.line);
        self.plane.merge(&o.plane);
        if o.max_angle > self.max_angle {
            self.max_angle = o.max_angle;
            self.max_line = o.max_line;
        }
    }
}

/// Run-length encode block labels.
pub(super) fn runs(blocks: &[Block]) -> Vec<LabelRun> {
    let mut out: Vec<LabelRun> = Vec::new();
    for b in blocks {
        if let Some(r) = out.last_mut() {
            if r.label == b.label && r.segment == b.segment {
                r.last = b.last;
                r.t_end = b.t1;
                r.frames += b.frames;
                continue;
            }
        }
        out.push(LabelRun {
            first: b.first,
            last: b.last,
            t_start: b.t0,
            t_end: b.t1,
            frames: b.frames,
            label: b.label,
            segment: b.segment,
        });
    }
    out
}
