//! General motion (paper Fig. 3c): the box is grasped, lifted, carried and turned in the air,
//! and put down again — possibly on another face.
//!
//! The carry itself is [`super::carry`]'s; this scene draws where it goes: to rest on a random
//! face with a random yaw, 10-25 cm away.

use super::carry::{carry, CarryPath};
use super::{random_unit_vector, Run, SceneOutput, Script};
use crate::spec::{BoxFace, BoxSpec};
use crate::world::PhysicsParams;
use crate::Result;
use nalgebra::{UnitQuaternion, Vector2};
use rand::rngs::StdRng;
use rand::Rng;

/// Run the general-motion scene.
pub fn run(spec: &BoxSpec, p: &PhysicsParams, rng: &mut StdRng) -> Result<SceneOutput> {
    let mu = spec.friction;
    let mut run = Run::on_table(spec, p, mu, rng);
    run.rest(1.0)?;
    let p0 = run.world.pose(run.boxb);

    // Where it ends: resting on a random face, with a random yaw, 10-25 cm away.
    let end_face = BoxFace::ALL[rng.random_range(0..6)];
    let (k, _) = end_face.axis_sign();
    let end_yaw = rng.random_range(-3.2..3.2);
    let dist = rng.random_range(0.1..0.25);
    let dir = rng.random_range(-3.2f64..3.2);
    let end_xy = p0.translation.vector.xy() + Vector2::new(dir.cos(), dir.sin()) * dist;
    let lift = rng.random_range(0.08..0.18);
    let mid_rotation =
        UnitQuaternion::from_axis_angle(&random_unit_vector(rng), rng.random_range(0.6..2.0))
            * p0.rotation;
    let mid_xy = (p0.translation.vector.xy() + end_xy) * 0.5
        + Vector2::new(rng.random_range(-0.05..0.05), rng.random_range(-0.05..0.05));
    let path = CarryPath {
        lift,
        mid_xy,
        mid_rotation,
        end_face,
        end_yaw,
        end_xy,
    };
    let durations: [f64; 4] = std::array::from_fn(|leg| {
        if leg == 3 {
            rng.random_range(0.6..1.0)
        } else {
            rng.random_range(0.8..1.6)
        }
    });
    let (grasp, release) = carry(&mut run, &path.key_poses(spec, &p0), &durations)?;
    run.settle(4.0)?;
    run.rest(1.0)?;
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
