//! A thin wrapper over a rapier world tuned for accurate quasi-static contact.
//!
//! Rapier's defaults favour games. For toppling onsets that match rigid-body theory this crate
//! sets (see the crate README for the measurements):
//! * `contact_recycling = false`: recycled contacts keep their normals and lever arms until a
//!   body has turned about 11°, which delays a topple by 3-8° of tilt;
//! * the Coulomb friction model (one friction cone per contact point instead of one per patch
//!   plus a twist constraint), so a pivoting box does not slip at its edge;
//! * stiffer contacts (`contact_softness` and `static_contact_softness` at a high natural
//!   frequency), so a box does not sink into its support and roll early.
//!
//! All positions go in and out as nalgebra types; the conversion is in [`crate::convert`].

use crate::convert::{pose_from_na, pose_to_na, vec_from_na, vec_to_na};
use crate::spec::BoxSpec;
use ::nalgebra::{Isometry3, Vector3};
use rapier3d_f64::prelude::*;
use serde::{Deserialize, Serialize};

/// Physics settings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PhysicsParams {
    /// Physics steps per second \[Hz\].
    pub step_hz: f64,
    /// Contact natural frequency \[Hz\] (rapier's default is 30 Hz, 60 Hz against fixed bodies).
    pub contact_hz: f64,
    /// Contact damping ratio (rapier's default is 10).
    pub contact_damping: f64,
    /// Solver iterations (substeps) per step.
    pub solver_iterations: usize,
    /// Keep rapier's contact recycling (off by default: it delays toppling).
    pub contact_recycling: bool,
    /// Use rapier's simplified (patch) friction model instead of Coulomb.
    pub simplified_friction: bool,
}

impl Default for PhysicsParams {
    fn default() -> Self {
        PhysicsParams {
            step_hz: 960.0,
            contact_hz: 240.0,
            contact_damping: 5.0,
            solver_iterations: 4,
            contact_recycling: false,
            simplified_friction: false,
        }
    }
}

/// Handle of a body in a [`World`].
pub type Body = RigidBodyHandle;

/// A rapier world plus the current time.
pub struct World {
    pw: PhysicsWorld,
    /// Simulated time \[s\].
    pub t: f64,
    /// Step length \[s\].
    pub dt: f64,
}

/// Gravity in the simulated world \[m/s²\]: z is up.
pub const GRAVITY: [f64; 3] = [0.0, 0.0, -9.81];

/// An empty rapier world with gravity [`GRAVITY`] and the contact settings of `p`
/// (shared by [`World`] and the arm's [`crate::arm::ArmSim`]).
pub fn physics_world(p: &PhysicsParams) -> PhysicsWorld {
    let mut pw = PhysicsWorld::new();
    pw.gravity = Vector::new(GRAVITY[0], GRAVITY[1], GRAVITY[2]);
    let ip = &mut pw.integration_parameters;
    ip.dt = 1.0 / p.step_hz;
    ip.num_solver_iterations = p.solver_iterations;
    ip.contact_recycling = p.contact_recycling;
    ip.friction_model = if p.simplified_friction {
        FrictionModel::Simplified
    } else {
        FrictionModel::Coulomb
    };
    let soft = SpringCoefficients::new(p.contact_hz, p.contact_damping);
    ip.contact_softness = soft;
    ip.static_contact_softness = soft;
    pw
}

/// The rigid body and collider of the box of `spec` at `world_from_box`, with friction `mu`
/// (combined with the other surface's by the smaller). Its mass properties are the spec's mass,
/// CoM and inertia, never derived from a density. A learnt object's spec
/// ([`crate::learnt::learnt_spec`]) gives the learnt body instead.
pub fn box_builders(
    spec: &BoxSpec,
    mu: f64,
    world_from_box: &Isometry3<f64>,
) -> (RigidBodyBuilder, ColliderBuilder) {
    if let Some(l) = &spec.learnt {
        // A hull with no volume (which no closed learnt shape has) falls back to the box of the
        // spec's extents below.
        if let Some(b) = l.body.builders(mu, world_from_box) {
            return b;
        }
    }
    let h = spec.half_extents();
    let mp = MassProperties::new(
        vec_from_na(&spec.com_box().coords),
        spec.mass,
        vec_from_na(&spec.principal_inertia()),
    );
    let body = RigidBodyBuilder::dynamic()
        .pose(pose_from_na(world_from_box))
        .can_sleep(false);
    let col = ColliderBuilder::cuboid(h.x, h.y, h.z)
        .mass_properties(mp)
        .friction(mu)
        .friction_combine_rule(CoefficientCombineRule::Min);
    (body, col)
}

impl World {
    /// An empty world with gravity `-9.81 e_z` m/s².
    pub fn new(p: &PhysicsParams) -> World {
        World {
            pw: physics_world(p),
            t: 0.0,
            dt: 1.0 / p.step_hz,
        }
    }

