//! The arm in rapier: a multibody (reduced coordinates) built from the URDF model, revolute
//! joints with position motors that track a [`JointTrajectory`], a fixed base, gravity on, and
//! boxes that ride on the palm through contact and friction only.
//!
//! The world is set up exactly like [`crate::world::World`] (same [`PhysicsParams`]: no contact
//! recycling, Coulomb friction, stiff contacts, 960 Hz), so a box behaves on the arm's palm as
//! it does on the kinematic plate of the instrumented scene. The world is a plain rapier
//! [`PhysicsWorld`] (public: add anything to it) because `World` does not expose its rapier
//! world to other modules.
//!
//! Motors: acceleration-based position motors (rapier's default model: stiffness and damping
//! act like `ω²` and `2ζω`, independent of the link inertias) with the trajectory's position and
//! velocity as targets and the URDF's torque limits as force caps. With
//! [`ArmSimOptions::gravity_compensation`] (default, as on the real Panda, whose controller
//! compensates the arm's own weight) every link carries a constant upward force equal to its
//! weight at its centre of mass; whatever is on the palm is not compensated.

use super::ik::Arm;
use super::model::{BodySpec, ShapeKind};
use super::path::JointTrajectory;
use super::{ArmError, Result};
use crate::convert::{pose_from_na, pose_to_na, rot_from_na, vec_from_na, vec_to_na};
use crate::spec::BoxSpec;
use crate::world::PhysicsParams;
use ::nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, UnitQuaternion, Vector3};
use rapier3d_f64::prelude::*;

/// Collision group of the arm's colliders (they never collide with each other).
pub const ARM_GROUP: Group = Group::GROUP_1;
/// Collision group of objects (boxes, tables): they collide with everything.
pub const OBJECT_GROUP: Group = Group::GROUP_2;

/// Options of an [`ArmSim`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArmSimOptions {
    /// Physics settings (the crate's defaults: 960 Hz, no contact recycling, Coulomb friction).
    pub physics: PhysicsParams,
    /// Where the arm's base stands: `world_from_base`.
    pub world_from_base: Isometry3<f64>,
    /// Friction coefficient of the palm (combined with an object's by taking the smaller).
    pub palm_friction: f64,
    /// Friction of the arm's other links.
    pub link_friction: f64,
    /// Natural frequency of the joint position motors \[Hz\].
    pub motor_frequency: f64,
    /// Damping ratio of the joint position motors.
    pub motor_damping_ratio: f64,
    /// Cancel the weight of the arm's links (not of what is on the palm).
    pub gravity_compensation: bool,
    /// Cap motor torques at the URDF's effort limits.
    pub torque_limits: bool,
    /// Projected Gauss-Seidel iterations inside each solver iteration (rapier's
    /// `num_internal_pgs_iterations`; [`crate::world::World`] keeps rapier's 1). Rapier does not
    /// warm-start multibody motor constraints, and with 1 a 0.6 kg box resting on the
    /// motor-held palm was measured to creep ~20 µm/s; with 2, 0.5 µm/s; with 4, 2 nm/s, at
    /// ~20% more time per step.
    pub pgs_iterations: usize,
}

impl Default for ArmSimOptions {
    fn default() -> Self {
        ArmSimOptions {
            physics: PhysicsParams::default(),
            world_from_base: Isometry3::identity(),
            palm_friction: 0.9,
            link_friction: 0.5,
            motor_frequency: 40.0,
            motor_damping_ratio: 1.0,
            gravity_compensation: true,
            torque_limits: true,
            pgs_iterations: 4,
        }
    }
}

/// Palm tracking error: simulated palm against the palm pose the joint targets command.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TrackingError {
    /// Distance between the palm origins \[m\].
    pub position: f64,
    /// Angle between the palm frames \[rad\].
    pub angle: f64,
}

impl TrackingError {
    /// The larger of each component.
    pub fn max(self, o: TrackingError) -> TrackingError {
        TrackingError {
            position: self.position.max(o.position),
            angle: self.angle.max(o.angle),
        }
    }
}

