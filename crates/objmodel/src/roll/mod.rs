//! Rolls: where an object turns about one of its edges in the middle of a motion (a tossed box
//! that lands on an edge and rolls over it onto a face), found and measured without a rest to
//! measure them from.
//!
//! A segment's edge is measured from the rest before the segment ([`crate::classify`]); a toss
//! has no such rest (it starts in the hand), and measured back from the rest after it, a roll's
//! edge is off by the 1-5 mm the box slides after the roll. A rotation about a fixed edge
//! needs no reference: between any two of its frames the relative motion is a rotation about
//! the same world line, and the edge is that line in the object frame ([`fit`]: a point and a
//! direction fixed in the object whose images stay fixed in the world, fitted to all the frames
//! at once, with its χ² under the noise model and its covariance).
//!
//! A roll is a window of frames, in a part that taught nothing and is not a flight or an impact
//! ([`mark_rolls`]), that:
//! 1. the fixed-line model explains: its end frames' screw does not advance along its axis
//!    (`no_pitch`, χ²₁ at the tests' `alpha`), the model passes χ² at [`ROLL_FIT_ALPHA`] while
//!    the window is grown, the window is cut where its line changes (`split_at_change`, χ²₉)
//!    and its end frames are dropped while the fit of the others rejects them (χ²₅ at
//!    `alpha`), it is cut to the frames that turn one way (`one_way`: a turn back is an
//!    impact) and to those whose turn a pendulum explains (`swing`: nothing but gravity turns
//!    an object about a fixed edge; a face that lands stops the turn at once), and it then
//!    passes χ² at `alpha` over at least [`MIN_ROLL_FRAMES`] frames;
//! 2. turns far enough about the line to locate it against the contact's own wander (as a
//!    topple must: `classify::parts::edge_turns_too_little`), about a line within
//!    `r_palm` of the object's origin (as a topple's edge must be: a hand swinging the object
//!    about its wrist turns it about a fixed line off the object);
//! 3. turns about a level line, when gravity is known (an edge rolled over lies in the face on
//!    the level support: `direction_off_level`, χ²₁ at `alpha`);
//! 4. the fall of a point of the object with gravity does not explain (χ² at `alpha`;
//!    `FlightTest::falls_at`, the flight model without its rotation test), or explains only
//!    with a point that the object cannot have: farther from its origin than a flight's centre
//!    of mass may be (`flight::MAX_COM_M`, beyond its σ), or other than the centre of mass the
//!    demonstration's flights determined (for a demonstration that flew, else the one the
//!    flights of the demonstrations learnt with it agree on: [`crate::shared_com`]). A spinning object in flight turns about a moving
//!    axis, which over a short window can pass for a fixed one; and a roll's frames pass for a
//!    flight of the point that accelerates with gravity, its centre of acceleration, about
//!    0.3 m from the edge. The flight's rotation test is not asked: a window whose translation
//!    a fall explains shows the roll's line too weakly to teach an edge, however it turned.
//!
//! Such a window is a `roll` part. It teaches its edge when the edge is located well enough to
//! be a feature: within 5 mm and 3° of its estimate but with probability `alpha`
//! ([`crate::edge::max_sigmas`]); when the turn does not go on about another line right after it
//! (`withhold_drifting`: a contact that slides or rolls); and, in a segment between two rests
//! that turned the object about the roll's line alone, when its edge lies on the support in
//! both rests (`parts::off_support`); otherwise the part says why it taught nothing.

mod fit;
mod parts;
mod record;
mod swing;

pub use fit::{fit, frame_chi2, RollFit, RollNoise};
pub use parts::mark_rolls;
pub use record::{RejectedRoll, Roll};

use crate::edge::EdgeObservation;
use crate::flight::{FlightFrame, FlightTest};
use crate::support::SupportObservation;
use nalgebra::Vector3;

