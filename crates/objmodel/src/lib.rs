//! # objmodel
//!
//! Learn *object description trees* from 6D pose demonstrations, after Sanan, Bretan & Heck,
//! "Learning Object Models for Non-prehensile Manipulation" (IROS 2019).
//!
//! Data flows one way, and each stage has a module named after the paper's concept:
//!
//! ```text
//! file ─format─▶ trajectory ─clean─▶ screws (se3, screw) ─classify─▶ segments
//!      ─edge / face / dynamics─▶ observation ─tree─▶ object description tree
//!      ─shape / mass─▶ export (MJCF, URDF) / prediction / skill
//! (learn: the one pipeline that orders these stages)
//! ```
//!
//! * [`se3`]: exact exponential and logarithm of SE(3) and SO(3), twists.
//! * [`screw`]: screw parameters of a twist (paper eq. 1-3) and the plane normal (eq. 5).
//! * [`format`](mod@format): TUM and CSV pose files, with errors that name file, line and problem.
//! * [`trajectory`]: time-stamped poses, demonstrations (optionally with a palm).
//! * [`clean`]: quaternion sign continuity and rejection of single-frame tag flips.
//! * [`noise`]: tracking-noise estimation from the data itself; [`shared_noise`]: the noise
//!   of a demonstration that cannot measure its own, from those learnt with it.
//! * [`stats`]: the few distributions the tests need (chi-square quantiles).
//! * [`classify`]: Algorithm 1, the paper-literal version and the robust one.
//! * [`edge`], [`face`]: Algorithm 2 and eq. 5 estimates with covariances.
//! * [`recording`]: the frames the dynamics need, kept in bounded memory during the one pass.
//! * [`flight`]: free flights (the centre of mass falls with gravity) and their impacts, found
//!   on the kept frames and put into the parts list; they teach no feature. [`shared_com`]:
//!   the centre of mass the flights of all the demonstrations learnt together agree on,
//!   which tells a tossed object's roll from its flight.
//! * [`landing`]: the rests reached after a flight, which teach the face rested on once a
//!   landing of another demonstration agrees in down and place; [`support`]: the height of
//!   the plane the object rests on, from the edges it turned about on it, which gives the
//!   landings' faces their offsets.
//! * [`length_check`]: whether positions read in metres (their unit undeclared) look like
//!   metres; a millimetre file read as metres teaches nothing, and says which unit to give.
//! * [`vertical`]: the vertical that the rests of many demonstrations turn about, which
//!   checks the gravity given (a motion-capture frame with y up, learnt as z up).
//! * [`dynamics`], [`pendulum`]: each topple's angles, onset, φ and pendulum fit.
//! * [`observation`]: what one demonstration shows (classification and dynamics).
//! * [`tree`]: the object description tree, its JSON schema and incremental fusion.
//! * [`learn`]: **the learning pipeline**, the one entry point every front end calls.
//! * [`shape`]: the object's convex polyhedron from the tree's faces (vertices, extents);
//!   [`mass`]: its volume, centroid and inertia at uniform density; [`export`]: the body a
//!   simulator needs, as MJCF and URDF; [`prediction`]: the pendulums of every (face, edge)
//!   pair the shape and the CoM predict, demonstrated or not.
//! * [`args`]: values given on the command line as text (a pose, gravity, a vector).
//! * [`synth`]: a small kinematic generator of demonstrations with exact ground truth.
//!
//! The code that exists only for speed (four-lane kernels, their AVX2 copies, the parsing
//! thread) is a crate-private implementation detail behind one module, `fast`; every kernel
//! there gives the bits of the plainer code it mirrors in the modules above.
//!
//! Units are SI throughout (m, rad, s, kg); files in millimetres or milliseconds are converted
//! as they are read ([`format::LengthUnit`], [`format::TimeUnit`]). Transforms are named by frames: `world_from_object`
//! maps a point in object coordinates to world coordinates.

#![warn(missing_docs)]

pub mod args;
pub mod arrival;
pub mod classify;
pub mod clean;
pub mod dynamics;
pub mod edge;
pub mod error;
pub mod export;
pub mod face;
mod fast;
pub mod flight;
pub mod format;
pub mod friction;
pub mod geometry;
pub mod inertia;
pub mod landing;
pub mod learn;
pub mod length_check;
pub mod mass;
pub mod noise;
pub mod noise_correlation;
pub mod observation;
pub mod onset;
pub mod pendulum;
pub mod prediction;
pub mod recording;
pub mod rest_place;
pub mod roll;
pub mod screw;
pub mod se3;
pub mod shape;
pub mod shared_com;
pub mod shared_noise;
pub mod skill;
pub mod start_rest;
pub mod stats;
pub mod support;
pub mod synth;
#[cfg(test)]
mod testing;
pub mod trajectory;
pub mod tree;
pub mod vertical;

#[doc(hidden)]
pub use fast::bench;

pub use error::{Error, Result};
pub use se3::Twist;
pub use trajectory::{Demonstration, StampedPose};
