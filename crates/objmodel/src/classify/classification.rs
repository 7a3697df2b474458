//! What classifying a demonstration gives ([`Classification`]): its kind, the labels of its
//! frames, its motion segments with what each taught, its topples, parts and rolls.

use super::config::Method;
use crate::edge::EdgeObservation;
use crate::face::FaceObservation;
use crate::geometry::Line;
use crate::noise::NoiseModel;
use nalgebra::{UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

/// The kind of a demonstration or motion segment.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Kind {
    /// Edge rotation trajectory (ERT).
    Topple,
    /// Face slide trajectory (FST).
    Slide,
    /// Anything else (and what nothing has shown to be a contact mode).
    #[default]
    General,
}

impl Kind {
    /// The JSON name.
    pub fn as_str(self) -> &'static str {
        match self {
            Kind::Topple => "topple",
            Kind::Slide => "slide",
            Kind::General => "general",
        }
    }
}

/// The label of one frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Label {
    /// The object is at rest (no vote).
    Rest,
    /// Rejected as a tracking outlier (tag flip) (no vote).
    Outlier,
    /// Moving, but not yet measurably displaced from the segment's reference (no vote).
    Still,
    /// Consistent with rotation about the segment's edge.
    Topple,
    /// Consistent with planar motion on the segment's face.
    Slide,
    /// Neither.
    General,
    /// After the end of a completed topple's edge rotation: the object leaves its edge, falls
    /// and lands on the adjacent face (no vote; step 6 above).
    Landing,
    /// (Paper method) moving, but neither the axis nor the normal matched the previous frame's
    /// (no vote).
    Unlabelled,
    /// Free flight: the centre of mass falls with gravity (parts only, see [`crate::flight`];
    /// no vote).
    Flight,
    /// Where a flight breaks: the velocity jumps (a bounce, a landing, a catch) (parts only;
    /// no vote).
    Impact,
    /// A rotation about a fixed edge inside a motion, measured without a rest (parts only, see
    /// [`crate::roll`]; no vote).
    Roll,
    /// Relative to a palm, before an edge rotation measured from the stop before its fall: the
    /// object settled, crept or slipped on the palm, turned from its rest by less than a turn
    /// that locates an edge (parts only, see [`crate::onset`]; no vote).
    Creep,
}

impl Label {
    /// The kind this label votes for, if it votes.
    pub fn vote(self) -> Option<Kind> {
        match self {
            Label::Topple => Some(Kind::Topple),
            Label::Slide => Some(Kind::Slide),
            Label::General => Some(Kind::General),
            _ => None,
        }
    }
}

/// Frame counts per vote.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Votes {
    /// Frames labelled topple.
    pub topple: u64,
    /// Frames labelled slide.
    pub slide: u64,
    /// Frames labelled general.
    pub general: u64,
}

impl Votes {
    /// Add `n` votes for `k`.
    pub fn add(&mut self, k: Kind, n: u64) {
        match k {
            Kind::Topple => self.topple += n,
            Kind::Slide => self.slide += n,
            Kind::General => self.general += n,
        }
    }

    /// Total votes.
    pub fn total(&self) -> u64 {
        self.topple + self.slide + self.general
    }

    /// The winner (ties broken topple > slide > general); `None` with no votes.
    pub fn winner(&self) -> Option<Kind> {
        if self.total() == 0 {
            return None;
        }
        let mut best = (Kind::Topple, self.topple);
        for (k, n) in [(Kind::Slide, self.slide), (Kind::General, self.general)] {
            if n > best.1 {
                best = (k, n);
            }
        }
        Some(best.0)
    }
}

/// A run of consecutive frames with one label (run-length encoded per-frame labels).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct LabelRun {
    /// Index (0-based, in the object file) of the first frame of the run.
    pub first: usize,
    /// Index of the last frame of the run (inclusive).
    pub last: usize,
    /// Time of the first frame \[s\].
    pub t_start: f64,
    /// Time of the last frame \[s\].
    pub t_end: f64,
    /// Number of frames in the run (fewer than `last - first + 1` if frames were dropped).
    pub frames: u64,
    /// The label.
    pub label: Label,
    /// Motion segment the run belongs to, if any.
    pub segment: Option<usize>,
}

/// A frame of largest rotation: (angle \[rad\], its screw axis, its rotation vector \[rad\]).
pub(crate) type LargestRotation = (f64, Line, Vector3<f64>);