/// Significance level at which the fixed-line model must explain a window while the window is
/// grown (the same reasoning as [`crate::flight::FLIGHT_FIT_ALPHA`]: the grown window ends
/// where the model only just passes; at 1% a slip at its end is cut sooner).
pub const ROLL_FIT_ALPHA: f64 = 0.01;

/// Fewest frames of a roll: the free-flight model, which a roll must reject (a spinning
/// object in flight turns about a moving axis that over a few frames passes for a fixed
/// one: on 500 simulated tosses a 3-frame "roll" in a flight taught an edge 50 mm off), is
/// testable from [`crate::flight::MIN_FLIGHT_FRAMES`] frames on.
pub const MIN_ROLL_FRAMES: usize = crate::flight::MIN_FLIGHT_FRAMES;

/// Most frames a roll's first window may need to turn far enough to locate its edge: a bound
/// on the search's work (a window is grown from every frame), not on the data: 256 frames are
/// a second at 250 Hz and 8 s at 30 Hz, far longer than a roll of a tossed object; a slower
/// rotation about an edge is a topple, measured from the rest before it.
pub const MAX_TURN_SEARCH_FRAMES: usize = 256;

/// What the finder needs besides the frames.
pub struct RollTest<'a> {
    /// The noise and the contact's tolerance.
    pub noise: RollNoise,
    /// Significance level of the tests.
    pub alpha: f64,
    /// Unit "down" in the world, when known.
    pub down: Option<Vector3<f64>>,
    /// The flight model, when gravity is known.
    pub flight: Option<&'a FlightTest>,
    /// How far \[m\] the contact may wander: it sets the turn a roll needs.
    pub tolerance_m: f64,
    /// The contact's depth \[m\] ([`crate::classify::RobustConfig::contact_depth_m`]).
    pub contact_depth_m: f64,
    /// Farthest \[m\] an edge of the object may lie from its origin
    /// ([`crate::classify::PaperThresholds::r_palm`], as for a topple's edge).
    pub r_max: f64,
    /// The object's centre of mass (object frame) and its covariance, when the
    /// demonstration's flights determined it, or, for a demonstration that flew, the flights
    /// of those learnt with it ([`crate::shared_com`]).
    pub com: Option<(Vector3<f64>, nalgebra::Matrix3<f64>)>,
}

/// A window of frames that the fixed-line model explains and that turned far enough, with
/// what the other tests said (`None`: it passed them all).
#[derive(Clone, Debug)]
pub struct Candidate {
    /// First frame (index in the slice).
    pub first: usize,
    /// Last frame.
    pub last: usize,
    /// The fit.
    pub fit: RollFit,
    /// Why it is not a roll, if it is not (such windows are not returned).
    pub rejected: Option<String>,
    /// Why it teaches nothing although it is a roll, if it does not.
    pub withheld: Option<String>,
    /// Whether it was rejected although it has enough frames and turned far enough (by its χ²
    /// at `alpha`, its line's place, level or the flight model), rather than for too few
    /// frames or too little turn: its frames are then not looked at again.
    pub physics: bool,
}

