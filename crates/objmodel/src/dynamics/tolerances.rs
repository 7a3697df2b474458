//! The windows and tolerances of the dynamics' fits, and the χ² test a fit must pass to
//! teach a φ.

use crate::pendulum;

/// Largest relative rotation \[rad\] (15°) kept in the onset window: enough of the start of the
/// topple to fix the change-point model, before the fall stops being polynomial.
pub const ONSET_WINDOW_RAD: f64 = 0.26;
/// Time \[s\] after the palm starts to tilt before the object's angle relative to it is taken
/// as steady in the onset window: a compliant contact (or a latency between the palm's tracker
/// and the object's) makes the object lag the palm's start by a step, which settles within
/// about 20 ms on MuJoCo's soft contact.
pub const PALM_SETTLE_S: f64 = 0.1;
/// Least change of the palm's tilt \[rad\] (0.2°) taken as its start, however small its noise.
pub const PALM_START_RAD: f64 = 0.003_490_658_503_988_659;
/// Fewest samples of each phase (the rest, the steady tilt before the onset) that the onset
/// window keeps.
pub const MIN_ONSET_FRAMES: usize = 5;
/// Rest before the first moving frame \[s\] included in the onset window.
pub const ONSET_REST_S: f64 = 2.0;
/// Relative rotation \[rad\] (8.6°) up to which the pendulum-on-palm model is fitted (the palm
/// may move fast after that, and the object may leave its edge).
pub const SUPPORT_FIT_RAD: f64 = 0.15;
/// Model tolerance \[rad\] of the pendulum (0.1°), added in quadrature to the tracking noise when
/// fitting a fall: contacts are compliant and edges not perfectly sharp, so a real fall
/// departs from the ideal pendulum by about this much.
pub const PENDULUM_TOLERANCE_RAD: f64 = 0.001_745_329_251_994_329_5;
/// Frames within this angle \[rad\] (2°) of where the object comes to rest are the landing, not
/// the fall.
pub const LANDING_RAD: f64 = 0.034_906_585_039_886_59;
/// Rest frames closer than this \[s\] to the first moving frame are not used as the reference.
pub const REST_MARGIN_S: f64 = 0.3;
/// At most this many rest frames are averaged for the reference.
pub const MAX_REST_FRAMES: usize = 60;
/// Half-width \[s\] of the local linear smoothing of the palm tilt.
pub const SMOOTH_S: f64 = 0.25;
/// Standard deviation \[rad\] of φ uniform on its admissible range (0, π/2) for an object
/// resting on a face: `π / (2√12)` ≈ 0.45 rad. A model fit whose φ is less certain than that
/// tells less than the bounds themselves (a fall of a few frames leaves φ and `k` trading off
/// against the unknown start state); its φ is not used.
pub const PHI_PRIOR_SIGMA_RAD: f64 = std::f64::consts::FRAC_PI_2 / 3.464_101_615_137_754_6;

/// Whether a pendulum fit with `params` parameters explains its frames within the noise: its
/// χ² passes at the 1% level (a fall or an onset that is not a free pendulum teaches no φ).
pub(super) fn passes_with(f: &pendulum::FallFit, params: usize) -> bool {
    let dof = f.frames as f64 - params as f64;
    dof > 0.0 && f.chi2_per_dof <= crate::stats::chi2_threshold(dof, 0.01) / dof
}
