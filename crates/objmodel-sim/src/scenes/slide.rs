//! Slide (paper Fig. 3b): a low push on a low-friction table, off the face's centre line, so the
//! box slides and turns on its bottom face without tipping.
//!
//! The box stays flat while the push height satisfies `h < d / μ` (see [`super::topple`]); the
//! scene pushes at `h ≤ 0.5 d / μ`.

use super::push::{Finger, Push, FINGER_RADIUS};
use super::{edge_lever, Run, SceneOutput, Script};
use crate::spec::BoxSpec;
use crate::world::PhysicsParams;
use crate::{Result, SimError};
use nalgebra::Vector3;
use rand::rngs::StdRng;
use rand::Rng;

/// Run the slide scene.
pub fn run(spec: &BoxSpec, p: &PhysicsParams, rng: &mut StdRng) -> Result<SceneOutput> {
    let mu = rng.random_range(0.12..0.3f64).min(spec.friction);
    let axis = rng.random_range(0..2usize);
    let sign = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
    let (d, _) = edge_lever(spec, axis, sign);
    let h = spec.half_extents();
    let lo = FINGER_RADIUS + 0.002;
    let hi = (0.35 * spec.dims[2]).min(0.5 * d / mu);
    if hi <= lo {
        return Err(SimError::InvalidSpec(format!(
            "box '{}' is too low to push without tipping",
            spec.name
        )));
    }
    let side = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
    let push = Push {
        axis,
        sign,
        height: rng.random_range(lo..hi),
        lateral: side * rng.random_range(0.3..0.7) * h[1 - axis],
        yaw: rng.random_range(-15f64..15.0).to_radians(),
        speed: rng.random_range(0.05..0.12),
    };
    let distance = rng.random_range(0.06..0.14);

    let mut run = Run::on_table(spec, p, mu, rng);
    run.rest(1.0)?;
    let (start, e) = push.line(&run, spec);
    let mut finger = Finger::new(&mut run, start);
    let motion_start = run.world.t;
    let down = -Vector3::z();
    let max_tilt = finger.slide_to(&mut run, start + e * (0.015 + distance), push.speed, &down)?;
    finger.withdraw(&mut run, &e)?;
    run.settle(6.0)?;
    run.rest(1.0)?;
    if max_tilt > 5f64.to_radians() {
        return Err(SimError::Scene(format!(
            "the box tipped by {:.1} deg while sliding",
            max_tilt.to_degrees()
        )));
    }
    let script = Script {
        mu,
        palm: false,
        motion_start,
        notes: vec![
            ("push_axis".into(), axis as f64),
            ("push_sign".into(), sign),
            ("push_height".into(), push.height),
            ("push_lateral".into(), push.lateral),
            ("push_yaw".into(), push.yaw),
            ("push_speed".into(), push.speed),
            ("push_distance".into(), distance),
        ],
        ..Default::default()
    };
    Ok(run.finish(script))
}
