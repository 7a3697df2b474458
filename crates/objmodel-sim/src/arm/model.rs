//! The arm as read from its URDF, in this workspace's nalgebra: the serial chain of revolute
//! joints from the base link to the palm, and one rigid body per moving link with the links
//! hanging off it by fixed joints merged in (their collision shapes and inertias).

use super::{ArmError, Result};
use nalgebra::{Isometry3, Matrix3, Point3, Translation3, Unit, UnitQuaternion, Vector3};
use std::collections::HashMap;

/// A revolute joint of the chain.
#[derive(Debug, Clone, PartialEq)]
pub struct JointSpec {
    /// URDF name.
    pub name: String,
    /// `parent_from_joint` at zero angle: the URDF `<origin>`, in the parent body's frame.
    pub origin: Isometry3<f64>,
    /// Rotation axis in the joint (child link) frame.
    pub axis: Unit<Vector3<f64>>,
    /// Lower position limit \[rad\] (`-inf` for a continuous joint).
    pub lower: f64,
    /// Upper position limit \[rad\] (`+inf` for a continuous joint).
    pub upper: f64,
    /// Velocity limit \[rad/s\].
    pub velocity: f64,
    /// Torque limit \[N m\].
    pub effort: f64,
}

/// Mass, centre of mass and inertia (about the centre of mass, in the body frame).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InertialSpec {
    /// Mass \[kg\].
    pub mass: f64,
    /// Centre of mass in the body frame \[m\].
    pub com: Point3<f64>,
    /// Inertia tensor about the centre of mass, body axes \[kg m²\].
    pub inertia: Matrix3<f64>,
}

impl InertialSpec {
    /// Nothing.
    pub fn zero() -> InertialSpec {
        InertialSpec {
            mass: 0.0,
            com: Point3::origin(),
            inertia: Matrix3::zeros(),
        }
    }

    /// This inertial expressed in another frame: `other_from_this` maps this frame into it.
    pub fn transformed(&self, other_from_this: &Isometry3<f64>) -> InertialSpec {
        let r = other_from_this.rotation.to_rotation_matrix();
        InertialSpec {
            mass: self.mass,
            com: other_from_this * self.com,
            inertia: r.matrix() * self.inertia * r.matrix().transpose(),
        }
    }

    /// The sum of two rigidly joined inertials (parallel-axis theorem), both in the same frame.
    pub fn add(&self, o: &InertialSpec) -> InertialSpec {
        let m = self.mass + o.mass;
        if m <= 0.0 {
            return InertialSpec::zero();
        }
        let c = Point3::from((self.com.coords * self.mass + o.com.coords * o.mass) / m);
        let shift = |i: &InertialSpec| {
            let d = i.com - c;
            i.inertia + (Matrix3::identity() * d.dot(&d) - d * d.transpose()) * i.mass
        };
        InertialSpec {
            mass: m,
            com: c,
            inertia: shift(self) + shift(o),
        }
    }
}

/// A collision shape's geometry (URDF conventions: cylinders and capsules along local `z`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ShapeKind {
    /// A box of half extents.
    Cuboid(Vector3<f64>),
    /// A cylinder along `z`: radius, half length.
    Cylinder(f64, f64),
    /// A capsule along `z`: radius, half length of the cylindrical part.
    Capsule(f64, f64),
    /// A sphere of radius.
    Sphere(f64),
}

/// A collision shape placed in its body's frame.
#[derive(Debug, Clone, PartialEq)]
pub struct CollisionShape {
    /// The URDF link it belongs to.
    pub link: String,
    /// `body_from_shape`.
    pub pose: Isometry3<f64>,
    /// The geometry.
    pub kind: ShapeKind,
}

/// One rigid body of the arm: a URDF link plus every link fixed to it.
#[derive(Debug, Clone, PartialEq)]
pub struct BodySpec {
    /// Name of the URDF link whose frame is the body frame.
    pub name: String,
    /// Merged inertial of the link and its fixed children.
    pub inertial: InertialSpec,
    /// Collision shapes of the link and its fixed children.
    pub shapes: Vec<CollisionShape>,
    /// Each merged URDF link and `body_from_link`.
    pub links: Vec<(String, Isometry3<f64>)>,
}

