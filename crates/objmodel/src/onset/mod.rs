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

mod adopt;
mod after_creep;
mod before_fall;
pub mod creep;
mod span;

pub use adopt::CARRIED_FRACTION;

use crate::classify::{Classification, Config, Label, LabelRun};
use crate::classify::{MIN_EDGE_FRAMES, MIN_FACE_FRAMES};
use crate::recording::{RecordedFrame, Recording};
use adopt::{adopt, teaches_edge, Remeasured};
use span::{classify_from, classify_span, largest_turn, Start};

/// How many times a later part may itself be split at a later part of its own.
pub const MAX_DEPTH: usize = 3;

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
    // Without gravity a flight cannot be told from a contact mode (`crate::flight`), and the
    // part before a later one may have been a throw: a tossed box's flight passed for a
    // slide, measured from its onset, and taught a face 25° off (MuJoCo tosses learnt with
    // `--gravity none`). Relative to a palm nothing flies.
    let world_without_gravity = config.gravity.is_none() && !c.instrumented;
    if config.method != crate::classify::Method::Robust
        || recording.object_stride > 1
        || recording.palm_stride > 1
        || world_without_gravity
    {
        return;
    }
    remeasure(c, recording, config, MAX_DEPTH);
    after_creep::remeasure_after_creep(c, recording, config);
    before_fall::remeasure_from_the_stop(c, recording, config);
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
                before_fall: false,
                creep: false,
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
            before_fall: false,
            creep: false,
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