/// The arm in a rapier world.
pub struct ArmSim {
    /// The rapier world (gravity `-9.81 e_z`, tuned like [`crate::world::World`]).
    pub world: PhysicsWorld,
    /// Simulated time \[s\].
    pub t: f64,
    /// Step length \[s\].
    pub dt: f64,
    /// The arm's kinematics (same URDF).
    pub arm: Arm,
    /// The fixed base body.
    pub base: RigidBodyHandle,
    /// The moving links' bodies, joint order (`links[i]` is moved by joint `i`).
    pub links: Vec<RigidBodyHandle>,
    /// The multibody joints, base to palm.
    pub joints: Vec<MultibodyJointHandle>,
    /// The palm's collider.
    pub palm_collider: Option<ColliderHandle>,
    /// Every collider of the arm (base, links, palm).
    pub arm_colliders: Vec<ColliderHandle>,
    /// `world_from_base`.
    pub world_from_base: Isometry3<f64>,
    last_from_palm: Isometry3<f64>,
    target_q: Vec<f64>,
    target_qd: Vec<f64>,
    trajectory: Option<(JointTrajectory, f64)>,
    stiffness: f64,
    damping: f64,
}

/// A rapier world set up like [`crate::world::World::new`].
pub use crate::world::physics_world;

/// Rapier mass properties of a body spec (principal axes from nalgebra's eigen-decomposition).
fn mass_properties(b: &BodySpec) -> MassProperties {
    let i = &b.inertial;
    if i.mass <= 0.0 {
        return MassProperties::new(Vector::ZERO, 0.0, Vector::ZERO);
    }
    let sym = (i.inertia + i.inertia.transpose()) * 0.5;
    let eig = sym.symmetric_eigen();
    let mut vecs: Matrix3<f64> = eig.eigenvectors;
    let mut vals = eig.eigenvalues;
    if vecs.determinant() < 0.0 {
        vecs.swap_columns(1, 2);
        vals.swap_rows(1, 2);
    }
    let rot = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(vecs));
    // Floor tiny principal moments so the solver never sees a zero inertia.
    let floor = 1e-6;
    let vals = vals.map(|v| v.max(floor));
    MassProperties::with_principal_inertia_frame(
        vec_from_na(&i.com.coords),
        i.mass,
        vec_from_na(&vals),
        rot_from_na(&rot),
    )
}

fn collider_of(kind: &ShapeKind, pose: &Isometry3<f64>) -> ColliderBuilder {
    // Rapier's cylinders run along y, URDF's along z.
    let z_to_y = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_2);
    let (b, p) = match *kind {
        ShapeKind::Cuboid(h) => (ColliderBuilder::cuboid(h.x, h.y, h.z), *pose),
        ShapeKind::Cylinder(r, hl) => (ColliderBuilder::cylinder(hl, r), pose * z_to_y),
        ShapeKind::Capsule(r, hl) => (ColliderBuilder::capsule_z(hl, r), *pose),
        ShapeKind::Sphere(r) => (ColliderBuilder::ball(r), *pose),
    };
    b.position(pose_from_na(&p)).density(0.0)
}

