//! How a demonstration is classified: the method, its thresholds and tolerances, gravity and
//! the clocks ([`Config`]).

use super::palm::Clocks;
use crate::noise::NoiseModel;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// Which Algorithm 1 to run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// The statistical version that works at real tracking noise (default).
    #[default]
    Robust,
    /// The paper's Algorithm 1, literally.
    Paper,
}

/// The paper's thresholds (Algorithm 1), used by [`Method::Paper`]; `r_palm` is also used by
/// the robust method.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PaperThresholds {
    /// `p_th` \[m/rad\]: |pitch| below this is "no translation along the axis".
    pub pitch: f64,
    /// `l_th` \[rad\]: consecutive axes closer than this are "the same axis".
    pub axis_angle: f64,
    /// `n_th` \[rad\]: consecutive plane normals closer than this are "the same plane".
    pub normal_angle: f64,
    /// `r_palm` \[m\]: an axis farther than this from the object origin is not an edge of it
    /// (the paper: the size of the palm, known a priori). Default 0.5 m: the tag may sit on the
    /// far side of a 20 cm box from the edge it topples about.
    pub r_palm: f64,
    /// A frame moves if its rotation from g(0) exceeds this \[rad\] ...
    pub motion_rotation: f64,
    /// ... or its translation exceeds this \[m\].
    pub motion_translation: f64,
}

impl Default for PaperThresholds {
    fn default() -> Self {
        Self {
            pitch: 0.01,
            axis_angle: 5f64.to_radians(),
            normal_angle: 5f64.to_radians(),
            r_palm: 0.5,
            motion_rotation: 1e-3,
            motion_translation: 1e-4,
        }
    }
}

/// Parameters of the robust method. Every one is a probability, a duration or a physical
/// tolerance, not a threshold on a noisy quantity.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct RobustConfig {
    /// Significance level of the per-frame χ² tests (rest, fit to line, fit to plane).
    pub alpha: f64,
    /// Significance level of the tag-flip outlier test.
    pub outlier_alpha: f64,
    /// Width \[s\] of the window over which the local velocity is fitted for the rest test.
    pub rest_window_s: f64,
    /// A rest shorter than this \[s\] inside a motion does not start a new segment.
    pub min_rest_s: f64,
    /// Number of frames at the start of each stream used to estimate the noise.
    pub warmup_frames: usize,
    /// Tracking noise of the object's tracker (`world_from_object`); `None` estimates it from
    /// the data. In an instrumented demonstration the motion relative to the palm carries the
    /// palm's noise too, turned by the palm's orientation noise over the object's distance
    /// from it: the learner propagates both ([`crate::noise::relative`]).
    pub noise: Option<NoiseModel>,
    /// Tracking noise of the palm (`world_from_palm`), used with a given `noise`; `None`:
    /// estimated from the palm's first frames. A palm posed by the robot's joint encoders may
    /// be far better than the camera on the object.
    #[serde(default)]
    pub palm_noise: Option<NoiseModel>,
    /// Model tolerance \[m\]: how far a real contact line may wander (rounded edges, compliant
    /// surfaces, micro-slip) and still count as one edge; added in quadrature to the noise of
    /// each frame, and the least systematic error of a topple's edge point (one trajectory per
    /// demonstration: it does not average down over the frames).
    pub edge_tolerance_m: f64,
    /// Model tolerance \[rad\] on directions (edge direction, plane normal).
    pub edge_tolerance_rad: f64,
    /// Contact depth \[m\]: the standard deviation of the pivot's offset from the edge along
    /// the bisector of its faces (a rounded edge, a compliant contact that sinks under the
    /// weight), which no frame of a topple and neither rest shows; common to every topple
    /// about the edge ([`crate::edge::EdgeObservation::add_contact_depth_var`]).
    #[serde(default = "default_contact_depth_m")]
    pub contact_depth_m: f64,
    /// Largest angle \[rad\] between a topple axis and the horizontal, and between a slide's
    /// plane normal and the vertical, when gravity is known.
    pub max_axis_tilt_rad: f64,
    /// How many frames the first rest's pose is worth, where fewer than it holds (`None`: all
    /// of them). A rest held at one frame's pose, from which a later part is measured again
    /// ([`crate::onset`]), is one frame's pose with that frame's noise, however long it is
    /// held; the segment after it must not count it as a mean of many.
    #[serde(skip)]
    pub held_rest_frames: Option<f64>,
    /// Whether an object frame whose pose repeats the one before it exactly is a tracker
    /// holding its last pose (left out, as a glitch is) rather than a measurement. Set by the
    /// learner where the noise at rest makes an exact repeat all but impossible
    /// ([`crate::learn`], `held_poses.rs`); an exact tracker (a simulator's) repeats its poses
    /// at rest, and its repeats are kept.
    #[serde(skip)]
    pub repeats_are_held: bool,
    /// The object's centre of mass that the flights of the demonstrations learnt together
    /// measured ([`crate::shared_com`]), set by the learner: a roll in a demonstration with a
    /// flight is told from a flight by it where the demonstration's own flights do not
    /// determine the point ([`crate::roll`]), and the flights are flights of it
    /// ([`crate::flight`]).
    #[serde(skip)]
    pub com: Option<crate::shared_com::SharedCom>,
}

