//! From the learnt tree to a simulation of the object: the body a simulator needs (shape,
//! mass, centre of mass, inertia, friction) and its descriptions for MuJoCo ([`mjcf`]) and any
//! URDF simulator ([`urdf`]).
//!
//! The body's frame is the object frame: the tracked frame whose poses the demonstration files
//! give. Its shape is the convex polyhedron of the learnt faces ([`crate::shape`]); its centre
//! of mass the one the pendulums determine (`tree.com`), or, without one, the shape's centroid
//! at uniform density; its inertia from the pendulums' falls where they determine it, else the
//! shape's at uniform density, about that centre ([`crate::inertia`]). Mass cannot come from
//! kinematics: the caller gives it. Friction: the caller's, else the data's estimate, else
//! [`DEFAULT_FRICTION`] raised above the data's lower bound ([`crate::friction`]). Each choice is
//! recorded in [`Body::notes`], and the files say them too.

pub mod mjcf;
pub mod urdf;

use crate::mass;
use crate::shape::Shape;
pub use crate::shape::{box_fit, BoxFit, BOX_ANGLE_RAD};
use crate::tree::Tree;
use crate::{Error, Result};
use nalgebra::{Matrix3, Vector3};

/// Coulomb friction coefficient used when none is given (rubber-like contact on a table).
pub const DEFAULT_FRICTION: f64 = 0.8;

/// The learnt object as a rigid body for a simulator.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    /// Its shape.
    pub shape: Shape,
    /// The shape as a box, when it is one.
    pub box_fit: Option<BoxFit>,
    /// Mass \[kg\].
    pub mass_kg: f64,
    /// Centre of mass \[m\], object frame.
    pub com: Vector3<f64>,
    /// Inertia tensor about the centre of mass \[kg m²\], object-frame axes.
    pub inertia: Matrix3<f64>,
    /// Coulomb friction coefficient.
    pub friction: f64,
    /// Where each property came from, for the files and the user.
    pub notes: Vec<String>,
}

impl Body {
    /// The body of a learnt tree, with the given mass \[kg\] and friction (None: the default).
    /// A tree whose faces do not close a shape is an error that says which demonstrations are
    /// missing.
    pub fn from_tree(tree: &Tree, mass_kg: f64, friction: Option<f64>) -> Result<Body> {
        if !(mass_kg.is_finite() && mass_kg > 0.0) {
            return Err(Error::Data(format!(
                "the mass must be a positive number of kilograms, not {mass_kg}"
            )));
        }
        if let Some(mu) = friction.filter(|mu| !(mu.is_finite() && *mu >= 0.0)) {
            return Err(Error::Data(format!(
                "the friction coefficient must be >= 0, not {mu}"
            )));
        }
        let shape = tree
            .reconstruct_shape()
            .map_err(|e| Error::Data(format!("no closed shape to export: {e}")))?;
        let uniform = mass::uniform(&shape);
        let mut notes = vec![format!(
            "shape: the convex polyhedron of {} learnt faces, {} vertices",
            shape.faces.len(),
            shape.vertices.len()
        )];
        for (id, why) in &shape.left_out {
            notes.push(format!("face {id} left out of the shape: {why}"));
        }
        for why in &shape.assumptions {
            notes.push(format!("shape: {why}"));
        }
        // A centre of mass outside the shape contradicts it: it is not used.
        let outside = |c: &Vector3<f64>| shape.outside(c).map_or(0.0, |(d, _)| d);
        let com = match &tree.com {
            Some(c) if outside(&c.point) <= 0.0 => {
                notes.push(format!("centre of mass: learnt from {}", c.learnt_from()));
                c.point
            }
            Some(c) => {
                notes.push(format!(
                    "centre of mass: the shape's centroid at uniform density; the one learnt \
                     from {} lies {:.1} mm outside the shape, so they contradict each other \
                     and it is not used",
                    c.learnt_from(),
                    outside(&c.point) * 1e3
                ));
                uniform.centroid
            }
            None => {
                notes.push(
                    "centre of mass: the shape's centroid at uniform density (neither \
                     pendulums nor flights determine it: toppling demonstrations about three \
                     edges of different directions would, or tosses that spin in flight)"
                        .to_string(),
                );
                uniform.centroid
            }
        };
        let inertia = crate::inertia::learn(tree, &shape, &com);
        notes.push(format!(
            "inertia ({}): {}",
            match inertia.source {
                crate::inertia::InertiaSource::Pendulums => "from the pendulums",
                crate::inertia::InertiaSource::PendulumsAndUniformDensity =>
                    "from the pendulums and the shape at uniform density",
                crate::inertia::InertiaSource::UniformDensity => "the shape at uniform density",
            },
            inertia.note
        ));
        notes.push(format!(
            "mass: {mass_kg} kg, given (kinematics cannot tell it)"
        ));
        let friction = match friction {
            Some(mu) => {
                notes.push(format!("friction: {mu}, given"));
                mu
            }
            None => friction_from(tree, &mut notes),
        };
        Ok(Body {
            box_fit: box_fit(&shape),
            inertia: inertia.matrix() * mass_kg,
            shape,
            mass_kg,
            com,
            friction,
            notes,
        })
    }
}

