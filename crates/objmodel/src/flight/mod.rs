//! Flights and impacts: where a demonstration's object flies freely (its centre of mass falls
//! with gravity, whatever it spins) and where a flight breaks (the velocity jumps: an impact,
//! a bounce, a catch).
//!
//! A flight is a run of frames that the free-flight model ([`fit`]) explains at the tests'
//! significance `alpha`, whose rotation is torque-free ([`torque_free`]: its angular velocity
//! changes no faster than any rigid body's can without a torque), that the model without
//! acceleration does not (the fall shows above the noise: a rest, a constant-velocity carry or
//! a rotation about a fixed edge is not a flight), whose centre of mass lies within `r_max` of
//! the object's origin, and that has at least [`MIN_FLIGHT_FRAMES`] frames. Flights are found
//! on the kept frames ([`crate::recording`]) of the runs of parts a flight may split (see
//! [`mark_flights`]), after
//! the classification, never on the stream: a greedy scan from each frame, the window grown (doubling, then bisecting)
//! to the longest that the model explains, kept if it is a flight, else the scan moves on by
//! one frame.
//!
//! Where the centre of mass is known (the point that the flights of the demonstrations learnt
//! together agree on, [`crate::shared_com`], as `learn` observes a toss again with it), the
//! model is the fall of that point ([`FlightTest::with_known_com`], [`fit::fit_known`]): over
//! a few frames a flight's own point can take in frames that are no flight (a box that lands
//! on an edge and rolls over it), which the known point cannot, so the flight ends where the
//! roll starts and the roll can be found ([`crate::roll`]). A flight's reported centre of mass
//! is still its own frames' (fitted without the known point: a measurement of its own, for the
//! pooling).
//!
//! Flights and impacts teach no contact feature: they only split the parts that taught
//! nothing ([`mark`](parts::mark_flights)), and a flight reports its fitted centre of mass.

mod after_topple;
pub mod fit;
mod off_palm;
mod parts;
pub mod torque_free;

pub use after_topple::withhold_topples_that_fly;
pub use fit::{FlightFit, FlightFrame, KnownCom, FLIGHT_TOLERANCE_M};
pub use off_palm::withhold_after_leaving_the_palm;
pub use parts::mark_flights;
pub(crate) use parts::{split_parts, Span};

use crate::noise::NoiseModel;
use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

/// Fewest frames a flight must have. The model has 9 unknowns and 3 equations a frame, so 4
/// frames leave 3 residual degrees of freedom; 5 keep the fit over-determined (3 residual
/// degrees of freedom) with any one frame left out, so that one bad frame (a tag flip the
/// cleaner missed) cannot be absorbed by the unknowns and still pass.
pub const MIN_FLIGHT_FRAMES: usize = 5;

/// Significance level (at least) at which the flight model must explain a window: the scan
/// grows each window to the longest the model explains, so a window ends where the model
/// only just passes, and a motion that is not a flight (a topple's fall, whose centre of
/// acceleration falls with gravity for an instant) passes at the tests' 10⁻³ over windows
/// of tens of milliseconds; at 1% it does not, and a real flight loses at most a frame or
/// two at its ends, where its χ² rises steeply.
pub const FLIGHT_FIT_ALPHA: f64 = 0.01;

/// Longest impact \[s\]: the frames after a flight's last one, up to the next flight or contact
/// mode and at most this long, are its impact (a bounce or a landing takes a few
/// milliseconds; the rapier tosses' impacts, until the corners settle, at most 50 ms).
pub const MAX_IMPACT_S: f64 = 0.05;

/// Farthest \[m\] a flight's centre of mass may lie from the object's origin (the tag): an
/// object up to about 40 cm across. The bound matters: a rotation about an edge has, at each
/// instant, a point that accelerates with gravity (its centre of acceleration, `g / √(α² + ω⁴)`
/// from the edge: about 0.3 m in a topple's fall), and over a short window a point near it
/// passes for a falling centre of mass; the prior's scale and the noise of `R c` use it too.
pub const MAX_COM_M: f64 = 0.25;

/// The centre of mass a flight measured: the point of the object that fell with gravity.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ComEstimate {
    /// The point, object frame \[m\].
    pub point: Vector3<f64>,
    /// Its covariance \[m²\].
    pub covariance: Matrix3<f64>,
    /// How the point moves with the gravity it was measured under: `∂point/∂g` (see
    /// [`FlightFit::com_gravity_sensitivity`]).
    #[serde(default = "Matrix3::zeros")]
    pub gravity_sensitivity: Matrix3<f64>,
    /// Frames of the flight it was fitted to.
    pub frames: usize,
}

/// One flight in a slice of frames: `first..=last` index the slice.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Flight {
    /// Its first frame.
    pub first: usize,
    /// Its last frame.
    pub last: usize,
    /// The model fitted to its frames.
    pub fit: FlightFit,
}

