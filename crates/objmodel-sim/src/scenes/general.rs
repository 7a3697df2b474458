//! General motion (paper Fig. 3c): the box is grasped, lifted, carried and turned in the air,
//! and put down again — possibly on another face.
//!
//! The grasp is kinematic: while held the box follows a chain of key poses with minimum-jerk
//! timing `s(τ) = 10τ³ − 15τ⁴ + 6τ⁵` (translation interpolated linearly in `s`, rotation by
//! slerp), then it is released 1.5 mm above the table at rest and falls into place.

use super::{facing_yaw, resting_pose, Run, SceneOutput, Script};
use crate::spec::{BoxFace, BoxSpec};
use crate::world::PhysicsParams;
use crate::Result;
use nalgebra::{Isometry3, Translation3, Unit, UnitQuaternion, Vector3};
use rand::rngs::StdRng;
use rand::Rng;

/// Minimum-jerk timing `s(τ) = 10τ³ − 15τ⁴ + 6τ⁵` of `τ` clamped to \[0, 1\].
pub fn min_jerk(tau: f64) -> f64 {
    let t = tau.clamp(0.0, 1.0);
    t * t * t * (10.0 - 15.0 * t + 6.0 * t * t)
}

fn random_axis(rng: &mut StdRng) -> Unit<Vector3<f64>> {
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

/// Run the general-motion scene.
pub fn run(spec: &BoxSpec, p: &PhysicsParams, rng: &mut StdRng) -> Result<SceneOutput> {
    let mu = spec.friction;
    let mut run = Run::new(p);
    run.world.add_table(mu);
    let yaw = facing_yaw(spec, rng);
    let start = resting_pose(spec, yaw, rng);
    run.place_box(spec, mu, &start);
    run.rest(1.0)?;
    let p0 = run.world.pose(run.boxb);

    // Where it ends: resting on a random face, with a random yaw, 10-25 cm away.
    let face = BoxFace::ALL[rng.random_range(0..6)];
    let n = face.normal();
    let (k, _) = face.axis_sign();
    let down_rot = UnitQuaternion::rotation_between(&n, &-Vector3::z()).unwrap_or_else(|| {
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI)
    });
    let end_rot =
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), rng.random_range(-3.2..3.2)) * down_rot;
    let dist = rng.random_range(0.1..0.25);
    let dir = rng.random_range(-3.2f64..3.2);
    let end_xy = p0.translation.vector.xy() + nalgebra::Vector2::new(dir.cos(), dir.sin()) * dist;
    let rest_h = spec.half_extents()[k] + 0.0015;
    let end = Isometry3::from_parts(Translation3::new(end_xy.x, end_xy.y, rest_h), end_rot);

    let lift = rng.random_range(0.08..0.18);
    let mid_rot = UnitQuaternion::from_axis_angle(&random_axis(rng), rng.random_range(0.6..2.0))
        * p0.rotation;
    let mid_xy = (p0.translation.vector.xy() + end_xy) * 0.5
        + nalgebra::Vector2::new(rng.random_range(-0.05..0.05), rng.random_range(-0.05..0.05));
    let keys = [
        p0,
        Isometry3::from_parts(
            Translation3::from(p0.translation.vector + Vector3::z() * lift),
            p0.rotation,
        ),
        Isometry3::from_parts(
            Translation3::new(mid_xy.x, mid_xy.y, rest_h + lift + 0.05),
            mid_rot,
        ),
        Isometry3::from_parts(
            Translation3::new(end_xy.x, end_xy.y, rest_h + 0.04),
            end_rot,
        ),
        end,
    ];
    let durations: Vec<f64> = (0..4)
        .map(|i| {
            if i == 3 {
                rng.random_range(0.6..1.0)
            } else {
                rng.random_range(0.8..1.6)
            }
        })
        .collect();

    let boxb = run.boxb;
    run.world.set_grasped(boxb, true);
    let grasp = run.world.t;
    for (i, dur) in durations.iter().enumerate() {
        let (a, b) = (keys[i], keys[i + 1]);
        let t0 = run.world.t;
        while run.world.t < t0 + dur - 0.5 * run.world.dt {
            let s = min_jerk((run.world.t + run.world.dt - t0) / dur);
            let tr = a.translation.vector.lerp(&b.translation.vector, s);
            let rot = a.rotation.slerp(&b.rotation, s);
            run.world
                .set_kinematic(boxb, &Isometry3::from_parts(Translation3::from(tr), rot));
            run.step()?;
        }
    }
    run.world.set_grasped(boxb, false);
    let release = run.world.t;
    run.settle(4.0)?;
    run.rest(1.0)?;
    let _ = start;
    let script = Script {
        mu,
        palm: false,
        motion_start: grasp,
        carry: Some((grasp, release)),
        notes: vec![
            ("lift".into(), lift),
            ("carry_distance".into(), dist),
            ("final_face".into(), k as f64),
        ],
        ..Default::default()
    };
    Ok(run.finish(script))
}
