//! The scenes: one per kind of demonstration in the paper (Fig. 3, Fig. 7), plus a compound one.
//!
//! Every scene rests about 1 s, moves, lets the box come to rest and rests about 1 s more. It
//! records the box pose (and the support's, a table or a palm) at every physics step; the
//! 30 Hz output is a subsample of that record and the ground truth events are found on the
//! full-rate record.

pub mod carry;
pub mod compound;
pub mod general;
pub mod instrumented;
pub mod push;
pub mod session;
pub mod slide;
pub mod topple;
pub mod topple_slide;
pub mod toss;

use crate::spec::BoxSpec;
use crate::world::{Body, PhysicsParams, World};
use crate::{Result, SimError};
use nalgebra::{Isometry3, Translation3, Unit, UnitQuaternion, Vector3};
use rand::Rng;

/// One full-rate record: time, `world_from_box` (geometric box frame) and `world_from_support`
/// (the table, fixed at identity, or the palm's tracked frame: origin on its top surface, `z`
/// its normal).
#[derive(Debug, Clone, Copy)]
pub struct Sample {
    /// Time \[s\].
    pub t: f64,
    /// Pose of the box's geometric frame.
    pub world_from_box: Isometry3<f64>,
    /// Pose of the support's frame.
    pub world_from_support: Isometry3<f64>,
}

/// Named instants a scene script knows about (used to label segments in the truth).
#[derive(Debug, Clone, Default)]
pub struct Script {
    /// Effective box–support friction coefficient used.
    pub mu: f64,
    /// Whether the support is a tracked palm.
    pub palm: bool,
    /// When the scripted motion (push, tilt, grasp) began \[s\].
    pub motion_start: f64,
    /// Compound scene: when the second (toppling) push began \[s\].
    pub second_phase: Option<f64>,
    /// General scene: grasp and release times \[s\].
    pub carry: Option<(f64, f64)>,
    /// Other intervals during which a hand holds the box (a throw before its release, the
    /// carries of a session) \[s\].
    pub grasps: Vec<(f64, f64)>,
    /// Free-form description of the randomised choices (push height, speed, tilt rate, ...).
    pub notes: Vec<(String, f64)>,
}

/// What a scene produced.
#[derive(Debug, Clone)]
pub struct SceneOutput {
    /// Full-rate record.
    pub samples: Vec<Sample>,
    /// Physics step rate \[Hz\].
    pub step_hz: f64,
    /// The scripted facts.
    pub script: Script,
}

/// A running scene: the world, the box, the support and the record.
pub struct Run {
    /// The physics world.
    pub world: World,
    /// The box body.
    pub boxb: Body,
    /// The palm, if the support is a kinematic plate (else the support is the fixed table).
    pub plate: Option<Body>,
    /// The record so far.
    pub samples: Vec<Sample>,
    /// Hard cap on simulated time \[s\].
    pub max_t: f64,
}

/// Settling thresholds: speed below 1 mm/s and turn rate below 0.01 rad/s relative to support.
const REST_V: f64 = 1e-3;
const REST_W: f64 = 1e-2;

impl Run {
    /// A world with the box resting on its `-z` face at `world_from_box`.
    pub fn new(p: &PhysicsParams) -> Run {
        Run {
            world: World::new(p),
            boxb: Body::invalid(),
            plate: None,
            samples: Vec::new(),
            max_t: 60.0,
        }
    }

    /// A world with the fixed table (friction `mu`) and the box standing on its `-z` face near
    /// the origin, its tag facing the camera ([`facing_yaw`], then [`resting_pose`], each
    /// drawing from `rng`, in that order).
    pub fn on_table<R: Rng>(spec: &BoxSpec, p: &PhysicsParams, mu: f64, rng: &mut R) -> Run {
        let mut run = Run::new(p);
        run.world.add_table(mu);
        let yaw = facing_yaw(spec, rng);
        run.place_box(spec, mu, &resting_pose(spec, yaw, rng));
        run
    }

    /// Place the box; records the first sample.
    pub fn place_box(&mut self, spec: &BoxSpec, mu: f64, world_from_box: &Isometry3<f64>) {
        self.boxb = self.world.add_box(spec, mu, world_from_box);
        self.record();
    }

    fn support(&self) -> Isometry3<f64> {
        self.plate
            .map(|p| self.world.pose(p))
            .unwrap_or_else(Isometry3::identity)
    }

    fn record(&mut self) {
        let s = Sample {
            t: self.world.t,
            world_from_box: self.world.pose(self.boxb),
            world_from_support: self.support(),
        };
        self.samples.push(s);
    }

