//! A 7-DoF arm (a Franka Emika Panda) with a flat palm: its URDF, kinematics, inverse
//! kinematics, palm paths turned into joint trajectories, and its simulation in rapier.
//!
//! * [`Arm`]: loads a URDF ([`Arm::panda`] for the shipped `assets/panda_palm.urdf`), forward
//!   kinematics `base_from_palm` ([`Arm::fk`]), the geometric Jacobian, manipulability, and
//!   damped-least-squares inverse kinematics with joint limits as hard bounds and a null-space
//!   term that keeps the arm away from its limits and from singularities ([`Arm::ik`]).
//! * [`JointTrajectory`]: a palm path (waypoints, or a function of time) turned into a
//!   continuous, velocity-limited joint trajectory ([`Arm::plan_palm_path`],
//!   [`Arm::plan_palm_motion`]).
//! * [`ArmSim`]: the arm as a rapier multibody (revolute joints with position motors) in a world
//!   tuned like [`crate::world`], with boxes that ride on the palm through contact and friction.
//!
//! Frames: `base` (the arm's `panda_link0`), `palm` (origin on the middle of the palm's top
//! surface, `z` its outward normal), `world` (the simulation, `z` up). [`Arm::fk`] gives
//! `base_from_palm`; [`ArmSim::palm_pose`] gives `world_from_palm`.
//!
//! Measured (`cargo test -p objmodel-sim --test arm -- --nocapture`, and the example
//! `arm_tilt`): forward kinematics equals the textbook DH product of Franka's table to 1e-12;
//! IK round trips land within 1e-9 m / 1e-9 rad (seeds within 0.3 rad: 150/150; from the palm-up
//! pose with restarts: 40/40 random reachable poses), ~2 ms per solve; a 20° palm tilt over 4 s
//! with a 0.6 kg box on the palm is tracked within 0.073 mm and 0.022° (mostly the static sag
//! under the uncompensated box; without gravity compensation 0.62 mm and 0.13°); a box on the
//! level palm drifts 4 nm in 3 s; a 0.1 x 0.1 x 0.2 m box topples at a palm tilt 0.098° past
//! φ when tilted at 1°/s, as on the kinematic plate of the instrumented scene; the simulation
//! runs at 16-19 simulated s per wall s (release, one thread; rapier's multibody mass matrix
//! dominates).
//!
//! Kinematics come from the `k` crate reading the same URDF as the simulation; `k` uses an older
//! nalgebra than this workspace, and [`kin`] is the only module that touches its types. The IK
//! iteration is written here (on `k`'s forward kinematics and Jacobian) because `k`'s
//! `JacobianIkSolver` clamps joints after each step without removing them from the solve
//! (it stalls at limits), uses an undamped pseudo-inverse (large steps near singularities) and
//! takes a null-space term only as a fixed function of the joint positions.

mod ik;
pub mod kin;
mod model;
mod path;
mod sim;

pub use ik::{Arm, IkOptions, IkSolution};
pub use model::{ArmModel, BodySpec, CollisionShape, InertialSpec, JointSpec, ShapeKind};
pub use path::{JointTrajectory, PlanOptions};
pub use sim::{ArmSim, ArmSimOptions, TrackingError};

/// The shipped URDF: a Franka Emika Panda with a 0.20 x 0.20 x 0.01 m palm at its flange
/// (`assets/panda_palm.urdf` at the repository root, embedded at build time).
pub const PANDA_PALM_URDF: &str = include_str!("../../../../assets/panda_palm.urdf");

/// Path of the shipped URDF in the source tree.
pub const PANDA_PALM_URDF_PATH: &str =
    concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/panda_palm.urdf");

/// Name of the tracked palm link in the shipped URDF.
pub const PALM_LINK: &str = "palm";

/// The Panda's joint acceleration limits \[rad/s²\] (Franka Control Interface documentation,
/// "Limits for Panda"; URDF has no element for them).
pub const PANDA_ACCEL_LIMITS: [f64; 7] = [15.0, 7.5, 10.0, 12.5, 15.0, 20.0, 20.0];

/// The Panda's "ready" pose \[rad\] (Franka's and MoveIt's default start configuration): the flange
/// points down in front of the robot.
pub const PANDA_READY: [f64; 7] = [
    0.0,
    -std::f64::consts::FRAC_PI_4,
    0.0,
    -3.0 * std::f64::consts::FRAC_PI_4,
    0.0,
    std::f64::consts::FRAC_PI_2,
    std::f64::consts::FRAC_PI_4,
];

/// A configuration with the palm level and facing up (palm frame axes along the base's),
/// its origin at `(0.45, 0, 0.35)` m in the base frame, every joint at least 20% of its range
/// from its limits, manipulability 0.059. From it the planner tilts the palm by 45° about any
/// horizontal axis through a point near its middle. Found by IK from random seeds (the Panda's
/// joint 6 range keeps the simple planar "elbow up, wrist flipped" poses out of reach: those put
/// the palm either below 0.15 m or behind the base).
pub const PANDA_PALM_UP: [f64; 7] = [
    -1.273989, 0.952367, 1.089808, -2.395397, 1.731063, 0.820842, -0.901842,
];

/// Where [`PANDA_PALM_UP`] puts the palm origin in the base frame \[m\].
pub const PANDA_PALM_UP_POSITION: [f64; 3] = [0.45, 0.0, 0.35];

/// Errors of the arm.
#[derive(Debug, thiserror::Error)]
pub enum ArmError {
    /// The URDF could not be read or parsed.
    #[error("URDF: {0}")]
    Urdf(String),
    /// The URDF parsed but does not describe a serial arm this module can use.
    #[error("arm model: {0}")]
    Model(String),
    /// A joint vector has the wrong length or a non-finite entry.
    #[error("joint vector: {0}")]
    BadJoints(String),
    /// Inverse kinematics did not reach the target.
    #[error(
        "IK did not converge after {iterations} iterations: position error {position_error:.3e} m, \
         rotation error {rotation_error:.3e} rad (target out of reach, beyond the joint limits, or \
         the seed is too far)"
    )]
    NoConvergence {
        /// Iterations run.
        iterations: usize,
        /// Remaining position error \[m\].
        position_error: f64,
        /// Remaining rotation error \[rad\].
        rotation_error: f64,
    },
    /// A palm path needs a joint faster than its limit.
    #[error(
        "joint {joint} would move at {speed:.3} rad/s at t = {time:.3} s, above its limit of \
         {limit:.3} rad/s (x {fraction}): slow the palm motion down by {factor:.2}x"
    )]
    VelocityLimit {
        /// Joint index (0-based).
        joint: usize,
        /// Time along the path \[s\].
        time: f64,
        /// Required speed \[rad/s\].
        speed: f64,
        /// Allowed speed \[rad/s\] (the URDF limit times the planner's fraction).
        limit: f64,
        /// The fraction of the URDF limit the planner allows.
        fraction: f64,
        /// How much longer the motion must take.
        factor: f64,
    },
    /// A palm path passes too close to a singularity.
    #[error("palm path passes near a singularity at t = {time:.3} s (manipulability {manipulability:.2e} < {threshold:.2e})")]
    Singular {
        /// Time along the path \[s\].
        time: f64,
        /// Manipulability there.
        manipulability: f64,
        /// The planner's threshold.
        threshold: f64,
    },
    /// Bad arguments (empty path, non-positive time step, ...).
    #[error("{0}")]
    Invalid(String),
}

/// Result with [`ArmError`].
pub type Result<T> = std::result::Result<T, ArmError>;
