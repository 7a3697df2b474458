//! The tilt at which a body resting on a palm starts to topple: the palm (a 40 × 40 cm plate)
//! tilts slowly about a horizontal axis through its middle, with the body resting on a given
//! face and the tilt carrying it towards a given direction, until it tips over the downhill
//! edge of that face or slides.
//!
//! Quasi-statically the body tips when the tilt reaches `φ = atan2(d, h)` ([`tipping_angle`]):
//! `d` the distance along the face from the CoM's projection to the downhill edge, `h` the
//! CoM's height above the face; it slides first if `tan φ > μ`. The simulated palm starts a few
//! degrees below that angle, holds still while the body settles, and tilts at [`RATE`]; the
//! onset is the last tilt at which the body was within [`STILL_RAD`] of its settled attitude
//! on the palm, once it has turned [`TIPPED_RAD`] (a topple) or moved [`SLID_M`] along the palm
//! first (a slide).

use crate::rigid::RigidModel;
use crate::scenes::instrumented::PLATE_HALF;
use crate::world::{PhysicsParams, World};
use nalgebra::{Isometry3, Matrix3, Point3, Rotation3, Translation3, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

/// Tilt rate of the palm \[rad/s\] (1°/s).
pub const RATE: f64 = 0.017_453_292_519_943_295;
/// The body has started to topple when it has turned this much on the palm \[rad\] (2°).
pub const TIPPED_RAD: f64 = 0.034_906_585_039_886_59;
/// It is still at rest on the palm while within this angle of its settled attitude \[rad\]
/// (0.1°: contact compliance turns a resting body by far less).
pub const STILL_RAD: f64 = 0.001_745_329_251_994_329_5;
/// It has slid when the middle of its downhill edge has moved this far along the palm \[m\].
pub const SLID_M: f64 = 2e-3;
/// Degrees below the quasi-static angle at which the palm starts.
pub const START_BELOW_DEG: f64 = 4.0;

/// What the body did on the tilting palm.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "what", content = "tilt_rad")]
pub enum Onset {
    /// It started to topple at this tilt \[rad\].
    Topples(f64),
    /// It started to slide at this tilt \[rad\].
    Slides(f64),
    /// Nothing happened up to the end of the tilt.
    Neither,
}

/// The quasi-static tipping angle \[rad\] of `model` resting on its face of outward normal `n`
/// (body frame) when the tilt carries it towards `e` (body frame, along the face), from its
/// corners and CoM.
pub fn tipping_angle(model: &RigidModel, n: &Vector3<f64>, e: &Vector3<f64>) -> f64 {
    let corners = model.corners();
    let low = corners.iter().map(|c| n.dot(c)).fold(f64::MIN, f64::max);
    let h = low - n.dot(&model.com);
    let d = corners
        .iter()
        .filter(|c| n.dot(c) > low - 1e-6)
        .map(|c| e.dot(&(c - model.com)))
        .fold(f64::MIN, f64::max);
    d.atan2(h)
}

/// The middle of the edge of `model`'s face `n` that lies farthest along `e` (body frame).
fn downhill_edge_middle(model: &RigidModel, n: &Vector3<f64>, e: &Vector3<f64>) -> Vector3<f64> {
    let corners = model.corners();
    let low = corners.iter().map(|c| n.dot(c)).fold(f64::MIN, f64::max);
    let face: Vec<&Vector3<f64>> = corners.iter().filter(|c| n.dot(c) > low - 1e-6).collect();
    let far = face.iter().map(|c| e.dot(c)).fold(f64::MIN, f64::max);
    let edge: Vec<&&Vector3<f64>> = face.iter().filter(|c| e.dot(c) > far - 1e-6).collect();
    edge.iter().map(|c| **c).sum::<Vector3<f64>>() / edge.len() as f64
}

/// `world_from_body` of `model` resting on its face `n` on the palm's top surface (the plane
/// `z = 0` of `world_from_palm`), CoM above the palm's middle, `e` along the palm's `x`.
fn resting_on(
    model: &RigidModel,
    n: &Vector3<f64>,
    e: &Vector3<f64>,
    world_from_palm: &Isometry3<f64>,
) -> Isometry3<f64> {
    let from = Matrix3::from_columns(&[*e, n.cross(e), *n]);
    let to = Matrix3::from_columns(&[Vector3::<f64>::x(), -Vector3::y(), -Vector3::z()]);
    let r = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(
        to * from.transpose(),
    ));
    let lowest = model
        .corners()
        .iter()
        .map(|c| (r * c).z)
        .fold(f64::MAX, f64::min);
    let com = r * model.com;
    let palm_from_body =
        Isometry3::from_parts(Translation3::new(-com.x, -com.y, -lowest + 1e-4), r);
    world_from_palm * palm_from_body
}

