//! Simulated objects: rectangular boxes with mass, friction, an offset centre of mass, and a
//! tracking tag stuck on one face.
//!
//! Frames: `box` has its origin at the box's geometric centre and axes along its edges, so the
//! box occupies `[-a, a] × [-b, b] × [-c, c]` with half extents `(a, b, c)`. `tag` is the tracked
//! frame: its origin lies on one face, a few mm off that face's centre, its `z` axis is the
//! face's outward normal, and it is turned about that normal. The learner only ever sees poses
//! of `tag`; `box_from_tag` maps tag coordinates to box coordinates.

use crate::rigid::{Geometry, RigidModel};
use crate::{Result, SimError};
use nalgebra::{Isometry3, Matrix3, Point3, Rotation3, Translation3, UnitQuaternion, Vector3};
use rand::Rng;
use serde::{Deserialize, Serialize};

/// One of the six faces of a box, named by its outward normal in the box frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BoxFace {
    /// Normal `+x`.
    PosX,
    /// Normal `-x`.
    NegX,
    /// Normal `+y`.
    PosY,
    /// Normal `-y`.
    NegY,
    /// Normal `+z`.
    PosZ,
    /// Normal `-z`.
    NegZ,
}

impl BoxFace {
    /// All six faces.
    pub const ALL: [BoxFace; 6] = [
        BoxFace::PosX,
        BoxFace::NegX,
        BoxFace::PosY,
        BoxFace::NegY,
        BoxFace::PosZ,
        BoxFace::NegZ,
    ];

    /// Axis index (0 = x, 1 = y, 2 = z) and sign (±1) of the outward normal.
    pub fn axis_sign(self) -> (usize, f64) {
        match self {
            BoxFace::PosX => (0, 1.0),
            BoxFace::NegX => (0, -1.0),
            BoxFace::PosY => (1, 1.0),
            BoxFace::NegY => (1, -1.0),
            BoxFace::PosZ => (2, 1.0),
            BoxFace::NegZ => (2, -1.0),
        }
    }

    /// The face with outward normal `sign · e_axis`.
    pub fn from_axis_sign(axis: usize, sign: f64) -> BoxFace {
        match (axis, sign >= 0.0) {
            (0, true) => BoxFace::PosX,
            (0, false) => BoxFace::NegX,
            (1, true) => BoxFace::PosY,
            (1, false) => BoxFace::NegY,
            (_, true) => BoxFace::PosZ,
            (_, false) => BoxFace::NegZ,
        }
    }

    /// Outward unit normal in the box frame.
    pub fn normal(self) -> Vector3<f64> {
        let (k, s) = self.axis_sign();
        let mut n = Vector3::zeros();
        n[k] = s;
        n
    }

    /// The face of `dirs` (unit vectors in the box frame) whose outward normal is closest to `d`.
    pub fn closest_to(d: &Vector3<f64>) -> BoxFace {
        let k = d.iamax();
        BoxFace::from_axis_sign(k, d[k])
    }
}

/// Where the tracking tag sits: on `face`, displaced by `offset` \[m\] along the face's in-plane
/// axes `(u, v)` from the face centre, and turned by `yaw` \[rad\] about the outward normal.
///
/// The face axes are `v = e_z` for side faces and `v = e_x` for the `±z` faces, `n` the outward
/// normal and `u = v × n`, so `(u, v, n)` is right handed. The tag frame is then
/// `box_from_tag = (R, c + offset₀ u + offset₁ v)` with `R = [u v n] · Rz(yaw)`, `c` the face centre.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TagMount {
    /// Face the tag is stuck on.
    pub face: BoxFace,
    /// Offset of the tag origin from the face centre along `(u, v)` \[m\].
    pub offset: [f64; 2],
    /// Rotation of the tag about the face's outward normal \[rad\].
    pub yaw: f64,
}

impl TagMount {
    /// A sticker as a person would place it: on a random side face (`±x`, `±y`), up to 6 mm off
    /// centre along each face axis, and turned by up to ±40 degrees.
    pub fn random<R: Rng>(rng: &mut R) -> TagMount {
        let faces = [BoxFace::PosX, BoxFace::NegX, BoxFace::PosY, BoxFace::NegY];
        TagMount {
            face: faces[rng.random_range(0..4)],
            offset: [
                rng.random_range(-0.006..0.006),
                rng.random_range(-0.006..0.006),
            ],
            yaw: rng.random_range(-40f64..40.0).to_radians(),
        }
    }

    /// The tag centred on `face` and not turned.
    pub fn centred(face: BoxFace) -> TagMount {
        TagMount {
            face,
            offset: [0.0, 0.0],
            yaw: 0.0,
        }
    }
}

/// A simulated box: size, mass, centre of mass, friction and where its tag is.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BoxSpec {
    /// A short name used in file names and the manifest.
    pub name: String,
    /// Full edge lengths along the box's `x`, `y`, `z` axes \[m\].
    pub dims: [f64; 3],
    /// Mass \[kg\].
    pub mass: f64,
    /// Centre of mass relative to the geometric centre, in the box frame \[m\] (a weight inside).
    pub com_offset: [f64; 3],
    /// Coulomb friction coefficient between the box and the table or palm in the push and tilt
    /// scenes (the slide scene uses its own low value; the effective value is in the truth).
    pub friction: f64,
    /// The tracking tag.
    pub tag: TagMount,
    /// A learnt object in place of the box ([`crate::learnt`]): its body and tag frame
    /// replace those the numbers above describe (which then give its extents and CoM for the
    /// scenes' scripts).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub learnt: Option<Learnt>,
}

