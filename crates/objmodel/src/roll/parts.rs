//! Rolls in a classification: found in the kept frames of each run of parts that taught
//! nothing (not rests, landings, flights or impacts), put into `c.rolls` and, as `roll` parts,
//! into `c.parts`; the turns that looked like rolls and were not, into `c.rolls_rejected`.

use super::{find_rolls_and_rejected, RejectedRoll, Roll, RollNoise, RollTest};
use crate::classify::{Classification, Config, Label, Part};
use crate::flight::{FlightFrame, FlightTest, Span, MAX_COM_M};
use crate::recording::{RecordedFrame, Recording};
use nalgebra::{Matrix3, Vector3};

/// Whether a part's frames may hold a roll: it taught nothing and is a motion that no other
/// model explains (not a rest, a completed topple's landing, a flight or an impact), nor an
/// edge rotation whose line the rests showed to be off the support
/// ([`crate::classify::OFF_SUPPORT`]) or off level ([`crate::classify::OFF_LEVEL`]).
fn scanned(p: &Part) -> bool {
    !matches!(
        p.kind,
        Label::Rest | Label::Landing | Label::Flight | Label::Impact | Label::Roll
    ) && p.taught.is_empty()
        && p.segment.is_some()
        && p.withheld.as_ref().is_none_or(|w| {
            !w.contains(crate::classify::OFF_SUPPORT) && !w.contains(crate::classify::OFF_LEVEL)
        })
}

/// Find the rolls of `c`'s motions in the kept frames ([`super::find_rolls`]) and put them
/// into `c.rolls` and `c.parts`. Nothing happens without a noise model, without gravity (a
/// spinning object in flight turns about an axis that over a few frames passes for a fixed
/// line, and only the flight model, which needs gravity's direction, tells it from a roll:
/// with `--gravity none`, 144 of 183 edges learnt from MuJoCo tosses were off the box),
/// relative to a palm (the support moves with it), or when the kept frames are thinned (a
/// roll lasts a few tens of frames).
pub fn mark_rolls(c: &mut Classification, recording: &Recording, config: &Config) {
    let Some(noise) = c.noise.or(config.robust.noise) else {
        return;
    };
    let Some(down) = config.gravity.and_then(|g| g.try_normalize(1e-12)) else {
        return;
    };
    if c.instrumented || c.parts.is_empty() || recording.object_stride > 1 {
        return;
    }
    let robust = &config.robust;
    let flight = FlightTest::new(down * crate::pendulum::G, noise, robust.alpha, MAX_COM_M);
    // The χ² is the tracking noise's alone: a contact's own wander is what the turn a roll
    // needs covers (`tolerance_m` below). Added per frame to the noise, the wander hid a box
    // pivoting on a vertex and a slipping edge: on 500 simulated tosses at motion-capture
    // noise, with the classifier's 0.3 mm and 0.5° added, seven rolls taught edges 6-17 mm or
    // 3-45° off; without them, none (and 24 of 47 measurable rolls were found).
    let test = RollTest {
        noise: RollNoise {
            noise,
            tolerance_m: 0.0,
            tolerance_rad: 0.0,
        },
        alpha: robust.alpha,
        down: Some(down),
        flight: Some(&flight),
        tolerance_m: robust.edge_tolerance_m,
        contact_depth_m: robust.contact_depth_m,
        r_max: config.paper.r_palm,
        com: known_com(&c.parts).or_else(|| com_learnt_together(c, config)),
    };
    let outlier = c.is_outlier();
    let mut runs: Vec<(usize, usize, Option<usize>)> = Vec::new();
    for p in c.parts.iter().filter(|p| scanned(p)) {
        match runs.last_mut() {
            Some(r) if r.2 == p.segment && r.1 + 1 == p.first => r.1 = p.last,
            _ => runs.push((p.first, p.last, p.segment)),
        }
    }
    let mut spans: Vec<Span> = Vec::new();
    for &(first, last, segment) in &runs {
        let rests = segment
            .and_then(|s| c.segments.get(s))
            .and_then(crate::classify::parts::RestPair::of_segment);
        let kept: Vec<&RecordedFrame> = recording
            .objects_in(first, last)
            .iter()
            .filter(|f| !outlier(f.index))
            .collect();
        let frames: Vec<FlightFrame> = kept.iter().map(|&f| f.into()).collect();
        let (rolls, rejected) = find_rolls_and_rejected(&frames, &test);
        c.rolls_rejected
            .extend(rejected.into_iter().map(|r| RejectedRoll {
                t_start: kept[r.first].t,
                t_end: kept[r.last].t,
                frames: r.last + 1 - r.first,
                turn: r.fit.turn.abs(),
                why: r.rejected.unwrap_or_default(),
            }));
        for mut r in rolls {
            let (a, b) = (kept[r.first], kept[r.last]);
            // Said with any other reason the roll has (its line moved, it is located too
            // poorly): off the support, it is no edge, however well located.
            let off = rests.as_ref().and_then(|rests| {
                off_support(
                    &test.edge(&r.fit, &c.name),
                    &r.fit,
                    rests,
                    &down,
                    noise,
                    robust,
                )
            });
            r.withheld = match (off, r.withheld.take()) {
                (Some(off), Some(other)) => Some(format!("{other}; and {off}")),
                (off, other) => off.or(other),
            };
            let taught = r.withheld.is_none();
            // A taught roll's edge lies on the support: its world line's height is the
            // support's.
            let support = taught.then(|| test.support(&r.fit, &down, &c.name));
            c.rolls.push(Roll {
                first: a.index as usize,
                last: b.index as usize,
                t_start: a.t,
                t_end: b.t,
                edge: test.edge(&r.fit, &c.name),
                turn: r.fit.turn.abs(),
                chi2: r.fit.chi2,
                dof: r.fit.dof,
                taught,
                withheld: r.withheld.clone(),
                support,
            });
            spans.push(Span {
                kind: Label::Roll,
                first: a.index as usize,
                last: b.index as usize,
                com: None,
                taught: if taught {
                    vec!["edge".to_string()]
                } else {
                    Vec::new()
                },
                withheld: r.withheld,
            });
        }
    }
    crate::flight::split_parts(c, recording, &spans, scanned);
}

