//! The same physical box described in a turned box frame, so that the scenes, which always
//! start with the box resting on its `-z` face, start it on another face.
//!
//! Turning changes only the description: the tag stays where it is stuck and the centre of mass
//! where the weight is, so the tag-frame truth and the learner's data are those of the same
//! object. `box2_from_box` is a rotation that maps box axes onto box axes (a signed
//! permutation); the turned spec has the dimensions and the centre of mass in the new axes and
//! the tag mount that gives `box2_from_tag = box2_from_box · box_from_tag` exactly.

use crate::spec::{BoxFace, BoxSpec, TagMount};
use crate::{Result, SimError};
use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, Vector3};
use serde::{Deserialize, Serialize};

/// A way to set a box down on another face than its bottom (`-z`) one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Turn {
    /// Half a turn about its `x` axis: it rests on its top (`+z`) face.
    UpsideDown,
    /// A quarter turn about `y`: it stands on its `+x` end.
    OnPosX,
    /// A quarter turn about `-y`: it stands on its `-x` end.
    OnNegX,
}

impl Turn {
    /// Every turn.
    pub const ALL: [Turn; 3] = [Turn::UpsideDown, Turn::OnPosX, Turn::OnNegX];

    /// Its name in file names and the manifest.
    pub fn name(self) -> &'static str {
        match self {
            Turn::UpsideDown => "upside-down",
            Turn::OnPosX => "on-pos-x",
            Turn::OnNegX => "on-neg-x",
        }
    }

    /// `box2_from_box`: a signed permutation of the axes.
    pub fn rotation(self) -> Rotation3<f64> {
        let m = match self {
            Turn::UpsideDown => Matrix3::new(1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, -1.0),
            // +x -> -z, z -> x
            Turn::OnPosX => Matrix3::new(0.0, 0.0, 1.0, 0.0, 1.0, 0.0, -1.0, 0.0, 0.0),
            // -x -> -z, z -> -x
            Turn::OnNegX => Matrix3::new(0.0, 0.0, -1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0),
        };
        Rotation3::from_matrix_unchecked(m)
    }

    /// The spec of the same box turned so.
    pub fn apply(self, spec: &BoxSpec) -> BoxSpec {
        turned(spec, &self.rotation()).expect("a turn maps box axes onto box axes")
    }
}

/// The spec of the same box upside down: turned half a turn about its `x` axis, so that it
/// rests on what was its top (`+z`) face.
pub fn upside_down(spec: &BoxSpec) -> BoxSpec {
    Turn::UpsideDown.apply(spec)
}

/// The spec of the same box in the frame `box2` (`box2_from_box` must map each box axis onto
/// a box axis, up to sign).
pub fn turned(spec: &BoxSpec, box2_from_box: &Rotation3<f64>) -> Result<BoxSpec> {
    let r = box2_from_box.matrix();
    let signed_permutation = (0..3).all(|j| {
        let col = r.column(j);
        let k = col.iamax();
        (col[k].abs() - 1.0).abs() < 1e-9 && (0..3).all(|i| i == k || col[i].abs() < 1e-9)
    });
    if !signed_permutation || (r.determinant() - 1.0).abs() > 1e-9 {
        return Err(SimError::InvalidSpec(
            "a box can only be turned by a rotation that maps its axes onto its axes".into(),
        ));
    }
    let mut dims = [0.0; 3];
    for (j, d) in spec.dims.iter().enumerate() {
        dims[r.column(j).iamax()] = *d;
    }
    let com = box2_from_box * Vector3::from(spec.com_offset);
    let box2_from_tag = box2_from_box * spec.box_from_tag().rotation;
    let tag_z = box2_from_tag * Vector3::z();
    let face = BoxFace::closest_to(&tag_z);
    let mut out = BoxSpec {
        dims,
        com_offset: [com.x, com.y, com.z],
        tag: TagMount::centred(face),
        learnt: None,
        ..spec.clone()
    };
    if let Some(l) = &spec.learnt {
        let turn = Isometry3::from_parts(Translation3::identity(), (*box2_from_box).into());
        out.learnt = Some(crate::learnt::Learnt {
            body: l.body.in_frame(&turn),
            box_from_tag: turn * l.box_from_tag,
        });
        return Ok(out);
    }
    // The mount's frame with no offset and no yaw: the face centre and the face axes.
    let bare = out.box_from_tag();
    let origin = box2_from_box * spec.box_from_tag().translation.vector;
    let local = bare.inverse() * nalgebra::Point3::from(origin);
    let r_local = bare.rotation.inverse() * box2_from_tag;
    let x = r_local * Vector3::x();
    out.tag = TagMount {
        face,
        offset: [local.x, local.y],
        yaw: x.y.atan2(x.x),
    };
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{rngs::StdRng, SeedableRng};

    /// The turned spec is the same object: its tag frame, corners and centre of mass in the tag
    /// frame are those of the original, for every tag placement and every quarter-turn frame.
    #[test]
    fn a_turned_box_is_the_same_object_seen_from_its_tag() {
        let mut rng = StdRng::seed_from_u64(5);
        let turns = [
            Rotation3::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI),
            Rotation3::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2),
            Rotation3::from_axis_angle(&Vector3::z_axis(), -std::f64::consts::FRAC_PI_2),
            Rotation3::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_2)
                * Rotation3::from_axis_angle(&Vector3::z_axis(), std::f64::consts::FRAC_PI_2),
        ];
        for _ in 0..20 {
            let spec = BoxSpec::new("b", [0.1, 0.07, 0.2], 0.5)
                .with_com([0.01, -0.005, 0.02])
                .with_tag(TagMount::random(&mut rng));
            for t in &turns {
                // Snap the rounding of the axis-angle matrix to exact ±1 and 0.
                let t = Rotation3::from_matrix_unchecked(t.matrix().map(|x| x.round()));
                let s2 = turned(&spec, &t).unwrap();
                let want =
                    nalgebra::Isometry3::from_parts(nalgebra::Translation3::identity(), t.into())
                        * spec.box_from_tag();
                let got = s2.box_from_tag();
                assert!((want.translation.vector - got.translation.vector).norm() < 1e-12);
                assert!(want.rotation.angle_to(&got.rotation) < 1e-9);
                let c1 = spec.tag_from_box() * spec.com_box();
                let c2 = s2.tag_from_box() * s2.com_box();
                assert!((c1 - c2).norm() < 1e-12);
                let h2 = s2.half_extents();
                assert!((h2.product() - spec.half_extents().product()).abs() < 1e-15);
            }
        }
        for t in Turn::ALL {
            let spec = BoxSpec::new("b", [0.1, 0.07, 0.2], 0.5);
            let down = t.rotation().inverse() * -Vector3::z();
            let (k, sign) = match t {
                Turn::UpsideDown => (2, 1.0),
                Turn::OnPosX => (0, 1.0),
                Turn::OnNegX => (0, -1.0),
            };
            assert_eq!(
                down,
                Vector3::ith(k, sign),
                "{t:?} rests on the face it says"
            );
            assert!((t.apply(&spec).dims[2] - spec.dims[k]).abs() < 1e-15);
        }
        let flipped =
            upside_down(&BoxSpec::new("b", [0.1, 0.07, 0.2], 0.5).with_com([0.0, 0.0, 0.03]));
        assert_eq!(flipped.com_offset, [0.0, 0.0, -0.03]);
        assert!(turned(
            &BoxSpec::new("b", [0.1, 0.1, 0.1], 1.0),
            &Rotation3::from_axis_angle(&Vector3::z_axis(), 0.3)
        )
        .is_err());
    }
}
