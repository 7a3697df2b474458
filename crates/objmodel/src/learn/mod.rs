//! The learning pipeline: the one entry point that the command line, the simulator's task loop
//! and evaluation, and the tests call, so that the same demonstrations give the same model
//! wherever they come from.
//!
//! ```text
//! source ─▶ classify (Algorithm 1, 2: segments, edges, faces) ─┐
//!        └▶ recorder (the frames, bounded) ────────────────────┴▶ check ─▶ dynamics ─▶ Observation ─▶ Tree::add
//! ```
//!
//! One pass over each file: while the stream is classified, a [`Recorder`](crate::recording::Recorder) keeps its frames
//! (all of them up to its capacity, evenly thinned beyond: see [`crate::recording`]); once the
//! classification is known, it is checked against the kept frames (was the noise measurable?
//! were the rests that a motion reached on the support? [`crate::arrival`]), the dynamics of
//! each topple are fitted to the kept frames
//! ([`crate::dynamics::analyse`]), and the demonstration's geometry and pendulums enter the
//! tree together ([`Tree::add`](crate::tree::Tree::add)), under the identity of its poses (the kept frames'
//! fingerprint, not its name). A file is read a second time only where its first frames
//! measured the motion rather than the noise and a rest measures the noise
//! (`tracker_noise::noise_check`), or where the tracker's noise is correlated from frame to frame
//! (`tracker_noise::correlated_noise`): it is classified again with that noise; and where no
//! rest measures it, learnt with others at its frame rate, it is read again with the noise that
//! their rests measure together ([`crate::shared_noise`]); and where a thrown object's own
//! flights do not determine its centre of mass, it is read again with the one that the flights
//! of all the demonstrations agree on, which tells its rolls from flights
//! ([`crate::shared_com`]); and where a file that does not name its columns (TUM) has moving
//! frames that teach no edge, it is read again in the other quaternion order, which may show
//! it written that way (`quaternion_check.rs`). Gravity comes from the
//! [`Config`]: without it the topples'
//! dynamics cannot be measured (their angles are from the vertical), which the report says.
//! A demonstration without motion teaches nothing and is not added.
//!
//! ```no_run
//! use objmodel::learn::{Config, Learner, Source};
//! use objmodel::tree::Tree;
//! # fn main() -> objmodel::Result<()> {
//! let learner = Learner::new(Config::default());
//! let mut tree = Tree::default();
//! let reports = learner.learn(
//!     &mut tree,
//!     &[Source::file("demo1.tum"), Source::instrumented("demo2.tum", "demo2.palm.tum")],
//! )?;
//! for r in &reports {
//!     println!("{}: {}", r.classification.name, r.classification.kind.as_str());
//! }
//! # Ok(())
//! # }
//! ```
//!
//! An OptiTrack Motive take holding the object and the palm as two rigid bodies is a source
//! ([`Source::Take`]), read as two files are. A ROS 2 bag is a source too ([`Source::Bag`]):
//! its object and palm streams are read into memory ([`crate::format::bag`]), and may hold
//! several demonstrations when it is split at rests ([`Learner::observe_all`],
//! [`Learner::learn`] take them all).
//!
//! The stages, one file each, in the order a demonstration passes them: `source.rs` (where it
//! comes from), `units.rs` (its stamps in seconds, its positions in metres, its palm on the
//! object's clock), `observe.rs` (classified in one pass, then its topples' dynamics),
//! `checks.rs` (what the kept frames say of the classification, with `held_poses.rs` and
//! `tracker_noise.rs`), `quaternion_check.rs` (were its quaternions read in the order they
//! were written?), `fuse.rs` (what the demonstrations learnt together share, with
//! `tracker_noise.rs` and `com_sharing.rs`; gravity checked, `gravity_check.rs`; then the
//! tree), and `readable.rs` (learning past files that cannot be read).
//!
//! The two clocks ([`Config::clocks`]): the palm's stamps are shifted by
//! [`Clocks::palm_time_offset_s`](crate::classify::Clocks) before anything else, and the stamps
//! of files and in-memory demonstrations in milliseconds, microseconds or nanoseconds are
//! converted to seconds ([`crate::format::detect_time_unit`]), with a warning.

pub use crate::classify::Config;
use crate::recording::DEFAULT_CAPACITY;
use crate::shared_noise::SharedNoise;

mod checks;
mod com_sharing;
mod fuse;
mod gravity_check;
mod held_poses;
mod observe;
mod quaternion_check;
mod readable;
mod source;
mod tracker_noise;
mod units;

pub use fuse::nothing_to_learn;
pub use gravity_check::NOT_LEARNT;
pub use readable::LeftOut;
pub use source::Source;

/// The learning pipeline, configured once.
#[derive(Clone, Debug)]
pub struct Learner {
    config: Config,
    capacity: usize,
    /// Whether [`Learner::learn`] checks the gravity given against the demonstrations.
    gravity_checked: bool,
    /// The support's height the user gave, if any ([`Learner::with_support`]).
    support: Option<crate::support::SupportObservation>,
    /// Where the config's noise is shared by other demonstrations ([`crate::shared_noise`]):
    /// what they measured.
    shared: Option<SharedNoise>,
    /// Whether poses in memory were read from quaternions written in the configured order
    /// ([`Learner::with_memory_quaternions`]).
    memory_quaternions: bool,
}

impl Learner {
    /// A learner with this configuration (method, thresholds, gravity).
    pub fn new(config: Config) -> Self {
        Self {
            config,
            capacity: DEFAULT_CAPACITY,
            gravity_checked: true,
            support: None,
            shared: None,
            memory_quaternions: false,
        }
    }

    /// Take the poses of demonstrations in memory ([`Source::Memory`]) as read from four
    /// numbers written in [`Config::quaternion_order`] (as the Python package reads array rows
    /// `t x y z qx qy qz qw`), so that they are checked as pose files are: where the other
    /// order explains their motion by an edge that this one does not, they teach nothing and
    /// say which order to give (see `quaternion_check.rs`).
    pub fn with_memory_quaternions(mut self) -> Self {
        self.memory_quaternions = true;
        self
    }

    /// Learn with the support's height known: `height` \[m\] along −gravity in the frame the
    /// poses are given in, to `sigma_m` ([`crate::support::SupportObservation::given`]). Every
    /// rest on the support then gives its face an offset, without an edge on the support. An
    /// error unless the height is finite and its σ finite and positive.
    pub fn with_support(mut self, height: f64, sigma_m: f64) -> crate::Result<Self> {
        self.support = Some(crate::support::SupportObservation::given(height, sigma_m)?);
        Ok(self)
    }

    /// Learn without checking the gravity given against the demonstrations (see
    /// [`Learner::learn`]): for a gravity known to be right that the check doubts (a support
    /// tilted by more than a few degrees, hands that lift objects at about g).
    pub fn without_gravity_check(mut self) -> Self {
        self.gravity_checked = false;
        self
    }

    /// Keep at most `frames` frames per stream for the dynamics (default
    /// [`DEFAULT_CAPACITY`]); longer demonstrations are analysed at a lower rate.
    pub fn with_capacity(mut self, frames: usize) -> Self {
        self.capacity = frames;
        self
    }

    /// The configuration.
    pub fn config(&self) -> &Config {
        &self.config
    }
}
