//! A long session: 4-6 demonstrations in a row on one table — topples (a high push), slides (a
//! low off-centre push) and carries (grasp, lift, turn, put down) — with rests of 0.5-1.5 s
//! between them, in one file, as a motion-capture log of a whole session would hold them.
//!
//! Each action starts from the face the box rests on now. A topple or slide that this face
//! cannot give with the table's friction (see [`super::topple_slide`] for the bounds) becomes a
//! carry that stands the box back on its `-z` face, where both are possible (the table's
//! friction is chosen for that face as in [`super::compound`]).
//!
//! The script's notes list `action_i` for each action: 0 topple, 1 slide, 2 carry.

use super::carry::{self, CarryPath};
use super::push::{lowest_tipping_height, Finger, Push, FINGER_RADIUS};
use super::topple_slide::lever_on;
use super::{facing_yaw, Run, SceneOutput, Script};
use crate::events::rest_face;
use crate::spec::{BoxFace, BoxSpec};
use crate::world::PhysicsParams;
use crate::{Result, SimError};
use nalgebra::{Unit, UnitQuaternion, Vector2, Vector3};
use rand::rngs::StdRng;
use rand::Rng;

/// Where the finger waits between pushes, out of the way \[m\].
const PARK: [f64; 3] = [0.0, 0.8, 0.6];

/// A push from the current resting face `(k0, s0)` toward box direction `(k1, s1)`: its height
/// and whether it topples (else it slides), if friction `mu` allows it.
fn push_height(
    spec: &BoxSpec,
    mu: f64,
    rest: BoxFace,
    k1: usize,
    s1: f64,
    topple: bool,
) -> Option<f64> {
    let (k0, s0) = rest.axis_sign();
    let (d, hc) = lever_on(spec, k0, s0, k1, s1);
    if topple {
        let h_high = 0.88 * spec.dims[k0];
        let corner = lowest_tipping_height(spec, k1, d, hc);
        (h_high > hc.max(corner) && mu > 1.3 * d / h_high).then_some(h_high)
    } else {
        let h_low = FINGER_RADIUS + 0.003;
        (mu < 0.6 * d / h_low).then_some(h_low)
    }
}

/// Friction for which the `-z` face can be both toppled and slid, or None.
fn session_mu(spec: &BoxSpec) -> Option<f64> {
    for k1 in 0..2 {
        for s1 in [1.0, -1.0] {
            let (d, hc) = lever_on(spec, 2, -1.0, k1, s1);
            let h_high = 0.88 * spec.dims[2];
            let corner = lowest_tipping_height(spec, k1, d, hc);
            if h_high <= hc.max(corner) {
                continue;
            }
            let lo = 1.3 * d / h_high;
            // Some low push must slide: the largest slide bound over the four directions.
            let hi = (0..2)
                .flat_map(|k| [1.0, -1.0].map(|s| 0.6 * lever_on(spec, 2, -1.0, k, s).0))
                .fold(0.0, f64::max)
                / (FINGER_RADIUS + 0.003);
            if lo < hi {
                return Some((lo * hi).sqrt().min(1.2));
            }
        }
    }
    None
}

/// Push the box (resting on `rest`) toward `(k1, s1)` at `height`: a topple until it has
/// turned past its balance, or a slide of 5-10 cm.
fn push(
    run: &mut Run,
    finger: &mut Finger,
    spec: &BoxSpec,
    rest: BoxFace,
    (k1, s1, height, topple): (usize, f64, f64, bool),
    rng: &mut StdRng,
) -> Result<()> {
    let (k0, s0) = rest.axis_sign();
    let other = 3 - k0 - k1;
    let h = spec.half_extents();
    let p = Push {
        axis: k1,
        sign: s1,
        height,
        lateral: if topple {
            rng.random_range(-0.1..0.1) * h[other]
        } else {
            (if rng.random_bool(0.5) { 1.0 } else { -1.0 }) * rng.random_range(0.2..0.5) * h[other]
        },
        yaw: rng.random_range(-5f64..5.0).to_radians(),
        speed: rng.random_range(0.04..0.08),
    };
    let (start, e) = p.line_up(run, spec, k0, -s0);
    let safe = spec.dims.iter().cloned().fold(0.0, f64::max) + 0.05;
    finger.teleport(run, Vector3::new(start.x, start.y, safe))?;
    finger.move_to(run, start, 0.2, |_| false)?;
    let down = rest.normal();
    if topple {
        let (d, hc) = lever_on(spec, k0, s0, k1, s1);
        if !finger.tip_over(run, start + e * 0.4, p.speed, &down, d.atan2(hc))? {
            return Err(SimError::Scene("a session push did not tip the box".into()));
        }
    } else {
        let distance = rng.random_range(0.05..0.1);
        let max_tilt = finger.slide_to(run, start + e * (0.015 + distance), p.speed, &down)?;
        if max_tilt > 5f64.to_radians() {
            return Err(SimError::Scene("a session slide tipped the box".into()));
        }
    }
    finger.withdraw(run, &e)?;
    let up = Vector3::new(finger.pos.x, finger.pos.y, safe);
    finger.move_to(run, up, 0.2, |_| false)?;
    finger.teleport(run, Vector3::from(PARK))
}

