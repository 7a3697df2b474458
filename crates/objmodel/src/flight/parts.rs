//! Flights and impacts in a classification's parts list: the flights of each motion segment's
//! kept frames split the parts that taught nothing (general motion, an untaught slide or
//! topple, frames not yet measurably moving); parts that taught a feature, rests, and a
//! completed topple's landing (the topple explains it: the box leaves its edge and falls; in
//! its last tens of milliseconds a fast fall about the edge has a point near the box that
//! falls with gravity) stay whole. Each flight is followed by its impact: the frames after its last one up to the next
//! flight, up to [`MAX_IMPACT_S`], and up to a part that stays whole.

use super::{
    find_flights, ComEstimate, FlightFrame, FlightTest, KnownCom, MAX_COM_M, MAX_IMPACT_S,
};
use crate::classify::{Classification, Config, Label, Part};
use crate::recording::{RecordedFrame, Recording};

impl FlightTest {
    /// The flight test of a classified demonstration: gravity from `config`, the noise `c`
    /// used (or the one given), the tests' `alpha`, and [`MAX_COM_M`]. `None` without gravity
    /// (`--gravity none`: no flight can be told from a motion), without a noise model, or
    /// relative to a palm (the support moves).
    pub(crate) fn of_demonstration(
        c: &crate::classify::Classification,
        config: &crate::classify::Config,
    ) -> Option<Self> {
        Self::of_world_poses(c, config).filter(|_| !c.instrumented)
    }

    /// [`Self::of_demonstration`] for the object's poses in the world whatever they are
    /// measured relative to (an instrumented demonstration's too: its noise, of the motion
    /// relative to the palm, holds the palm's, so it is at least the object's).
    pub(crate) fn of_world_poses(
        c: &crate::classify::Classification,
        config: &crate::classify::Config,
    ) -> Option<Self> {
        let (g, noise) = (config.gravity?, c.noise.or(config.robust.noise)?);
        (g.norm() > 0.0).then(|| {
            let gravity = g.normalize() * crate::pendulum::G;
            let test = Self::new(gravity, noise, config.robust.alpha, MAX_COM_M);
            match config.robust.com {
                Some(s) => test.with_known_com(KnownCom {
                    point: s.point,
                    covariance: s.covariance,
                    fall: gravity - s.gravity_error,
                }),
                None => test,
            }
        })
    }
}

/// A flight, an impact or a roll, by frame index in the object stream, and what it taught.
#[derive(Clone, Debug)]
pub(crate) struct Span {
    pub kind: Label,
    pub first: usize,
    pub last: usize,
    pub com: Option<ComEstimate>,
    pub taught: Vec<String>,
    pub withheld: Option<String>,
}

/// Find the flights of `c`'s motion segments in the kept frames and put them, with their
/// impacts, into `c.parts`. Nothing happens without gravity (`--gravity none`: no flight can
/// be told from a motion), without a noise model, or relative to a palm (the support moves).
pub fn mark_flights(c: &mut Classification, recording: &Recording, config: &Config) {
    let Some(test) = FlightTest::of_demonstration(c, config).filter(|_| !c.parts.is_empty()) else {
        return;
    };
    let outlier = c.is_outlier();
    // The runs of parts a flight may split (consecutive, in one segment), by frame index:
    // only their frames are scanned.
    let mut runs: Vec<(usize, usize)> = Vec::new();
    let mut run_segment = None;
    for p in c
        .parts
        .iter()
        .filter(|p| splittable(p) && p.segment.is_some())
    {
        match runs.last_mut() {
            Some(r) if run_segment == p.segment && r.1 + 1 == p.first => r.1 = p.last,
            _ => {
                runs.push((p.first, p.last));
                run_segment = p.segment;
            }
        }
    }
    let mut spans: Vec<Span> = Vec::new();
    for &(first, last) in &runs {
        let run = recording.objects_in(first, last);
        let kept: Vec<&RecordedFrame> = run.iter().filter(|f| !outlier(f.index)).collect();
        let frames: Vec<FlightFrame> = kept.iter().map(|&f| f.into()).collect();
        let flights = find_flights(&frames, &test);
        for (k, f) in flights.iter().enumerate() {
            spans.push(Span {
                kind: Label::Flight,
                first: kept[f.first].index as usize,
                last: kept[f.last].index as usize,
                com: f.fit.com_determined.then(|| ComEstimate {
                    point: f.fit.com,
                    covariance: f.fit.com_cov,
                    gravity_sensitivity: f.fit.com_gravity_sensitivity,
                    frames: f.last + 1 - f.first,
                }),
                taught: Vec::new(),
                withheld: None,
            });
            // The impact: the frames (outliers too: a bounce may look like one) from the one
            // after the flight to the next flight's start or the run's end, within
            // MAX_IMPACT_S of the flight's end.
            let end_t = kept[f.last].t + MAX_IMPACT_S;
            let (after, before) = (
                kept[f.last].index,
                flights.get(k + 1).map_or(u64::MAX, |n| kept[n.first].index),
            );
            let impact: Vec<&RecordedFrame> = run
                .iter()
                .filter(|x| x.index > after && x.index < before)
                .take_while(|x| x.t <= end_t)
                .collect();
            if let (Some(a), Some(b)) = (impact.first(), impact.last()) {
                spans.push(Span {
                    kind: Label::Impact,
                    first: a.index as usize,
                    last: b.index as usize,
                    com: None,
                    taught: Vec::new(),
                    withheld: None,
                });
            }
        }
    }
    c.flight_coms = spans.iter().filter_map(|s| s.com.clone()).collect();
    withhold_disagreeing_coms(&mut spans);
    split_parts(c, recording, &spans, splittable);
}