/// The friction coefficient when none is given: the data's estimate, else [`DEFAULT_FRICTION`],
/// raised to [`BOUND_MARGIN`] times the data's lower bound when that is above it (so that the
/// simulated object holds where the real one held); the choice goes to `notes`.
fn friction_from(tree: &Tree, notes: &mut Vec<String>) -> f64 {
    let evidence = tree.friction.as_ref();
    if let Some(mu) = evidence.and_then(|f| f.estimate) {
        notes.push(format!(
            "friction: {mu:.3}, estimated from the demonstrations"
        ));
        return mu;
    }
    match evidence.and_then(|f| f.lower_bound) {
        Some(b) if b * BOUND_MARGIN > DEFAULT_FRICTION => {
            let mu = b * BOUND_MARGIN;
            notes.push(format!(
                "friction: {mu:.3}, {BOUND_MARGIN} x the lower bound {b:.3} the demonstrations \
                 show (above the default {DEFAULT_FRICTION}); not measured: give --friction"
            ));
            mu
        }
        Some(b) => {
            notes.push(format!(
                "friction: {DEFAULT_FRICTION}, the default (the demonstrations show only \
                 that it is above {b:.3}); give --friction"
            ));
            DEFAULT_FRICTION
        }
        None => {
            notes.push(format!(
                "friction: {DEFAULT_FRICTION}, the default (no demonstration tells it); \
                 give --friction"
            ));
            DEFAULT_FRICTION
        }
    }
}

/// The factor on the data's friction lower bound when it is used instead of the default.
pub const BOUND_MARGIN: f64 = 1.1;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shape::tests_support::box_faces;
    use nalgebra::UnitQuaternion;

    /// A tree holding just these faces.
    fn box_tree(centre: Vector3<f64>, rotation: &UnitQuaternion<f64>, size: &Vector3<f64>) -> Tree {
        let faces = box_faces(centre, rotation, size)
            .into_iter()
            .map(|f| crate::tree::Face {
                id: f.id,
                normal: f.normal,
                offset: f.offset,
                offset_sigma_m: Some(f.offset_sigma_m),
                sigma_normal_rad: f.normal_sigma_rad,
                sign_known: f.outward,
                support: vec![],
                n_support: 1,
                evidence: Default::default(),
                observations: vec![],
                offset_unlocated: None,
            })
            .collect();
        Tree {
            faces,
            ..Tree::default()
        }
    }

    #[test]
    fn a_box_is_recognised_with_its_pose_and_size() {
        let centre = Vector3::new(0.03, -0.02, 0.11);
        let rotation = UnitQuaternion::from_euler_angles(0.3, -0.5, 1.1);
        let size = Vector3::new(0.2, 0.1, 0.3);
        let body = Body::from_tree(&box_tree(centre, &rotation, &size), 0.6, None).unwrap();
        let b = body.box_fit.expect("a box");
        assert!((b.centre - centre).norm() < 1e-12);
        // Its axes are the box's (up to order and sign), its size the box's along them.
        for a in 0..3 {
            let axis = b.rotation * Vector3::ith(a, 1.0);
            let k = (0..3)
                .find(|&k| (rotation * Vector3::ith(k, 1.0)).dot(&axis).abs() > 1.0 - 1e-9)
                .expect("a box axis");
            assert!((2.0 * b.half_extents[a] - size[k]).abs() < 1e-9, "{a} {k}");
        }
        assert_eq!(body.com, mass::uniform(&body.shape).centroid);
        assert!(body.notes.iter().any(|n| n.contains("uniform density")));
        assert!(Body::from_tree(&box_tree(centre, &rotation, &size), -1.0, None).is_err());
    }

    /// A learnt centre of mass outside the shape contradicts it: the centroid is used, and the
    /// notes say why; one inside is used as learnt.
    #[test]
    fn a_centre_of_mass_outside_the_shape_is_not_used() {
        let mut tree = box_tree(
            Vector3::zeros(),
            &UnitQuaternion::identity(),
            &Vector3::new(0.2, 0.1, 0.3),
        );
        for (point, used) in [
            (Vector3::new(0.0, 0.07, 0.0), false),
            (Vector3::new(0.02, 0.01, -0.1), true),
        ] {
            tree.com = Some(crate::tree::CentreOfMass {
                point,
                rms_residual_m: 0.0,
                pendulums: 3,
                covariance: None,
                sigma_m: None,
                chi2_per_dof: None,
                ..Default::default()
            });
            let body = Body::from_tree(&tree, 1.0, None).unwrap();
            assert_eq!(body.com == point, used);
            assert_eq!(
                body.notes.iter().any(|n| n.contains("outside the shape")),
                !used
            );
        }
    }

    #[test]
    fn a_cut_box_is_not_a_box() {
        let mut tree = box_tree(
            Vector3::zeros(),
            &UnitQuaternion::identity(),
            &Vector3::new(0.2, 0.1, 0.3),
        );
        let mut cut = box_tree(
            Vector3::zeros(),
            &UnitQuaternion::identity(),
            &Vector3::new(0.2, 0.1, 0.3),
        )
        .faces
        .remove(0);
        cut.id = "f6".into();
        cut.normal = Vector3::new(1.0, 1.0, 0.0).normalize();
        cut.offset = Some(0.1);
        tree.faces.push(cut);
        let body = Body::from_tree(&tree, 1.0, Some(0.5)).unwrap();
        assert!(body.box_fit.is_none());
        assert_eq!(body.friction, 0.5);
    }
}
