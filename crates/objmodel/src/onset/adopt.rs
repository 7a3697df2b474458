//! A part re-measured from its onset ([`Remeasured`]), and what of it the first pass adopts.

use crate::classify::{Classification, Config, Kind, Label, LabelRun, Votes};
use crate::recording::{RecordedFrame, Recording};

/// Fraction of the largest rotation of the re-measured frames that the frames of a
/// re-measured edge must reach (see `adopt`).
pub const CARRIED_FRACTION: f64 = 0.5;

/// A part of a segment measured again from its onset: where, and what the classifier said of
/// the frames from there on.
#[derive(Clone, Debug)]
pub(super) struct Remeasured {
    /// Segment of the first pass.
    pub(super) segment: usize,
    /// Time of the reference frame \[s\] and of the part's first frame, and the reference's
    /// frame index.
    pub(super) t_reference: f64,
    pub(super) i_reference: u64,
    pub(super) t_onset: f64,
    /// The classification of the frames from the reference on (its frame indices are the
    /// first pass's).
    pub(super) sub: Classification,
    /// How it was measured, for `Segment::remeasured` (`None`: from the onset).
    pub(super) note: Option<String>,
    /// Whether it was measured from the stop before a fall on a palm (`super::before_fall`;
    /// then its edge is taught by [`teaches_edge_before_landing`]).
    pub(super) before_fall: bool,
    /// Whether the segment's moving frames before the reference are a creep on the palm
    /// (labelled [`Label::Creep`], which does not vote; see `super::before_fall`).
    pub(super) creep: bool,
}

/// Whether the first pass labelled a kept frame an outlier.
pub(super) fn is_outlier(c: &Classification, f: &RecordedFrame) -> bool {
    c.labels
        .iter()
        .any(|r| r.label == Label::Outlier && (r.first as u64..=r.last as u64).contains(&f.index))
}

/// Whether a re-measured part teaches an edge: its first segment's, if the edge's frames
/// carry the rotation. A topple measured from its onset carries the rotation of the frames
/// from there on (it is followed by its landing, or by a rest): an "edge" whose frames turn by
/// less than [`CARRIED_FRACTION`] of it explains a part of the motion that is not the topple
/// (a slide's first frames pass for rotations about a distant line).
pub(super) fn teaches_edge(sub: &Classification) -> bool {
    sub.segments.first().is_some_and(|s| {
        s.edge.as_ref().is_some_and(|e| {
            // (An edge from a later part of its own passed this against its own frames.)
            s.remeasured.is_some() || e.max_angle >= CARRIED_FRACTION * s.max_angle
        })
    })
}

/// Whether a part re-measured from the stop before a fall on a palm (`super::before_fall`)
/// teaches an edge: its first segment's, if the frames after the edge's are the topple's
/// landing (the classifier found the rests before and after on faces that meet at the edge's
/// direction, turned in its sense; `classify::analysis`). The rest of the rotation is then the
/// fall onto the next face, over which the pivot slides down the tilted palm: on MuJoCo's
/// palm topples it stays within about 1 mm of the edge up to 35-45°, and is 9-19 mm off at
/// 85°, so the edge's frames carry less than [`CARRIED_FRACTION`] of the rotation.
///
/// Only from that stop: measured from an earlier reference (a later part's onset before the
/// creep has ended), an edge of three frames 8 mm off the box passed so (MuJoCo's palm topples
/// at 30 Hz).
pub(super) fn teaches_edge_before_landing(sub: &Classification) -> bool {
    teaches_edge(sub) || sub.segments.first().is_some_and(|s| s.edge.is_some()) && lands(sub)
}

/// Whether the classifier labelled frames of a re-measured part's first segment the landing
/// of a completed topple.
fn lands(sub: &Classification) -> bool {
    sub.labels
        .iter()
        .any(|r| r.segment == Some(0) && r.label == Label::Landing)
}

/// Add what a re-measured part teaches to segment `r.segment`: its first segment's edge or
/// face (if it passed its tests), its labels and votes in place of the first pass's from the
/// onset on, and the topples regrouped.
pub(super) fn adopt(c: &mut Classification, r: Remeasured, recording: &Recording, config: &Config) {
    let k = r.segment;
    let Some(first) = r.sub.segments.first() else {
        return;
    };
    let seg = &mut c.segments[k];
    if first.edge.is_none() && first.face.is_none() {
        return;
    }
    let teaches = if r.before_fall {
        teaches_edge_before_landing
    } else {
        teaches_edge
    };
    if first.edge.is_some() && !teaches(&r.sub) {
        return;
    }
    // Measured from one frame, after another motion, a part may pass its edge model and still
    // locate its edge to ±20 mm (a slide, a rest and a topple taken for one part).
    let location = (crate::edge::EDGE_MATCH_M, crate::edge::EDGE_MATCH_RAD);
    if let Some(why) = first
        .edge
        .as_ref()
        .and_then(|e| crate::edge::unlocated(e, location, "a part measured from its onset"))
    {
        seg.withheld = Some(why);
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
    let creep = |mut run: LabelRun| {
        if r.creep && matches!(run.label, Label::Topple | Label::General | Label::Still) {
            run.label = Label::Creep;
        }
        run
    };
    // Measured from the stop before a fall up to where it first reached its largest turn,
    // a completed topple's frames after that are still its landing (the classifier labels
    // every frame after a completed topple's rotation that is not on its edge so): the
    // object lies on the next face and may slide on down the tilted palm.
    let landed = r.before_fall && lands(&r.sub);
    let landing = |mut run: LabelRun| {
        if landed && run.label.vote().is_some() {
            run.label = Label::Landing;
        }
        run
    };
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
        if run.last <= i_ref {
            keep(creep(run), &mut labels, &mut votes);
            continue;
        }
        if run.first > i_sub_end {
            keep(landing(run), &mut labels, &mut votes);
            continue;
        }
        // Up to the reference: the first pass's (or the creep's); then the re-measured
        // labels; after them, the first pass's again (or the landing's).
        if let Some(head) = clip(&run, 0, i_ref) {
            keep(creep(head), &mut labels, &mut votes);
        }
        if !inserted {
            inserted = true;
            for mut s in r.sub.labels.iter().copied() {
                s.segment = Some(k);
                keep(s, &mut labels, &mut votes);
            }
        }
        if let Some(tail) = clip(&run, i_sub_end + 1, usize::MAX) {
            keep(landing(tail), &mut labels, &mut votes);
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
    // A re-measured topple of the object alone teaches its edge, not its pendulum: the
    // dynamics fit the frames labelled topple in its segment, and those before the onset keep
    // the first pass's labels (a creep's, an edge slip's). On the weighted box's on-end topples
    // of the standard dataset such pendulums were 5-15° off in φ and moved the learnt CoM (0.1
    // to 0.6 mm, clean). The dynamics need the face rested on before; without it they are not
    // fitted. On a palm the angles are the object's relative to the palm, which a creep down
    // the palm leaves at rest: the onset and the pendulum on the palm hold (MuJoCo, 120 Hz,
    // exact poses: every topple on a palm creeps 1-3 mm first, and their φ were 0.1° off at
    // most, within 0.8 σ, where none was learnt before).
    if !c.instrumented {
        for t in &mut c.topples {
            if t.segments
                .iter()
                .any(|&i| c.segments[i].remeasured.is_some())
            {
                t.resting_normal_before = None;
            }
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