impl ArmSim {
    /// The arm at joint positions `q0` (within limits), holding them.
    pub fn new(arm: &Arm, q0: &[f64], o: &ArmSimOptions) -> Result<ArmSim> {
        let model = arm.model();
        if q0.len() != model.dof() || q0.iter().any(|v| !v.is_finite()) {
            return Err(ArmError::BadJoints(format!(
                "start configuration {q0:?} for a {}-joint arm",
                model.dof()
            )));
        }
        if !arm.within_limits(q0, 1e-9) {
            return Err(ArmError::BadJoints(format!(
                "start configuration {q0:?} is outside the joint limits"
            )));
        }
        let mut world = physics_world(&o.physics);
        world.integration_parameters.num_internal_pgs_iterations = o.pgs_iterations.max(1);
        let arm_groups = InteractionGroups::new(
            ARM_GROUP,
            Group::ALL.difference(ARM_GROUP),
            InteractionTestMode::And,
        );
        let wfb = o.world_from_base;
        let base = world.insert_body(RigidBodyBuilder::fixed().pose(pose_from_na(&wfb)));
        let mut palm_collider = None;
        let mut arm_colliders = Vec::new();
        let palm_name = model.tip_link.clone();
        let mut add_colliders =
            |world: &mut PhysicsWorld, body: RigidBodyHandle, spec: &BodySpec| {
                for s in &spec.shapes {
                    let is_palm = s.link == palm_name;
                    let mu = if is_palm {
                        o.palm_friction
                    } else {
                        o.link_friction
                    };
                    let c = collider_of(&s.kind, &s.pose)
                        .friction(mu)
                        .friction_combine_rule(CoefficientCombineRule::Min)
                        .collision_groups(arm_groups);
                    let h = world.insert_collider(c, Some(body));
                    arm_colliders.push(h);
                    if is_palm {
                        palm_collider = Some(h);
                    }
                }
            };
        add_colliders(&mut world, base, &model.bodies[0]);

        let omega = 2.0 * std::f64::consts::PI * o.motor_frequency;
        let stiffness = omega * omega;
        let damping = 2.0 * o.motor_damping_ratio * omega;
        let x_to_axis = |axis: &Vector3<f64>| {
            UnitQuaternion::rotation_between(&Vector3::x(), axis).unwrap_or_else(|| {
                UnitQuaternion::from_axis_angle(&Vector3::z_axis(), std::f64::consts::PI)
            })
        };

        let mut links = Vec::new();
        let mut joints = Vec::new();
        let mut parent = base;
        let mut world_from_parent = wfb;
        let g = Vector3::new(0.0, 0.0, -9.81);
        for (i, js) in model.joints.iter().enumerate() {
            let spec = &model.bodies[i + 1];
            let world_from_link =
                world_from_parent * js.origin * UnitQuaternion::from_axis_angle(&js.axis, q0[i]);
            let rb = RigidBodyBuilder::dynamic()
                .pose(pose_from_na(&world_from_link))
                .additional_mass_properties(mass_properties(spec))
                .can_sleep(false);
            let body = world.insert_body(rb);
            if o.gravity_compensation {
                // A constant force at the centre of mass; rapier keeps user forces until reset.
                world.bodies[body].add_force(vec_from_na(&(-g * spec.inertial.mass)), true);
            }
            add_colliders(&mut world, body, spec);
            let align = x_to_axis(&js.axis);
            let mut gj = GenericJointBuilder::new(JointAxesMask::LOCKED_REVOLUTE_AXES)
                .local_frame1(pose_from_na(&(js.origin * align)))
                .local_frame2(pose_from_na(&Isometry3::from_parts(
                    Translation3::identity(),
                    align,
                )))
                .contacts_enabled(false)
                .motor_model(JointAxis::AngX, MotorModel::AccelerationBased)
                .motor_position(JointAxis::AngX, q0[i], stiffness, damping);
            if js.lower.is_finite() && js.upper.is_finite() {
                gj = gj.limits(JointAxis::AngX, [js.lower, js.upper]);
            }
            if o.torque_limits && js.effort.is_finite() {
                gj = gj.motor_max_force(JointAxis::AngX, js.effort);
            }
            let h = world
                .multibody_joints
                .insert(parent, body, gj.build(), true)
                .ok_or_else(|| ArmError::Model(format!("rapier refused joint {}", js.name)))?;
            links.push(body);
            joints.push(h);
            parent = body;
            world_from_parent = world_from_link;
        }
        let mut sim = ArmSim {
            world,
            t: 0.0,
            dt: 1.0 / o.physics.step_hz,
            arm: arm.clone(),
            base,
            links,
            joints,
            palm_collider,
            arm_colliders,
            world_from_base: wfb,
            last_from_palm: model.last_from_tip,
            target_q: q0.to_vec(),
            target_qd: vec![0.0; q0.len()],
            trajectory: None,
            stiffness,
            damping,
        };
        sim.set_configuration(q0)?;
        Ok(sim)
    }