impl RollTest<'_> {
    fn passes(&self, f: &RollFit, alpha: f64) -> bool {
        f.dof >= 1.0 && f.chi2 <= crate::stats::chi2_threshold(f.dof, alpha)
    }

    /// The fit of `frames` if the model explains them at [`ROLL_FIT_ALPHA`].
    fn explains(&self, frames: &[FlightFrame]) -> Option<RollFit> {
        fit(frames, &self.noise).filter(|f| self.passes(f, ROLL_FIT_ALPHA.max(self.alpha)))
    }

    /// Whether the flight fitted to a window needs a centre of mass the object cannot have. A
    /// roll's frames pass the flight model over a short window with a point near its centre
    /// of acceleration (`flight::MAX_COM_M`: about 0.3 m from the edge in a fall), which is
    /// not the centre of mass. Ruled out: a point farther from the object's origin than a
    /// flight's centre of mass may be (the flight test's `r_max`) by more than its standard
    /// deviation along that distance times the normal quantile of `alpha` (one-sided); and,
    /// when the demonstration's flights determined the centre of mass, a point other than it
    /// (χ²₃ at `alpha` on their difference, under both covariances).
    fn com_rules_out(&self, f: &crate::flight::FlightFit) -> bool {
        let r = f.com.norm();
        let off_object = self.flight.is_some_and(|t| {
            let u = f.com / r.max(1e-12);
            let sigma = u.dot(&(f.com_cov * u)).max(0.0).sqrt();
            r - t.r_max > crate::stats::normal_quantile(1.0 - self.alpha) * sigma
        });
        off_object
            || self.com.is_some_and(|(c, cov)| {
                let d = f.com - c;
                (f.com_cov + cov).try_inverse().is_some_and(|w| {
                    d.dot(&(w * d)) > crate::stats::chi2_threshold(3.0, self.alpha)
                })
            })
    }

    /// The fit as the edge observation of demonstration `demo`, with the contact's wander
    /// (`tolerance_m`, a rounded edge, a soft contact that lets the pivot sink) as the least
    /// error of its point: one roll is one path of the contact, so that error is common to its
    /// frames and does not average down over them, as for a topple's edge
    /// (`classify::analysis`), and the contact's depth, common to every roll about the edge
    /// (along a direction normal to the line that is not known: a roll's faces are not). The
    /// fit's own χ² tests are the tracking noise's alone.
    pub fn edge(&self, fit: &RollFit, demo: &str) -> EdgeObservation {
        let mut e = fit.edge(demo);
        e.add_systematic_point_var(self.tolerance_m.powi(2));
        e.add_contact_depth_var(None, self.contact_depth_m.powi(2));
        e
    }

    /// The support's height a roll's fitted world line measures (its edge lies on the
    /// support), with the same least error as its edge ([`Self::edge`]); `down` is unit.
    pub fn support(&self, fit: &RollFit, down: &Vector3<f64>, demo: &str) -> SupportObservation {
        let p = fit.world_line.point;
        let var = down.dot(&(fit.world_point_cov * down)).max(0.0) + self.tolerance_m.powi(2);
        SupportObservation {
            demo: demo.to_string(),
            height: -down.dot(&p),
            sigma_m: var.sqrt(),
            across: p - down * down.dot(&p),
            from: "roll".to_string(),
        }
    }

    /// The smallest turn \[rad\] that locates an edge against the contact's wander.
    fn min_turn(&self) -> f64 {
        let s = (self.tolerance_m / (2.0 * crate::classify::parts::EDGE_LOCATION_M)).min(1.0);
        2.0 * s.asin()
    }
}

/// Whether the motion from frame `a` to frame `b` is a rotation without translation along its
/// axis, as a roll's is (Algorithm 1's pitch test, made statistical): the screw of
/// `world_from_object_b · world_from_object_a⁻¹` advances by `d = pitch · θ` along its axis,
/// which under the roll model is the two frames' noise only, of variance
/// `2 (σ_p² + σ_r² ρ²)` (ρ the object origin's distance from the axis, the lever arm of a
/// rotation error); `d²` over it is χ²₁, tested at `alpha`. A necessary condition of the
/// fixed-line model that costs one screw, tested before the model's fit (most windows of a
/// general motion fail it).
fn no_pitch(a: &FlightFrame, b: &FlightFrame, test: &RollTest) -> bool {
    let rel = fit::pose(b) * fit::pose(a).inverse();
    let Some(s) =
        crate::screw::Screw::from_twist(&crate::se3::Twist::log(&rel)).filter(|s| s.is_rotation())
    else {
        return false;
    };
    let u = s.direction.into_inner();
    let mut r = a.position - s.point;
    r -= u * u.dot(&r);
    let n = &test.noise.noise;
    let var = 2.0
        * (n.sigma_position.powi(2)
            + test.noise.tolerance_m.powi(2)
            + n.sigma_rotation.powi(2) * r.norm_squared());
    let d = s.pitch * s.magnitude;
    d * d <= var * crate::stats::chi2_threshold(1.0, test.alpha)
}

