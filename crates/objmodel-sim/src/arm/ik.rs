//! [`Arm`]: forward kinematics (through `k`, see [`super::kin`]) and damped-least-squares
//! inverse kinematics with joint limits and a null-space term.

use super::kin::Kin;
use super::model::ArmModel;
use super::{ArmError, Result, PALM_LINK, PANDA_PALM_URDF};
use nalgebra::{DMatrix, DVector, Isometry3, Matrix6xX, Vector6};
use std::path::Path;
use std::sync::Mutex;

/// Options of [`Arm::ik_with`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IkOptions {
    /// Iteration cap.
    pub max_iterations: usize,
    /// Converged when the palm position is within this \[m\] ...
    pub position_tolerance: f64,
    /// ... and its orientation within this \[rad\].
    pub rotation_tolerance: f64,
    /// Largest damping `λ` of the damped least squares, reached at a singularity; damping
    /// starts when the smallest singular value of the Jacobian drops below
    /// [`IkOptions::singular_threshold`] (Nakamura-Hanafusa / Chiaverini variable damping) and
    /// fades out as the pose error falls below 1 cm (so the last steps converge fast).
    pub max_damping: f64,
    /// Smallest singular value below which damping starts.
    pub singular_threshold: f64,
    /// Joint limits are hard bounds shrunk by this margin \[rad\], so a tracking motor never
    /// presses on the simulator's limit stops.
    pub limit_margin: f64,
    /// Gain of the null-space step per iteration (0 turns it off).
    pub null_space_gain: f64,
    /// Iterations that include the null-space step; the rest only polish the palm pose.
    pub null_space_iterations: usize,
    /// Weight of the joint-range term: the gradient of `½ Σ ((q - mid)/half_range)²`.
    pub limit_weight: f64,
    /// Weight of the manipulability term: the gradient of `ln w(q)`, `w = sqrt(det(J Jᵀ))`.
    pub manipulability_weight: f64,
    /// Cap on one iteration's palm correction: position \[m\] ...
    pub max_position_step: f64,
    /// ... and rotation \[rad\].
    pub max_rotation_step: f64,
    /// Cap on one iteration's change of any joint \[rad\].
    pub max_joint_step: f64,
}

impl Default for IkOptions {
    fn default() -> Self {
        IkOptions {
            max_iterations: 300,
            position_tolerance: 1e-9,
            rotation_tolerance: 1e-9,
            max_damping: 0.05,
            singular_threshold: 0.04,
            limit_margin: 0.01,
            null_space_gain: 0.3,
            null_space_iterations: 40,
            limit_weight: 1.0,
            manipulability_weight: 0.2,
            max_position_step: 0.1,
            max_rotation_step: 0.4,
            max_joint_step: 0.3,
        }
    }
}

/// A solution of [`Arm::ik_with`].
#[derive(Debug, Clone, PartialEq)]
pub struct IkSolution {
    /// Joint positions \[rad\].
    pub q: Vec<f64>,
    /// Iterations used.
    pub iterations: usize,
    /// Remaining palm position error \[m\].
    pub position_error: f64,
    /// Remaining palm orientation error \[rad\].
    pub rotation_error: f64,
    /// Yoshikawa manipulability `sqrt(det(J Jᵀ))` at `q`.
    pub manipulability: f64,
    /// Smallest singular value of the Jacobian at `q`.
    pub min_singular_value: f64,
}

/// A serial arm with a palm: its model (from the URDF) and kinematics (from `k`).
pub struct Arm {
    model: ArmModel,
    kin: Mutex<Kin>,
}

impl Clone for Arm {
    fn clone(&self) -> Arm {
        Arm {
            model: self.model.clone(),
            kin: Mutex::new(self.kin.lock().unwrap_or_else(|e| e.into_inner()).clone()),
        }
    }
}

impl std::fmt::Debug for Arm {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Arm")
            .field("name", &self.model.name)
            .field("joints", &self.joint_names())
            .field("tip", &self.model.tip_link)
            .finish()
    }
}