    /// One physics step, recorded. Errors if the scene runs past `max_t` or the box falls off.
    pub fn step(&mut self) -> Result<()> {
        self.world.step();
        self.record();
        let z = self
            .samples
            .last()
            .map(|s| s.world_from_box.translation.z)
            .unwrap_or(0.0);
        if self.world.t > self.max_t {
            return Err(SimError::Scene(format!(
                "scene did not finish within {} s",
                self.max_t
            )));
        }
        if z < -0.2 || !z.is_finite() {
            return Err(SimError::Scene("the box fell off its support".into()));
        }
        Ok(())
    }

    /// Step for `seconds`.
    pub fn rest(&mut self, seconds: f64) -> Result<()> {
        let end = self.world.t + seconds;
        while self.world.t < end - 0.5 * self.world.dt {
            self.step()?;
        }
        Ok(())
    }

    /// Whether the box is at rest relative to its support now.
    pub fn box_at_rest(&self) -> bool {
        let (v, w) = self.world.velocity(self.boxb);
        let (vs, ws) = match self.plate {
            Some(p) => {
                let (vs, ws) = self.world.velocity(p);
                // velocity of the palm's material point at the box origin
                let r = self.world.pose(self.boxb).translation.vector
                    - self.world.pose(p).translation.vector;
                (vs + ws.cross(&r), ws)
            }
            None => (Vector3::zeros(), Vector3::zeros()),
        };
        (v - vs).norm() < REST_V && (w - ws).norm() < REST_W
    }

    /// Step until the box has been at rest for 0.2 s (at most `max_s` seconds).
    pub fn settle(&mut self, max_s: f64) -> Result<()> {
        let end = self.world.t + max_s;
        let mut calm = 0.0;
        while calm < 0.2 {
            self.step()?;
            calm = if self.box_at_rest() {
                calm + self.world.dt
            } else {
                0.0
            };
            if self.world.t > end {
                return Err(SimError::Scene(format!(
                    "the box did not come to rest within {max_s} s"
                )));
            }
        }
        Ok(())
    }

    /// Finish: the output record.
    pub fn finish(self, script: Script) -> SceneOutput {
        SceneOutput {
            samples: self.samples,
            step_hz: 1.0 / self.world.dt,
            script,
        }
    }

    /// Current tilt \[rad\] of the box's initial resting face away from the support plane:
    /// the angle between that face's outward normal and the support's `-z`.
    pub fn tilt(&self, rest_normal_box: &Vector3<f64>) -> f64 {
        let s = self.samples.last().expect("a sample");
        let n = (s.world_from_support.inverse() * s.world_from_box).rotation * rest_normal_box;
        n.angle(&-Vector3::z())
    }
}

/// A start pose for a box resting on its `-z` face on the plane `z = 0` of the support frame:
/// centred near `xy` (±2 cm), yawed by `yaw` \[rad\]. Lifted 0.1 mm so it settles without impact.
pub fn resting_pose<R: Rng>(spec: &BoxSpec, yaw: f64, rng: &mut R) -> Isometry3<f64> {
    let h = spec.half_extents();
    let x = rng.random_range(-0.02..0.02);
    let y = rng.random_range(-0.02..0.02);
    Isometry3::from_parts(
        Translation3::new(x, y, h.z + 1e-4),
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), yaw),
    )
}

/// A world yaw \[rad\] for a box standing on its `-z` face such that its tag (if on a side
/// face) faces the default camera, which looks from `-y`, within ±50°: a person demonstrating
/// keeps the tag in view.
pub fn facing_yaw<R: Rng>(spec: &BoxSpec, rng: &mut R) -> f64 {
    let n = spec.tag.face.normal();
    let jitter = rng.random_range(-50f64..50.0).to_radians();
    if n.z.abs() > 0.5 {
        return jitter * 3.0;
    }
    // yaw that turns the face normal's heading onto -y
    -std::f64::consts::FRAC_PI_2 - n.y.atan2(n.x) + jitter
}

/// A random direction, uniform on the sphere (drawn in the unit ball, by rejection).
pub fn random_unit_vector<R: Rng>(rng: &mut R) -> Unit<Vector3<f64>> {
    loop {
        let v = Vector3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        if v.norm() > 0.2 && v.norm() < 1.0 {
            return Unit::new_normalize(v);
        }
    }
}

/// The bottom edge of the `-z` face that a box tips over when its CoM is driven toward
/// horizontal box direction `axis · sign` (axis 0 or 1): its distance `d` \[m\] from the CoM's
/// projection and the CoM height `hc` \[m\] above the face; the tipping angle is `atan2(d, hc)`.
pub fn edge_lever(spec: &BoxSpec, axis: usize, sign: f64) -> (f64, f64) {
    let h = spec.half_extents();
    let c = spec.com_box();
    (h[axis] - sign * c[axis], h.z + c.z)
}
