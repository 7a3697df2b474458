//! The toppling skill, parameterised by the object description tree (paper Sec. IV): from the
//! learnt edges, their pendulums and the object's tracked pose on the palm, choose the line
//! about which to tilt the palm, and by how much.
//!
//! Frames: everything in the **palm frame** (origin on the palm's surface, z its normal);
//! the object's pose is `palm_from_object` of its tracked frame; gravity is given in the palm
//! frame (default -z, a level palm).
//!
//! The object rests on the face whose outward normal points along gravity. Each edge with a
//! pendulum for that face is a candidate: the object topples over it once the support face is
//! tilted about the edge by the pendulum's φ (measured from the vertical). Rotating the palm by
//! `tilt = φ - ψ₀ + margin` about the edge line (right-hand rule about the toppling axis), with
//! ψ₀ the tilt it already has, topples the object onto the adjacent face.
//!
//! An edge of that face about which no one demonstrated a topple is a candidate too, from the
//! pendulum the shape and the CoM predict (`tree.predictions`, with its propagated σ_φ in the
//! margin); the plan says so (`predicted`).

use crate::geometry::angle_about;
use crate::tree::{Tree, SAME_FACE_RAD};
use crate::{Error, Result};
use nalgebra::{Isometry3, Point3, Vector3};
use serde::{Deserialize, Serialize};

/// Smallest margin \[rad\] past φ (2°): real palms are not perfectly flat and φ is uncertain.
pub const MIN_MARGIN_RAD: f64 = 0.034_906_585_039_886_59;
/// Margin in standard deviations of φ added to [`MIN_MARGIN_RAD`].
pub const MARGIN_SIGMAS: f64 = 3.0;

/// A plan request.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanRequest {
    /// `palm_from_object`: the tracked object frame in the palm frame.
    pub palm_from_object: Isometry3<f64>,
    /// Preferred toppling direction in the palm frame (the edge whose toppling direction is
    /// closest to it is chosen); `None` chooses the edge easiest to topple (smallest tilt).
    pub towards: Option<Vector3<f64>>,
    /// Gravity in the palm frame (any length).
    pub gravity_in_palm: Vector3<f64>,
    /// Margin past φ \[rad\]; `None` uses `MIN_MARGIN_RAD + MARGIN_SIGMAS σ_φ`.
    pub margin: Option<f64>,
}

/// A toppling plan, in the palm frame.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Plan {
    /// Id of the edge toppled about.
    pub edge: String,
    /// Point of the tilt axis (the edge line) closest to the palm origin \[m\].
    pub axis_point: Vector3<f64>,
    /// Direction of the tilt axis; tilt by the right-hand rule about it.
    pub axis_direction: Vector3<f64>,
    /// How far to tilt the palm about the axis \[rad\].
    pub tilt: f64,
    /// The pendulum's φ \[rad\].
    pub phi: f64,
    /// Standard deviation of φ \[rad\], if known.
    pub phi_sigma: Option<f64>,
    /// The tilt the support face already has about the axis \[rad\].
    pub current_tilt: f64,
    /// Margin past φ \[rad\].
    pub margin: f64,
    /// Horizontal direction (palm frame) in which the object falls.
    pub topple_direction: Vector3<f64>,
    /// Outward normal of the face the object rests on, in the palm frame.
    pub resting_face_normal: Vector3<f64>,
    /// Outward normal of the face it will land on, in the palm frame, if learnt.
    pub landing_face_normal: Option<Vector3<f64>>,
    /// Whether the pendulum is predicted from the shape and the CoM (no one demonstrated a
    /// topple about this edge from this face) rather than observed; `edge` is then
    /// `RESTING/LANDING`, the two faces' ids.
    #[serde(default)]
    pub predicted: bool,
}