/// The angle \[rad\] between two frames' orientations.
fn angle_between(a: &FlightFrame, b: &FlightFrame) -> f64 {
    let c = ((b.rotation * a.rotation.transpose()).trace() - 1.0) * 0.5;
    c.clamp(-1.0, 1.0).acos()
}

/// The rolls in `frames` (time order, outliers removed), in order (see the module
/// documentation).
pub fn find_rolls(frames: &[FlightFrame], test: &RollTest) -> Vec<Candidate> {
    find_rolls_and_rejected(frames, test).0
}

/// The rolls in `frames` ([`find_rolls`]), and the windows about a level line (`off_level`)
/// rejected although they had enough frames and turned far enough (a [`Candidate`] whose
/// `physics` is set), in order: the turns a user may take for rolls. (Not those about a line
/// off level: an object spinning on the support or in the air turns about such a line.)
pub fn find_rolls_and_rejected(
    frames: &[FlightFrame],
    test: &RollTest,
) -> (Vec<Candidate>, Vec<Candidate>) {
    let min_frames = MIN_ROLL_FRAMES;
    let mut rejected = Vec::new();
    let min_turn = test.min_turn();
    let n = frames.len();
    let mut out = Vec::new();
    let mut i = 0;
    while i + min_frames <= n {
        // The first window from i that turns far enough.
        let limit = n.min(i + MAX_TURN_SEARCH_FRAMES);
        let Some(j) = (i + min_frames - 1..limit)
            .find(|&j| angle_between(&frames[i], &frames[j]) >= min_turn)
        else {
            i += 1;
            continue;
        };
        if !no_pitch(&frames[i], &frames[j], test) {
            i += 1;
            continue;
        }
        let Some(best) = test.explains(&frames[i..=j]) else {
            i += 1;
            continue;
        };
        let (end, best) = longest(frames, i, j + 1, best, test);
        let (first, end, best) = split_at_change(frames, i, end, best, test);
        let (first, end, fit) = trim(frames, first, end, best, test);
        let Some((first, end, fit)) = one_way(frames, first, end, fit, test) else {
            i += 1;
            continue;
        };
        let swing = swing::SwingTest {
            noise: &test.noise,
            alpha: test.alpha,
            min_frames,
        };
        let Some((first, end, fit)) = swing::swing_part(frames, first, end, fit, &swing) else {
            // No pendulum's turn from its start or to its end: it may hold one between an
            // impact before it and a landing after it, which a later start finds.
            i += 1;
            continue;
        };
        let c = judge(&frames[first..end], fit, test, min_turn);
        if c.rejected.is_some() {
            // A window rejected although it turned far enough over enough frames (not level,
            // a flight, ...) is not looked at again from a later start: its frames would have
            // as many more chances to pass.
            i = if c.physics { end } else { i + 1 };
            if c.physics && off_level(&c.fit, test).is_none() {
                rejected.push(Candidate {
                    first,
                    last: end - 1,
                    ..c
                });
            }
            continue;
        }
        out.push(Candidate {
            first,
            last: end - 1,
            ..c
        });
        i = end;
    }
    withhold_drifting(&mut out, test);
    (out, rejected)
}

/// Largest angle \[rad\] between the lines of two rolls, one right after the other and turning
/// the same way, that are taken for one turn whose line moved: half a box's right angle. A
/// tumble over the next edge of a box turns about a line parallel to the last (a face's width
/// away) or at right angles to it.
const ONE_TURN_RAD: f64 = std::f64::consts::FRAC_PI_4;