    /// Teleport the arm to `q` at rest and hold it there (set-up only: not for use while an
    /// object rests on the palm).
    pub fn set_configuration(&mut self, q: &[f64]) -> Result<()> {
        if q.len() != self.joints.len() {
            return Err(ArmError::BadJoints(format!("{} values", q.len())));
        }
        let link_ids: Vec<usize> = self
            .joints
            .iter()
            .map(|&h| self.world.multibody_joints.get(h).map(|(_, id)| id))
            .collect::<Option<Vec<_>>>()
            .ok_or_else(|| ArmError::Model("the arm's multibody is gone".into()))?;
        let (mb, _) = self.world.multibody_joints.get_mut(self.joints[0]).unwrap();
        // Let the multibody notice its root is fixed (drops the root's 6 free DoFs).
        mb.forward_kinematics(&self.world.bodies, true);
        let mut disp = vec![0.0; mb.ndofs()];
        for (i, &id) in link_ids.iter().enumerate() {
            let link = mb.link(id).expect("arm link");
            disp[link.assembly_id()] = q[i] - link.joint().coords()[3];
        }
        mb.apply_displacements(&disp);
        mb.generalized_velocity_mut().fill(0.0);
        mb.forward_kinematics(&self.world.bodies, false);
        mb.update_rigid_bodies(&mut self.world.bodies, true);
        for &b in &self.links {
            let rb = &mut self.world.bodies[b];
            rb.set_linvel(Vector::ZERO, true);
            rb.set_angvel(Vector::ZERO, true);
        }
        self.trajectory = None;
        self.target_q = q.to_vec();
        self.target_qd = vec![0.0; q.len()];
        self.apply_targets();
        Ok(())
    }

    fn apply_targets(&mut self) {
        for (i, &h) in self.joints.iter().enumerate() {
            if let Some((mb, link_id)) = self.world.multibody_joints.get_mut(h) {
                if let Some(link) = mb.link_mut(link_id) {
                    link.joint.data.set_motor(
                        JointAxis::AngX,
                        self.target_q[i],
                        self.target_qd[i],
                        self.stiffness,
                        self.damping,
                    );
                }
            }
        }
    }

    /// Command fixed joint targets (positions \[rad\], velocities \[rad/s\]); cancels a trajectory.
    pub fn set_joint_targets(&mut self, q: &[f64], qd: &[f64]) {
        assert_eq!(q.len(), self.joints.len());
        assert_eq!(qd.len(), self.joints.len());
        self.trajectory = None;
        self.target_q = q.to_vec();
        self.target_qd = qd.to_vec();
        self.apply_targets();
    }

    /// Follow `traj` from now on (its time 0 is the current time); afterwards hold its end.
    pub fn follow(&mut self, traj: JointTrajectory) {
        self.trajectory = Some((traj, self.t));
    }

    /// Whether a trajectory is still running.
    pub fn is_moving(&self) -> bool {
        self.trajectory
            .as_ref()
            .is_some_and(|(tr, t0)| self.t < t0 + tr.duration())
    }

    /// The joint targets at the current time (positions, velocities).
    pub fn targets(&self) -> (&[f64], &[f64]) {
        (&self.target_q, &self.target_qd)
    }

    /// Advance one step of `dt`: set the motors to the trajectory at the end of the step, step.
    pub fn step(&mut self) {
        if let Some((tr, t0)) = &self.trajectory {
            let (q, qd) = tr.sample(self.t + self.dt - t0);
            self.target_q = q;
            self.target_qd = qd;
        }
        self.apply_targets();
        self.world.step();
        self.t += self.dt;
    }

    /// Step for `seconds`.
    pub fn run_for(&mut self, seconds: f64) {
        let n = (seconds / self.dt).round() as usize;
        for _ in 0..n {
            self.step();
        }
    }

    /// Simulated joint positions \[rad\].
    pub fn joint_positions(&self) -> Vec<f64> {
        self.joints
            .iter()
            .map(|&h| {
                let (mb, id) = self.world.multibody_joints.get(h).expect("arm joint");
                mb.link(id).expect("arm link").joint().coords()[3]
            })
            .collect()
    }

    /// Simulated joint velocities \[rad/s\].
    pub fn joint_velocities(&self) -> Vec<f64> {
        self.joints
            .iter()
            .map(|&h| {
                let (mb, id) = self.world.multibody_joints.get(h).expect("arm joint");
                mb.joint_velocity(mb.link(id).expect("arm link"))[0]
            })
            .collect()
    }

    /// The simulated palm frame: `world_from_palm` (origin on the palm's top surface, `z` its
    /// normal), from the multibody's last link.
    pub fn palm_pose(&self) -> Isometry3<f64> {
        let last = *self.links.last().expect("an arm has links");
        pose_to_na(self.world.bodies[last].position()) * self.last_from_palm
    }