/// Why a roll's edge is no edge, when its segment turned the object from one rest to the
/// other about the roll's line, up to a turn about the vertical: then the roll was that
/// topple's fall, and its edge lies on the support in both rests
/// ([`crate::classify::parts::edge_on_support`]). A pushed box whose pivot slides as it falls
/// turns about a line below the table, which the roll's own tests pass: on MuJoCo at exact
/// poses, 26-30 mm off the box at 18-28 σ (`bench/mujoco_box_set.py`). The segment turned so
/// when the down direction of each rest, in the object frame, is square to the roll's edge
/// (within [`crate::edge::EDGE_MATCH_RAD`]) and the two are at least the roll's turn apart: a
/// turn about the vertical (the object spun or was pushed round on the support) moves no
/// edge's height. (Asked of the rests' whole rotation, a Drake push that turned its box 90°
/// about its edge and 10° about the vertical went untested, and its roll taught an edge 7.3 mm
/// off at σ 1.1 mm.) Not tested where a rest's down is not square to the edge (the object
/// rolled over other edges too).
fn off_support(
    edge: &crate::edge::EdgeObservation,
    fit: &super::RollFit,
    rests: &crate::classify::parts::RestPair,
    down: &Vector3<f64>,
    noise: crate::noise::NoiseModel,
    robust: &crate::classify::RobustConfig,
) -> Option<String> {
    let edge_direction = fit.object_line.direction;
    let (before, after) = (
        rests.r_before.inverse() * down,
        rests.r_after.inverse() * down,
    );
    let square = |d: &Vector3<f64>| {
        d.dot(&edge_direction).abs() <= crate::edge::EDGE_MATCH_RAD.sin() * d.norm()
    };
    if !(square(&before) && square(&after)) || before.angle(&after) < fit.turn.abs() {
        return None;
    }
    crate::classify::parts::edge_on_support(
        edge,
        rests,
        &-down,
        &noise,
        robust.edge_tolerance_m,
        robust.alpha,
    )
    .err()
}

/// The centre of mass that the flights of the demonstrations learnt with `c` measured together
/// (`config.robust.com`, [`crate::shared_com`]), where `c` has a flight: a thrown object's
/// roll is told from its flight by it. A demonstration without a flight keeps the fall of any
/// point as the roll's alternative (a finger that drives a fall about an edge is not a flight,
/// and the point that explains it need not be the centre of mass).
fn com_learnt_together(
    c: &Classification,
    config: &Config,
) -> Option<(Vector3<f64>, Matrix3<f64>)> {
    let s = config.robust.com.filter(|_| c.flew())?;
    Some((s.point, s.covariance))
}

/// The centre of mass that the flights among `parts` determined (their estimates fused by
/// their information), if any did.
fn known_com(parts: &[Part]) -> Option<(Vector3<f64>, Matrix3<f64>)> {
    let (mut info, mut sum) = (Matrix3::zeros(), Vector3::zeros());
    for e in parts.iter().filter_map(|p| p.com_estimate.as_ref()) {
        let Some(w) = e.covariance.try_inverse() else {
            continue;
        };
        info += w;
        sum += w * e.point;
    }
    let cov = info.try_inverse()?;
    Some((cov * sum, cov))
}
