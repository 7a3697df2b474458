//! Options shared by the commands that classify: every threshold of Algorithm 1, in SI units.

use anyhow::{bail, Result};
use nalgebra::Vector3;
use objmodel::classify::{Config, Method};
use objmodel::format::palm_path_for;
use std::path::{Path, PathBuf};

/// Parse "x,y,z" into a vector ([`objmodel::args::vec3`]).
pub fn parse_vec3(s: &str) -> Result<Vector3<f64>> {
    Ok(objmodel::args::vec3(s)?)
}

/// How to classify.
#[derive(clap::Args, Clone, Debug)]
pub struct ClassifyOpts {
    /// Algorithm 1 variant: `robust` (statistical tests, works at real tracking noise) or
    /// `paper` (the paper's thresholds, literally).
    #[arg(long, default_value = "robust", value_parser = ["robust", "paper"])]
    pub method: String,
    /// Gravity in the tracker's world frame, "gx,gy,gz" (any length), or "none" if unknown.
    /// A camera-frame tracker gives it as the camera's down direction, e.g. "0,1,0" for a
    /// level camera with y down.
    #[arg(long, default_value = "0,0,-1")]
    pub gravity: String,
    /// Significance level of the per-frame χ² tests (robust).
    #[arg(long, default_value_t = 1e-3)]
    pub alpha: f64,
    /// Significance level of the tag-flip outlier test (robust).
    #[arg(long, default_value_t = 1e-6)]
    pub outlier_alpha: f64,
    /// Window [s] of the local-velocity fit that tells rest from motion (robust).
    #[arg(long, default_value_t = 0.6)]
    pub rest_window: f64,
    /// Shortest rest [s] that separates two motion segments (robust).
    #[arg(long, default_value_t = 1.0)]
    pub min_rest: f64,
    /// Tracking position noise [m] per axis; estimated from the data if not given (robust).
    /// Where the frames show more noise than given (beyond sampling error), the larger is
    /// used, with a warning. Not given, a demonstration whose frames cannot measure it (a
    /// fast toss at 30 Hz) is learnt with the noise that the rests of the demonstrations
    /// learnt with it at its frame rate measure together (`learn`), taken as one tracker's.
    #[arg(long)]
    pub noise_position: Option<f64>,
    /// Tracking orientation noise [rad] per axis; estimated if not given (robust).
    #[arg(long)]
    pub noise_rotation: Option<f64>,
    /// The palm tracker's position noise [m] per axis, with --noise-position given, for an
    /// instrumented demonstration; default: estimated from the palm's first frames. A palm
    /// posed by the robot's joint encoders may be far better than the camera (robust).
    #[arg(long)]
    pub palm_noise_position: Option<f64>,
    /// The palm tracker's orientation noise [rad] per axis, with --noise-rotation given;
    /// default: estimated from the palm's first frames (robust).
    #[arg(long)]
    pub palm_noise_rotation: Option<f64>,
    /// Edge model tolerance [m]: how far a real contact line may wander (robust).
    #[arg(long, default_value_t = 3e-4)]
    pub edge_tolerance: f64,
    /// Contact depth [m]: σ of the pivot's offset from the edge along its faces' bisector (a
    /// rounded edge, a compliant contact), common to every topple about the edge (robust).
    #[arg(long, default_value_t = 1e-3)]
    pub contact_depth: f64,
    /// Direction model tolerance [rad] (robust; default 0.5°).
    #[arg(long, default_value_t = 0.5f64.to_radians())]
    pub edge_tolerance_angle: f64,
    /// Largest tilt [rad] of a topple axis from horizontal / a slide normal from vertical
    /// (robust, when gravity is known; default 45°).
    #[arg(long, default_value_t = 45f64.to_radians())]
    pub max_axis_tilt: f64,
    /// r_palm [m]: axes farther than this from the object origin are not edges.
    #[arg(long, default_value_t = 0.5)]
    pub r_palm: f64,
    /// p_th [m/rad]: pitch threshold (paper).
    #[arg(long, default_value_t = 0.01)]
    pub pitch_threshold: f64,
    /// l_th [rad]: axis angle threshold between consecutive frames (paper; default 5°).
    #[arg(long, default_value_t = 5f64.to_radians())]
    pub axis_angle_threshold: f64,
    /// n_th [rad]: plane normal angle threshold (paper; default 5°).
    #[arg(long, default_value_t = 5f64.to_radians())]
    pub normal_angle_threshold: f64,
    /// Seconds added to the palm's stamps to put them on the object's clock (a palm clock
    /// running 4 ms ahead needs -0.004).
    #[arg(
        long,
        value_name = "S",
        default_value_t = 0.0,
        allow_negative_numbers = true
    )]
    pub palm_time_offset: f64,
    /// Drop object frames whose nearest palm pose is farther than S seconds (the palm is
    /// interpolated at the others' stamps, slerp and linear).
    #[arg(long, value_name = "S", default_value_t = objmodel::classify::DEFAULT_MAX_DT_S)]
    pub max_dt: f64,
    /// The files' stamps are seconds: do not recognise milliseconds or nanoseconds (by their
    /// magnitude and spacing) and convert them.
    #[arg(long)]
    pub stamps_in_seconds: bool,
    /// The unit of the positions in files that do not declare theirs (TUM files, CSV headers
    /// without units; a header's `x [mm]` declares millimetres): m, cm or mm. Without it they
    /// are read as metres, and a demonstration whose noise or features are implausible in
    /// metres teaches nothing (its report says so)
    #[arg(long, value_name = "UNIT")]
    pub length_unit: Option<objmodel::format::LengthUnit>,
    /// The order of the quaternion in TUM files: xyzw (the format's) or wxyz, for files a
    /// tool wrote w first (MuJoCo, transforms3d, pyquaternion). Read in the wrong order, a
    /// file's rests teach faces that are not on the object. CSV headers name their columns,
    /// which decide.
    #[arg(long, value_name = "ORDER", default_value = "xyzw")]
    pub quat_order: objmodel::format::QuaternionOrder,
}

