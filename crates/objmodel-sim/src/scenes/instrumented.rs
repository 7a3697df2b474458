//! Instrumented topple (paper Fig. 7): the box stands on a plate held like a palm; the "user"
//! tilts the plate slowly about a horizontal axis until the box topples on it. Both the box and
//! the plate are tracked.
//!
//! Quasi-statically the box starts to turn about its downhill bottom edge when the tilt `θ`
//! carries the CoM's plumb line over that edge: `θ = φ = atan2(d, h_c)`, with `d` the distance
//! from the edge to the CoM measured along the face and `h_c` the CoM height above the face. It
//! slides first instead if `μ < tan φ`; the scene requires `μ ≥ 1.15 tan φ` and `φ ≤ 36°` (see [`MAX_PHI`]).
//!
//! The plate's tracked frame has its origin at the middle of its top surface and `z` along its
//! normal; the tilt axis lies in that surface, a few cm from the middle.

use super::{edge_lever, facing_yaw, resting_pose, Run, SceneOutput, Script};
use crate::spec::BoxSpec;
use crate::world::PhysicsParams;
use crate::{Result, SimError};
use nalgebra::{Isometry3, Translation3, Unit, UnitQuaternion, Vector3};
use rand::rngs::StdRng;
use rand::Rng;

/// Plate half extents \[m\]: 40 × 40 × 1 cm.
pub const PLATE_HALF: [f64; 3] = [0.2, 0.2, 0.005];

/// Rate at which the hand levels the palm again once the box is past its balance \[rad/s\].
pub const LEVEL_RATE: f64 = 1.0;

/// Largest tipping angle the scene accepts \[rad\] (36°): a box that topples at a steeper tilt
/// (a cube at 45°) lands hard and tumbles or slides off the palm. The standard brick's edges
/// at 34.7° are within it: it lands on the palm, and at real noise its topples teach φ within
/// their σ (6 of 6 tried).
pub const MAX_PHI: f64 = 0.628_318_530_717_958_6;

/// Options of an instrumented tilt.
#[derive(Debug, Clone, Copy)]
pub struct Tilt {
    /// Box axis (0 = x, 1 = y) pointing downhill, and its sign.
    pub axis: usize,
    /// Sign of the downhill box axis.
    pub sign: f64,
    /// Tilt rate \[rad/s\].
    pub rate: f64,
    /// Tilt axis offset from the plate middle, plate frame \[m\].
    pub pivot: [f64; 2],
    /// Stop tilting at this angle if the box has not toppled \[rad\].
    pub max_tilt: f64,
}

/// Run the instrumented-topple scene with a random tilt, towards the downhill edge `edge` (see
/// [`crate::SimOptions::edge`]) or a random one.
pub fn run(
    spec: &BoxSpec,
    p: &PhysicsParams,
    edge: Option<usize>,
    rng: &mut StdRng,
) -> Result<SceneOutput> {
    let mu = spec.friction;
    let topples = |d: f64, hc: f64| mu >= 1.15 * d / hc && d.atan2(hc) <= MAX_PHI;
    let Some(tilt) = random_tilt(spec, topples, edge, 80f64.to_radians(), rng) else {
        return Err(SimError::InvalidSpec(format!(
            "box '{}' ({:?} m) would slide on a tilted palm before toppling with friction {mu}: \
             every edge needs friction above 1.15 tan(phi), and a box whose tipping angle is above \
             36 deg tumbles down the palm",
            spec.name, spec.dims
        )));
    };
    run_with(spec, mu, &tilt, p, rng)
}

