//! A later part of a segment, measured from its own onset.
//!
//! The classifier measures every frame of a motion segment from the rest before it
//! ([`crate::classify`]), in one pass. A contact mode that starts after another motion of the
//! same segment, with no rest between (a push that slides a box and then tips it; a box that
//! lags and creeps a millimetre down a tilting palm before it topples), is therefore measured
//! from a pose it no longer has: its frames are the first motion composed with its own, and
//! they teach nothing (the part is withheld) or come out general. Here such a part is measured
//! again, from its own onset: the classifier runs over the kept frames ([`Recording`]) from the
//! frame before the part's first frame to the next segment, after a rest held at that frame's
//! pose (so that it is the reference, and the rest before it says which way is down). The
//! part then passes or fails every test a part measured from a rest must pass, and teaches
//! what it passes: a topple its edge, a slide its face.
//!
//! Where a part starts is where the parts before it end: the first run of at least
//! [`MIN_EDGE_FRAMES`] measurably moving frames that the first part's label does not explain
//! (the rule that ends a part in the classifier, `part_end`); a later part found that way is
//! split again at its own later part, up to [`MAX_DEPTH`] times. The reference is one frame:
//! any pose of a rotation about a fixed edge is a valid reference for the rest of that
//! rotation, so a reference a few frames after the real onset costs only angle.
//!
//! When nothing moved the object between the rest before the segment and the onset, the rest's
//! pose (a mean of many frames) is a better reference than one frame: the part is then
//! measured from the rest instead (`measured_from_rest`).
//!
//! An instrumented demonstration is measured relative to the palm; here its poses are
//! expressed in a world where the palm stays at its first pose (`P₀ · palm⁻¹ · object`), which
//! keeps the motion relative to the palm and the palm's "down" of the first pass.

mod after_creep;
pub mod creep;
mod span;

use crate::classify::{Classification, Config, Kind, Label, LabelRun, Votes};
use crate::classify::{MIN_EDGE_FRAMES, MIN_FACE_FRAMES};
use crate::recording::{RecordedFrame, Recording};
use span::{classify_from, classify_span, largest_turn, Start};

/// How many times a later part may itself be split at a later part of its own.
pub const MAX_DEPTH: usize = 3;

/// Seconds of rest held at the reference pose before a re-measured part, as a multiple of the
/// classifier's `min_rest_s` (the rest must be long enough to start a segment).
const HELD_REST: f64 = 1.25;

/// Fraction of the largest rotation of the re-measured frames that the frames of a
/// re-measured edge must reach (see `adopt`).
pub const CARRIED_FRACTION: f64 = 0.5;

/// A part of a segment measured again from its onset: where, and what the classifier said of
/// the frames from there on.
#[derive(Clone, Debug)]
struct Remeasured {
    /// Segment of the first pass.
    segment: usize,
    /// Time of the reference frame \[s\] and of the part's first frame, and the reference's
    /// frame index.
    t_reference: f64,
    i_reference: u64,
    t_onset: f64,
    /// The classification of the frames from the reference on (its frame indices are the
    /// first pass's).
    sub: Classification,
    /// How it was measured, for `Segment::remeasured` (`None`: from the onset).
    note: Option<String>,
}

/// Where the first part of segment `k` ends and a later one starts: the start time of the first
/// run of at least `MIN_EDGE_FRAMES` voting frames whose label differs from the first voting
/// label (outliers, still frames and landings neither end nor start a part); `None` if the
/// first part lasts to the end.
pub fn later_onset(labels: &[LabelRun], k: usize) -> Option<f64> {
    let mut first: Option<Label> = None;
    let (mut run, mut start) = (0u64, 0.0);
    for r in labels.iter().filter(|r| r.segment == Some(k)) {
        if r.label.vote().is_none() {
            continue;
        }
        match first {
            None => first = Some(r.label),
            Some(l) if l == r.label => run = 0,
            Some(_) => {
                if run == 0 {
                    start = r.t_start;
                }
                run += r.frames;
                if run as f64 >= MIN_EDGE_FRAMES.max(MIN_FACE_FRAMES) {
                    return Some(start);
                }
            }
        }
    }
    None
}