/// Whether two rolls turn the same way about lines less than [`ONE_TURN_RAD`] apart, in the
/// object frame. (It was parallel lines, within their σ at `alpha` or 3°: a pushed box in
/// Drake rolled on its side about a line that moved 10 mm and turned 3.3° between two windows
/// of one turn, σ 0.4° each, and both taught: an edge 20 mm off the box.)
fn same_turn(a: &RollFit, b: &RollFit) -> bool {
    let (ua, ub) = (a.object_line.direction, b.object_line.direction);
    let aligned = ua.dot(&ub) * a.turn.signum() * b.turn.signum() > 0.0;
    let angle = ua.cross(&ub).norm().atan2(ua.dot(&ub).abs());
    aligned && angle < ONE_TURN_RAD
}

/// How far \[m\] the second roll's line lies from the first's (in the object frame, normal to
/// the first), when that is more than their covariances and the contact's wander
/// (`tolerance_m`, for each) allow (χ²₂ at `alpha`); `None` when they may be one line (a roll
/// the change test cut where its contact wandered: on the standard set's rapier sessions,
/// three windows of one roll 1.2-1.5 mm apart at σ 1 mm).
fn line_moved(a: &RollFit, b: &RollFit, test: &RollTest) -> Option<f64> {
    let across =
        nalgebra::Matrix3x2::from_columns(&crate::geometry::normal_axes(&a.object_line.direction));
    let r = across.transpose() * (b.object_line.point - a.object_line.point);
    let wander = nalgebra::Matrix2::identity() * (2.0 * test.tolerance_m.powi(2));
    let s = across.transpose() * (a.point_cov + b.point_cov) * across + wander;
    let chi2 = s.try_inverse().map_or(f64::INFINITY, |w| r.dot(&(w * r)));
    (chi2 > crate::stats::chi2_threshold(2.0, test.alpha)).then(|| r.norm())
}

/// Rolls that follow each other without a frame between them (or one: a frame the cut between
/// them left out) and turn the same way ([`same_turn`]) about lines that are not one line
/// ([`line_moved`]) teach nothing: one turn whose line moved, where the change test cut it
/// ([`split_at_change`]). An object rolling over an
/// edge stops turning when its face lands, and tumbling on over the next edge its line jumps
/// by a face's width after the landing; a line that moves while the object turns on is a
/// contact that slides or rolls (on MuJoCo, a pushed box whose pivot slid along the table as
/// it fell turned about lines 25-47 mm below the table at 120 Hz, each window of its turn
/// passing the fixed-line model: `bench/mujoco_box_set.py`).
fn withhold_drifting(rolls: &mut [Candidate], test: &RollTest) {
    let drifting: Vec<(usize, f64)> = rolls
        .windows(2)
        .enumerate()
        .filter(|(_, w)| w[1].first <= w[0].last + 2)
        .filter(|(_, w)| same_turn(&w[0].fit, &w[1].fit))
        .filter_map(|(k, w)| Some((k, line_moved(&w[0].fit, &w[1].fit, test)?)))
        .collect();
    for (k, moved) in drifting {
        for r in &mut rolls[k..=k + 1] {
            r.withheld = Some(format!(
                "it turns on about a line {:.1} mm away, without a frame between: the \
                 line moved during one turn (a contact that slides or rolls), not an edge",
                moved * 1e3
            ));
        }
    }
}

/// The end (exclusive) of the longest window from `i`, at least to `end`, that the model
/// explains, and its fit: grown by doubling steps, then bisected.
fn longest(
    frames: &[FlightFrame],
    i: usize,
    end: usize,
    best: RollFit,
    test: &RollTest,
) -> (usize, RollFit) {
    crate::flight::grow_window(frames.len(), end, (end - i).max(2), best, |j| {
        test.explains(&frames[i..j])
    })
}