/// `target ⊖ current` as (position, rotation vector) in the base frame.
pub(crate) fn pose_error(target: &Isometry3<f64>, current: &Isometry3<f64>) -> Vector6<f64> {
    let dp = target.translation.vector - current.translation.vector;
    let dr = (target.rotation * current.rotation.inverse()).scaled_axis();
    Vector6::new(dp.x, dp.y, dp.z, dr.x, dr.y, dr.z)
}

fn manipulability_of(j: &Matrix6xX<f64>) -> f64 {
    (j * j.transpose()).determinant().max(0.0).sqrt()
}

impl Arm {
    /// Load a URDF file whose tip link is `palm`.
    pub fn load(path: impl AsRef<Path>) -> Result<Arm> {
        Arm::load_with_tip(path, PALM_LINK)
    }

    /// Load a URDF file with the given tip link.
    pub fn load_with_tip(path: impl AsRef<Path>, tip_link: &str) -> Result<Arm> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path)
            .map_err(|e| ArmError::Urdf(format!("{}: {e}", path.display())))?;
        Arm::from_urdf_str(&text, tip_link)
    }

    /// Parse URDF text with the given tip link.
    pub fn from_urdf_str(text: &str, tip_link: &str) -> Result<Arm> {
        let robot = urdf_rs::read_from_string(text).map_err(|e| ArmError::Urdf(e.to_string()))?;
        let model = ArmModel::from_robot(&robot, tip_link)?;
        let tip_joint = robot
            .joints
            .iter()
            .find(|j| j.child.link == tip_link)
            .map(|j| j.name.clone())
            .ok_or_else(|| ArmError::Model(format!("no joint has {tip_link:?} as its child")))?;
        let kin = Kin::new(&robot, &tip_joint)?;
        let names: Vec<String> = model.joints.iter().map(|j| j.name.clone()).collect();
        if kin.joint_names() != names {
            return Err(ArmError::Model(format!(
                "k's chain {:?} differs from the URDF chain {names:?}",
                kin.joint_names()
            )));
        }
        Ok(Arm {
            model,
            kin: Mutex::new(kin),
        })
    }

    /// The shipped Panda with its palm ([`super::PANDA_PALM_URDF`]).
    pub fn panda() -> Arm {
        Arm::from_urdf_str(PANDA_PALM_URDF, PALM_LINK).expect("the shipped URDF is valid")
    }

    /// The model read from the URDF.
    pub fn model(&self) -> &ArmModel {
        &self.model
    }

    /// Number of joints.
    pub fn dof(&self) -> usize {
        self.model.joints.len()
    }

    /// Joint names, base to palm.
    pub fn joint_names(&self) -> Vec<&str> {
        self.model.joints.iter().map(|j| j.name.as_str()).collect()
    }

    /// Lower position limits \[rad\].
    pub fn lower_limits(&self) -> Vec<f64> {
        self.model.joints.iter().map(|j| j.lower).collect()
    }

    /// Upper position limits \[rad\].
    pub fn upper_limits(&self) -> Vec<f64> {
        self.model.joints.iter().map(|j| j.upper).collect()
    }

    /// Velocity limits \[rad/s\].
    pub fn velocity_limits(&self) -> Vec<f64> {
        self.model.joints.iter().map(|j| j.velocity).collect()
    }

    /// Whether every joint is within its limits (inclusive, with `tol` slack).
    pub fn within_limits(&self, q: &[f64], tol: f64) -> bool {
        q.len() == self.dof()
            && self
                .model
                .joints
                .iter()
                .zip(q)
                .all(|(j, &v)| v >= j.lower - tol && v <= j.upper + tol)
    }

    fn check(&self, q: &[f64]) -> Result<()> {
        if q.len() != self.dof() {
            return Err(ArmError::BadJoints(format!(
                "{} values for a {}-joint arm",
                q.len(),
                self.dof()
            )));
        }
        if q.iter().any(|v| !v.is_finite()) {
            return Err(ArmError::BadJoints(format!("non-finite value in {q:?}")));
        }
        Ok(())
    }

    fn kin(&self) -> std::sync::MutexGuard<'_, Kin> {
        self.kin.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// `base_from_palm` at joint positions `q`.
    ///
    /// # Panics
    /// If `q` does not have one value per joint.
    pub fn fk(&self, q: &[f64]) -> Isometry3<f64> {
        assert_eq!(q.len(), self.dof(), "fk: one joint value per joint");
        self.kin().fk(q)
    }

    /// `base_from_palm` and the 6 x dof geometric Jacobian at `q`: rows are the palm origin's
    /// linear velocity and the palm's angular velocity, both in the base frame.
    ///
    /// # Panics
    /// If `q` does not have one value per joint.
    pub fn fk_jacobian(&self, q: &[f64]) -> (Isometry3<f64>, Matrix6xX<f64>) {
        assert_eq!(q.len(), self.dof(), "jacobian: one joint value per joint");
        self.kin().fk_jacobian(q)
    }

    /// The geometric Jacobian at `q` (see [`Arm::fk_jacobian`]).
    pub fn jacobian(&self, q: &[f64]) -> Matrix6xX<f64> {
        self.fk_jacobian(q).1
    }

    /// Yoshikawa's manipulability `sqrt(det(J Jᵀ))` at `q` (0 at a singularity).
    pub fn manipulability(&self, q: &[f64]) -> f64 {
        manipulability_of(&self.jacobian(q))
    }

    /// The smallest singular value of the Jacobian at `q`.
    pub fn min_singular_value(&self, q: &[f64]) -> f64 {
        self.jacobian(q)
            .singular_values()
            .iter()
            .cloned()
            .fold(f64::INFINITY, f64::min)
    }

    /// Inverse kinematics with default options: joint positions that put the palm at
    /// `base_from_palm = target`, starting from `seed` (see [`Arm::ik_with`]).
    pub fn ik(&self, target: &Isometry3<f64>, seed: &[f64]) -> Result<Vec<f64>> {
        Ok(self.ik_with(target, seed, &IkOptions::default())?.q)
    }

    /// Inverse kinematics: Newton iterations with damped least squares from `seed`.
    ///
    /// Each iteration solves `J Δq = e` (palm pose error `e`, capped to a trust region) by
    /// damped least squares, damping only near singularities; joints that would leave their
    /// limits (shrunk by [`IkOptions::limit_margin`]) are clamped to the bound and the rest
    /// re-solved for the remaining error. During the first
    /// [`IkOptions::null_space_iterations`] iterations a step in the null space of `J` descends
    /// a cost that pulls joints towards mid-range and raises manipulability; the remaining
    /// iterations polish the pose to the tolerances.
    pub fn ik_with(
        &self,
        target: &Isometry3<f64>,
        seed: &[f64],
        o: &IkOptions,
    ) -> Result<IkSolution> {
        self.check(seed)?;
        let n = self.dof();
        let lo: Vec<f64> = self
            .model
            .joints
            .iter()
            .map(|j| {
                let m = o.limit_margin.min(0.25 * (j.upper - j.lower));
                j.lower + m
            })
            .collect();
        let hi: Vec<f64> = self
            .model
            .joints
            .iter()
            .map(|j| {
                let m = o.limit_margin.min(0.25 * (j.upper - j.lower));
                j.upper - m
            })
            .collect();
        let mut q: Vec<f64> = seed
            .iter()
            .enumerate()
            .map(|(i, v)| v.clamp(lo[i], hi[i]))
            .collect();
        let kin = self.kin();
        let mut last = (f64::INFINITY, f64::INFINITY);
        for it in 0..=o.max_iterations {
            let (t, j) = kin.fk_jacobian(&q);
            let e = pose_error(target, &t);
            let ep = e.fixed_rows::<3>(0).norm();
            let er = e.fixed_rows::<3>(3).norm();
            last = (ep, er);
            let use_null = it < o.null_space_iterations && o.null_space_gain > 0.0;
            if ep <= o.position_tolerance && er <= o.rotation_tolerance {
                let sv = j.singular_values();
                return Ok(IkSolution {
                    q,
                    iterations: it,
                    position_error: ep,
                    rotation_error: er,
                    manipulability: manipulability_of(&j),
                    min_singular_value: sv.iter().cloned().fold(f64::INFINITY, f64::min),
                });
            }
            if it == o.max_iterations {
                break;
            }
            // Trust region on the task error.
            let mut e = e;
            if ep > o.max_position_step {
                let s = o.max_position_step / ep;
                e.fixed_rows_mut::<3>(0).scale_mut(s);
            }
            if er > o.max_rotation_step {
                let s = o.max_rotation_step / er;
                e.fixed_rows_mut::<3>(3).scale_mut(s);
            }
            let z = if use_null {
                Some(self.null_space_gradient(&kin, &q, &j, o))
            } else {
                None
            };
            let dq = self.constrained_step(&j, &e, z.as_ref(), &q, &lo, &hi, o);
            for i in 0..n {
                q[i] = (q[i] + dq[i]).clamp(lo[i], hi[i]);
            }
        }
        Err(ArmError::NoConvergence {
            iterations: o.max_iterations,
            position_error: last.0,
            rotation_error: last.1,
        })
    }

    /// One damped-least-squares step with joints clamped at their bounds.
    #[allow(clippy::too_many_arguments)]
    fn constrained_step(
        &self,
        j: &Matrix6xX<f64>,
        e: &Vector6<f64>,
        z: Option<&DVector<f64>>,
        q: &[f64],
        lo: &[f64],
        hi: &[f64],
        o: &IkOptions,
    ) -> DVector<f64> {
        let n = q.len();
        let mut locked = vec![false; n];
        let mut fixed = DVector::<f64>::zeros(n);
        let mut dq = DVector::<f64>::zeros(n);
        for _ in 0..=n {
            let mut jf = DMatrix::<f64>::zeros(6, n);
            for (c, &l) in locked.iter().enumerate() {
                if !l {
                    jf.set_column(c, &j.column(c));
                }
            }
            let rest = e - j * &fixed;
            let svd = jf.clone().svd(true, true);
            let u = svd.u.as_ref().unwrap();
            let vt = svd.v_t.as_ref().unwrap();
            let sv = &svd.singular_values;
            let smin = sv.iter().cloned().fold(f64::INFINITY, f64::min);
            let smax = sv.iter().cloned().fold(0.0, f64::max);
            // Damping only near a singularity, and fading with the error so the last
            // iterations are Gauss-Newton steps (fast convergence even at low manipulability).
            let lambda2 = if smin < o.singular_threshold {
                let r = smin / o.singular_threshold;
                let fade = (rest.norm() / 0.01).min(1.0);
                o.max_damping * o.max_damping * (1.0 - r * r) * fade
            } else {
                0.0
            };
            // Δq = V diag(σ / (σ² + λ²)) Uᵀ e
            let ute = u.transpose() * rest;
            let mut w = DVector::<f64>::zeros(sv.len());
            for k in 0..sv.len() {
                let s = sv[k];
                if s > 1e-12 * smax.max(1e-300) {
                    w[k] = ute[k] * s / (s * s + lambda2);
                }
            }
            let mut step = vt.transpose() * w;
            if let Some(z) = z {
                // Project onto the null space of the free Jacobian: (I - V_r V_rᵀ) z.
                let mut zf = z.clone();
                for c in 0..n {
                    if locked[c] {
                        zf[c] = 0.0;
                    }
                }
                let mut pz = zf.clone();
                for k in 0..sv.len() {
                    if sv[k] > 1e-9 * smax.max(1e-300) {
                        let v = vt.row(k).transpose();
                        pz -= &v * v.dot(&zf);
                    }
                }
                step += pz * o.null_space_gain;
            }
            for c in 0..n {
                if locked[c] {
                    step[c] = 0.0;
                }
            }
            // Joint step cap (keeps the direction).
            let total = &fixed + &step;
            let m = total.amax();
            dq = if m > o.max_joint_step {
                total * (o.max_joint_step / m)
            } else {
                total
            };
            let mut newly = false;
            for c in 0..n {
                if locked[c] {
                    continue;
                }
                let v = q[c] + dq[c];
                if v < lo[c] - 1e-12 || v > hi[c] + 1e-12 {
                    locked[c] = true;
                    fixed[c] = v.clamp(lo[c], hi[c]) - q[c];
                    newly = true;
                }
            }
            if !newly {
                break;
            }
        }
        dq
    }

    /// Descent direction of the null-space cost at `q`: towards mid-range, up the
    /// manipulability (finite differences of `ln w`).
    fn null_space_gradient(
        &self,
        kin: &Kin,
        q: &[f64],
        j: &Matrix6xX<f64>,
        o: &IkOptions,
    ) -> DVector<f64> {
        let n = q.len();
        let mut z = DVector::<f64>::zeros(n);
        for (i, jt) in self.model.joints.iter().enumerate() {
            if jt.lower.is_finite() && jt.upper.is_finite() {
                let mid = 0.5 * (jt.lower + jt.upper);
                let half = 0.5 * (jt.upper - jt.lower);
                z[i] -= o.limit_weight * (q[i] - mid) / (half * half);
            }
        }
        if o.manipulability_weight > 0.0 {
            let w0 = manipulability_of(j).max(1e-12).ln();
            let h = 1e-6;
            let mut qq = q.to_vec();
            for i in 0..n {
                qq[i] = q[i] + h;
                let (_, jh) = kin.fk_jacobian(&qq);
                let w1 = manipulability_of(&jh).max(1e-12).ln();
                z[i] += o.manipulability_weight * (w1 - w0) / h;
                qq[i] = q[i];
            }
        }
        z
    }

    /// A joint configuration for `target` found from several seeds: `seed`, the Panda's
    /// palm-up and ready configurations and mid-range; if none converges, up to 32 pseudo-random
    /// seeds (fixed sequence) until one does. Among the converged solutions of the fixed seeds it
    /// returns the one with the largest manipulability.
    pub fn ik_multi(&self, target: &Isometry3<f64>, seed: &[f64]) -> Result<IkSolution> {
        self.check(seed)?;
        let o = IkOptions::default();
        let mut seeds = vec![seed.to_vec()];
        if self.dof() == 7 {
            seeds.push(super::PANDA_PALM_UP.to_vec());
            seeds.push(super::PANDA_READY.to_vec());
        }
        let span: Vec<(f64, f64)> = self
            .model
            .joints
            .iter()
            .map(|j| {
                if j.lower.is_finite() && j.upper.is_finite() {
                    (j.lower, j.upper)
                } else {
                    (-std::f64::consts::PI, std::f64::consts::PI)
                }
            })
            .collect();
        seeds.push(span.iter().map(|(a, b)| 0.5 * (a + b)).collect());
        let mut best: Option<IkSolution> = None;
        let mut last_err = None;
        for s in &seeds {
            match self.ik_with(target, s, &o) {
                Ok(sol) => {
                    if best
                        .as_ref()
                        .is_none_or(|b| sol.manipulability > b.manipulability)
                    {
                        best = Some(sol);
                    }
                }
                Err(e) => last_err = Some(e),
            }
        }
        if let Some(b) = best {
            return Ok(b);
        }
        // A fixed xorshift sequence, so results do not depend on a global RNG.
        let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
        let mut unit = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..32 {
            let s: Vec<f64> = span.iter().map(|(a, b)| a + (b - a) * unit()).collect();
            match self.ik_with(target, &s, &o) {
                Ok(sol) => return Ok(sol),
                Err(e) => last_err = Some(e),
            }
        }
        Err(last_err.expect("at least one seed was tried"))
    }

    /// The palm-up configuration of the shipped Panda: [`super::PANDA_PALM_UP`] polished by IK
    /// so the palm is exactly level at [`super::PANDA_PALM_UP_POSITION`]. An error for an arm
    /// that is not the shipped Panda.
    pub fn palm_up_configuration(&self) -> Result<Vec<f64>> {
        if self.dof() != 7 || self.model.name != "panda_palm" {
            return Err(ArmError::Model(
                "no palm-up configuration is known for this arm".into(),
            ));
        }
        let target = Isometry3::translation(
            super::PANDA_PALM_UP_POSITION[0],
            super::PANDA_PALM_UP_POSITION[1],
            super::PANDA_PALM_UP_POSITION[2],
        );
        let o = IkOptions {
            null_space_iterations: 0,
            ..IkOptions::default()
        };
        Ok(self.ik_with(&target, &super::PANDA_PALM_UP, &o)?.q)
    }
}