/// Measure the later parts of the segments that taught nothing from their own start, and add
/// what they teach to the classification (see the module documentation).
pub fn remeasure_later_parts(c: &mut Classification, recording: &Recording, config: &Config) {
    if config.method != crate::classify::Method::Robust
        || recording.object_stride > 1
        || recording.palm_stride > 1
    {
        return;
    }
    remeasure(c, recording, config, MAX_DEPTH);
    after_creep::remeasure_after_creep(c, recording, config);
}

fn remeasure(c: &mut Classification, recording: &Recording, config: &Config, depth: usize) {
    if depth == 0 {
        return;
    }
    let mut config = *config;
    config.robust.noise = c.noise.or(config.robust.noise);
    let outlier = |f: &RecordedFrame| {
        c.labels.iter().any(|r| {
            r.label == Label::Outlier && (r.first as u64..=r.last as u64).contains(&f.index)
        })
    };
    let mut done = Vec::new();
    for k in 0..c.segments.len() {
        let s = &c.segments[k];
        if s.edge.is_some() || s.face.is_some() {
            continue;
        }
        let Some(t_onset) = later_onset(&c.labels, k) else {
            continue;
        };
        let t_end = c.segments.get(k + 1).map_or(f64::INFINITY, |n| n.t_start);
        let Some(reference) = recording
            .object
            .iter()
            .rev()
            .find(|f| f.t < t_onset && f.t >= s.t_start && !outlier(f))
        else {
            continue;
        };
        // First the frames up to the largest turn from the reference (a topple's landing; on
        // a tilted palm the box may slide on after it, and those frames, all at one pose, can
        // outnumber the fall's), then all of them.
        let turned = largest_turn(recording, reference, t_end);
        let up_to_turn = turned
            .and_then(|t| classify_from(c, recording, &config, reference, t + 1e-9))
            .filter(teaches_edge);
        let span_end = match (&up_to_turn, turned) {
            (Some(_), Some(t)) => t + 1e-9,
            _ => t_end,
        };
        let Some(mut sub) =
            up_to_turn.or_else(|| classify_from(c, recording, &config, reference, t_end))
        else {
            continue;
        };
        remeasure(&mut sub, recording, &config, depth - 1);
        if let Some((rest, from_rest)) =
            measured_from_rest(c, recording, &config, k, &sub, span_end)
        {
            done.push(Remeasured {
                segment: k,
                t_reference: rest.t,
                i_reference: rest.index,
                t_onset: c.segments[k].t_start,
                sub: from_rest,
                note: Some(format!(
                    "measured from the rest before it up to {:.2} s (after that, its landing), \
                     the same line as measured from the onset of its later part at {t_onset:.2} \
                     s",
                    span_end.min(c.segments[k].t_end)
                )),
            });
            continue;
        }
        done.push(Remeasured {
            segment: k,
            t_reference: reference.t,
            i_reference: reference.index,
            t_onset,
            sub,
            note: None,
        });
    }
    for r in done {
        adopt(c, r, recording, &config);
    }
}

