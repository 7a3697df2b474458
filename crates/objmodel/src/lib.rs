//! # objmodel
//!
//! Learn *object description trees* from 6D pose demonstrations, after Sanan, Bretan & Heck,
//! "Learning Object Models for Non-prehensile Manipulation" (IROS 2019).
//!
//! Data flows one way, and each stage has a module named after the paper's concept:
//!
//! ```text
//! file ─format─▶ trajectory ─clean─▶ screws (se3, screw) ─classify─▶ labels
//!      ─edge / face─▶ features ─tree─▶ object description tree ─▶ skill
//! ```
//!
//! * [`se3`]: exact exponential and logarithm of SE(3) and SO(3), twists.
//! * [`screw`]: screw parameters of a twist (paper eq. 1-3) and the plane normal (eq. 5).
//! * [`format`](mod@format): TUM and CSV pose files, with errors that name file, line and problem.
//! * [`trajectory`]: time-stamped poses, demonstrations (optionally with a palm).
//! * [`clean`]: quaternion sign continuity and rejection of single-frame tag flips.
//! * [`noise`]: tracking-noise estimation from the data itself.
//! * [`numeric`]: small numeric kernels of the per-frame loops (a first-quadrant `atan2`).
//! * [`lanes`]: four `f64` lanes for the kernels that take frames four at a time.
//! * [`stats`]: the few distributions the tests need (chi-square quantiles).
//! * [`classify`]: Algorithm 1, the paper-literal version and the robust one.
//! * [`edge`], [`face`]: Algorithm 2 and eq. 5 estimates with covariances.
//! * [`recording`]: the frames the dynamics need, kept in bounded memory during the one pass.
//! * [`dynamics`], [`pendulum`]: each topple's angles, onset, φ and pendulum fit.
//! * [`observation`]: what one demonstration shows (classification and dynamics).
//! * [`tree`]: the object description tree, its JSON schema and incremental fusion.
//! * [`learn`]: **the learning pipeline**, the one entry point every front end calls.
//! * [`args`]: values given on the command line as text (a pose, gravity, a vector).
//! * [`synth`]: a small kinematic generator of demonstrations with exact ground truth.
//!
//! Units are SI throughout (m, rad, s, kg). Transforms are named by frames: `world_from_object`
//! maps a point in object coordinates to world coordinates.

#![warn(missing_docs)]

pub mod args;
pub mod classify;
pub mod clean;
pub mod dynamics;
pub mod edge;
pub mod error;
pub mod face;
pub mod format;
pub mod geometry;
pub mod lanes;
pub mod learn;
pub mod noise;
pub mod numeric;
pub mod observation;
pub mod pendulum;
pub mod recording;
pub mod screw;
pub mod se3;
pub mod skill;
pub mod stats;
pub mod synth;
#[cfg(test)]
mod testing;
pub mod trajectory;
pub mod tree;

pub use error::{Error, Result};
pub use se3::Twist;
pub use trajectory::{Demonstration, StampedPose};
