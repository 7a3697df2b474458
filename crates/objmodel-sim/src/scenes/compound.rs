//! Compound (the paper's future work): one demonstration in which the box is first pushed low
//! and slides, then pushed high and topples — it exercises temporal segmentation.
//!
//! With `d` the lever of the tipping edge, the low push at `h_low` slides the box when
//! `μ < d / h_low` and the high push at `h_high` topples it when `μ > d / h_high`; the table's
//! friction is the geometric mean of `1.3 d / h_high` and `0.6 d / h_low`.

use super::push::{lowest_tipping_height, Finger, Push, FINGER_RADIUS};
use super::{edge_lever, Run, SceneOutput, Script};
use crate::spec::BoxSpec;
use crate::world::PhysicsParams;
use crate::{Result, SimError};
use nalgebra::Vector3;
use rand::rngs::StdRng;
use rand::Rng;

/// Run the compound scene.
pub fn run(spec: &BoxSpec, p: &PhysicsParams, rng: &mut StdRng) -> Result<SceneOutput> {
    let hz = spec.dims[2];
    let h_low = (FINGER_RADIUS + 0.003).max(0.12 * hz);
    let h_high = 0.88 * hz;
    let mut options = Vec::new();
    for axis in 0..2 {
        for sign in [1.0, -1.0] {
            let (d, hc) = edge_lever(spec, axis, sign);
            let (lo, hi) = (1.3 * d / h_high, 0.6 * d / h_low);
            let corner = lowest_tipping_height(spec, axis, d, hc);
            if lo < hi && h_high > hc && h_high > corner {
                options.push((axis, sign, (lo * hi).sqrt()));
            }
        }
    }
    if options.is_empty() {
        return Err(SimError::InvalidSpec(format!(
            "box '{}' has no edge that a high push topples and a low push slides",
            spec.name
        )));
    }
    let (axis, sign, mu) = options[rng.random_range(0..options.len())];
    let h = spec.half_extents();
    let mut push = Push {
        axis,
        sign,
        height: h_low,
        lateral: rng.random_range(-0.1..0.1) * h[1 - axis],
        yaw: rng.random_range(-5f64..5.0).to_radians(),
        speed: rng.random_range(0.04..0.08),
    };
    let slide_distance = rng.random_range(0.05..0.09);
    let (d, hc) = edge_lever(spec, axis, sign);
    let phi = d.atan2(hc);

    let mut run = Run::on_table(spec, p, mu, rng);
    run.rest(1.0)?;
    let motion_start = run.world.t;
    let (start, e) = push.line(&run, spec);
    let mut finger = Finger::new(&mut run, start);
    let down = -Vector3::z();
    let max_tilt = finger.slide_to(
        &mut run,
        start + e * (0.015 + slide_distance),
        push.speed,
        &down,
    )?;
    if max_tilt > 5f64.to_radians() {
        return Err(SimError::Scene("the low push tipped the box".into()));
    }
    // Back off, let the box stop, rise, and aim the high push at the box where it now is.
    finger.withdraw(&mut run, &e)?;
    run.settle(4.0)?;
    run.rest(rng.random_range(0.3..0.8))?;
    push.height = h_high;
    push.lateral = 0.0;
    push.yaw = rng.random_range(-3f64..3.0).to_radians();
    let (start2, e2) = push.line(&run, spec);
    let up = Vector3::new(finger.pos.x, finger.pos.y, h_high);
    finger.move_to(&mut run, up, 0.1, |_| false)?;
    finger.move_to(&mut run, start2, 0.1, |_| false)?;
    let second_phase = run.world.t;
    if !finger.tip_over(&mut run, start2 + e2 * 0.4, push.speed, &down, phi)? {
        return Err(SimError::Scene("the high push did not tip the box".into()));
    }
    finger.withdraw(&mut run, &e2)?;
    run.settle(6.0)?;
    run.rest(1.0)?;
    let script = Script {
        mu,
        palm: false,
        motion_start,
        second_phase: Some(second_phase),
        notes: vec![
            ("push_axis".into(), axis as f64),
            ("push_sign".into(), sign),
            ("slide_height".into(), h_low),
            ("topple_height".into(), h_high),
            ("slide_distance".into(), slide_distance),
            ("push_speed".into(), push.speed),
        ],
        ..Default::default()
    };
    Ok(run.finish(script))
}
