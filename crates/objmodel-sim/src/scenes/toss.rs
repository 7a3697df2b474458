//! Toss: a hand throws the box onto a table. The box leaves the hand 0.1-0.6 m above the table
//! (its lowest corner), moving 0.2-1.5 m/s sideways and -0.5..0.8 m/s up, spinning at
//! 1-15 rad/s about a random axis, in a random orientation; it flies, lands, bounces, slides
//! with spin, rolls over edges and comes to rest.
//!
//! The record starts 0.1-0.3 s before the release with the box in the hand, which moves it at
//! the release velocity (kinematic; mode `carried`), and ends a tail after the box has come to
//! rest: 0.08-0.15 s in a third of the tosses (a tracker log that stops soon after the object
//! does), else 0.3-1.0 s. Table friction 0.3-0.6 and restitution 0.1-0.5 (wood, plastic,
//! cardboard) are drawn per toss.

use super::{random_unit_vector, Run, SceneOutput, Script};
use crate::spec::BoxSpec;
use crate::world::{PhysicsParams, GRAVITY};
use crate::{Result, SimError};
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use rand::rngs::StdRng;
use rand::Rng;

/// A throw: the box's pose and velocity at the release.
#[derive(Debug, Clone, Copy)]
pub struct Throw {
    /// Box orientation at the release (`world_from_box` rotation).
    pub rotation: UnitQuaternion<f64>,
    /// Centre of mass at the release, world \[m\].
    pub com: Vector3<f64>,
    /// Velocity of the centre of mass \[m/s\].
    pub velocity: Vector3<f64>,
    /// Angular velocity \[rad/s\].
    pub spin: Vector3<f64>,
    /// How long the hand carries the box before the release \[s\].
    pub hold: f64,
}

impl Throw {
    /// `world_from_box` at time `dt` relative to the release (negative: in the hand), moving at
    /// the release's constant velocity and spin.
    pub fn pose_at(&self, spec: &BoxSpec, dt: f64) -> Isometry3<f64> {
        let r = UnitQuaternion::from_scaled_axis(self.spin * dt) * self.rotation;
        let com = self.com + self.velocity * dt;
        Isometry3::from_parts(Translation3::from(com - r * spec.com_box().coords), r)
    }
}

/// Height of the lowest corner of the box at `world_from_box` \[m\].
pub fn lowest_corner(spec: &BoxSpec, world_from_box: &Isometry3<f64>) -> f64 {
    let h = spec.half_extents();
    (0..8)
        .map(|j| {
            let s = |bit: usize| if j >> bit & 1 == 1 { 1.0 } else { -1.0 };
            (world_from_box * Point3::new(s(0) * h.x, s(1) * h.y, s(2) * h.z)).z
        })
        .fold(f64::INFINITY, f64::min)
}