/// Grasp the box, lift it, turn it and put it down on `face` (yaw `yaw`) near the origin.
fn carry(
    run: &mut Run,
    spec: &BoxSpec,
    end_face: BoxFace,
    end_yaw: f64,
    rng: &mut StdRng,
) -> Result<(f64, f64)> {
    let p0 = run.world.pose(run.boxb);
    let end_xy = Vector2::new(rng.random_range(-0.1..0.1), rng.random_range(-0.1..0.1));
    let lift = rng.random_range(0.08..0.15);
    let axis = Unit::new_normalize(Vector3::new(
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
        rng.random_range(0.2..1.0),
    ));
    let path = CarryPath {
        lift,
        mid_xy: (p0.translation.vector.xy() + end_xy) * 0.5,
        mid_rotation: UnitQuaternion::from_axis_angle(&axis, rng.random_range(0.5..1.5))
            * p0.rotation,
        end_face,
        end_yaw,
        end_xy,
    };
    let durations: [f64; 4] = std::array::from_fn(|leg| {
        if leg == 3 {
            rng.random_range(0.5..0.9)
        } else {
            rng.random_range(0.7..1.3)
        }
    });
    carry::carry(run, &path.key_poses(spec, &p0), &durations)
}

/// Run the session scene.
pub fn run(spec: &BoxSpec, p: &PhysicsParams, rng: &mut StdRng) -> Result<SceneOutput> {
    let mu = session_mu(spec).ok_or_else(|| {
        SimError::InvalidSpec(format!(
            "box '{}' cannot be both toppled and slid on its -z face by a push",
            spec.name
        ))
    })?;
    let mut run = Run::on_table(spec, p, mu, rng);
    let mut finger = Finger::new(&mut run, Vector3::from(PARK));
    run.rest(1.0)?;
    let motion_start = run.world.t;
    let n = rng.random_range(4..=6usize);
    let mut grasps = Vec::new();
    let mut notes = vec![("actions".to_string(), n as f64)];
    // Every kind of action at least once, the rest drawn.
    let mut plan: Vec<u8> = vec![0, 1, 2];
    while plan.len() < n {
        plan.push(rng.random_range(0..3u8));
    }
    for i in (1..plan.len()).rev() {
        plan.swap(i, rng.random_range(0..=i));
    }
    for (i, &want) in plan.iter().enumerate() {
        let rest = rest_face(run.samples.last().expect("a sample"));
        let (k0, _) = rest.axis_sign();
        let mut choices = Vec::new();
        if want < 2 {
            for k1 in (0..3).filter(|&k| k != k0) {
                for s1 in [1.0, -1.0] {
                    if let Some(h) = push_height(spec, mu, rest, k1, s1, want == 0) {
                        choices.push((k1, s1, h, want == 0));
                    }
                }
            }
        }
        let done = if choices.is_empty() {
            // A carry: to a random face, or back on -z when a push could not be made.
            let face = if want == 2 {
                BoxFace::ALL[rng.random_range(0..6)]
            } else {
                BoxFace::NegZ
            };
            let yaw = facing_yaw(spec, rng);
            grasps.push(carry(&mut run, spec, face, yaw, rng)?);
            2
        } else {
            let c = choices[rng.random_range(0..choices.len())];
            push(&mut run, &mut finger, spec, rest, c, rng)?;
            want
        };
        run.settle(6.0)?;
        notes.push((format!("action_{}", i + 1), done as f64));
        run.rest(rng.random_range(0.5..1.5))?;
    }
    run.rest(0.5)?;
    notes.push(("friction".into(), mu));
    let script = Script {
        mu,
        palm: false,
        motion_start,
        grasps,
        notes,
        ..Default::default()
    };
    Ok(run.finish(script))
}