/// A serial arm: `bodies[0]` is the fixed base, `joints[i]` moves `bodies[i + 1]`.
#[derive(Debug, Clone, PartialEq)]
pub struct ArmModel {
    /// The robot's name.
    pub name: String,
    /// The revolute joints from the base to the tip.
    pub joints: Vec<JointSpec>,
    /// The base and the moving bodies.
    pub bodies: Vec<BodySpec>,
    /// Name of the tip link (the palm).
    pub tip_link: String,
    /// `last_body_from_tip`: the tip (palm) frame in the last moving body's frame.
    pub last_from_tip: Isometry3<f64>,
}

fn pose_of(p: &urdf_rs::Pose) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(p.xyz[0], p.xyz[1], p.xyz[2]),
        UnitQuaternion::from_euler_angles(p.rpy[0], p.rpy[1], p.rpy[2]),
    )
}

fn inertial_of(l: &urdf_rs::Link) -> InertialSpec {
    let i = &l.inertial.inertia;
    let local = InertialSpec {
        mass: l.inertial.mass.value,
        com: Point3::origin(),
        inertia: Matrix3::new(
            i.ixx, i.ixy, i.ixz, //
            i.ixy, i.iyy, i.iyz, //
            i.ixz, i.iyz, i.izz,
        ),
    };
    local.transformed(&pose_of(&l.inertial.origin))
}

fn shapes_of(l: &urdf_rs::Link) -> Result<Vec<CollisionShape>> {
    l.collision
        .iter()
        .map(|c| {
            let kind = match &c.geometry {
                urdf_rs::Geometry::Box { size } => {
                    ShapeKind::Cuboid(Vector3::new(size[0], size[1], size[2]) * 0.5)
                }
                urdf_rs::Geometry::Cylinder { radius, length } => {
                    ShapeKind::Cylinder(*radius, length * 0.5)
                }
                urdf_rs::Geometry::Capsule { radius, length } => {
                    ShapeKind::Capsule(*radius, length * 0.5)
                }
                urdf_rs::Geometry::Sphere { radius } => ShapeKind::Sphere(*radius),
                urdf_rs::Geometry::Mesh { filename, .. } => {
                    return Err(ArmError::Model(format!(
                        "link {}: mesh collision shapes ({filename}) are not supported; use boxes, \
                         cylinders, capsules or spheres",
                        l.name
                    )))
                }
            };
            Ok(CollisionShape {
                link: l.name.clone(),
                pose: pose_of(&c.origin),
                kind,
            })
        })
        .collect()
}