/// A tilt towards a downhill edge drawn among those whose lever `(d, h_c)` (see
/// [`edge_lever`]) `accept`s (or the `edge`-th of them, modulo their number), at a random rate
/// (2-5°/s) about a random pivot, up to `max_tilt`; `None` if no edge is accepted.
fn random_tilt(
    spec: &BoxSpec,
    accept: impl Fn(f64, f64) -> bool,
    edge: Option<usize>,
    max_tilt: f64,
    rng: &mut StdRng,
) -> Option<Tilt> {
    let mut options = Vec::new();
    for axis in 0..2 {
        for sign in [1.0, -1.0] {
            let (d, hc) = edge_lever(spec, axis, sign);
            if accept(d, hc) {
                options.push((axis, sign));
            }
        }
    }
    if options.is_empty() {
        return None;
    }
    // Drawn even when `edge` is given: the other draws stay as they were.
    let drawn = rng.random_range(0..options.len());
    let (axis, sign) = options[edge.map_or(drawn, |e| e % options.len())];
    Some(Tilt {
        axis,
        sign,
        rate: rng.random_range(2f64..5.0).to_radians(),
        pivot: [rng.random_range(-0.03..0.03), rng.random_range(-0.03..0.03)],
        max_tilt,
    })
}

/// A slide on the tilting palm: the palm's friction `mu` is too low for the box to topple
/// towards a random downhill edge (`μ <= tan φ / 1.15`), so the box starts to slide down the
/// palm when the tilt reaches `atan μ`; the hand levels the palm (at 4 times the rate it
/// tilted it) once it slid 3 cm. The script's notes hold the tilt where it started to move
/// (`slide_tilt`, 0.1 mm).
pub fn run_slide(
    spec: &BoxSpec,
    mu: f64,
    p: &PhysicsParams,
    rng: &mut StdRng,
) -> Result<SceneOutput> {
    let slides = |d: f64, hc: f64| 1.15 * mu <= d / hc;
    let Some(tilt) = random_tilt(spec, slides, None, 60f64.to_radians(), rng) else {
        return Err(SimError::InvalidSpec(format!(
            "box '{}' would topple on a palm of friction {mu} before it slides",
            spec.name
        )));
    };
    run_until(spec, mu, &tilt, Goal::Slide(0.03), p, rng)
}

/// Run the scene with a given tilt and friction `mu` (the validation tests call this).
pub fn run_with(
    spec: &BoxSpec,
    mu: f64,
    tilt: &Tilt,
    p: &PhysicsParams,
    rng: &mut StdRng,
) -> Result<SceneOutput> {
    run_until(spec, mu, tilt, Goal::Topple, p, rng)
}

/// What the tilting hand waits for before it levels the palm again.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Goal {
    /// The box toppled: it is well past its balance.
    Topple,
    /// The box slid this far \[m\] down the palm (a palm too slippery for it to topple:
    /// `μ < tan φ`; the tilt where it starts to slide is `atan μ`).
    Slide(f64),
}