/// The edge of a part re-measured from its onset (`from_onset`, over the frames before
/// `span_end`), measured again from the rest before segment `k`, when the rest's pose is a
/// reference for it: the span from the rest to `span_end` classified as a segment of its
/// own teaches an edge (every test of a topple measured from a rest) that is the same line
/// as the edge measured from the onset (the likelihood-ratio test that pools topples, χ²₄ at
/// the classifier's α). Returns the last frame of the rest and that classification.
///
/// From its onset, the part is measured from one frame, whose error is common to all its
/// frames (it moves each frame's axis by about σ / (2 sin(θ/2))); the rest's pose is the mean
/// of many. It is a valid reference when nothing moved the object off the rotation between
/// the rest and the onset, and then the part's frames measured from it are the same line. A
/// creep or slide before the onset (a box creeping down a tilting palm) moves every frame's
/// axis, differently at each angle, and the lines differ: the onset's edge stays. On
/// MuJoCo's instrumented topples, why the first pass split the segment was mostly the landing
/// (many frames at one pose, whose axes agree with each other), which the span leaves out.
fn measured_from_rest<'r>(
    c: &Classification,
    recording: &'r Recording,
    config: &Config,
    k: usize,
    from_onset: &Classification,
    span_end: f64,
) -> Option<(&'r RecordedFrame, Classification)> {
    let onset_segment = from_onset.segments.first()?;
    if !teaches_edge(from_onset) || onset_segment.remeasured.is_some() {
        return None;
    }
    let s = &c.segments[k];
    let t_prev = k
        .checked_sub(1)
        .map_or(f64::NEG_INFINITY, |j| c.segments[j].t_end);
    let rest: Vec<&RecordedFrame> = recording
        .object
        .iter()
        .filter(|f| f.t > t_prev && f.t < s.t_start)
        .collect();
    let (first, last) = (rest.first()?, rest.last()?);
    // A rest the rest test established (the first frames of a file are called rest without
    // a window before them: `crate::start_rest`).
    if last.t - first.t < config.robust.rest_window_s {
        return None;
    }
    let sub = classify_span(
        c,
        recording,
        config,
        Start::Frames {
            t_from: first.t,
            skip: rest.len(),
        },
        span_end,
    )?;
    let rest_segment = sub.segments.first()?;
    if !teaches_edge(&sub) || rest_segment.remeasured.is_some() {
        return None;
    }
    let (a, b) = (&onset_segment.topple_stats, &rest_segment.topple_stats);
    let own = |s: &crate::geometry::LineStats| s.mean().map_or(0.0, |l| s.chi2(&l));
    let mut pooled = *a;
    pooled.merge(b);
    let lr = own(&pooled) - own(a) - own(b);
    (lr < crate::stats::chi2_threshold(4.0, config.robust.alpha)).then_some((*last, sub))
}

/// Whether the first pass labelled a kept frame an outlier.
fn is_outlier(c: &Classification, f: &RecordedFrame) -> bool {
    c.labels
        .iter()
        .any(|r| r.label == Label::Outlier && (r.first as u64..=r.last as u64).contains(&f.index))
}

/// Whether a re-measured part teaches an edge: its first segment's, if the edge's frames
/// carry the rotation. A topple measured from its onset carries the rotation of the frames
/// from there on (it is followed by its landing, or by a rest): an "edge" whose frames turn by
/// less than [`CARRIED_FRACTION`] of it explains a part of the motion that is not the topple
/// (a slide's first frames pass for rotations about a distant line).
fn teaches_edge(sub: &Classification) -> bool {
    sub.segments.first().is_some_and(|s| {
        s.edge.as_ref().is_some_and(|e| {
            // (An edge from a later part of its own passed this against its own frames.)
            s.remeasured.is_some() || e.max_angle >= CARRIED_FRACTION * s.max_angle
        })
    })
}