impl ArmModel {
    /// Read the serial chain from the root link to `tip_link`. Joints on the chain must be
    /// revolute, continuous or fixed; links fixed (directly or through other fixed joints) to a
    /// body are merged into it; links hanging off the chain by moving joints are ignored.
    pub fn from_robot(robot: &urdf_rs::Robot, tip_link: &str) -> Result<ArmModel> {
        let links: HashMap<&str, &urdf_rs::Link> =
            robot.links.iter().map(|l| (l.name.as_str(), l)).collect();
        if !links.contains_key(tip_link) {
            return Err(ArmError::Model(format!("no link named {tip_link:?}")));
        }
        let by_child: HashMap<&str, &urdf_rs::Joint> = robot
            .joints
            .iter()
            .map(|j| (j.child.link.as_str(), j))
            .collect();
        // Walk from the tip up to the root.
        let mut chain: Vec<&urdf_rs::Joint> = Vec::new();
        let mut cur = tip_link;
        while let Some(j) = by_child.get(cur) {
            chain.push(j);
            cur = j.parent.link.as_str();
            if chain.len() > robot.joints.len() {
                return Err(ArmError::Model("the URDF's joints form a cycle".into()));
            }
        }
        chain.reverse();
        let root = cur;

        let mut model = ArmModel {
            name: robot.name.clone(),
            joints: Vec::new(),
            bodies: Vec::new(),
            tip_link: tip_link.to_string(),
            last_from_tip: Isometry3::identity(),
        };
        // Fixed children of every link (for merging).
        let mut fixed_children: HashMap<&str, Vec<&urdf_rs::Joint>> = HashMap::new();
        for j in &robot.joints {
            if j.joint_type == urdf_rs::JointType::Fixed {
                fixed_children
                    .entry(j.parent.link.as_str())
                    .or_default()
                    .push(j);
            }
        }
        let body_of = |name: &str| -> Result<BodySpec> {
            let mut body = BodySpec {
                name: name.to_string(),
                inertial: InertialSpec::zero(),
                shapes: Vec::new(),
                links: Vec::new(),
            };
            let mut stack = vec![(name, Isometry3::identity())];
            while let Some((ln, body_from_link)) = stack.pop() {
                let l = links.get(ln).ok_or_else(|| {
                    ArmError::Model(format!("joint refers to missing link {ln:?}"))
                })?;
                body.inertial = body
                    .inertial
                    .add(&inertial_of(l).transformed(&body_from_link));
                for s in shapes_of(l)? {
                    body.shapes.push(CollisionShape {
                        pose: body_from_link * s.pose,
                        ..s
                    });
                }
                body.links.push((ln.to_string(), body_from_link));
                for j in fixed_children.get(ln).map(|v| v.as_slice()).unwrap_or(&[]) {
                    stack.push((j.child.link.as_str(), body_from_link * pose_of(&j.origin)));
                }
            }
            Ok(body)
        };

        model.bodies.push(body_of(root)?);
        // Fixed joints on the chain accumulate into the next moving joint's origin.
        let mut pending = Isometry3::identity();
        for j in &chain {
            match j.joint_type {
                urdf_rs::JointType::Fixed => pending *= pose_of(&j.origin),
                urdf_rs::JointType::Revolute | urdf_rs::JointType::Continuous => {
                    let axis = Vector3::new(j.axis.xyz[0], j.axis.xyz[1], j.axis.xyz[2]);
                    if axis.norm() < 1e-9 {
                        return Err(ArmError::Model(format!("joint {} has a zero axis", j.name)));
                    }
                    let (lower, upper) = if j.joint_type == urdf_rs::JointType::Continuous {
                        (f64::NEG_INFINITY, f64::INFINITY)
                    } else {
                        (j.limit.lower, j.limit.upper)
                    };
                    if lower.partial_cmp(&upper) != Some(std::cmp::Ordering::Less) {
                        return Err(ArmError::Model(format!(
                            "joint {} has limits [{lower}, {upper}]",
                            j.name
                        )));
                    }
                    if j.limit.velocity.is_nan() || j.limit.velocity <= 0.0 {
                        return Err(ArmError::Model(format!(
                            "joint {} needs a positive velocity limit",
                            j.name
                        )));
                    }
                    model.joints.push(JointSpec {
                        name: j.name.clone(),
                        origin: pending * pose_of(&j.origin),
                        axis: Unit::new_normalize(axis),
                        lower,
                        upper,
                        velocity: j.limit.velocity,
                        effort: if j.limit.effort > 0.0 {
                            j.limit.effort
                        } else {
                            f64::INFINITY
                        },
                    });
                    pending = Isometry3::identity();
                    model.bodies.push(body_of(&j.child.link)?);
                }
                _ => {
                    return Err(ArmError::Model(format!(
                    "joint {} is {:?}: only revolute, continuous and fixed joints are supported",
                    j.name, j.joint_type
                )))
                }
            }
        }
        if model.joints.is_empty() {
            return Err(ArmError::Model(format!(
                "no moving joint between {root:?} and {tip_link:?}"
            )));
        }
        model.last_from_tip = pending;
        // The tip must have been merged into the last body at `pending`.
        let last = model.bodies.last().unwrap();
        match last.links.iter().find(|(n, _)| n == tip_link) {
            Some((_, p)) if (p.to_homogeneous() - pending.to_homogeneous()).norm() < 1e-12 => {}
            _ => {
                return Err(ArmError::Model(format!(
                    "tip link {tip_link:?} is not rigidly attached to the last moving link"
                )))
            }
        }
        Ok(model)
    }

    /// Number of joints.
    pub fn dof(&self) -> usize {
        self.joints.len()
    }

    /// `base_from_tip` by plain products of the joint transforms (an independent check of `k`).
    pub fn fk_product(&self, q: &[f64]) -> Isometry3<f64> {
        let mut t = Isometry3::identity();
        for (j, &qi) in self.joints.iter().zip(q) {
            t = t * j.origin * UnitQuaternion::from_axis_angle(&j.axis, qi);
        }
        t * self.last_from_tip
    }
}