/// Level of the test of a flight's centre of mass against the other flights' of its
/// demonstration (the tree's other consistency checks' level).
pub const COM_AGREEMENT_ALPHA: f64 = 1e-4;

/// The flights of one demonstration measure one point of the object: each flight's centre of
/// mass is tested against the weighted mean of the others' (χ²₃ on the difference, with both
/// covariances, at [`COM_AGREEMENT_ALPHA`]), and a flight that fails reports none; nor does a
/// flight that no other confirms. A flight window that holds a short bounce can pass its own
/// χ² test with a wrong point absorbing the kink: on 200 motion-capture tosses
/// (`objmodel dataset --tosses 200`) the 69 flights' centres of mass were 3.3 σ off in the
/// median, 47 σ at the 90th percentile and 142 σ at worst, the worst flights of 15-37 frames.
/// With two flights that disagree neither can be blamed: both are withheld.
fn withhold_disagreeing_coms(spans: &mut [Span]) {
    let mut active: Vec<usize> = (0..spans.len())
        .filter(|&i| spans[i].com.is_some())
        .collect();
    let threshold = crate::stats::chi2_threshold(3.0, COM_AGREEMENT_ALPHA);
    let withhold = |s: &mut Span, why: String| {
        s.com = None;
        s.withheld = Some(format!("centre of mass not taught: {why}"));
    };
    // The worst flight goes first, then the test is repeated on the others.
    while active.len() >= 2 {
        let worst = active
            .iter()
            .filter_map(|&i| disagreement(spans, &active, i).map(|(c, d)| (i, c, d)))
            .max_by(|a, b| a.1.total_cmp(&b.1));
        let Some((i, chi2, dist)) = worst.filter(|w| w.1 > threshold) else {
            return;
        };
        let why = format!(
            "{:.0} mm from the other flights' (χ²₃ {chi2:.0}, beyond {threshold:.0}); a flight \
             that holds a bounce can pass for one with a wrong point",
            dist * 1e3
        );
        if active.len() == 2 {
            for &j in &active {
                withhold(&mut spans[j], why.clone());
            }
            return;
        }
        withhold(&mut spans[i], why);
        active.retain(|&j| j != i);
    }
    if let [i] = active[..] {
        withhold(
            &mut spans[i],
            "no other flight of the demonstration to check it against (a flight that holds a \
             bounce can pass for one with a wrong point)"
                .into(),
        );
    }
}

/// χ²₃ of flight `i`'s centre of mass against the weighted mean of the other `active` ones',
/// and their distance \[m\]; `None` where a covariance is singular.
fn disagreement(spans: &[Span], active: &[usize], i: usize) -> Option<(f64, f64)> {
    let (mut info, mut info_x) = (nalgebra::Matrix3::zeros(), nalgebra::Vector3::zeros());
    for &j in active.iter().filter(|&&j| j != i) {
        let e = spans[j].com.as_ref()?;
        let inv = e.covariance.try_inverse()?;
        info += inv;
        info_x += inv * e.point;
    }
    let others_cov = info.try_inverse()?;
    let e = spans[i].com.as_ref()?;
    let d = e.point - others_cov * info_x;
    let inv = (e.covariance + others_cov).try_inverse()?;
    Some((d.dot(&(inv * d)), d.norm()))
}