/// One motion segment: the frames between two rests, analysed against one reference pose.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Segment {
    /// Pooled line statistics of the frames labelled topple.
    #[serde(skip)]
    pub(crate) topple_stats: crate::geometry::LineStats,
    /// Largest rotation among them.
    #[serde(skip)]
    pub(crate) topple_best: Option<LargestRotation>,
    /// Per-axis variance \[m²\] of the edge point beyond the frames' noise (the split-half
    /// lack of fit of a pivot that moved), added to the edge's point covariance.
    #[serde(skip)]
    pub(crate) topple_systematic_var: f64,
    /// Per-axis variance \[rad²\] of the edge direction beyond the frames' noise (the
    /// split-half lack of fit of an axis that turned), added to the direction covariance.
    #[serde(skip)]
    pub(crate) topple_systematic_direction_var: f64,
    /// What the rests before and after measure of the edge point (it is on the support in
    /// both), applied to the segment's edge and to its topple's.
    #[serde(skip)]
    pub(crate) support_constraint: Option<crate::edge::PointConstraint>,
    /// Time of the first moving frame \[s\].
    pub t_start: f64,
    /// Time of the last moving frame \[s\].
    pub t_end: f64,
    /// The segment's kind.
    pub kind: Kind,
    /// Its votes.
    pub votes: Votes,
    /// Largest rotation from the reference \[rad\].
    pub max_angle: f64,
    /// The fitted edge, for a topple segment.
    pub edge: Option<EdgeObservation>,
    /// The fitted face, for a slide segment.
    pub face: Option<FaceObservation>,
    /// Outward normal (object frame) of the face the object rested on before, if known.
    pub resting_normal_before: Option<Vector3<f64>>,
    /// Outward normal (object frame) of the face it rested on after, if known.
    pub resting_normal_after: Option<Vector3<f64>>,
    /// Why the segment taught no edge (or face) although its frames vote topple (slide):
    /// the part follows another mode of motion in the same segment and is not measured from
    /// its own start.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub withheld: Option<String>,
    /// Frames of the rest before the segment (0 if none, or not counted).
    #[serde(default)]
    pub resting_frames_before: u64,
    /// Frames of the rest after it.
    #[serde(default)]
    pub resting_frames_after: u64,
    /// Where the object frame's origin was in the rest before, in the frame the poses are given
    /// in (absent when gravity is unknown).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub resting_place_before: Option<crate::landing::RestPlace>,
    /// Where it was in the rest after, likewise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub resting_place_after: Option<crate::landing::RestPlace>,
    /// The object's orientation over the rest before (`world_from_object`, the mean over the
    /// rest's frames, as the quaternion `[x, y, z, w]`), when its down is known (gravity given).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub resting_rotation_before: Option<UnitQuaternion<f64>>,
    /// The orientation over the rest after, likewise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub resting_rotation_after: Option<UnitQuaternion<f64>>,
    /// Whether the rest before was on the support: a contact mode (slide, edge rotation)
    /// measured from it leaves it and passes its test.
    #[serde(default)]
    pub departs_from_support: bool,
    /// Whether the rest after is on the support: a contact mode that passed its test lasts
    /// until it (a completed topple's landing aside), or the motion that reaches it, measured
    /// back from it, is one (set by [`crate::learn`], which keeps the frames to test that).
    #[serde(default)]
    pub arrives_on_support: bool,
    /// When the segment's feature comes from a later part of it, measured again from that
    /// part's own onset (set by [`crate::learn`], which keeps the frames; see
    /// [`crate::onset`]): where.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub remeasured: Option<String>,
    /// The first frame of that later part (its parts start there).
    #[serde(skip)]
    pub(crate) onset_frame: Option<usize>,
    /// Why the part before that onset taught nothing, if the first pass said why.
    #[serde(skip)]
    pub(crate) withheld_before_onset: Option<String>,
}

/// One topple of a demonstration: one or more topple segments about one edge.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Topple {
    /// Indices of its segments.
    pub segments: Vec<usize>,
    /// The edge, from all its segments' frames.
    pub edge: EdgeObservation,
    /// Outward normal (object frame) of the face rested on before, if known.
    pub resting_normal_before: Option<Vector3<f64>>,
    /// Outward normal (object frame) of the face rested on after, if known.
    pub resting_normal_after: Option<Vector3<f64>>,
}

