//! The parts of a demonstration, for the report: its rests and, within each motion segment,
//! the runs of one contact mode (topple, slide, general motion, a topple's landing), each with
//! its times and what it taught or why it taught nothing.
//!
//! A part is a run of per-frame labels of one kind that goes on through interruptions shorter
//! than a part needs to be a part ([`super::MIN_EDGE_FRAMES`] moving frames labelled
//! otherwise), as the segment analysis ends parts (`parts::part_end`); outliers and frames not
//! yet measurably moving belong to the part they interrupt (or to the next one, at a segment's
//! start).

use super::{Classification, Label, LabelRun, Part, MIN_EDGE_FRAMES};

/// The parts of a classification's labels, each with what it taught.
pub(crate) fn parts(c: &Classification) -> Vec<Part> {
    let mut out: Vec<Part> = Vec::new();
    // Runs that take no side (outliers, still frames) wait for the next part of their segment.
    let mut pending: Option<LabelRun> = None;
    for r in &c.labels {
        let kind = match r.label {
            Label::Outlier | Label::Still | Label::Unlabelled => {
                pending = Some(match pending {
                    Some(p) if p.segment == r.segment => join(p, r),
                    _ => *r,
                });
                continue;
            }
            l => l,
        };
        let mut run = *r;
        if let Some(p) = pending.take() {
            if p.segment == r.segment {
                run = join(p, r);
                run.label = kind;
            } else {
                push_or_extend(&mut out, p);
            }
        }
        // A segment's later part measured from its own onset starts a part there.
        let onset = run
            .segment
            .and_then(|k| c.segments.get(k))
            .and_then(|s| s.onset_frame)
            .is_some_and(|i| run.first >= i && out.last().is_some_and(|l| l.last < i));
        match out.last_mut() {
            Some(last) if last.segment == run.segment && last.kind == kind && !onset => {
                extend(last, &run);
            }
            _ => out.push(new_part(&run, kind)),
        }
    }
    if let Some(p) = pending {
        push_or_extend(&mut out, p);
    }
    merge_short_interruptions(c, &mut out);
    mark_taught(c, &mut out);
    out
}

fn join(a: LabelRun, b: &LabelRun) -> LabelRun {
    LabelRun {
        last: b.last,
        t_end: b.t_end,
        frames: a.frames + b.frames,
        ..a
    }
}

fn new_part(r: &LabelRun, kind: Label) -> Part {
    Part {
        kind,
        t_start: r.t_start,
        t_end: r.t_end,
        first: r.first,
        last: r.last,
        frames: r.frames,
        segment: r.segment,
        taught: Vec::new(),
        withheld: None,
        com_estimate: None,
    }
}

fn extend(p: &mut Part, r: &LabelRun) {
    p.t_end = r.t_end;
    p.last = r.last;
    p.frames += r.frames;
}

/// Outliers or still frames with no part after them in their segment: they join the part
/// before (or stand as a part of their own label).
fn push_or_extend(out: &mut Vec<Part>, r: LabelRun) {
    match out.last_mut() {
        Some(last) if last.segment == r.segment => extend(last, &r),
        _ => out.push(new_part(&r, r.label)),
    }
}

/// A moving part shorter than [`MIN_EDGE_FRAMES`] between two parts of one kind in one segment
/// is an interruption of that part, not a part.
fn merge_short_interruptions(c: &Classification, out: &mut Vec<Part>) {
    let moving = |l: Label| l.vote().is_some();
    let onset_between = |a: &Part, n: &Part| {
        a.segment
            .and_then(|k| c.segments.get(k))
            .and_then(|s| s.onset_frame)
            .is_some_and(|i| a.last < i && i <= n.first)
    };
    // One pass (a removal in place is quadratic: 10⁶-pose files have 10⁵ parts).
    let input = std::mem::take(out);
    let mut i = 0;
    while i < input.len() {
        let b = &input[i];
        if let (Some(a), Some(n)) = (out.last_mut(), input.get(i + 1)) {
            if moving(b.kind)
                && (b.frames as f64) < MIN_EDGE_FRAMES
                && a.kind == n.kind
                && moving(a.kind)
                && a.segment == b.segment
                && b.segment == n.segment
                && !onset_between(a, n)
            {
                a.t_end = n.t_end;
                a.last = n.last;
                a.frames += b.frames + n.frames;
                i += 2;
                continue;
            }
        }
        out.push(b.clone());
        i += 1;
    }
}