/// Tilt the palm under `model` resting on its face `n` towards `e` (body frame; `e` is made
/// perpendicular to `n`), friction `mu` between them, from [`START_BELOW_DEG`] below the
/// quasi-static angle `phi` (\[rad\]) up to `phi` plus `beyond` \[rad\].
pub fn onset(
    model: &RigidModel,
    n: &Vector3<f64>,
    e: &Vector3<f64>,
    mu: f64,
    phi: f64,
    beyond: f64,
) -> Onset {
    let n = n.normalize();
    let e = (e - n * n.dot(e)).normalize();
    let mut world = World::new(&PhysicsParams::default());
    let start = (phi - START_BELOW_DEG.to_radians()).max(0.0);
    let pivot = Vector3::new(0.0, 0.0, 0.3);
    let palm_at = |theta: f64| {
        Isometry3::from_parts(
            Translation3::from(pivot),
            UnitQuaternion::from_axis_angle(&Vector3::y_axis(), theta),
        )
    };
    let plate = world.add_plate(PLATE_HALF, mu, &palm_at(start));
    let Some((b, c)) = model.builders(mu, &resting_on(model, &n, &e, &palm_at(start))) else {
        return Onset::Neither;
    };
    let body = world.add_body(b, c);
    let relative = |w: &World| w.pose(plate).inverse() * w.pose(body);
    // The middle of the downhill edge: it stays put on the palm while the body tips about it.
    let pivot_point = Point3::from(downhill_edge_middle(model, &n, &e));
    let com_on_palm = |w: &World| relative(w) * pivot_point;
    // Settle for half a second at the start tilt.
    let settle_steps = (0.5 / world.dt) as usize;
    for _ in 0..settle_steps {
        world.set_kinematic(plate, &palm_at(start));
        world.step();
    }
    let settled = relative(&world);
    let settled_com = com_on_palm(&world);
    let (mut theta, mut last_still) = (start, start);
    let end = phi + beyond;
    while theta < end {
        theta += RATE * world.dt;
        world.set_kinematic(plate, &palm_at(theta));
        world.step();
        let turned = settled.rotation.angle_to(&relative(&world).rotation);
        let moved = (com_on_palm(&world) - settled_com).xy().norm();
        if turned <= STILL_RAD && moved < SLID_M / 4.0 {
            last_still = theta;
        }
        if turned > TIPPED_RAD {
            return Onset::Topples(last_still);
        }
        if moved > SLID_M {
            return Onset::Slides(last_still);
        }
    }
    Onset::Neither
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spec::BoxSpec;

    /// A box with an offset CoM tips within half a degree of its quasi-static angle, towards
    /// each side of its bottom face, and a slippery one slides instead.
    #[test]
    fn a_box_tips_at_its_quasi_static_angle() {
        let spec = BoxSpec::new("b", [0.08, 0.1, 0.16], 0.6).with_com([0.01, 0.0, -0.02]);
        let m = RigidModel::of_box(&spec);
        let n = -Vector3::z();
        for e in [Vector3::x(), -Vector3::x(), Vector3::y()] {
            let phi = tipping_angle(&m, &n, &e);
            let h = 0.08 - 0.02;
            let d = e.abs().dot(&spec.half_extents()) - e.dot(&spec.com_box().coords);
            assert!((phi - d.atan2(h)).abs() < 1e-12);
            match onset(&m, &n, &e, 1.0, phi, 3f64.to_radians()) {
                Onset::Topples(t) => {
                    assert!((t - phi).abs() < 0.5f64.to_radians(), "{e}: {t} vs {phi}")
                }
                other => panic!("{e}: {other:?}"),
            }
        }
        let e = -Vector3::x();
        let phi = tipping_angle(&m, &n, &e);
        match onset(&m, &n, &e, 0.3 * phi.tan(), phi, 3f64.to_radians()) {
            Onset::Slides(t) => assert!(t < phi),
            other => panic!("{other:?}"),
        }
    }
}