/// The result of classifying one demonstration. (Its `Default` is what the classifiers fill in
/// for the fields that the learner's later stages set: no parts, rolls, warnings or counts.)
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Classification {
    /// The demonstration's name.
    pub name: String,
    /// `"topple"`, `"slide"` or `"general"`.
    pub kind: Kind,
    /// Method used.
    pub method: Method,
    /// True when the motion analysed is relative to a tracked palm (`palm_from_object`).
    pub instrumented: bool,
    /// Frames read (object file).
    pub frames: u64,
    /// Frames rejected as tracking outliers.
    pub outliers: u64,
    /// Of those, frames left out as the tracker's held poses: repeats of the pose before them
    /// that the tracker's noise rules out (see `crate::clean::held`).
    #[serde(default)]
    pub held_frames: u64,
    /// Lines of the object's file where the tracker lost the object (every pose value NaN,
    /// empty or zero: `format::SkippedLines`), left out as frames not recorded; not counted
    /// in `frames`. (Poses in memory and bags: 0; a bag's warnings count its own.)
    #[serde(default)]
    pub lost_frames: u64,
    /// The same of the palm's file.
    #[serde(default)]
    pub palm_lost_frames: u64,
    /// Lines of the object's file that repeat the pose line before them exactly (its time and
    /// pose: a logger that wrote a line twice), left out (`format::SkippedLines`); not counted
    /// in `frames`. (Poses in memory and bags: 0.)
    #[serde(default)]
    pub duplicate_lines: u64,
    /// The same of the palm's file.
    #[serde(default)]
    pub palm_duplicate_lines: u64,
    /// Votes over all segments.
    pub votes: Votes,
    /// Tracking noise used by the tests.
    pub noise: Option<NoiseModel>,
    /// Whether `noise` follows from noise the user gave (propagated to the motion relative to
    /// the palm for an instrumented demonstration), rather than estimated from the data.
    #[serde(default)]
    pub noise_given: bool,
    /// Where the trackers' noise is correlated from frame to frame: what was measured, and
    /// `noise` is then from the long-run noise ([`crate::noise_correlation`]).
    #[serde(default)]
    pub noise_correlation: Option<crate::noise_correlation::TrackerCorrelations>,
    /// Whether the tracking noise could not be measured on the demonstration's frames (its
    /// motion between frames exceeds the noise, and no rest is long enough to measure it)
    /// and none was given: then it teaches nothing (see [`Self::withheld`]).
    #[serde(default)]
    pub noise_unmeasurable: bool,
    /// Where the noise could not be measured on the demonstration's frames, the noise that
    /// other demonstrations learnt with it measured at its frame rate
    /// ([`crate::shared_noise`]), which `noise` follows from (or the larger of it and what
    /// its frames show, which a warning says).
    #[serde(default)]
    pub noise_shared: Option<crate::shared_noise::SharedNoise>,
    /// The median time between the object's frames \[s\] (as learnt; `None` before the
    /// frames are checked, or with fewer than two).
    #[serde(default)]
    pub frame_interval_s: Option<f64>,
    /// Motion segments.
    pub segments: Vec<Segment>,
    /// The topples (segments grouped by edge), with their edges.
    pub topples: Vec<Topple>,
    /// Per-frame labels, run-length encoded.
    pub labels: Vec<LabelRun>,
    /// The paper's Algorithm 2 edge (line at the frame of largest rotation), for a topple.
    pub paper_edge: Option<Line>,
    /// What looked wrong with the input without making it unreadable (e.g. timestamps that do
    /// not look like seconds), for the user to check.
    #[serde(default)]
    pub warnings: Vec<String>,
    /// Whether a motion looked like a topple or slide under another direction of gravity than
    /// the one given (see the warnings): then the faces rested on are not taught from gravity.
    #[serde(default)]
    pub gravity_doubted: bool,
    /// The demonstration's parts in time order (rests, and the contact modes within each
    /// segment), each with what it taught ([`Classification::fill_parts`]).
    #[serde(default)]
    pub parts: Vec<Part>,
    /// The rolls over an edge found inside its motions ([`crate::roll`]), each with its edge
    /// and whether it taught it.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub rolls: Vec<crate::roll::Roll>,
    /// The turns inside its motions that looked like rolls and are not ([`crate::roll`]: the
    /// fixed-line model explained them, about a level line, over enough frames and turn; a
    /// later test rejected them), each with why.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub rolls_rejected: Vec<crate::roll::RejectedRoll>,
    /// Why the demonstration teaches nothing at all ([`Classification::withhold_all`]), if it
    /// does not.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub withheld: Option<String>,
    /// The unit the positions were read in where it is known (declared by the files, or
    /// given: [`Config::length_unit`](super::Config)), and converted to metres from; `None`
    /// where metres were assumed (and checked: [`crate::length_check`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub length_unit: Option<crate::format::LengthUnit>,
    /// Where its rolls were told from flights by the centre of mass that the flights of the
    /// demonstrations learnt with it measured together ([`crate::shared_com`]), that point.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub com_shared: Option<crate::shared_com::SharedCom>,
    /// The centre of mass each flight of the demonstration measured, where it determined one,
    /// before the flights are checked against each other (pooled over the demonstrations
    /// learnt together: [`crate::shared_com`]).
    #[serde(skip)]
    pub flight_coms: Vec<crate::flight::ComEstimate>,
}