impl BoxSpec {
    /// A uniform box (centred CoM), friction 0.8, tag centred on `+x`.
    pub fn new(name: &str, dims: [f64; 3], mass: f64) -> BoxSpec {
        BoxSpec {
            name: name.to_string(),
            dims,
            mass,
            com_offset: [0.0; 3],
            friction: 0.8,
            tag: TagMount::centred(BoxFace::PosX),
            learnt: None,
        }
    }

    /// Builder: set the centre-of-mass offset from the geometric centre \[m\].
    pub fn with_com(mut self, com_offset: [f64; 3]) -> Self {
        self.com_offset = com_offset;
        self
    }

    /// Builder: set the friction coefficient.
    pub fn with_friction(mut self, mu: f64) -> Self {
        self.friction = mu;
        self
    }

    /// Builder: set the tag mount.
    pub fn with_tag(mut self, tag: TagMount) -> Self {
        self.tag = tag;
        self
    }

    /// Half extents `(a, b, c)` \[m\].
    pub fn half_extents(&self) -> Vector3<f64> {
        Vector3::from(self.dims) * 0.5
    }

    /// Centre of mass in the box frame \[m\].
    pub fn com_box(&self) -> Point3<f64> {
        Point3::from(Vector3::from(self.com_offset))
    }

    /// Principal moments of inertia about the CoM \[kg m²\]: those of a uniform box,
    /// `I_x = m (b'² + c'²) / 12` with `b', c'` the full edge lengths (the weight inside is
    /// not modelled in the inertia: quasi-static toppling does not depend on it).
    pub fn principal_inertia(&self) -> Vector3<f64> {
        let [x, y, z] = self.dims;
        let m = self.mass / 12.0;
        Vector3::new(
            m * (y * y + z * z),
            m * (x * x + z * z),
            m * (x * x + y * y),
        )
    }

    /// The tag frame in the box frame (see [`TagMount`]).
    pub fn box_from_tag(&self) -> Isometry3<f64> {
        if let Some(l) = &self.learnt {
            return l.box_from_tag;
        }
        let h = self.half_extents();
        let n = self.tag.face.normal();
        let v = if self.tag.face.axis_sign().0 == 2 {
            Vector3::x()
        } else {
            Vector3::z()
        };
        let u = v.cross(&n);
        let (k, s) = self.tag.face.axis_sign();
        let mut c = Vector3::zeros();
        c[k] = s * h[k];
        let origin = c + u * self.tag.offset[0] + v * self.tag.offset[1];
        let face_rot = Rotation3::from_matrix_unchecked(Matrix3::from_columns(&[u, v, n]));
        let r = UnitQuaternion::from_rotation_matrix(&face_rot)
            * UnitQuaternion::from_axis_angle(&Vector3::z_axis(), self.tag.yaw);
        Isometry3::from_parts(Translation3::from(origin), r)
    }

    /// The box frame in the tag frame: `box_from_tag⁻¹`.
    pub fn tag_from_box(&self) -> Isometry3<f64> {
        self.box_from_tag().inverse()
    }

    /// Check that the numbers describe a physical box.
    pub fn validate(&self) -> Result<()> {
        let bad = |m: String| Err(SimError::InvalidSpec(m));
        if self
            .dims
            .iter()
            .any(|d| !(d.is_finite() && *d >= 0.005 && *d <= 2.0))
        {
            return bad(format!(
                "box dimensions {:?} m must each be between 0.005 and 2 m",
                self.dims
            ));
        }
        if !(self.mass.is_finite() && self.mass > 0.0 && self.mass <= 100.0) {
            return bad(format!(
                "mass {} kg must be positive and at most 100 kg",
                self.mass
            ));
        }
        if !(self.friction.is_finite() && self.friction > 0.0 && self.friction <= 3.0) {
            return bad(format!("friction {} must be in (0, 3]", self.friction));
        }
        let h = self.half_extents();
        for k in 0..3 {
            if !self.com_offset[k].is_finite() || self.com_offset[k].abs() > 0.8 * h[k] {
                return bad(format!(
                    "centre-of-mass offset {:?} m must stay inside 80% of the half extents {:?} m",
                    self.com_offset,
                    [h.x, h.y, h.z]
                ));
            }
        }
        Ok(())
    }
}

/// A learnt object as a scene's box: its body in the box frame, and where its tag is.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Learnt {
    /// The rigid body, box frame.
    pub body: RigidModel,
    /// The tag (object) frame in the box frame.
    pub box_from_tag: Isometry3<f64>,
}

impl RigidModel {
    /// The box of `spec` in its box frame (centre, axes along its edges).
    pub fn of_box(spec: &BoxSpec) -> RigidModel {
        RigidModel {
            geometry: Geometry::Cuboid {
                body_from_box: Isometry3::identity(),
                half_extents: spec.half_extents(),
            },
            mass: spec.mass,
            com: spec.com_box().coords,
            inertia: Matrix3::from_diagonal(&spec.principal_inertia()),
            friction: spec.friction,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tag_sits_on_its_face_with_outward_z() {
        let mut rng = <rand::rngs::StdRng as rand::SeedableRng>::seed_from_u64(1);
        for _ in 0..20 {
            let spec =
                BoxSpec::new("b", [0.1, 0.12, 0.2], 0.5).with_tag(TagMount::random(&mut rng));
            let t = spec.box_from_tag();
            let n = spec.tag.face.normal();
            let z = t.rotation * Vector3::z();
            assert!((z - n).norm() < 1e-12);
            let (k, s) = spec.tag.face.axis_sign();
            assert!((t.translation.vector[k] - s * spec.half_extents()[k]).abs() < 1e-12);
            assert!((t.rotation.to_rotation_matrix().matrix().determinant() - 1.0).abs() < 1e-12);
        }
    }
}