/// Choose the edge and the tilt. Errors (which trigger a request for a demonstration) when the
/// tree has no edge with a pendulum for the face the object rests on.
pub fn plan(tree: &Tree, req: &PlanRequest) -> Result<Plan> {
    let g = req
        .gravity_in_palm
        .try_normalize(1e-12)
        .ok_or_else(|| Error::Data("gravity in the palm frame must not be zero".into()))?;
    let rot = req.palm_from_object.rotation;
    let down_obj = rot.inverse() * g;
    let mut candidates = Vec::new();
    for e in &tree.edges {
        // A pendulum the others contradict is not planned with: its prediction is, below.
        for p in e.pendulums.iter().filter(|p| p.com_conflict.is_none()) {
            let Some(phi) = p.phi else { continue };
            if p.resting_face_normal.angle(&down_obj) > SAME_FACE_RAD {
                continue;
            }
            let u = rot * p.toppling_axis;
            let n = rot * p.resting_face_normal;
            let current = angle_about(&u, &-g, &-n);
            let margin = req
                .margin
                .unwrap_or(MIN_MARGIN_RAD + MARGIN_SIGMAS * p.phi_sigma.unwrap_or(0.0));
            let point = (req.palm_from_object * Point3::from(e.point)).coords;
            let axis_point = point - u * u.dot(&point);
            // The object falls away from the face's interior: -(u × n), made horizontal.
            let fall = -(u.cross(&n));
            let fall = (fall - g * g.dot(&fall))
                .try_normalize(1e-12)
                .unwrap_or(fall);
            let landing = e
                .faces
                .iter()
                .filter_map(|id| tree.faces.iter().find(|f| &f.id == id))
                .map(|f| rot * f.normal)
                .find(|m| m.angle(&n) > SAME_FACE_RAD);
            candidates.push(Plan {
                edge: e.id.clone(),
                axis_point,
                axis_direction: u,
                tilt: phi - current + margin,
                phi,
                phi_sigma: p.phi_sigma,
                current_tilt: current,
                margin,
                topple_direction: fall,
                resting_face_normal: n,
                landing_face_normal: landing,
                predicted: false,
            });
        }
    }
    // Edges of the face no one demonstrated (or whose observed pendulum the others contradict):
    // the pendulums the shape and the CoM predict.
    let unobserved = |q: &&crate::prediction::PredictedPendulum| {
        q.observed.as_ref().is_none_or(|o| o.contradicted)
    };
    for q in tree.predictions.iter().filter(unobserved) {
        if q.resting_normal.angle(&down_obj) > SAME_FACE_RAD || q.phi <= 0.0 {
            continue;
        }
        let u = rot * q.edge_direction;
        let n = rot * q.resting_normal;
        let current = angle_about(&u, &-g, &-n);
        let margin = req
            .margin
            .unwrap_or(MIN_MARGIN_RAD + MARGIN_SIGMAS * q.phi_sigma.unwrap_or(0.0));
        let point = (req.palm_from_object * Point3::from(q.edge_point)).coords;
        let fall = -(u.cross(&n));
        let fall = (fall - g * g.dot(&fall))
            .try_normalize(1e-12)
            .unwrap_or(fall);
        let landing = tree
            .shape
            .as_ref()
            .and_then(|s| s.faces.iter().find(|f| f.id == q.landing_face))
            .map(|f| rot * f.normal);
        candidates.push(Plan {
            edge: format!("{}/{}", q.resting_face, q.landing_face),
            axis_point: point - u * u.dot(&point),
            axis_direction: u,
            tilt: q.phi - current + margin,
            phi: q.phi,
            phi_sigma: q.phi_sigma,
            current_tilt: current,
            margin,
            topple_direction: fall,
            resting_face_normal: n,
            landing_face_normal: landing,
            predicted: true,
        });
    }
    let key = |p: &Plan| match req.towards {
        Some(t) => -p.topple_direction.dot(&t.normalize()),
        None => p.tilt,
    };
    candidates.into_iter().min_by(|a, b| key(a).total_cmp(&key(b))).ok_or_else(|| {
        // An edge of this face measured but too loosely to be taught: say so, and what helps.
        let loose = tree
            .unlocated_edges()
            .filter(|w| {
                w.edge
                    .pendulums
                    .iter()
                    .any(|p| p.resting_face_normal.angle(&down_obj) <= SAME_FACE_RAD)
            })
            .map(|w| {
                format!(
                    "; edge {} of this face was measured, but located to ±{:.1} mm and ±{:.2}° \
                     only, too loosely to be taught: another demonstration of toppling about it \
                     is needed",
                    w.edge.id,
                    w.edge.sigma_point_m * 1e3,
                    w.edge.sigma_direction_rad.to_degrees()
                )
            })
            .collect::<String>();
        Error::Data(format!(
            "no learnt edge with a toppling model for the face the object rests on (outward normal [{:.3}, {:.3}, {:.3}] in the object frame): a demonstration of toppling it from this face is needed{loose}",
            down_obj.x, down_obj.y, down_obj.z
        ))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tree::{Edge, Pendulum};
    use nalgebra::{Translation3, UnitQuaternion};

    /// A 0.1 x 0.1 x 0.2 box (object frame at its centre) with one learnt bottom edge along y
    /// at x = +0.05, z = -0.1, toppling positively about +y... over the +x side.
    fn tree_with_edge(phi: f64) -> Tree {
        let mut t = Tree::default();
        let e: Edge = serde_json::from_value(serde_json::json!({
            "id": "e0", "point": [0.05, 0.0, -0.1], "direction": [0.0, 1.0, 0.0],
            "point_cov": [[0.0,0.0,0.0],[0.0,0.0,0.0],[0.0,0.0,0.0]], "direction_cov": [[0.0,0.0,0.0],[0.0,0.0,0.0],[0.0,0.0,0.0]], "sigma_point_m": 0.0, "sigma_direction_rad": 0.0,
            "support": [], "n_support": 1, "faces": [], "pendulums": [], "observations": []
        })).unwrap();
        t.edges.push(e);
        t.edges[0].pendulums.push(Pendulum {
            resting_face_normal: -Vector3::z(),
            toppling_axis: Vector3::y(),
            phi: Some(phi),
            l_p: None,
            phi_sigma: Some(0.0),
            inertia_ratio_m: None,
            support: vec![],
            observations: vec![],
            com_conflict: None,
        });
        t
    }

    #[test]
    fn plan_for_a_box_on_a_level_palm_is_its_edge_and_phi() {
        let phi = 0.1f64.atan2(0.2).max(0.05f64.atan2(0.1));
        let t = tree_with_edge(phi);
        // Box resting on the palm, centre 0.1 m above it, turned 90° about z.
        let pose = Isometry3::from_parts(
            Translation3::new(0.02, 0.0, 0.1),
            UnitQuaternion::from_scaled_axis(Vector3::z() * std::f64::consts::FRAC_PI_2),
        );
        let p = plan(
            &t,
            &PlanRequest {
                palm_from_object: pose,
                towards: None,
                gravity_in_palm: -Vector3::z(),
                margin: Some(0.05),
            },
        )
        .unwrap();
        // The edge (x = 0.05, z = -0.1 along y) maps to x = 0.02, y = 0.05, z = 0 along -x.
        assert!((p.axis_direction - Vector3::new(-1.0, 0.0, 0.0)).norm() < 1e-12);
        assert!(
            (p.axis_point - Vector3::new(0.0, 0.05, 0.0)).norm() < 1e-12,
            "{:?}",
            p.axis_point
        );
        assert!((p.tilt - (phi + 0.05)).abs() < 1e-12 && p.current_tilt.abs() < 1e-12);
        // It falls towards +y (the side of the edge).
        assert!(
            (p.topple_direction - Vector3::y()).norm() < 1e-12,
            "{:?}",
            p.topple_direction
        );
        // Rotating the palm (in the world, gravity -z) by phi about that line puts the CoM (the
        // object origin) vertically above the edge.
        let r = UnitQuaternion::from_scaled_axis(p.axis_direction * phi);
        let com_after = r * (Vector3::new(0.02, 0.0, 0.1) - p.axis_point);
        let h = com_after - p.axis_direction * p.axis_direction.dot(&com_after);
        assert!(h.cross(&Vector3::z()).norm() < 1e-12, "{h:?}");
    }

    /// The face's only edge measured too loosely to be taught (`tree/unlocated.rs`): no plan,
    /// and the error names that edge and asks for another demonstration of it; an unlocated
    /// edge of another face is not named.
    #[test]
    fn a_loosely_located_edge_is_named_when_no_plan_can_be_made() {
        let mut t = tree_with_edge(0.4);
        let mut e = t.edges.remove(0);
        e.sigma_point_m = 3.1e-3;
        e.sigma_direction_rad = 0.5f64.to_radians();
        let mut other = e.clone();
        other.id = "e7".into();
        other.pendulums[0].resting_face_normal = Vector3::x();
        for edge in [e, other] {
            t.withheld_edges.push(crate::tree::WithheldEdge {
                edge,
                why: "loose".into(),
                faces: Vec::new(),
                unlocated: true,
            });
        }
        let req = PlanRequest {
            palm_from_object: Isometry3::translation(0.0, 0.0, 0.1),
            towards: None,
            gravity_in_palm: -Vector3::z(),
            margin: None,
        };
        let msg = plan(&t, &req).unwrap_err().to_string();
        assert!(
            msg.contains("edge e0 of this face was measured, but located to ±3.1 mm"),
            "{msg}"
        );
        assert!(msg.contains("another demonstration"), "{msg}");
        assert!(!msg.contains("e7"), "{msg}");
        // Withheld for another reason (a contradiction), it is not offered as loose.
        t.withheld_edges
            .iter_mut()
            .for_each(|w| w.unlocated = false);
        let msg = plan(&t, &req).unwrap_err().to_string();
        assert!(!msg.contains("located to"), "{msg}");
    }

    /// A box no one toppled, whose shape and CoM are known: the plan tilts about the edge the
    /// prediction gives, with its phi, says that it is predicted, and its margin holds 3 σ_φ.
    #[test]
    fn an_edge_no_one_demonstrated_is_planned_from_its_prediction() {
        use crate::shape::{reconstruct, tests_support::box_faces};
        let size = Vector3::new(0.1, 0.1, 0.2);
        let shape = reconstruct(&box_faces(
            Vector3::zeros(),
            &UnitQuaternion::identity(),
            &size,
        ))
        .unwrap();
        let com = Vector3::new(0.01, 0.0, 0.0);
        let mut t = Tree {
            predictions: crate::prediction::uncertain(
                &shape,
                &com,
                &(nalgebra::Matrix3::identity() * 1e-6),
            ),
            shape: Some(shape),
            ..Tree::default()
        };
        let pose =
            Isometry3::from_parts(Translation3::new(0.0, 0.0, 0.1), UnitQuaternion::identity());
        let p = plan(
            &t,
            &PlanRequest {
                palm_from_object: pose,
                towards: None,
                gravity_in_palm: -Vector3::z(),
                margin: None,
            },
        )
        .unwrap();
        assert!(p.predicted);
        // Easiest: over the +x edge, the CoM 0.04 m from it across, 0.1 m up.
        let phi = 0.04f64.atan2(0.1);
        assert!((p.phi - phi).abs() < 1e-12, "{} vs {phi}", p.phi);
        assert!((p.topple_direction - Vector3::x()).norm() < 1e-12);
        let sigma = p.phi_sigma.unwrap();
        assert!(sigma > 0.0);
        assert!((p.margin - (MIN_MARGIN_RAD + MARGIN_SIGMAS * sigma)).abs() < 1e-12);
        // A demonstrated pendulum on that face wins over no prediction only by its tilt; with
        // the prediction marked observed, it is not offered twice.
        t.predictions.iter_mut().for_each(|q| {
            q.observed = Some(crate::prediction::ObservedPendulum {
                edge: "e0".into(),
                phi: q.phi,
                phi_sigma: None,
                l_p: None,
                phi_z: None,
                contradicted: false,
            })
        });
        let request = PlanRequest {
            palm_from_object: pose,
            towards: None,
            gravity_in_palm: -Vector3::z(),
            margin: None,
        };
        assert!(plan(&t, &request).is_err());
        // An observed pendulum the others contradict gives way to the prediction again.
        t.predictions.iter_mut().for_each(|q| {
            q.observed.as_mut().unwrap().contradicted = true;
        });
        let p = plan(&t, &request).unwrap();
        assert!(p.predicted && (p.phi - phi).abs() < 1e-12);
    }

    #[test]
    fn no_plan_for_an_unknown_resting_face() {
        let t = tree_with_edge(0.4);
        let upside_down = Isometry3::from_parts(
            Translation3::new(0.0, 0.0, 0.1),
            UnitQuaternion::from_scaled_axis(Vector3::x() * std::f64::consts::PI),
        );
        let e = plan(
            &t,
            &PlanRequest {
                palm_from_object: upside_down,
                towards: None,
                gravity_in_palm: -Vector3::z(),
                margin: None,
            },
        )
        .unwrap_err();
        assert!(e.to_string().contains("no learnt edge"), "{e}");
    }
}