impl Classification {
    /// The flights' centres of mass that the demonstration teaches ([`Self::flight_coms`]):
    /// none where it teaches nothing ([`Self::withheld`]) or the object was on a palm.
    pub fn flight_coms_taught(&self) -> &[crate::flight::ComEstimate] {
        if self.instrumented || self.withheld.is_some() {
            &[]
        } else {
            &self.flight_coms
        }
    }

    /// Whether the object flew in the demonstration (a part of it is a flight,
    /// [`crate::flight`]): its rolls are then told from flights by a centre of mass
    /// ([`crate::roll`], [`crate::shared_com`]).
    pub fn flew(&self) -> bool {
        self.parts.iter().any(|p| p.kind == Label::Flight)
    }

    /// Whether the object frame of index `i` (in the stream) was rejected as an outlier: a
    /// binary search of the outlier label runs.
    pub fn is_outlier(&self) -> impl Fn(u64) -> bool {
        let outliers: Vec<(u64, u64)> = self
            .labels
            .iter()
            .filter(|r| r.label == Label::Outlier)
            .map(|r| (r.first as u64, r.last as u64))
            .collect();
        move |i: u64| {
            let k = outliers.partition_point(|r| r.1 < i);
            outliers.get(k).is_some_and(|r| r.0 <= i)
        }
    }

    /// Edge observations, one per topple.
    pub fn edges(&self) -> impl Iterator<Item = &EdgeObservation> {
        self.topples.iter().map(|t| &t.edge)
    }

    /// Face observations: slides' planes; for topples, the faces rested on before and after
    /// (with the offsets their edges give); and [`Classification::rest_faces`].
    pub fn faces(&self) -> Vec<FaceObservation> {
        let mut out: Vec<FaceObservation> = self
            .segments
            .iter()
            .filter_map(|s| s.face.clone())
            .collect();
        for t in &self.topples {
            for n in [t.resting_normal_before, t.resting_normal_after]
                .into_iter()
                .flatten()
            {
                out.push(FaceObservation::from_rest(&n, &t.edge));
            }
        }
        out.extend(self.rest_faces());
        out
    }
}

/// One part of a demonstration.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Part {
    /// What the object did: `rest`, `topple`, `slide`, `general` (carried, rolling, tumbling:
    /// no contact mode the learner can use), `landing` (after a completed topple), `flight`
    /// (free fall), `impact` (where a flight breaks) (flights and impacts: see
    /// [`crate::flight`]) or `roll` (a rotation about a fixed edge inside a motion, measured
    /// without a rest: see [`crate::roll`]).
    pub kind: Label,
    /// Time of the part's first frame \[s\].
    pub t_start: f64,
    /// Time of its last frame \[s\].
    pub t_end: f64,
    /// Index of its first frame in the object stream.
    pub first: usize,
    /// Index of its last frame.
    pub last: usize,
    /// Its frames (outliers included).
    pub frames: u64,
    /// The motion segment it belongs to (a rest: the segment before it; `None` before the
    /// first motion).
    pub segment: Option<usize>,
    /// What it taught: `"edge"` (a topple's or a roll's), `"face"` (a slide's plane),
    /// `"resting face"` (a rest on the support, with gravity).
    #[serde(default)]
    pub taught: Vec<String>,
    /// Why a part of a contact mode, or a rest (the last of its segment's), taught nothing,
    /// when the learner said why.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub withheld: Option<String>,
    /// A flight's centre of mass, when the flight turned enough to determine it (object frame;
    /// the tree pools those of all its demonstrations: `tree/flights.rs`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub com_estimate: Option<crate::flight::ComEstimate>,
}
