//! Direct topple (paper Fig. 3a): the box stands on a fixed table and a fingertip pushes it
//! above its centre of mass until it tips over a bottom edge onto the adjacent face.
//!
//! With the push at height `h` along a box axis, friction `μ` and the tipping edge at
//! horizontal distance `d` from the CoM, the box turns rather than slides when the push moment
//! beats the weight's, `F h > m g d`, before friction gives way, `F ≤ μ m g` (the smooth finger
//! adds no vertical load), i.e. when `h > d / μ`. The scene pushes at `h ≥ 1.3 d / μ`.

use super::push::{lowest_tipping_height, Finger, Push};
use super::{edge_lever, Run, SceneOutput, Script};
use crate::spec::BoxSpec;
use crate::world::PhysicsParams;
use crate::{Result, SimError};
use nalgebra::Vector3;
use rand::rngs::StdRng;
use rand::Rng;

/// Pushes that can topple `spec` with friction `mu`: `(axis, sign, lowest usable height)`.
pub fn feasible_pushes(spec: &BoxSpec, mu: f64) -> Vec<(usize, f64, f64)> {
    let hz = spec.dims[2];
    let mut out = Vec::new();
    for axis in 0..2 {
        for sign in [1.0, -1.0] {
            let (d, hc) = edge_lever(spec, axis, sign);
            // The finger must still touch the pushed face when the box has turned past its
            // balance.
            let corner = lowest_tipping_height(spec, axis, d, hc);
            let lo = (1.3 * d / mu).max(hc + 0.15 * (hz - hc)).max(corner);
            if lo < 0.9 * hz {
                out.push((axis, sign, lo));
            }
        }
    }
    out
}

/// Run the direct-topple scene.
pub fn run(spec: &BoxSpec, p: &PhysicsParams, rng: &mut StdRng) -> Result<SceneOutput> {
    let mu = spec.friction;
    let options = feasible_pushes(spec, mu);
    if options.is_empty() {
        return Err(SimError::InvalidSpec(format!(
            "box '{}' ({:?} m, friction {mu}) cannot be toppled by a push: every edge needs a push \
             above 90% of its height; raise the friction or use a taller box",
            spec.name, spec.dims
        )));
    }
    let (axis, sign, lo) = options[rng.random_range(0..options.len())];
    let h = spec.half_extents();
    let push = Push {
        axis,
        sign,
        height: rng.random_range(lo..0.9 * spec.dims[2]),
        lateral: rng.random_range(-0.15..0.15) * h[1 - axis],
        yaw: rng.random_range(-5f64..5.0).to_radians(),
        speed: rng.random_range(0.03..0.08),
    };
    let (d, hc) = edge_lever(spec, axis, sign);
    let phi = d.atan2(hc);

    let mut run = Run::on_table(spec, p, mu, rng);
    run.rest(1.0)?;
    let (start, e) = push.line(&run, spec);
    let mut finger = Finger::new(&mut run, start);
    let motion_start = run.world.t;
    let down = -Vector3::z();
    if !finger.tip_over(&mut run, start + e * 0.4, push.speed, &down, phi)? {
        return Err(SimError::Scene("the push did not tip the box".into()));
    }
    // Pull the finger back out of the way and let the box land.
    finger.withdraw(&mut run, &e)?;
    run.settle(6.0)?;
    run.rest(1.0)?;
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
        ],
        ..Default::default()
    };
    Ok(run.finish(script))
}