/// A window cut where the line changes: for every cut that leaves at least
/// [`MIN_SIDE_FRAMES`] frames on each side (every `stride`-th of them, at most
/// [`MAX_CUTS`]), the two sides are fitted apart, and `χ²_whole − χ²_before − χ²_after`, χ²₉
/// under one line (the second line's nine parameters), is compared with its quantile at
/// `alpha` over the number of cuts tried (Bonferroni). When the largest is significant, the
/// side that turned more is kept and tested again. A grown window is explained as a whole at
/// [`ROLL_FIT_ALPHA`], but the roll's frames and a slip or a bounce beside it may each fit
/// a line of their own, and the whole's χ² dilutes their difference.
fn split_at_change(
    frames: &[FlightFrame],
    mut start: usize,
    mut end: usize,
    mut best: RollFit,
    test: &RollTest,
) -> (usize, usize, RollFit) {
    loop {
        let n = end - start;
        if n < 2 * MIN_SIDE_FRAMES {
            break;
        }
        let cuts = n + 1 - 2 * MIN_SIDE_FRAMES;
        let stride = cuts.div_ceil(MAX_CUTS);
        let tried = cuts.div_ceil(stride);
        let limit = crate::stats::chi2_threshold(9.0, test.alpha / tried as f64);
        let mut top: Option<(f64, usize, RollFit, RollFit)> = None;
        for k in (start + MIN_SIDE_FRAMES..=end - MIN_SIDE_FRAMES).step_by(stride) {
            let (Some(a), Some(b)) = (
                fit(&frames[start..k], &test.noise),
                fit(&frames[k..end], &test.noise),
            ) else {
                continue;
            };
            let lr = best.chi2 - a.chi2 - b.chi2;
            if lr > limit && top.as_ref().is_none_or(|t| lr > t.0) {
                top = Some((lr, k, a, b));
            }
        }
        let Some((_, k, a, b)) = top else {
            break;
        };
        if a.turn.abs() >= b.turn.abs() {
            (end, best) = (k, a);
        } else {
            (start, best) = (k, b);
        }
    }
    (start, end, best)
}

/// Fewest frames on each side of a change-point cut: a line needs three frames to be tested
/// ([`crate::classify::MIN_EDGE_FRAMES`]).
const MIN_SIDE_FRAMES: usize = 3;

/// Most cuts a change-point scan fits (a bound on its work; the cuts are spread evenly).
const MAX_CUTS: usize = 32;

/// A window's ends trimmed: while its first (last) frame is not explained by the fit of the
/// others (χ²₅ at `alpha`), it is left out; a window grown to the longest the model explains
/// takes in frames of the slip or bounce around the roll whose deviations the whole window's
/// χ² dilutes.
fn trim(
    frames: &[FlightFrame],
    mut start: usize,
    mut end: usize,
    mut best: RollFit,
    test: &RollTest,
) -> (usize, usize, RollFit) {
    let limit = crate::stats::chi2_threshold(5.0, test.alpha);
    let min_frames = MIN_ROLL_FRAMES;
    while end - start > min_frames {
        let head = fit(&frames[start + 1..end], &test.noise);
        let tail = fit(&frames[start..end - 1], &test.noise);
        let bad_head = head.filter(|f| frame_chi2(f, &frames[start], &test.noise) > limit);
        let bad_tail = tail.filter(|f| frame_chi2(f, &frames[end - 1], &test.noise) > limit);
        match (bad_head, bad_tail) {
            (Some(f), _) => (start, best) = (start + 1, f),
            (None, Some(f)) => (end, best) = (end - 1, f),
            (None, None) => break,
        }
    }
    (start, end, best)
}

