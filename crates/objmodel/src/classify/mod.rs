//! Algorithm 1: is a demonstration a topple (edge rotation), a slide (face slide) or general?
//!
//! Two implementations share the front end (parsing, relative motion, screws):
//!
//! * [`Method::Paper`]: the paper's Algorithm 1 as written. Frame i's screw of
//!   `g'(i) = g(0)⁻¹ g(i)` is compared with frame i-1's: `|pitch| < p_th`, axis angle `< l_th` and
//!   `|r| < r_palm` give *topple*; otherwise normal angle `< n_th` gives *slide*; a large pitch
//!   gives *general*. The demo is the most frequent label over moving frames.
//! * [`Method::Robust`] (default), which works at real tracking noise:
//!   1. the noise is estimated from the data ([`crate::noise`]); single-frame tag flips are
//!      rejected and quaternion signs made continuous ([`crate::clean`]);
//!   2. frames at rest do not vote: a χ²₆ test on the local velocity (least-squares slope of the
//!      pose over a window of [`RobustConfig::rest_window_s`]) separates rest from motion;
//!      motion between rests forms a *segment* whose reference pose is the mean of the rest
//!      before it (a better `g(0)` than one noisy frame);
//!   3. instead of comparing each frame with its noisy predecessor, each frame is tested against
//!      the segment's best *fixed line* (topple) and best *fixed plane of motion* (slide), found
//!      by MSAC over the frames (robust to the end of a topple, where the object leaves its edge)
//!      and refined by weighted least squares. Residuals are normalised by their variance
//!      propagated from the tracking noise (plus a small model tolerance), so one χ² level
//!      `alpha` replaces the hand-set angle thresholds;
//!   4. physics: a topple axis lies in the supporting face, so within
//!      [`RobustConfig::max_axis_tilt_rad`] of horizontal, and a slide's plane normal within the
//!      same angle of vertical, when the direction of gravity is known;
//!   5. the label of a frame is topple if it fits the line, else slide if it fits the plane, else
//!      general; the demonstration's kind is the most frequent label (ties: topple, slide);
//!   6. the frames after a completed topple's edge rotation (it ended at rest on the adjacent
//!      face across the edge) are its landing and do not vote (see `analysis::completed_topple`).
//!
//! The modules, in the order the data flows through them (each imports only modules above it,
//! and the result and configuration types here):
//!
//! * `sample`: a kept frame or the place of a rejected one, as the stages pass them on;
//! * `cleaning`: noise warm-up and tag-flip rejection per stream; `palm`: the motion relative
//!   to a tracked palm;
//! * `rotation_sum`, `rest_sums`, `rest`: the accumulated rotation and the windowed χ² rest
//!   test; `rest_test`: the test with its noise warm-up, and the verdicts it passes on;
//! * `frame_model`: a moving frame's motion and screw against its segment's reference, and its
//!   noise model; `rest_stats`: a rest's mean pose and drift;
//! * `block`: the sufficient statistics of a run of frames; `segments`: the motion segments;
//! * `msac`: the fixed-line and fixed-plane fits; `analysis`: what one segment teaches;
//!   `parts`: where a segment's parts end and what each must show to teach;
//!   `conclusion`: what the segments teach together (votes, topples by edge); `rest_faces`:
//!   what the rests teach (faces from gravity, landings, the support's height);
//! * `robust`, `paper`: the two methods, streaming; `analyzer`: the [`Analyzer`] that drives
//!   them; `files`: [`classify_files`].

mod analysis;
mod analyzer;
mod block;
pub(crate) mod cleaning;
mod conclusion;
mod files;
pub(crate) mod frame_model;
mod lack_of_fit;
mod msac;
mod palm;
mod paper;
mod part_list;
pub(crate) mod parts;
mod rest;
mod rest_faces;
mod rest_stats;
mod rest_sums;
pub(crate) mod rest_test;
mod robust;
pub(crate) mod rotation_sum;
pub(crate) mod sample;
mod segments;

pub use analysis::{MIN_EDGE_FRAMES, MIN_FACE_FRAMES};
pub use analyzer::Analyzer;
pub(crate) use conclusion::group_topples;
pub use files::classify_files;
pub(crate) use files::classify_files_recording;
pub use palm::{Clocks, DEFAULT_MAX_DT_S};
pub use part_list::Part;

use crate::edge::EdgeObservation;
use crate::face::FaceObservation;
use crate::geometry::Line;
use crate::noise::NoiseModel;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// Which Algorithm 1 to run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// The statistical version that works at real tracking noise (default).
    #[default]
    Robust,
    /// The paper's Algorithm 1, literally.
    Paper,
}

/// The paper's thresholds (Algorithm 1), used by [`Method::Paper`]; `r_palm` is also used by
/// the robust method.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PaperThresholds {
    /// `p_th` \[m/rad\]: |pitch| below this is "no translation along the axis".
    pub pitch: f64,
    /// `l_th` \[rad\]: consecutive axes closer than this are "the same axis".
    pub axis_angle: f64,
    /// `n_th` \[rad\]: consecutive plane normals closer than this are "the same plane".
    pub normal_angle: f64,
    /// `r_palm` \[m\]: an axis farther than this from the object origin is not an edge of it
    /// (the paper: the size of the palm, known a priori). Default 0.5 m: the tag may sit on the
    /// far side of a 20 cm box from the edge it topples about.
    pub r_palm: f64,
    /// A frame moves if its rotation from g(0) exceeds this \[rad\] ...
    pub motion_rotation: f64,
    /// ... or its translation exceeds this \[m\].
    pub motion_translation: f64,
}