/// A random throw for `spec` that lands near the world origin (in front of the camera).
///
/// Two in five are skimming throws: a face within 15° of down, released 0.1-0.2 m up, spun
/// about the vertical (1-10 rad/s) and moving mostly sideways, so the box lands flat and
/// slides with spin; the others are tumbling throws in any orientation.
pub fn random_throw(spec: &BoxSpec, rng: &mut StdRng) -> Throw {
    let skim = rng.random_bool(0.4);
    let (rotation, drop, vz, spin) = if skim {
        let face = crate::spec::BoxFace::ALL[rng.random_range(0..6)];
        let down =
            UnitQuaternion::rotation_between(&face.normal(), &-Vector3::z()).unwrap_or_else(|| {
                UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI)
            });
        let yaw = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), rng.random_range(-3.2..3.2));
        let tip = UnitQuaternion::from_scaled_axis(
            random_unit_vector(rng).into_inner() * rng.random_range(0f64..15.0).to_radians(),
        );
        let spin = Vector3::z() * rng.random_range(-10.0..10.0)
            + random_unit_vector(rng).into_inner() * rng.random_range(0.0..1.0);
        (
            tip * yaw * down,
            rng.random_range(0.1..0.2),
            rng.random_range(-0.3..0.2),
            spin,
        )
    } else {
        (
            UnitQuaternion::from_scaled_axis(
                random_unit_vector(rng).into_inner() * rng.random_range(0.0..std::f64::consts::PI),
            ),
            rng.random_range(0.1..0.6),
            rng.random_range(-0.5..0.8),
            random_unit_vector(rng).into_inner() * rng.random_range(1.0..15.0),
        )
    };
    let speed = rng.random_range(0.2..1.5);
    let heading: f64 = rng.random_range(-3.2..3.2);
    let hold = rng.random_range(0.1..0.3);
    let velocity = Vector3::new(speed * heading.cos(), speed * heading.sin(), vz);
    let g = -GRAVITY[2];
    let t_fall = (vz + (vz * vz + 2.0 * g * drop).sqrt()) / g;
    let aim = Vector3::new(
        rng.random_range(-0.05..0.05),
        rng.random_range(-0.05..0.05),
        0.0,
    );
    let mut throw = Throw {
        rotation,
        com: aim - velocity.xy().push(0.0) * t_fall,
        velocity,
        spin,
        hold,
    };
    // Lift the release so that its lowest corner is `drop` above the table.
    throw.com.z = 0.0;
    throw.com.z = drop - lowest_corner(spec, &throw.pose_at(spec, 0.0));
    // The hand must not drag the box through the table before the release.
    while throw.hold > 0.02
        && (0..=20).any(|k| {
            let t = -throw.hold * k as f64 / 20.0;
            lowest_corner(spec, &throw.pose_at(spec, t)) < 0.03
        })
    {
        throw.hold *= 0.5;
    }
    throw
}

/// Run the toss scene.
pub fn run(spec: &BoxSpec, p: &PhysicsParams, rng: &mut StdRng) -> Result<SceneOutput> {
    let mu = rng.random_range(0.3..0.6);
    let restitution = rng.random_range(0.1..0.5);
    let throw = random_throw(spec, rng);
    let tail = if rng.random_bool(1.0 / 3.0) {
        rng.random_range(0.08..0.15)
    } else {
        rng.random_range(0.3..1.0)
    };
    run_with(spec, mu, restitution, &throw, tail, p)
}

/// Run a given throw onto a table of friction `mu` and restitution `restitution`, recording
/// until the box has rested `tail` seconds.
pub fn run_with(
    spec: &BoxSpec,
    mu: f64,
    restitution: f64,
    throw: &Throw,
    tail: f64,
    p: &PhysicsParams,
) -> Result<SceneOutput> {
    let mut run = Run::new(p);
    run.max_t = 20.0;
    run.world.add_table(mu);
    run.place_box(spec, mu, &throw.pose_at(spec, -throw.hold));
    let boxb = run.boxb;
    run.world.set_restitution(boxb, restitution);
    run.world.set_grasped(boxb, true);
    let dt = run.world.dt;
    let steps = (throw.hold / dt).round() as usize;
    for k in 1..=steps {
        let t = (k as f64 - steps as f64) * dt;
        run.world.set_kinematic(boxb, &throw.pose_at(spec, t));
        run.step()?;
    }
    let release = run.world.t;
    run.world.set_grasped(boxb, false);
    run.world.set_velocity(boxb, &throw.velocity, &throw.spin);
    run.settle(12.0)?;
    // `settle` stops 0.2 s after the box came to rest.
    let rest_start = run.world.t - 0.2;
    if tail > 0.2 {
        run.rest(tail - 0.2)?;
    }
    let mut out = run.finish(Script::default());
    let end = rest_start + tail;
    out.samples.retain(|s| s.t <= end + 1e-9);
    if out.samples.len() < 2 {
        return Err(SimError::Scene("the toss left no record".into()));
    }
    out.script = Script {
        mu,
        palm: false,
        motion_start: release,
        grasps: vec![(0.0, release)],
        notes: vec![
            ("restitution".into(), restitution),
            ("release_time".into(), release),
            (
                "release_height".into(),
                lowest_corner(spec, &throw.pose_at(spec, 0.0)),
            ),
            ("release_speed".into(), throw.velocity.norm()),
            ("release_vz".into(), throw.velocity.z),
            ("spin".into(), throw.spin.norm()),
            ("rest_start".into(), rest_start),
            ("tail".into(), tail),
        ],
        ..Default::default()
    };
    Ok(out)
}
