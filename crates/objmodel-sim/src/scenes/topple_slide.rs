//! Topple then slide: a high push topples the box onto an adjacent face; then, after a rest, a
//! low off-centre push slides and turns it on that face — the mirror of [`super::compound`].
//!
//! Resting on face `(k0, s0)` (axis, sign), a push toward box direction `s1 e_{k1}` at height
//! `h` tips the box over that edge when `μ > d / h` (see [`super::topple`]) and leaves it flat
//! when `μ < d / h`, with lever `d = h_{k1} − s1 c_{k1}` (half extent minus CoM offset). The
//! high push (at `h_high = 0.88` of the standing height) needs `μ > 1.3 d₁ / h_high`; the low
//! push on the new face (at `h_low`, just above the fingertip's radius) needs
//! `μ < 0.6 d₂ / h_low`; the table's friction is the geometric mean of the two bounds.

use super::push::{lowest_tipping_height, Finger, Push, FINGER_RADIUS};
use super::{edge_lever, Run, SceneOutput, Script};
use crate::spec::BoxSpec;
use crate::world::PhysicsParams;
use crate::{Result, SimError};
use nalgebra::Vector3;
use rand::rngs::StdRng;
use rand::Rng;

/// Lever `d` and CoM height `h_c` for a box resting on face `(k0, s0)` tipping toward box
/// direction `s1 e_{k1}`.
pub fn lever_on(spec: &BoxSpec, k0: usize, s0: f64, k1: usize, s1: f64) -> (f64, f64) {
    let h = spec.half_extents();
    let c = spec.com_box();
    (h[k1] - s1 * c[k1], h[k0] - s0 * c[k0])
}

/// A topple, then a slide on the new face: `(topple axis, sign, slide axis, sign, μ)` choices.
fn options(spec: &BoxSpec, h_high: f64, h_low: f64) -> Vec<(usize, f64, usize, f64, f64)> {
    let mut out = Vec::new();
    for axis in 0..2 {
        for sign in [1.0, -1.0] {
            let (d, hc) = edge_lever(spec, axis, sign);
            let corner = lowest_tipping_height(spec, axis, d, hc);
            if h_high <= hc.max(corner) {
                continue;
            }
            let lo = 1.3 * d / h_high;
            // On its new face (k0 = axis, s0 = sign) the box can be pushed along the old z
            // axis or the other old horizontal axis.
            for k2 in [2, 1 - axis] {
                for s2 in [1.0, -1.0] {
                    let (d2, _) = lever_on(spec, axis, sign, k2, s2);
                    let hi = 0.6 * d2 / h_low;
                    if lo < hi {
                        out.push((axis, sign, k2, s2, (lo * hi).sqrt().min(1.2)));
                    }
                }
            }
        }
    }
    out
}

/// Run the topple-then-slide scene.
pub fn run(spec: &BoxSpec, p: &PhysicsParams, rng: &mut StdRng) -> Result<SceneOutput> {
    let hz = spec.dims[2];
    let h_high = 0.88 * hz;
    let h_low = FINGER_RADIUS + 0.003;
    let opts = options(spec, h_high, h_low);
    if opts.is_empty() {
        return Err(SimError::InvalidSpec(format!(
            "box '{}' has no edge that a high push topples and then a face that a low push slides",
            spec.name
        )));
    }
    let (axis, sign, k2, s2, mu) = opts[rng.random_range(0..opts.len())];
    let h = spec.half_extents();
    let topple = Push {
        axis,
        sign,
        height: h_high,
        lateral: rng.random_range(-0.1..0.1) * h[1 - axis],
        yaw: rng.random_range(-4f64..4.0).to_radians(),
        speed: rng.random_range(0.03..0.08),
    };
    let (d, hc) = edge_lever(spec, axis, sign);
    let phi = d.atan2(hc);

    let mut run = Run::on_table(spec, p, mu, rng);
    run.rest(1.0)?;
    let motion_start = run.world.t;
    let (start, e) = topple.line(&run, spec);
    let mut finger = Finger::new(&mut run, start);
    let down = -Vector3::z();
    if !finger.tip_over(&mut run, start + e * 0.4, topple.speed, &down, phi)? {
        return Err(SimError::Scene("the high push did not tip the box".into()));
    }
    finger.withdraw(&mut run, &e)?;
    run.settle(6.0)?;
    let mut new_down = Vector3::zeros();
    new_down[axis] = sign;
    if run.tilt(&new_down) > 3f64.to_radians() {
        return Err(SimError::Scene(
            "the box did not land on the face next to its edge".into(),
        ));
    }
    run.rest(rng.random_range(0.4..1.0))?;

    // The slide: push low along box axis k2 (horizontal now), off the centre line so it turns.
    let other = 3 - axis - k2;
    let side = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
    let slide = Push {
        axis: k2,
        sign: s2,
        height: h_low,
        lateral: side * rng.random_range(0.2..0.5) * h[other],
        yaw: rng.random_range(-10f64..10.0).to_radians(),
        speed: rng.random_range(0.05..0.1),
    };
    let distance = rng.random_range(0.05..0.1);
    let (start2, e2) = slide.line_up(&run, spec, axis, -sign);
    let safe = spec.dims.iter().cloned().fold(0.0, f64::max) + 0.03;
    let over = |v: &Vector3<f64>| Vector3::new(v.x, v.y, safe);
    let up = over(&finger.pos);
    finger.move_to(&mut run, up, 0.2, |_| false)?;
    finger.move_to(&mut run, over(&start2), 0.2, |_| false)?;
    finger.move_to(&mut run, start2, 0.2, |_| false)?;
    let second_phase = run.world.t;
    let max_tilt = finger.slide_to(
        &mut run,
        start2 + e2 * (0.015 + distance),
        slide.speed,
        &new_down,
    )?;
    if max_tilt > 5f64.to_radians() {
        return Err(SimError::Scene(format!(
            "the low push tipped the lying box by {:.1} deg",
            max_tilt.to_degrees()
        )));
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
            ("topple_axis".into(), axis as f64),
            ("topple_sign".into(), sign),
            ("topple_height".into(), h_high),
            ("topple_speed".into(), topple.speed),
            ("slide_axis".into(), k2 as f64),
            ("slide_sign".into(), s2),
            ("slide_height".into(), h_low),
            ("slide_lateral".into(), slide.lateral),
            ("slide_distance".into(), distance),
            ("slide_speed".into(), slide.speed),
        ],
        ..Default::default()
    };
    Ok(run.finish(script))
}