impl Default for RobustConfig {
    fn default() -> Self {
        Self {
            alpha: 1e-3,
            outlier_alpha: 1e-6,
            rest_window_s: 0.6,
            min_rest_s: 1.0,
            warmup_frames: 300,
            noise: None,
            palm_noise: None,
            edge_tolerance_m: 3e-4,
            edge_tolerance_rad: 0.5f64.to_radians(),
            contact_depth_m: default_contact_depth_m(),
            max_axis_tilt_rad: 45f64.to_radians(),
            held_rest_frames: None,
            repeats_are_held: false,
            com: None,
        }
    }
}

/// 1 mm: about the depth of a soft contact under a box of a few hundred grams (MuJoCo's
/// default contacts), and the radius of a cardboard box's edge.
fn default_contact_depth_m() -> f64 {
    1e-3
}

/// Everything that configures classification.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Config {
    /// Which algorithm.
    pub method: Method,
    /// The paper's thresholds.
    pub paper: PaperThresholds,
    /// The robust method's parameters.
    pub robust: RobustConfig,
    /// Gravity direction (unit or not) in the tracker's world frame; `None` if unknown.
    /// Default: -z (z up).
    pub gravity: Option<Vector3<f64>>,
    /// The object's and the palm's clocks (offset, pairing tolerance, time units).
    #[serde(default)]
    pub clocks: Clocks,
    /// The unit of positions in files and poses that do not declare their own (a CSV
    /// header's `x [mm]` does: [`crate::format::LengthUnit`]); `None`: metres, which the
    /// learner checks against the data ([`crate::length_check`]).
    #[serde(default)]
    pub length_unit: Option<crate::format::LengthUnit>,
    /// The order of the quaternion in pose files that do not name their columns (TUM
    /// files): x y z w, the format's, or w x y z where a tool wrote them so
    /// ([`crate::format::QuaternionOrder`]). CSV headers name theirs; poses in memory are
    /// `UnitQuaternion`s.
    #[serde(default)]
    pub quaternion_order: crate::format::QuaternionOrder,
}

impl Config {
    /// This configuration with pose files' quaternions read in `order` where they do not name
    /// their columns ([`Config::quaternion_order`]).
    pub fn with_quaternion_order(mut self, order: crate::format::QuaternionOrder) -> Self {
        self.quaternion_order = order;
        self
    }
}

impl Default for Config {
    fn default() -> Self {
        Self {
            method: Method::Robust,
            paper: PaperThresholds::default(),
            robust: RobustConfig::default(),
            gravity: Some(Vector3::new(0.0, 0.0, -1.0)),
            clocks: Clocks::default(),
            length_unit: None,
            quaternion_order: Default::default(),
        }
    }
}