impl ClassifyOpts {
    /// The library configuration, validated.
    pub fn config(&self) -> Result<Config> {
        let method = if self.method == "paper" {
            Method::Paper
        } else {
            Method::Robust
        };
        let mut c = Config {
            method,
            ..Config::default()
        };
        c.gravity = objmodel::args::gravity(&self.gravity)?;
        for (name, v) in [
            ("--alpha", self.alpha),
            ("--outlier-alpha", self.outlier_alpha),
        ] {
            if !(v > 0.0 && v < 1.0) {
                bail!("{name} must be a probability in (0, 1), got {v}");
            }
        }
        for (name, v) in [
            ("--rest-window", self.rest_window),
            ("--r-palm", self.r_palm),
            ("--pitch-threshold", self.pitch_threshold),
            ("--axis-angle-threshold", self.axis_angle_threshold),
            ("--normal-angle-threshold", self.normal_angle_threshold),
        ] {
            if !(v > 0.0 && v.is_finite()) {
                bail!("{name} must be positive, got {v}");
            }
        }
        for (name, v) in [
            ("--edge-tolerance", self.edge_tolerance),
            ("--contact-depth", self.contact_depth),
        ] {
            if !(v >= 0.0 && v.is_finite()) {
                bail!("{name} must be zero or positive (metres), got {v}");
            }
        }
        c.robust.alpha = self.alpha;
        c.robust.outlier_alpha = self.outlier_alpha;
        c.robust.rest_window_s = self.rest_window;
        c.robust.min_rest_s = self.min_rest;
        c.robust.edge_tolerance_m = self.edge_tolerance;
        c.robust.edge_tolerance_rad = self.edge_tolerance_angle;
        c.robust.contact_depth_m = self.contact_depth;
        c.robust.max_axis_tilt_rad = self.max_axis_tilt;
        use objmodel::noise::NoiseModel;
        c.robust.noise = NoiseModel::from_options(
            ("--noise-position", self.noise_position),
            ("--noise-rotation", self.noise_rotation),
        )
        .map_err(anyhow::Error::msg)?;
        c.robust.palm_noise = NoiseModel::from_options(
            ("--palm-noise-position", self.palm_noise_position),
            ("--palm-noise-rotation", self.palm_noise_rotation),
        )
        .map_err(anyhow::Error::msg)?;
        if c.robust.palm_noise.is_some() && c.robust.noise.is_none() {
            bail!(
                "--palm-noise-position and --palm-noise-rotation need --noise-position and \
                 --noise-rotation (without them the noise of the motion relative to the palm \
                 is estimated from it)"
            );
        }
        c.paper.r_palm = self.r_palm;
        c.paper.pitch = self.pitch_threshold;
        c.paper.axis_angle = self.axis_angle_threshold;
        c.paper.normal_angle = self.normal_angle_threshold;
        if !self.palm_time_offset.is_finite() {
            bail!("--palm-time-offset must be finite");
        }
        if !(self.max_dt >= 0.0 && self.max_dt.is_finite()) {
            bail!("--max-dt must be a duration >= 0, got {}", self.max_dt);
        }
        c.clocks.palm_time_offset_s = self.palm_time_offset;
        c.clocks.max_dt_s = self.max_dt;
        c.clocks.detect_time_unit = !self.stamps_in_seconds;
        c.length_unit = self.length_unit;
        c.quaternion_order = self.quat_order;
        Ok(c)
    }
}

/// The palm file of `demo`: the one given, else NAME.palm.* beside it unless `ignore`.
pub fn palm_for(demo: &Path, explicit: Option<&Path>, ignore: bool) -> Option<PathBuf> {
    match explicit {
        Some(p) => Some(p.to_path_buf()),
        None if ignore => None,
        None => palm_path_for(demo),
    }
}
