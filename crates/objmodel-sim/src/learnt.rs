//! The learnt object in place of a specified box: the scenes (topple, instrumented, slide,
//! general, compound) run with the rigid body built from a learnt model — its shape (a cuboid
//! where the shape is a box, else the convex hull of its vertices), its centre of mass and
//! inertia, and a given mass and friction ([`objmodel::export::Body`]).
//!
//! The scenes script their motions from a box's extents and CoM, and start the box on its
//! `-z` face. The learnt body gets a box frame for them: for a box, its own axes, with `x`
//! the axis of the tag's face (so that the tag faces the camera as on a specified box) and `z`
//! the longest other axis, pointing away from the CoM (it stands on its bottom face, as the
//! standard boxes do); for another shape, the object axes about the middle of its extents.
//! The tag frame is the object frame, so the truth the scenes write is in the model's frame.

use crate::rigid::{Geometry, RigidModel};
pub use crate::spec::Learnt;
use crate::spec::{BoxFace, BoxSpec, TagMount};
use nalgebra::{Isometry3, Matrix3, Point3, Rotation3, Translation3, UnitQuaternion, Vector3};
use objmodel::export::Body;

/// The box frame the scenes use for `model` (object frame): `box_from_object`, and the half
/// extents in it.
fn box_frame(model: &RigidModel) -> (Isometry3<f64>, Vector3<f64>) {
    match &model.geometry {
        Geometry::Cuboid {
            body_from_box,
            half_extents,
        } => {
            let axis = |k: usize| body_from_box.rotation * Vector3::ith(k, 1.0);
            // x: the box axis nearest the tag's normal (object z), pointing out of the tag face.
            let kx = (0..3)
                .max_by(|&a, &b| axis(a).z.abs().total_cmp(&axis(b).z.abs()))
                .expect("three axes");
            let x = axis(kx) * axis(kx).z.signum();
            let kz = (0..3)
                .filter(|&k| k != kx)
                .max_by(|&a, &b| half_extents[a].total_cmp(&half_extents[b]))
                .expect("two other axes");
            let centre = body_from_box.translation.vector;
            let mut z = axis(kz);
            if z.dot(&(model.com - centre)) > 0.0 {
                z = -z;
            }
            let y = z.cross(&x);
            let ky = 3 - kx - kz;
            let object_from_box = Isometry3::from_parts(
                Translation3::from(centre),
                UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(
                    Matrix3::from_columns(&[x, y, z]),
                )),
            );
            let half = Vector3::new(half_extents[kx], half_extents[ky], half_extents[kz]);
            (object_from_box.inverse(), half)
        }
        Geometry::Hull { points } => {
            let min = points
                .iter()
                .fold(Vector3::repeat(f64::INFINITY), |m, p| m.inf(p));
            let max = points
                .iter()
                .fold(Vector3::repeat(f64::NEG_INFINITY), |m, p| m.sup(p));
            (Isometry3::from(-(min + max) / 2.0), (max - min) / 2.0)
        }
    }
}

/// The spec of a scene's box that is the learnt `body` (object frame), named `name`: its
/// dimensions, CoM, mass and friction are the learnt ones, and [`BoxSpec::learnt`] carries the
/// body and the tag frame.
pub fn learnt_spec(body: &Body, name: &str) -> BoxSpec {
    let model = RigidModel::of_body(body);
    let (box_from_object, half) = box_frame(&model);
    let in_box = model.in_frame(&box_from_object);
    let tag_normal = box_from_object.rotation * Vector3::z();
    let com = (box_from_object * Point3::from(model.com)).coords;
    let mut spec = BoxSpec::new(name, (half * 2.0).into(), body.mass_kg)
        .with_com(com.into())
        .with_friction(body.friction)
        .with_tag(TagMount::centred(BoxFace::closest_to(&tag_normal)));
    spec.learnt = Some(Learnt {
        body: in_box,
        box_from_tag: box_from_object,
    });
    spec
}

#[cfg(test)]
mod tests {
    use super::*;
    use objmodel::shape::{reconstruct, LearntFace};

    /// A learnt body that is a specified box, seen from that box's tag: its scene spec has the
    /// box's extents, CoM and tag frame up to the box's symmetries.
    #[test]
    fn a_learnt_box_becomes_the_box_it_is() {
        let spec = BoxSpec::new("b", [0.08, 0.1, 0.2], 0.6)
            .with_com([0.01, 0.0, -0.02])
            .with_tag(TagMount {
                face: BoxFace::NegY,
                offset: [0.003, -0.004],
                yaw: 0.4,
            });
        let tag_from_box = spec.tag_from_box();
        let faces: Vec<LearntFace> = BoxFace::ALL
            .iter()
            .map(|f| {
                let n = tag_from_box.rotation * f.normal();
                let (k, _) = f.axis_sign();
                let centre = tag_from_box * Point3::origin();
                LearntFace {
                    id: format!("{f:?}"),
                    normal: n,
                    outward: true,
                    offset: Some(n.dot(&centre.coords) + spec.half_extents()[k]),
                    offset_sigma_m: 1e-3,
                    normal_sigma_rad: 0.01,
                }
            })
            .collect();
        let shape = reconstruct(&faces).unwrap();
        let box_fit = objmodel::export::box_fit(&shape);
        let com = (tag_from_box * spec.com_box()).coords;
        let body = Body {
            shape,
            box_fit,
            mass_kg: 0.6,
            com,
            inertia: Matrix3::identity() * 1e-3,
            friction: 0.7,
            notes: vec![],
        };
        let s = learnt_spec(&body, "learnt");
        let mut dims = s.dims;
        let mut want = spec.dims;
        dims.sort_by(f64::total_cmp);
        want.sort_by(f64::total_cmp);
        for (a, b) in dims.iter().zip(want) {
            assert!((a - b).abs() < 1e-9);
        }
        assert!((s.dims[2] - 0.2).abs() < 1e-9, "stands on its long axis");
        assert!(s.com_offset[2] <= 0.0);
        assert_eq!(s.tag.face, BoxFace::PosX);
        // The CoM in the tag frame is the body's.
        let back = s.tag_from_box() * s.com_box();
        assert!((back.coords - com).norm() < 1e-12);
        s.validate().unwrap();
        // The corners of the scene's box are the true box's, in the tag frame.
        let l = s.learnt.as_ref().unwrap();
        for c in l.body.corners() {
            let t = s.tag_from_box() * Point3::from(c);
            let b = spec.box_from_tag() * t;
            let h = spec.half_extents();
            assert!((0..3).all(|k| (b[k].abs() - h[k]).abs() < 1e-9), "{b}");
        }
    }
}