impl Default for PaperThresholds {
    fn default() -> Self {
        Self {
            pitch: 0.01,
            axis_angle: 5f64.to_radians(),
            normal_angle: 5f64.to_radians(),
            r_palm: 0.5,
            motion_rotation: 1e-3,
            motion_translation: 1e-4,
        }
    }
}

/// Parameters of the robust method. Every one is a probability, a duration or a physical
/// tolerance, not a threshold on a noisy quantity.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct RobustConfig {
    /// Significance level of the per-frame χ² tests (rest, fit to line, fit to plane).
    pub alpha: f64,
    /// Significance level of the tag-flip outlier test.
    pub outlier_alpha: f64,
    /// Width \[s\] of the window over which the local velocity is fitted for the rest test.
    pub rest_window_s: f64,
    /// A rest shorter than this \[s\] inside a motion does not start a new segment.
    pub min_rest_s: f64,
    /// Number of frames at the start of each stream used to estimate the noise.
    pub warmup_frames: usize,
    /// Tracking noise; `None` estimates it from the data.
    pub noise: Option<NoiseModel>,
    /// Model tolerance \[m\]: how far a real contact line may wander (rounded edges, compliant
    /// surfaces, micro-slip) and still count as one edge; added in quadrature to the noise of
    /// each frame, and the least systematic error of a topple's edge point (one trajectory per
    /// demonstration: it does not average down over the frames).
    pub edge_tolerance_m: f64,
    /// Model tolerance \[rad\] on directions (edge direction, plane normal).
    pub edge_tolerance_rad: f64,
    /// Largest angle \[rad\] between a topple axis and the horizontal, and between a slide's
    /// plane normal and the vertical, when gravity is known.
    pub max_axis_tilt_rad: f64,
}

impl Default for RobustConfig {
    fn default() -> Self {
        Self {
            alpha: 1e-3,
            outlier_alpha: 1e-6,
            rest_window_s: 0.6,
            min_rest_s: 1.0,
            warmup_frames: 300,
            noise: None,
            edge_tolerance_m: 3e-4,
            edge_tolerance_rad: 0.5f64.to_radians(),
            max_axis_tilt_rad: 45f64.to_radians(),
        }
    }
}

/// Everything that configures classification.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Config {
    /// Which algorithm.
    pub method: Method,
    /// The paper's thresholds.
    pub paper: PaperThresholds,
    /// The robust method's parameters.
    pub robust: RobustConfig,
    /// Gravity direction (unit or not) in the tracker's world frame; `None` if unknown.
    /// Default: -z (z up).
    pub gravity: Option<Vector3<f64>>,
    /// The object's and the palm's clocks (offset, pairing tolerance, time units).
    #[serde(default)]
    pub clocks: Clocks,
}

impl Default for Config {
    fn default() -> Self {
        Self {
            method: Method::Robust,
            paper: PaperThresholds::default(),
            robust: RobustConfig::default(),
            gravity: Some(Vector3::new(0.0, 0.0, -1.0)),
            clocks: Clocks::default(),
        }
    }
}

/// The kind of a demonstration or motion segment.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Kind {
    /// Edge rotation trajectory (ERT).
    Topple,
    /// Face slide trajectory (FST).
    Slide,
    /// Anything else.
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
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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

/// The result of classifying one demonstration.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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
    /// Votes over all segments.
    pub votes: Votes,
    /// Tracking noise used by the tests.
    pub noise: Option<NoiseModel>,
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
    /// Why the demonstration teaches nothing at all ([`Classification::withhold_all`]), if it
    /// does not.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub withheld: Option<String>,
}

impl Classification {
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

    /// Teach nothing: every edge, face and rest of the classification is withheld, for the
    /// reason given (which becomes a warning and [`Self::withheld`]); the labels and votes
    /// stay.
    pub fn withhold_all(&mut self, why: &str) {
        self.topples.clear();
        for s in &mut self.segments {
            if s.edge.is_some() || s.face.is_some() {
                s.withheld = Some(why.to_string());
            }
            s.edge = None;
            s.face = None;
            s.departs_from_support = false;
            s.arrives_on_support = false;
        }
        self.paper_edge = None;
        self.withheld = Some(why.to_string());
        self.warnings
            .push(format!("{why}; nothing is learnt from it"));
        self.fill_parts();
    }

    /// Fill [`Self::parts`] from the labels and what the segments taught.
    pub fn fill_parts(&mut self) {
        self.parts = part_list::parts(self);
    }
}

/// Classify a demonstration held in memory.
pub fn classify(demo: &crate::Demonstration, config: &Config) -> crate::Result<Classification> {
    let mut a = Analyzer::new(&demo.name, config, demo.palm.is_some());
    match &demo.palm {
        None => demo.object.iter().for_each(|p| a.push_object(p)),
        Some(palm) => {
            let (mut i, mut j) = (0, 0);
            while i < demo.object.len() || j < palm.len() {
                let take_palm =
                    j < palm.len() && (i >= demo.object.len() || palm[j].t <= demo.object[i].t);
                if take_palm {
                    a.push_palm(&palm[j]);
                    j += 1;
                } else {
                    a.push_object(&demo.object[i]);
                    i += 1;
                }
            }
        }
    }
    a.finish()
}
