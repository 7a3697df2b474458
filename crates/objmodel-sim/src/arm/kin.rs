//! The one boundary with the `k` kinematics crate, which speaks nalgebra 0.30 (this workspace
//! uses 0.34): everything that crosses is copied component by component into 0.34 types here,
//! and nothing else in the crate names a `k` or nalgebra-0.30 type.
//!
//! `k` builds its chain from the same parsed URDF ([`urdf_rs::Robot`]) as the simulation, and
//! gives forward kinematics (`SerialChain::end_transform`) and the geometric Jacobian
//! (`k::jacobian`: rows are the linear then the angular velocity of the tip, in the base frame,
//! with the tip origin as reference point).

use super::{ArmError, Result};
use nalgebra::{Isometry3, Matrix6xX, Quaternion, Translation3, UnitQuaternion};

/// `k`'s serial chain from the base to the tip joint. `k`'s nodes are shared, mutable state
/// (`Arc<Mutex<_>>`), so [`Kin::clone`] rebuilds the chain from the URDF instead of sharing it.
pub struct Kin {
    robot: urdf_rs::Robot,
    tip_joint: String,
    chain: k::SerialChain<f64>,
}

impl std::fmt::Debug for Kin {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Kin")
            .field("robot", &self.robot.name)
            .field("tip_joint", &self.tip_joint)
            .field("dof", &self.chain.dof())
            .finish()
    }
}

impl Clone for Kin {
    fn clone(&self) -> Kin {
        Kin::new(&self.robot, &self.tip_joint).expect("the chain was built from this URDF before")
    }
}

fn iso_from_k(t: &k::Isometry3<f64>) -> Isometry3<f64> {
    let q = t.rotation.quaternion();
    Isometry3::from_parts(
        Translation3::new(t.translation.x, t.translation.y, t.translation.z),
        UnitQuaternion::new_unchecked(Quaternion::new(q.w, q.i, q.j, q.k)),
    )
}

impl Kin {
    /// `k`'s chain from the URDF's root to the joint `tip_joint` (whose child is the tip link).
    pub fn new(robot: &urdf_rs::Robot, tip_joint: &str) -> Result<Kin> {
        let full = k::Chain::<f64>::from(robot);
        let end = full
            .find(tip_joint)
            .ok_or_else(|| ArmError::Model(format!("k: no joint named {tip_joint:?}")))?;
        let chain = k::SerialChain::from_end(end);
        Ok(Kin {
            robot: robot.clone(),
            tip_joint: tip_joint.to_string(),
            chain,
        })
    }

    /// Number of moving joints.
    pub fn dof(&self) -> usize {
        self.chain.dof()
    }

    /// Names of the moving joints, base to tip.
    pub fn joint_names(&self) -> Vec<String> {
        self.chain.iter_joints().map(|j| j.name.clone()).collect()
    }

    /// Position limits of the moving joints as `k` read them (`None` when unlimited).
    pub fn limits(&self) -> Vec<Option<(f64, f64)>> {
        self.chain
            .iter_joints()
            .map(|j| j.limits.as_ref().map(|r| (r.min, r.max)))
            .collect()
    }

    /// `base_from_tip` at joint positions `q` (length [`Kin::dof`], not checked here).
    pub fn fk(&self, q: &[f64]) -> Isometry3<f64> {
        self.chain.set_joint_positions_unchecked(q);
        iso_from_k(&self.chain.end_transform())
    }

    /// `base_from_tip` and the 6 x dof geometric Jacobian (linear rows first) at `q`.
    pub fn fk_jacobian(&self, q: &[f64]) -> (Isometry3<f64>, Matrix6xX<f64>) {
        self.chain.set_joint_positions_unchecked(q);
        let t = iso_from_k(&self.chain.end_transform());
        let j = k::jacobian(&self.chain);
        let n = j.ncols();
        let jac = Matrix6xX::from_fn(n, |r, c| j[(r, c)]);
        (t, jac)
    }
}