/// Put `spans` (in time order, each within a run of parts that `splittable` admits) into
/// `c.parts`, splitting the parts they fall in; parts `splittable` refuses stay whole.
pub(crate) fn split_parts(
    c: &mut Classification,
    recording: &Recording,
    spans: &[Span],
    splittable: impl Fn(&Part) -> bool,
) {
    if spans.is_empty() {
        return;
    }
    let time_of = |i: usize| {
        let k = recording.object.partition_point(|f| (f.index as usize) < i);
        recording.object.get(k).map(|f| f.t)
    };
    let time_before = |i: usize| {
        let k = recording
            .object
            .partition_point(|f| (f.index as usize) <= i);
        k.checked_sub(1).map(|k| recording.object[k].t)
    };
    let mut out: Vec<Part> = Vec::with_capacity(c.parts.len() + 2 * spans.len());
    let mut last_span: Option<usize> = None;
    for p in std::mem::take(&mut c.parts) {
        if !splittable(&p) {
            last_span = None;
            out.push(p);
            continue;
        }
        let mut cur = p.first;
        for (k, s) in spans
            .iter()
            .enumerate()
            .filter(|(_, s)| s.last >= p.first && s.first <= p.last)
        {
            let (a, b) = (s.first.max(p.first), s.last.min(p.last));
            if a > cur {
                let piece = (p.kind, cur, a - 1, None);
                push_piece(&mut out, &p, piece, None, false, &time_of, &time_before);
            }
            // A span cut by a part boundary continues the piece before.
            let join = last_span == Some(k) && out.last().is_some_and(|l| l.last + 1 == a);
            let piece = (s.kind, a, b, s.com.clone());
            push_piece(&mut out, &p, piece, Some(s), join, &time_of, &time_before);
            last_span = Some(k);
            cur = b + 1;
        }
        if cur <= p.last {
            let piece = (p.kind, cur, p.last, None);
            push_piece(&mut out, &p, piece, None, false, &time_of, &time_before);
            last_span = None;
        }
    }
    c.parts = out;
}

/// Whether a flight may split part `p`: it taught nothing, and it is not a rest or a
/// completed topple's landing.
fn splittable(p: &Part) -> bool {
    !matches!(p.kind, Label::Rest | Label::Landing) && p.taught.is_empty()
}

/// A piece of a part: its kind, first and last frame, and a flight's centre of mass.
type Piece = (Label, usize, usize, Option<ComEstimate>);

/// Append the piece `first..=last` of part `p` as a part of `kind` (of the span `span`, or a
/// remnant of `p`), or join it to the part before (`join`: the same span, cut by a part
/// boundary).
fn push_piece(
    out: &mut Vec<Part>,
    p: &Part,
    (kind, first, last, com): Piece,
    span: Option<&Span>,
    join: bool,
    time_of: &impl Fn(usize) -> Option<f64>,
    time_before: &impl Fn(usize) -> Option<f64>,
) {
    let t_start = if first == p.first {
        p.t_start
    } else {
        time_of(first).unwrap_or(p.t_start)
    };
    let t_end = if last == p.last {
        p.t_end
    } else {
        time_before(last).unwrap_or(p.t_end)
    };
    let frames = (last + 1 - first) as u64;
    if let Some(prev) = out.last_mut().filter(|_| join) {
        prev.last = last;
        prev.t_end = t_end;
        prev.frames += frames;
        return;
    }
    out.push(Part {
        kind,
        t_start,
        t_end,
        first,
        last,
        frames: frames.min(p.frames),
        segment: p.segment,
        taught: span.map(|s| s.taught.clone()).unwrap_or_default(),
        withheld: match span {
            Some(s) => s.withheld.clone(),
            None => p.withheld.clone(),
        },
        com_estimate: com,
    });
}

#[cfg(test)]
mod com_agreement_tests {
    use super::*;
    use nalgebra::{Matrix3, Vector3};

    fn flight(x: f64, sigma: f64) -> Span {
        Span {
            kind: Label::Flight,
            first: 0,
            last: 0,
            com: Some(ComEstimate {
                point: Vector3::new(x, 0.01, -0.02),
                covariance: Matrix3::identity() * sigma * sigma,
                gravity_sensitivity: Matrix3::zeros(),
                frames: 40,
            }),
            taught: Vec::new(),
            withheld: None,
        }
    }

    fn kept(spans: &[Span]) -> Vec<bool> {
        spans.iter().map(|s| s.com.is_some()).collect()
    }

    #[test]
    fn flights_that_agree_keep_their_centres_of_mass() {
        let mut s = vec![flight(0.010, 1e-3), flight(0.0115, 1e-3)];
        withhold_disagreeing_coms(&mut s);
        assert_eq!(kept(&s), [true, true]);
    }

    #[test]
    fn a_flight_the_others_contradict_is_withheld() {
        let mut s = vec![
            flight(0.010, 1e-3),
            flight(0.080, 2e-3),
            flight(0.0105, 1e-3),
        ];
        withhold_disagreeing_coms(&mut s);
        assert_eq!(kept(&s), [true, false, true]);
        assert!(s[1].withheld.as_ref().unwrap().contains("other flights"));
    }

    #[test]
    fn two_flights_that_disagree_are_both_withheld_and_a_lone_one_too() {
        let mut s = vec![flight(0.010, 1e-3), flight(0.030, 1e-3)];
        withhold_disagreeing_coms(&mut s);
        assert_eq!(kept(&s), [false, false]);
        let mut s = vec![flight(0.010, 1e-3)];
        withhold_disagreeing_coms(&mut s);
        assert_eq!(kept(&s), [false]);
        assert!(s[0].withheld.as_ref().unwrap().contains("no other flight"));
    }
}