/// A window cut to where it turns one way. An object rolls over an edge one way, as gravity
/// turns it; a turn back is an impact: a box that rolls onto its face and bounces, or, on a
/// soft contact, sinks into the support and springs back about another line. Under tracking
/// noise the fixed-line model can take in such frames (on MuJoCo tosses at 0.4 mm, a roll
/// onto a face, its face 8 mm deep in the table and back, fitted one line 6.5 mm from the
/// edge at σ 0.5 mm).
///
/// The frames' angles `θ_k` about the fitted world line (from the first frame's orientation)
/// have the rotation noise of two frames, `2 σ_r²` per difference. Where the window's turn
/// runs from its smallest angle to its largest (in the direction it turned), a frame after
/// the last extreme, or before the first, that lies back from it by more than the χ²₁
/// quantile at `alpha` over the frames tested (Bonferroni) is a turn back: the window is cut
/// to the frames between the two extremes, and fitted again. Returns the window unchanged when
/// no frame turns back, and `None` when the part that turns one way is too short to fit
/// ([`MIN_ROLL_FRAMES`]).
fn one_way(
    frames: &[FlightFrame],
    start: usize,
    end: usize,
    fit: RollFit,
    test: &RollTest,
) -> Option<(usize, usize, RollFit)> {
    let theta = swing::angles_about(&frames[start..end], &fit.world_line.direction);
    let (mut lo, mut hi) = (0, 0);
    for (k, &a) in theta.iter().enumerate() {
        if a < theta[lo] {
            lo = k;
        }
        if a > theta[hi] {
            hi = k;
        }
    }
    let (a, b) = (lo.min(hi), lo.max(hi));
    let n = theta.len();
    let limit = (2.0
        * test.noise.noise.sigma_rotation.powi(2)
        * crate::stats::chi2_threshold(1.0, test.alpha / n as f64))
    .sqrt();
    let back = |k: usize, extreme: usize| (theta[k] - theta[extreme]).abs() > limit;
    let turns_back = (b + 1..n).any(|k| back(k, b)) || (0..a).any(|k| back(k, a));
    if !turns_back {
        return Some((start, end, fit));
    }
    if b + 1 - a < MIN_ROLL_FRAMES {
        return None;
    }
    let f = fit::fit(&frames[start + a..=start + b], &test.noise)?;
    Some((start + a, start + b + 1, f))
}

/// Why the world line of `fit` is not level, when gravity is known and it is not (an edge
/// rolled over on a level support is level: `classify::parts::direction_off_level`).
fn off_level(fit: &RollFit, test: &RollTest) -> Option<String> {
    test.down.and_then(|d| {
        crate::classify::parts::direction_off_level(
            &fit.world_line.direction,
            &fit.world_direction_cov,
            &d,
            test.alpha,
        )
    })
}

/// The tests after the model: the turn, the level line, the flight alternative, and whether the
/// edge is located well enough to be taught.
fn judge(frames: &[FlightFrame], fit: RollFit, test: &RollTest, min_turn: f64) -> Candidate {
    let mut c = Candidate {
        first: 0,
        last: 0,
        fit,
        rejected: None,
        withheld: None,
        physics: false,
    };
    let edge = test.edge(&fit, "");
    c.rejected = if fit.frames < MIN_ROLL_FRAMES || !test.passes(&fit, test.alpha) {
        Some("the fixed-line model does not explain it".into())
    } else if fit.object_line.point.norm() > test.r_max {
        Some(format!(
            "its line is {:.0} mm from the object's origin, farther than an edge of the object \
             may be ({:.0} mm)",
            fit.object_line.point.norm() * 1e3,
            test.r_max * 1e3
        ))
    } else if fit.turn.abs() < min_turn {
        crate::classify::parts::edge_turns_too_little(&edge, test.tolerance_m)
            .or_else(|| Some("it turns too little".into()))
    } else if let Some(w) = off_level(&fit, test) {
        Some(w)
    } else if test
        .flight
        .and_then(|f| f.falls_at(frames, test.alpha))
        .is_some_and(|f| !test.com_rules_out(&f))
    {
        Some("a point of the object falling freely explains it too".into())
    } else {
        None
    };
    c.physics = c.rejected.is_some() && fit.frames >= MIN_ROLL_FRAMES && fit.turn.abs() >= min_turn;
    c.withheld = crate::edge::unlocated(&edge, crate::edge::max_sigmas(test.alpha), "a roll");
    c
}

#[cfg(test)]
mod tests;