/// What the finder needs besides the frames.
#[derive(Clone, Debug)]
pub struct FlightTest {
    /// Gravity, world frame \[m/s²\].
    pub gravity: Vector3<f64>,
    /// Tracking noise.
    pub noise: NoiseModel,
    /// Significance level of the χ² tests.
    pub alpha: f64,
    /// Farthest \[m\] the centre of mass may lie from the object's origin (and the prior's
    /// scale).
    pub r_max: f64,
    /// The centre of mass, where it is known ([`Self::with_known_com`]): a window is then a
    /// flight of that point.
    pub known_com: Option<KnownCom>,
    /// χ² quantiles computed so far, by (α's bits, degrees of freedom rounded to an integer):
    /// the scan tests thousands of windows of a few hundred distinct sizes.
    pub thresholds: std::cell::RefCell<std::collections::HashMap<(u64, u32), f64>>,
}

impl FlightTest {
    /// A test with these parameters.
    pub fn new(gravity: Vector3<f64>, noise: NoiseModel, alpha: f64, r_max: f64) -> Self {
        Self {
            gravity,
            noise,
            alpha,
            r_max,
            known_com: None,
            thresholds: Default::default(),
        }
    }

    /// This test with the centre of mass known: the flight model's point is then `known`'s,
    /// and its acceleration the one `known`'s flights fell with ([`fit::fit_known`]). A
    /// flight's reported centre of mass is still its own frames' ([`find_flights`]).
    pub fn with_known_com(mut self, known: KnownCom) -> Self {
        self.known_com = Some(known);
        self
    }

    /// The acceleration a flight's point falls with: gravity, or the known point's.
    fn fall(&self) -> Vector3<f64> {
        self.known_com.map_or(self.gravity, |k| k.fall)
    }

    /// The flight model fitted to `frames`: of any point of the object, or of the known one.
    fn fit(&self, frames: &[FlightFrame]) -> Option<FlightFit> {
        match &self.known_com {
            Some(k) => fit::fit_known(frames, k, &self.noise, self.r_max),
            None => fit::fit(frames, &self.gravity, &self.noise, self.r_max, false),
        }
    }

    /// The χ² quantile at `alpha` for `dof` degrees of freedom rounded to an integer (at
    /// least 1), computed once.
    fn threshold(&self, dof: f64, alpha: f64) -> f64 {
        let k = dof.round().max(1.0) as u32;
        *self
            .thresholds
            .borrow_mut()
            .entry((alpha.to_bits(), k))
            .or_insert_with(|| crate::stats::chi2_threshold(k as f64, alpha))
    }

    /// Whether a fit passes its χ² test at `alpha`.
    fn passes(&self, f: &FlightFit, alpha: f64) -> bool {
        f.chi2 <= self.threshold(f.dof, alpha)
    }

    /// Whether `frames` turn as a free body can ([`torque_free`]) at the significance level
    /// `alpha` (three pairs of thirds, each at `alpha / 3`). The rotation noise is floored
    /// ([`NoiseModel::floored`]): exact poses still sample a simulator's steps.
    fn turns_freely(&self, frames: &[FlightFrame], alpha: f64) -> bool {
        let chi2 = torque_free::torque_chi2(frames, self.noise.floored().sigma_rotation);
        chi2 <= self.threshold(3.0, alpha / 3.0)
    }

    /// The flight model's fit to `frames` if it explains them at the significance level
    /// `alpha`: the centre of mass falls with gravity and the rotation is torque-free.
    pub(crate) fn explains_at(&self, frames: &[FlightFrame], alpha: f64) -> Option<FlightFit> {
        self.falls_at(frames, alpha)
            .filter(|_| self.turns_freely(frames, alpha))
    }

    /// The fit of a point of the object (the known one, where it is known) falling with gravity
    /// to `frames` if it explains them at the significance level `alpha`, whatever the
    /// rotation: half of the flight model.
    /// A roll is tested against it (`roll::judge`): where the fall of a point explains a
    /// roll's frames, the roll's line is too weakly shown to teach an edge, even when the
    /// rotation says the object was not flying (with the whole flight model there, a Drake
    /// push at motion-capture noise taught two edges 7 mm off at σ 1 mm from two rolls in the
    /// fall of the pushed box).
    pub(crate) fn falls_at(&self, frames: &[FlightFrame], alpha: f64) -> Option<FlightFit> {
        self.fit(frames).filter(|f| self.passes(f, alpha))
    }

    /// Whether the flight model explains `frames`, at [`FLIGHT_FIT_ALPHA`] or the tests'
    /// level if larger.
    fn explains(&self, frames: &[FlightFrame]) -> Option<FlightFit> {
        self.explains_at(frames, self.alpha.max(FLIGHT_FIT_ALPHA))
    }

