//! # objmodel-sim
//!
//! A simulated world that produces demonstrations for `objmodel`, with exact ground truth: the
//! stand-in for the robot, the camera and the user of Sanan, Bretan & Heck (IROS 2019).
//!
//! * [`spec`]: boxes (size, mass, offset centre of mass, friction) and the tag stuck on them;
//!   [`turned`]: the same box resting on another face; [`rigid`]: a rigid body in its own
//!   frame, from a spec, a learnt model ([`learnt`], which also puts it in the scenes) or a
//!   URDF ([`urdf_body`]); [`onset`]: the tilt at which it starts to topple on a palm.
//! * [`world`]: rapier3d-f64 tuned for accurate toppling (no contact recycling, Coulomb
//!   friction, stiff contacts); [`convert`] is the one glam ↔ nalgebra boundary.
//! * [`scenes`]: direct topple, instrumented topple, slide, general motion, compound
//!   (slide then topple); and the messy ones: topple then slide, toss, session.
//! * [`noise`]: tracking noise (Gaussian, dropped frames, sign flips, tag mirror flips; camera
//!   and motion-capture presets).
//! * [`events`], [`modes`], [`truth`]: what really happened, in the tag frame; [`modes`] the
//!   contact mode of every interval (see `docs/dataset.md`).
//! * [`demo`]: [`simulate`] and [`write_demo`]; [`dataset`]: the standard data set.
//! * [`eval`]: the learner measured against the truth of a data set; [`claims`]: the learnt
//!   model against the true box in simulation (corners, CoM, topple onsets on a palm).
//! * [`arm`]: a 7-DoF Franka Panda with a palm (URDF, kinematics, IK, rapier multibody).
//! * [`task`]: the toppling skill on the arm and the Fig. 1 loop (try, fail, ask for a
//!   demonstration, learn, succeed).
//!
//! Units are SI (m, kg, s, rad). Frames: `world` (z up, the table's top is `z = 0`), `box` (the
//! box's geometric centre and edges), `tag` (the tracked frame), `palm` (the plate's top
//! surface, `z` its normal). Transforms read right to left: `world_from_tag` maps tag
//! coordinates to world coordinates.
//!
//! ```no_run
//! use objmodel_sim::{simulate, write_demo, BoxSpec, TrackerNoise, SceneKind};
//! let spec = BoxSpec::new("tall", [0.1, 0.1, 0.2], 0.6).with_com([0.02, 0.0, 0.0]);
//! let demo = simulate(SceneKind::Topple, &spec, &TrackerNoise::real(), 3).unwrap();
//! write_demo(std::path::Path::new("out"), "tall_topple", &demo).unwrap();
//! ```

#![warn(missing_docs)]

pub mod arm;
pub mod calibration;
pub mod claims;
pub mod convert;
pub mod dataset;
pub mod demo;
pub mod eval;
pub mod eval_precision;
pub mod events;
pub mod learnt;
pub mod modes;
pub mod noise;
pub mod onset;
pub mod rigid;
pub mod scenes;
pub mod spec;
pub mod task;
pub mod truth;
pub mod turned;
pub mod urdf_body;
pub mod world;

pub use dataset::{standard_dataset, write_dataset, DatasetPlan, Manifest, Progress};
pub use demo::{
    simulate, simulate_clean, simulate_with, write_demo, CleanDemo, DemoFiles, SimDemo, SimOptions,
};
pub use noise::TrackerNoise;
pub use spec::{BoxFace, BoxSpec, TagMount};
pub use truth::Truth;
pub use world::PhysicsParams;

use serde::{Deserialize, Serialize};

/// Errors of the simulator.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// The box, noise model or options cannot make the requested scene.
    #[error("{0}")]
    InvalidSpec(String),
    /// The scene ran but did not do what it should (the box did not topple, fell off, ...).
    #[error("scene failed: {0}")]
    Scene(String),
    /// Writing a file failed.
    #[error(transparent)]
    Io(#[from] objmodel::Error),
    /// Serialising JSON failed.
    #[error("JSON: {0}")]
    Json(#[from] serde_json::Error),
}

/// Result with [`SimError`].
pub type Result<T> = std::result::Result<T, SimError>;

/// The kinds of demonstration (paper Fig. 3 and Fig. 7, plus a compound one).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SceneKind {
    /// A finger pushes the box on a table above its CoM until it topples.
    Topple,
    /// The box stands on a tracked palm that tilts until the box topples.
    InstrumentedTopple,
    /// A low push slides and turns the box on a slippery table.
    Slide,
    /// The box is carried through the air, turned and put down.
    General,
    /// A slide, then a topple, in one demonstration.
    Compound,
    /// A topple, then a slide on the new face, in one demonstration.
    ToppleSlide,
    /// A box thrown onto a table: flight, impacts, bounces, slides, rolls, rest.
    Toss,
    /// A long session: several topples, slides and carries in a row, with rests between.
    Session,
}

impl SceneKind {
    /// The kinds of the original standard dataset: one demonstration each (the compound is a
    /// slide and a topple). [`SceneKind::MESSY`] lists the others.
    pub const ALL: [SceneKind; 5] = [
        SceneKind::Topple,
        SceneKind::InstrumentedTopple,
        SceneKind::Slide,
        SceneKind::General,
        SceneKind::Compound,
    ];

    /// The scenes of real, messy demonstrations (issue 20): compounds, tosses, sessions.
    pub const MESSY: [SceneKind; 3] = [SceneKind::ToppleSlide, SceneKind::Toss, SceneKind::Session];

    /// Short name used in file names and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            SceneKind::Topple => "topple",
            SceneKind::InstrumentedTopple => "instrumented",
            SceneKind::Slide => "slide",
            SceneKind::General => "general",
            SceneKind::Compound => "compound",
            SceneKind::ToppleSlide => "topple_slide",
            SceneKind::Toss => "toss",
            SceneKind::Session => "session",
        }
    }

    /// The kind label of the truth: "topple" (also for instrumented), "slide", "general",
    /// "compound", and for the messy scenes their own names ("topple_slide", "toss",
    /// "session"), whose features are in the truth's `modes`.
    pub fn truth_kind(self) -> &'static str {
        match self {
            SceneKind::Topple | SceneKind::InstrumentedTopple => "topple",
            SceneKind::Slide => "slide",
            SceneKind::General => "general",
            SceneKind::Compound => "compound",
            SceneKind::ToppleSlide => "topple_slide",
            SceneKind::Toss => "toss",
            SceneKind::Session => "session",
        }
    }

    /// Parse a [`SceneKind::name`].
    pub fn from_name(s: &str) -> Option<SceneKind> {
        SceneKind::ALL
            .into_iter()
            .chain(SceneKind::MESSY)
            .find(|k| k.name() == s)
    }
}