    /// The palm's linear velocity at its origin and angular velocity (world frame).
    pub fn palm_velocity(&self) -> (Vector3<f64>, Vector3<f64>) {
        let last = *self.links.last().expect("an arm has links");
        let b = &self.world.bodies[last];
        let p = self.palm_pose().translation.vector;
        (
            vec_to_na(b.velocity_at_point(vec_from_na(&p))),
            vec_to_na(b.angvel()),
        )
    }

    /// The palm pose the current joint targets command: `world_from_base · fk(target)`.
    pub fn commanded_palm_pose(&self) -> Isometry3<f64> {
        self.world_from_base * self.arm.fk(&self.target_q)
    }

    /// The palm pose the running trajectory asks for at the current time (the planned pose,
    /// not re-derived from joints); the commanded pose when no trajectory runs.
    pub fn planned_palm_pose(&self) -> Isometry3<f64> {
        match &self.trajectory {
            Some((tr, t0)) => {
                let (q, _) = tr.sample(self.t - t0);
                self.world_from_base * self.arm.fk(&q)
            }
            None => self.commanded_palm_pose(),
        }
    }

    /// Simulated palm against the palm the trajectory asks for at the current time.
    pub fn tracking_error(&self) -> TrackingError {
        let a = self.palm_pose();
        let b = self.planned_palm_pose();
        TrackingError {
            position: (a.translation.vector - b.translation.vector).norm(),
            angle: a.rotation.angle_to(&b.rotation),
        }
    }

    /// Add a box as a dynamic body at `world_from_box` (mass, CoM and inertia from the spec,
    /// friction `spec.friction` combined with the palm's by the smaller).
    pub fn add_box(&mut self, spec: &BoxSpec, world_from_box: &Isometry3<f64>) -> RigidBodyHandle {
        let (body, col) = crate::world::box_builders(spec, spec.friction, world_from_box);
        let col = col.collision_groups(InteractionGroups::new(
            OBJECT_GROUP,
            Group::ALL,
            InteractionTestMode::And,
        ));
        self.world.insert(body, col).0
    }

    /// Add a box resting on the palm: `palm_from_box` in the current palm frame (use
    /// [`ArmSim::on_palm`] for a box standing on its `-z` face).
    pub fn add_box_on_palm(
        &mut self,
        spec: &BoxSpec,
        palm_from_box: &Isometry3<f64>,
    ) -> RigidBodyHandle {
        let w = self.palm_pose() * palm_from_box;
        self.add_box(spec, &w)
    }

    /// `palm_from_box` for a box standing on its `-z` face at `(x, y)` on the palm, turned by
    /// `yaw` about the palm normal.
    pub fn on_palm(spec: &BoxSpec, x: f64, y: f64, yaw: f64) -> Isometry3<f64> {
        Isometry3::from_parts(
            Translation3::new(x, y, spec.half_extents().z),
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), yaw),
        )
    }

    /// The arm's colliders that `body` touches now (a contact point closer than 0.1 mm; rapier
    /// also keeps predictive contacts up to 2 cm apart, which are not counted).
    pub fn arm_colliders_touching(&self, body: RigidBodyHandle) -> Vec<ColliderHandle> {
        let mut out = Vec::new();
        for &c in self.world.bodies[body].colliders() {
            for pair in self.world.narrow_phase.contact_pairs_with(c) {
                let touching = pair
                    .find_deepest_contact()
                    .is_some_and(|(_, contact)| contact.dist < 1e-4);
                if !touching {
                    continue;
                }
                let other = if pair.collider1 == c {
                    pair.collider2
                } else {
                    pair.collider1
                };
                if self.arm_colliders.contains(&other) && !out.contains(&other) {
                    out.push(other);
                }
            }
        }
        out
    }

    /// Whether `body` touches the palm and no other part of the arm.
    pub fn touches_palm_only(&self, body: RigidBodyHandle) -> bool {
        let t = self.arm_colliders_touching(body);
        t.len() == 1 && Some(t[0]) == self.palm_collider
    }

    /// Pose of any body: `world_from_body`.
    pub fn body_pose(&self, body: RigidBodyHandle) -> Isometry3<f64> {
        pose_to_na(self.world.bodies[body].position())
    }
}