    /// Whether `frames`, which the model explains with `f`, are a flight: enough of them, the
    /// centre of mass on the object, and the model without acceleration (its point on the
    /// object too: [`fit::fit_on_object`]) rejected, both on its own (χ² at `alpha`) and
    /// against the flight's: its χ² exceeds the flight's by more than the χ²₃ quantile at
    /// `alpha` (the three components of the acceleration), so that a window the flight model
    /// explains only just, as the longest window the scan grows is, does not count because a
    /// no better model fails just as narrowly.
    fn is_flight(&self, frames: &[FlightFrame], f: &FlightFit) -> bool {
        frames.len() >= MIN_FLIGHT_FRAMES
            && f.com.norm() <= self.r_max
            && fit::fit_on_object(frames, &Vector3::zeros(), &self.noise, self.r_max).is_some_and(
                |z| {
                    !self.passes(&z, self.alpha)
                        && z.chi2 - f.chi2 > self.threshold(3.0, self.alpha)
                },
            )
    }
}

/// The flights in `frames` (time order, outliers removed), in order. From each frame, the
/// window is grown to the longest the model explains; if that is a flight, later starts within
/// its first half are tried too (its first frames may be the end of the throw, which fit the
/// parabola over a short window but break it over a long one), and the start whose window
/// reaches farthest is kept.
pub fn find_flights(frames: &[FlightFrame], test: &FlightTest) -> Vec<Flight> {
    let mut out = Vec::new();
    let n = frames.len();
    let mut i = 0;
    while i + MIN_FLIGHT_FRAMES <= n {
        let Some((mut end, mut best)) = longest(frames, i, MIN_FLIGHT_FRAMES, test) else {
            i += 1;
            continue;
        };
        if !test.is_flight(&frames[i..end], &best) {
            i += 1;
            continue;
        }
        let mut start = i;
        for s in i + 1..i + (end - i) / 2 {
            // Only a start whose window passes the current end can reach farther.
            if end >= n || test.explains(&frames[s..end + 1]).is_none() {
                continue;
            }
            if let Some((e, f)) = longest(frames, s, end + 1 - s, test) {
                if e > end && test.is_flight(&frames[s..e], &f) {
                    (start, end, best) = (s, e, f);
                }
            }
        }
        let (start, end, mut best) = trim(frames, start, end, best, test);
        // The final fit works out whether the flight determines its centre of mass.
        if let Some(f) = fit::fit(
            &frames[start..end],
            &test.gravity,
            &test.noise,
            test.r_max,
            true,
        ) {
            best = f;
        }
        out.push(Flight {
            first: start,
            last: end - 1,
            fit: best,
        });
        i = end;
    }
    out
}

/// A flight's ends trimmed: while its first (last) frame is not explained by the flight fitted
/// to the others (its residual's χ²₃ at `alpha`), it is left out. A window grown to the longest
/// the model explains may take in a few frames of the throw before it (or of the impact after
/// it) whose deviations, each clear alone, the χ² over the whole window dilutes.
fn trim(
    frames: &[FlightFrame],
    mut start: usize,
    mut end: usize,
    mut best: FlightFit,
    test: &FlightTest,
) -> (usize, usize, FlightFit) {
    let limit = test.threshold(3.0, test.alpha);
    while end - start > MIN_FLIGHT_FRAMES {
        let (head, tail) = (
            test.fit(&frames[start + 1..end]),
            test.fit(&frames[start..end - 1]),
        );
        let g = test.fall();
        let bad_head = head.filter(|f| fit::frame_chi2(f, &frames[start], &g, &test.noise) > limit);
        let bad_tail =
            tail.filter(|f| fit::frame_chi2(f, &frames[end - 1], &g, &test.noise) > limit);
        match (bad_head, bad_tail) {
            (Some(f), _) => (start, best) = (start + 1, f),
            (None, Some(f)) => (end, best) = (end - 1, f),
            (None, None) => break,
        }
    }
    (start, end, best)
}

/// The end (exclusive) of the longest window from `i` of at least `len` frames that the
/// flight model explains, and its fit: the window doubled while it passes, then bisected.
fn longest(
    frames: &[FlightFrame],
    i: usize,
    len: usize,
    test: &FlightTest,
) -> Option<(usize, FlightFit)> {
    let best = test.explains(&frames[i..i + len])?;
    Some(grow_window(
        frames.len(),
        i + len,
        len.max(MIN_FLIGHT_FRAMES),
        best,
        |j| test.explains(&frames[i..j]),
    ))
}

/// The largest end `good..=n` that `explains` accepts, and its value, from an accepted end
/// `good` (`best` its value): the end advanced by steps that double from `step` while it is
/// accepted, then bisected between the last accepted and the first rejected. Shared by the
/// flights' and the rolls' window scans.
pub(crate) fn grow_window<T>(
    n: usize,
    mut good: usize,
    mut step: usize,
    mut best: T,
    explains: impl Fn(usize) -> Option<T>,
) -> (usize, T) {
    let mut bad = None;
    while good < n {
        let j = (good + step).min(n);
        match explains(j) {
            Some(f) => {
                (good, best) = (j, f);
                step *= 2;
            }
            None => {
                bad = Some(j);
                break;
            }
        }
    }
    if let Some(mut hi) = bad {
        while hi - good > 1 {
            let mid = (good + hi) / 2;
            match explains(mid) {
                Some(f) => (good, best) = (mid, f),
                None => hi = mid,
            }
        }
    }
    (good, best)
}

#[cfg(test)]
mod tests;