    /// A fixed table: a slab whose top surface is the plane `z = 0`, with friction `mu`.
    pub fn add_table(&mut self, mu: f64) -> Body {
        let body = RigidBodyBuilder::fixed().translation(Vector::new(0.0, 0.0, -0.05));
        let col = ColliderBuilder::cuboid(2.0, 2.0, 0.05)
            .friction(mu)
            .friction_combine_rule(CoefficientCombineRule::Min);
        self.pw.insert(body, col).0
    }

    /// A kinematic plate (a palm) of half extents `half` whose body frame is on the middle of
    /// its top surface (`z` its outward normal), placed at `world_from_plate`.
    pub fn add_plate(
        &mut self,
        half: [f64; 3],
        mu: f64,
        world_from_plate: &Isometry3<f64>,
    ) -> Body {
        let body =
            RigidBodyBuilder::kinematic_position_based().pose(pose_from_na(world_from_plate));
        let col = ColliderBuilder::cuboid(half[0], half[1], half[2])
            .translation(Vector::new(0.0, 0.0, -half[2]))
            .friction(mu)
            .friction_combine_rule(CoefficientCombineRule::Min);
        self.pw.insert(body, col).0
    }

    /// A kinematic spherical fingertip of `radius` \[m\] at `pos`, with friction `mu`.
    pub fn add_finger(&mut self, radius: f64, mu: f64, pos: &Vector3<f64>) -> Body {
        let body = RigidBodyBuilder::kinematic_position_based().translation(vec_from_na(pos));
        let col = ColliderBuilder::ball(radius)
            .friction(mu)
            .friction_combine_rule(CoefficientCombineRule::Min);
        self.pw.insert(body, col).0
    }

    /// The box of `spec` as a dynamic body at `world_from_box`, in contact with friction `mu`.
    /// Its mass properties are the spec's mass, CoM and inertia, never derived from a density.
    pub fn add_box(&mut self, spec: &BoxSpec, mu: f64, world_from_box: &Isometry3<f64>) -> Body {
        let (body, col) = box_builders(spec, mu, world_from_box);
        self.pw.insert(body, col).0
    }

    /// A body from its builders (see [`crate::rigid::RigidModel::builders`]).
    pub fn add_body(&mut self, body: RigidBodyBuilder, collider: ColliderBuilder) -> Body {
        self.pw.insert(body, collider).0
    }

    /// Set the friction of every collider of `body`.
    pub fn set_friction(&mut self, body: Body, mu: f64) {
        let cols: Vec<ColliderHandle> = self.pw.bodies[body].colliders().to_vec();
        for c in cols {
            self.pw.colliders[c].set_friction(mu);
        }
    }

    /// Set the restitution of every collider of `body`, combined with the other surface's by
    /// the larger (the table's is 0).
    pub fn set_restitution(&mut self, body: Body, e: f64) {
        let cols: Vec<ColliderHandle> = self.pw.bodies[body].colliders().to_vec();
        for c in cols {
            let col = &mut self.pw.colliders[c];
            col.set_restitution(e);
            col.set_restitution_combine_rule(CoefficientCombineRule::Max);
        }
    }

    /// Set a dynamic body's velocity: its centre of mass's \[m/s\] and its angular velocity
    /// \[rad/s\], world frame.
    pub fn set_velocity(&mut self, body: Body, v_com: &Vector3<f64>, w: &Vector3<f64>) {
        let b = &mut self.pw.bodies[body];
        b.set_linvel(vec_from_na(v_com), true);
        b.set_angvel(vec_from_na(w), true);
    }

    /// Pose of a body's frame in the world: `world_from_body`.
    pub fn pose(&self, body: Body) -> Isometry3<f64> {
        pose_to_na(self.pw.bodies[body].position())
    }

    /// Linear velocity of the body's frame origin \[m/s\] and angular velocity \[rad/s\], world frame.
    pub fn velocity(&self, body: Body) -> (Vector3<f64>, Vector3<f64>) {
        let b = &self.pw.bodies[body];
        let origin = b.position().translation;
        (
            vec_to_na(b.velocity_at_point(origin)),
            vec_to_na(b.angvel()),
        )
    }

    /// Command where a kinematic body will be after the next step.
    pub fn set_kinematic(&mut self, body: Body, world_from_body: &Isometry3<f64>) {
        self.pw.bodies[body].set_next_kinematic_position(pose_from_na(world_from_body));
    }

    /// Turn a dynamic body into a kinematic one (grasped), or back (released, at rest).
    pub fn set_grasped(&mut self, body: Body, grasped: bool) {
        let b = &mut self.pw.bodies[body];
        if grasped {
            b.set_body_type(RigidBodyType::KinematicPositionBased, true);
        } else {
            b.set_body_type(RigidBodyType::Dynamic, true);
            b.set_linvel(Vector::ZERO, true);
            b.set_angvel(Vector::ZERO, true);
        }
    }

    /// Advance one step of `dt`.
    pub fn step(&mut self) {
        self.pw.step();
        self.t += self.dt;
    }
}