/// Add what a re-measured part teaches to segment `r.segment`: its first segment's edge or
/// face (if it passed its tests), its labels and votes in place of the first pass's from the
/// onset on, and the topples regrouped.
fn adopt(c: &mut Classification, r: Remeasured, recording: &Recording, config: &Config) {
    let k = r.segment;
    let Some(first) = r.sub.segments.first() else {
        return;
    };
    let seg = &mut c.segments[k];
    if first.edge.is_none() && first.face.is_none() {
        return;
    }
    if first.edge.is_some() && !teaches_edge(&r.sub) {
        return;
    }
    // The labels from the reference on are the re-measured ones, in segment k.
    let i_ref = r.i_reference as usize;
    let i_sub_end = r.sub.labels.last().map_or(i_ref, |l| l.last);
    // A run's frames within [a, b], as a run (times from the kept frames).
    let clip = |run: &LabelRun, a: usize, b: usize| -> Option<LabelRun> {
        let (a, b) = (run.first.max(a), run.last.min(b));
        let inside: Vec<&RecordedFrame> = recording
            .object
            .iter()
            .filter(|f| (a as u64..=b as u64).contains(&f.index))
            .collect();
        let (first, last) = (inside.first()?, inside.last()?);
        Some(LabelRun {
            first: first.index as usize,
            last: last.index as usize,
            t_start: first.t,
            t_end: last.t,
            frames: inside.len() as u64,
            ..*run
        })
    };
    let mut labels: Vec<LabelRun> = Vec::with_capacity(c.labels.len() + r.sub.labels.len());
    let mut votes = Votes::default();
    let mut inserted = false;
    let keep = |run: LabelRun, labels: &mut Vec<LabelRun>, votes: &mut Votes| {
        if let Some(v) = run.label.vote() {
            votes.add(v, run.frames);
        }
        labels.push(run);
    };
    for run in c.labels.drain(..) {
        if run.segment != Some(k) {
            labels.push(run);
            continue;
        }
        if run.last <= i_ref || run.first > i_sub_end {
            keep(run, &mut labels, &mut votes);
            continue;
        }
        // Up to the reference: the first pass's; then the re-measured labels; after them,
        // the first pass's again.
        if let Some(head) = clip(&run, 0, i_ref) {
            keep(head, &mut labels, &mut votes);
        }
        if !inserted {
            inserted = true;
            for mut s in r.sub.labels.iter().copied() {
                s.segment = Some(k);
                keep(s, &mut labels, &mut votes);
            }
        }
        if let Some(tail) = clip(&run, i_sub_end + 1, usize::MAX) {
            keep(tail, &mut labels, &mut votes);
        }
    }
    c.labels = labels;
    c.votes.topple = c.votes.topple - seg.votes.topple + votes.topple;
    c.votes.slide = c.votes.slide - seg.votes.slide + votes.slide;
    c.votes.general = c.votes.general - seg.votes.general + votes.general;
    seg.votes = votes;
    seg.kind = votes.winner().unwrap_or(Kind::General);
    // (An edge from a later part of the re-measured part: that part's onset.)
    let note = r
        .note
        .clone()
        .or_else(|| first.remeasured.clone())
        .unwrap_or_else(|| {
            format!(
            "measured from its onset at {:.2} s (the pose at {:.2} s), after the part before it",
            r.t_onset, r.t_reference
        )
        });
    if let Some(e) = &first.edge {
        seg.edge = Some(e.clone());
        seg.topple_stats = first.topple_stats;
        seg.topple_systematic_var = first.topple_systematic_var;
        seg.topple_systematic_direction_var = first.topple_systematic_direction_var;
        seg.topple_best = first.topple_best;
    } else if let Some(f) = &first.face {
        seg.face = Some(f.clone());
    }
    seg.remeasured = Some(note);
    seg.onset_frame = first
        .onset_frame
        .or_else(|| r.sub.labels.first().map(|l| l.first));
    seg.withheld_before_onset = seg.withheld.take();
    // A part that lasts to the rest after arrives on it as the first pass's would.
    seg.arrives_on_support |= first.arrives_on_support;
    c.kind = c.votes.winner().unwrap_or(Kind::General);
    c.topples = crate::classify::group_topples(&c.segments, config.robust.alpha, &c.name);
    // A re-measured topple teaches its edge, not its pendulum: the dynamics fit the frames
    // labelled topple in its segment, and those before the onset keep the first pass's labels
    // (a creep's, an edge slip's). On the weighted box's on-end topples of the standard dataset
    // such pendulums were 5-15° off in φ and moved the learnt CoM (0.1 to 0.6 mm, clean). The
    // dynamics need the face rested on before; without it they are not fitted.
    for t in &mut c.topples {
        if t.segments
            .iter()
            .any(|&i| c.segments[i].remeasured.is_some())
        {
            t.resting_normal_before = None;
        }
    }
    if c.paper_edge.is_none() {
        c.paper_edge = c
            .topples
            .iter()
            .max_by_key(|t| t.edge.frames)
            .and_then(|t| t.edge.paper_line);
    }
}