/// Run the scene until `goal`, with friction `mu` between the box and the palm.
pub fn run_until(
    spec: &BoxSpec,
    mu: f64,
    tilt: &Tilt,
    goal: Goal,
    p: &PhysicsParams,
    rng: &mut StdRng,
) -> Result<SceneOutput> {
    let mut run = Run::new(p);
    let plate_yaw = rng.random_range(-3.2..3.2);
    let world_from_plate0 = Isometry3::from_parts(
        Translation3::new(0.0, 0.0, 0.25),
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), plate_yaw),
    );
    // Contacts take the smaller friction: the box's `mu` on a grippy palm (a topple), or a
    // slippery palm's `mu` (a slide).
    let plate_mu = match goal {
        Goal::Topple => mu.max(1.0),
        Goal::Slide(_) => mu,
    };
    let plate = run
        .world
        .add_plate(PLATE_HALF, plate_mu, &world_from_plate0);
    run.plate = Some(plate);
    let box_yaw = facing_yaw(spec, rng) - plate_yaw;
    let mut plate_from_box = resting_pose(spec, box_yaw, rng);
    // Downhill direction e; place the box uphill so that it lands on the plate after falling
    // a body height past its edge.
    let mut e_box = Vector3::zeros();
    e_box[tilt.axis] = tilt.sign;
    let e_plate = plate_from_box.rotation * e_box;
    let h_e = spec.half_extents()[tilt.axis];
    let shift = (PLATE_HALF[0] - 0.03 - h_e - spec.dims[2]).min(0.0);
    plate_from_box.translation.vector += e_plate * shift;
    run.place_box(spec, mu, &(world_from_plate0 * plate_from_box));
    run.rest(1.0)?;

    // Downhill direction e (world), tilt axis a = z × e through the pivot on the plate surface.
    let e = world_from_plate0.rotation * e_plate;
    let a = Unit::new_normalize(Vector3::z().cross(&e));
    let pivot = world_from_plate0 * nalgebra::Point3::new(tilt.pivot[0], tilt.pivot[1], 0.0);
    let plate_at = |theta: f64| {
        let r = UnitQuaternion::from_axis_angle(&a, theta);
        let about = Translation3::from(pivot.coords)
            * Isometry3::from_parts(Translation3::identity(), r)
            * Translation3::from(-pivot.coords);
        about * world_from_plate0
    };

    let motion_start = run.world.t;
    let down = -Vector3::z();
    let ramp = 0.5; // s to reach full rate (smooth start, as a hand would)
    let mut theta = 0.0;
    let mut t_local = 0.0;
    let mut toppled_at = None;
    let mut past = false;
    let box_on_plate = |run: &Run| {
        (run.world.pose(plate).inverse() * run.world.pose(run.boxb))
            .translation
            .vector
    };
    let start_on_plate = box_on_plate(&run);
    let mut slide_start: Option<f64> = None;
    let (d, hc) = edge_lever(spec, tilt.axis, tilt.sign);
    let phi = d.atan2(hc);
    loop {
        t_local += run.world.dt;
        let rate = tilt.rate * (t_local / ramp).min(1.0);
        if !past {
            theta += rate * run.world.dt;
            past = match goal {
                // Once the box is well past its balance, the hand levels the palm to catch it.
                Goal::Topple => run.tilt(&down) > phi + 10f64.to_radians(),
                // Once it slid far enough, the hand levels the palm to stop it.
                Goal::Slide(distance) => {
                    let moved = (box_on_plate(&run) - start_on_plate).norm();
                    if moved > 1e-4 && slide_start.is_none() {
                        slide_start = Some(theta);
                    }
                    moved > distance
                }
            };
        } else {
            // A slide is stopped gently: the palm levelled at 4 times the rate it was tilted.
            let level_rate = match goal {
                Goal::Topple => LEVEL_RATE,
                Goal::Slide(_) => 4.0 * tilt.rate,
            };
            theta = (theta - level_rate * run.world.dt).max(0.0);
        }
        if theta > tilt.max_tilt {
            return Err(SimError::Scene(
                "the palm reached its maximum tilt without a topple".into(),
            ));
        }
        run.world.set_kinematic(plate, &plate_at(theta));
        run.step()?;
        if past && theta == 0.0 && matches!(goal, Goal::Slide(_)) && run.box_at_rest() {
            break;
        }
        if toppled_at.is_none() && run.tilt(&down) > 45f64.to_radians() {
            toppled_at = Some(run.world.t);
        }
        if let Some(t0) = toppled_at {
            if theta == 0.0 && run.world.t - t0 > 0.3 && run.box_at_rest() {
                break;
            }
            if run.world.t - t0 > 6.0 {
                return Err(SimError::Scene(
                    "the box did not come to rest on the palm".into(),
                ));
            }
        }
    }
    run.settle(4.0)?;
    run.rest(1.0)?;
    let script = Script {
        mu,
        palm: true,
        motion_start,
        notes: vec![
            ("downhill_axis".into(), tilt.axis as f64),
            ("downhill_sign".into(), tilt.sign),
            ("tilt_rate".into(), tilt.rate),
            ("final_tilt".into(), theta),
        ]
        .into_iter()
        .chain(slide_start.map(|s| ("slide_tilt".into(), s)))
        .collect(),
        ..Default::default()
    };
    Ok(run.finish(script))
}
