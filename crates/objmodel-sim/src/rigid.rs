//! A rigid body described in its own frame, whatever it comes from: a specified box (the
//! truth), a learnt model ([`crate::learnt`]) or a URDF file ([`crate::urdf_body`]); and the
//! rapier body that simulates it.
//!
//! The body's frame is any frame fixed to the object; the learnt model's and the URDF's is the
//! object frame (the tracked tag's). Its mass properties (mass, centre of mass, full inertia
//! tensor) are given, never derived from a density: the collider has density zero and the
//! body carries them.

use crate::convert::{pose_from_na, vec_from_na};
use ::nalgebra::{Isometry3, Matrix3, Point3, Vector3};
use rapier3d_f64::prelude::*;
use serde::{Deserialize, Serialize};

/// The collision geometry, in the body frame.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Geometry {
    /// A box of `half_extents` \[m\] whose own frame (centre, axes along its edges) is
    /// `body_from_box`.
    Cuboid {
        /// The box's frame in the body frame.
        body_from_box: Isometry3<f64>,
        /// Half its edge lengths \[m\].
        half_extents: Vector3<f64>,
    },
    /// The convex hull of these points \[m\].
    Hull {
        /// The hull's corners.
        points: Vec<Vector3<f64>>,
    },
}

/// A rigid body: geometry, mass properties and friction, in its body frame.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RigidModel {
    /// Collision geometry.
    pub geometry: Geometry,
    /// Mass \[kg\].
    pub mass: f64,
    /// Centre of mass \[m\].
    pub com: Vector3<f64>,
    /// Inertia tensor about the centre of mass \[kg m²\], body axes.
    pub inertia: Matrix3<f64>,
    /// Coulomb friction coefficient.
    pub friction: f64,
}

impl RigidModel {
    /// The learnt object of an export body, in the object frame.
    pub fn of_body(body: &objmodel::export::Body) -> RigidModel {
        let geometry = match &body.box_fit {
            Some(b) => Geometry::Cuboid {
                body_from_box: Isometry3::from_parts(b.centre.into(), b.rotation),
                half_extents: b.half_extents,
            },
            None => Geometry::Hull {
                points: body.shape.vertices.clone(),
            },
        };
        RigidModel {
            geometry,
            mass: body.mass_kg,
            com: body.com,
            inertia: body.inertia,
            friction: body.friction,
        }
    }

    /// The same body described in the frame `new`: `new_from_body` maps body coordinates to
    /// `new` coordinates.
    pub fn in_frame(&self, new_from_body: &Isometry3<f64>) -> RigidModel {
        let r = new_from_body.rotation.to_rotation_matrix();
        let geometry = match &self.geometry {
            Geometry::Cuboid {
                body_from_box,
                half_extents,
            } => Geometry::Cuboid {
                body_from_box: new_from_body * body_from_box,
                half_extents: *half_extents,
            },
            Geometry::Hull { points } => Geometry::Hull {
                points: points
                    .iter()
                    .map(|p| (new_from_body * Point3::from(*p)).coords)
                    .collect(),
            },
        };
        RigidModel {
            geometry,
            com: (new_from_body * Point3::from(self.com)).coords,
            inertia: r.matrix() * self.inertia * r.matrix().transpose(),
            ..self.clone()
        }
    }

    /// The corners of the geometry \[m\], body frame.
    pub fn corners(&self) -> Vec<Vector3<f64>> {
        match &self.geometry {
            Geometry::Cuboid {
                body_from_box,
                half_extents: h,
            } => (0..8)
                .map(|i| {
                    let s = |b: usize| if i & (1 << b) == 0 { -1.0 } else { 1.0 };
                    let c = Point3::new(s(0) * h.x, s(1) * h.y, s(2) * h.z);
                    (body_from_box * c).coords
                })
                .collect(),
            Geometry::Hull { points } => points.clone(),
        }
    }

    /// The rapier body and collider at `world_from_body`, with friction `mu` (combined with the
    /// other surface's by the smaller). None when the hull is degenerate.
    pub fn builders(
        &self,
        mu: f64,
        world_from_body: &Isometry3<f64>,
    ) -> Option<(RigidBodyBuilder, ColliderBuilder)> {
        let i = &self.inertia;
        let col = |c: usize| vec_from_na(&i.column(c).into_owned());
        let mp = MassProperties::with_inertia_matrix(
            vec_from_na(&self.com),
            self.mass,
            rapier3d_f64::math::Matrix::from_cols(col(0), col(1), col(2)),
        );
        let body = RigidBodyBuilder::dynamic()
            .pose(pose_from_na(world_from_body))
            .additional_mass_properties(mp)
            .can_sleep(false);
        let col = match &self.geometry {
            Geometry::Cuboid {
                body_from_box,
                half_extents: h,
            } => ColliderBuilder::cuboid(h.x, h.y, h.z).position(pose_from_na(body_from_box)),
            Geometry::Hull { points } => {
                let pts: Vec<Vector> = points.iter().map(vec_from_na).collect();
                ColliderBuilder::convex_hull(&pts)?
            }
        };
        let col = col
            .density(0.0)
            .friction(mu)
            .friction_combine_rule(CoefficientCombineRule::Min);
        Some((body, col))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spec::BoxSpec;
    use ::nalgebra::{Translation3, UnitQuaternion};

    /// Moving a body into another frame and back changes nothing; its corners and CoM move
    /// with the frame, the inertia turns with it.
    #[test]
    fn a_frame_change_moves_everything_alike() {
        let spec = BoxSpec::new("b", [0.1, 0.07, 0.2], 0.5).with_com([0.01, 0.0, -0.02]);
        let m = RigidModel::of_box(&spec);
        let t = Isometry3::from_parts(
            Translation3::new(0.1, -0.3, 0.02),
            UnitQuaternion::from_euler_angles(0.3, -1.0, 2.0),
        );
        let moved = m.in_frame(&t);
        for (a, b) in m.corners().iter().zip(moved.corners()) {
            assert!(((t * Point3::from(*a)).coords - b).norm() < 1e-12);
        }
        let back = moved.in_frame(&t.inverse());
        assert!((back.com - m.com).norm() < 1e-12);
        assert!((back.inertia - m.inertia).norm() < 1e-15);
        // Eigenvalues (principal moments) do not change.
        let mut a: Vec<f64> = m.inertia.symmetric_eigenvalues().iter().copied().collect();
        let mut b: Vec<f64> = moved
            .inertia
            .symmetric_eigenvalues()
            .iter()
            .copied()
            .collect();
        a.sort_by(f64::total_cmp);
        b.sort_by(f64::total_cmp);
        assert!(a.iter().zip(&b).all(|(x, y)| (x - y).abs() < 1e-15));
        let hull = RigidModel {
            geometry: Geometry::Hull {
                points: m.corners(),
            },
            ..m.clone()
        };
        assert!(hull.builders(0.5, &t).is_some());
    }
}