/// Put each segment's features, and the faces rested on, on the parts that taught them.
fn mark_taught(c: &Classification, out: &mut [Part]) {
    for (k, s) in c.segments.iter().enumerate() {
        // A re-measured segment's feature comes from the first part of its kind from the
        // onset on.
        let from = s.onset_frame.unwrap_or(0);
        let of_kind = |out: &[Part], label: Label| {
            out.iter()
                .position(|p| p.segment == Some(k) && p.kind == label && p.first >= from)
        };
        if s.edge.is_some() {
            if let Some(j) = of_kind(out, Label::Topple) {
                out[j].taught.push("edge".into());
            }
        }
        if s.face.is_some() {
            if let Some(j) = of_kind(out, Label::Slide) {
                out[j].taught.push("face".into());
            }
        }
        for w in [&s.withheld, &s.withheld_before_onset]
            .into_iter()
            .flatten()
        {
            let label = if w.starts_with("face") {
                Label::Slide
            } else {
                Label::Topple
            };
            if let Some(p) = out
                .iter_mut()
                .find(|p| p.segment == Some(k) && p.kind == label && p.withheld.is_none())
            {
                p.withheld = Some(w.clone());
            }
        }
    }
    mark_rests(c, out);
}

/// Put on each rest what it taught (the face rested on) or why it taught nothing, from the
/// parts `out` as they are (again after flights are found: a landing follows one).
fn mark_rests(c: &Classification, out: &mut [Part]) {
    // Rest k is the one before segment k (the last: after the last segment); the rest after
    // segment s is the last part of s (rests inside a segment do not split it).
    let not_taught = c.resting_faces_not_taught_among(out);
    for j in 0..out.len() {
        let p = &out[j];
        if p.kind != Label::Rest {
            continue;
        }
        let last_of_segment = out.get(j + 1).is_none_or(|n| n.segment != p.segment);
        let k = match p.segment {
            None => 0,
            Some(s) if last_of_segment => s + 1,
            Some(_) => continue,
        };
        let p = &mut out[j];
        p.taught.retain(|t| t != RESTING_FACE);
        p.withheld = None;
        match not_taught.get(k) {
            Some(None) => p.taught.push(RESTING_FACE.into()),
            Some(Some(why)) => p.withheld = Some(why.clone()),
            None => {}
        }
    }
}

/// What a rest on the support teaches.
const RESTING_FACE: &str = "resting face";

impl Classification {
    /// Teach nothing: every edge, face and rest of the classification is withheld, for the
    /// reason given (which becomes a warning and [`Self::withheld`]); the labels and votes
    /// stay, and so do the parts once flights and rolls are marked in them (each part that
    /// taught something, measured a centre of mass or said why it taught nothing then gives
    /// this reason).
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
        for r in self.rolls.iter_mut().filter(|r| r.taught) {
            r.taught = false;
            r.support = None;
            r.withheld = Some(why.to_string());
        }
        self.paper_edge = None;
        self.withheld = Some(why.to_string());
        self.warnings
            .push(format!("{why}; nothing is learnt from it"));
        let marked = self
            .parts
            .iter()
            .any(|p| matches!(p.kind, Label::Flight | Label::Impact | Label::Roll));
        if !marked {
            self.fill_parts();
            return;
        }
        // The labels alone would give the parts back without the flights and rolls.
        for p in &mut self.parts {
            if !p.taught.is_empty() || p.com_estimate.is_some() || p.withheld.is_some() {
                p.taught.clear();
                p.withheld = Some(why.to_string());
            }
        }
    }

    /// Fill [`Self::parts`] from the labels and what the segments taught.
    pub fn fill_parts(&mut self) {
        self.parts = parts(self);
    }

    /// Say again on each rest of [`Self::parts`] what it taught, or why nothing, once the
    /// parts are final (flights split from the motions: a rest after one is a landing).
    pub(crate) fn mark_rests(&mut self) {
        let mut parts = std::mem::take(&mut self.parts);
        mark_rests(self, &mut parts);
        self.parts = parts;
    }
}
