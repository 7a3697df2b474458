//! Palm paths to joint trajectories: sequential inverse kinematics seeded by the previous
//! sample (continuity), a null-space motion bounded in rate (no configuration jumps), and checks
//! on joint speed and manipulability.

use super::ik::{Arm, IkOptions};
use super::{ArmError, Result};
use nalgebra::Isometry3;

/// A joint trajectory sampled every `dt`, with the palm poses it was planned for.
#[derive(Debug, Clone, PartialEq)]
pub struct JointTrajectory {
    /// Sample spacing \[s\].
    pub dt: f64,
    /// Joint positions at `t = k dt` \[rad\].
    pub q: Vec<Vec<f64>>,
    /// Joint velocities at the samples \[rad/s\] (central differences, one-sided at the ends).
    pub qd: Vec<Vec<f64>>,
    /// The planned `base_from_palm` at the samples.
    pub palm: Vec<Isometry3<f64>>,
    /// Manipulability at the samples.
    pub manipulability: Vec<f64>,
    /// Velocity limits of the joints \[rad/s\] (from the URDF).
    pub velocity_limits: Vec<f64>,
    /// Largest IK residual along the path: position \[m\], rotation \[rad\].
    pub ik_residual: (f64, f64),
}

impl JointTrajectory {
    /// A trajectory that holds `q` for `duration` seconds.
    pub fn hold(q: &[f64], palm: Isometry3<f64>, duration: f64, dt: f64) -> JointTrajectory {
        let n = ((duration / dt).ceil() as usize).max(1) + 1;
        JointTrajectory {
            dt,
            q: vec![q.to_vec(); n],
            qd: vec![vec![0.0; q.len()]; n],
            palm: vec![palm; n],
            manipulability: vec![f64::NAN; n],
            velocity_limits: vec![f64::INFINITY; q.len()],
            ik_residual: (0.0, 0.0),
        }
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.q.len()
    }

    /// Whether there are no samples.
    pub fn is_empty(&self) -> bool {
        self.q.is_empty()
    }

    /// Duration \[s\].
    pub fn duration(&self) -> f64 {
        (self.q.len().saturating_sub(1)) as f64 * self.dt
    }

    /// The last joint positions.
    pub fn end(&self) -> &[f64] {
        self.q.last().expect("a trajectory has samples")
    }

    /// Smallest manipulability along the path.
    pub fn min_manipulability(&self) -> f64 {
        self.manipulability
            .iter()
            .cloned()
            .fold(f64::INFINITY, f64::min)
    }

    /// Largest `|q̇_i| / limit_i` along the path.
    pub fn max_velocity_fraction(&self) -> f64 {
        let mut m: f64 = 0.0;
        for w in self.q.windows(2) {
            for ((a, b), v) in w[0].iter().zip(&w[1]).zip(&self.velocity_limits) {
                m = m.max((b - a).abs() / self.dt / v);
            }
        }
        m
    }

    /// Largest `|q̈_i| / limit_i` along the path (second differences of the samples), e.g. with
    /// [`super::PANDA_ACCEL_LIMITS`]. The planner does not enforce acceleration limits.
    pub fn max_acceleration_fraction(&self, limits: &[f64]) -> f64 {
        let mut m: f64 = 0.0;
        for w in self.q.windows(3) {
            for (i, l) in limits.iter().enumerate().take(w[0].len()) {
                let a = (w[2][i] - 2.0 * w[1][i] + w[0][i]) / (self.dt * self.dt);
                m = m.max(a.abs() / l);
            }
        }
        m
    }

    /// Positions and velocities at time `t` (cubic Hermite between samples, so positions and
    /// velocities are continuous; held at the ends outside `[0, duration]`).
    pub fn sample(&self, t: f64) -> (Vec<f64>, Vec<f64>) {
        let n = self.q.len();
        let dof = self.q[0].len();
        if n == 1 || t <= 0.0 {
            return (
                self.q[0].clone(),
                if t < 0.0 {
                    vec![0.0; dof]
                } else {
                    self.qd[0].clone()
                },
            );
        }
        if t >= self.duration() {
            let last = n - 1;
            let v = if t > self.duration() {
                vec![0.0; dof]
            } else {
                self.qd[last].clone()
            };
            return (self.q[last].clone(), v);
        }
        let x = t / self.dt;
        let k = (x.floor() as usize).min(n - 2);
        let s = x - k as f64;
        let h = self.dt;
        let (h00, h10, h01, h11) = (
            2.0 * s * s * s - 3.0 * s * s + 1.0,
            s * s * s - 2.0 * s * s + s,
            -2.0 * s * s * s + 3.0 * s * s,
            s * s * s - s * s,
        );
        let (d00, d10, d01, d11) = (
            6.0 * s * s - 6.0 * s,
            3.0 * s * s - 4.0 * s + 1.0,
            -6.0 * s * s + 6.0 * s,
            3.0 * s * s - 2.0 * s,
        );
        let (q0, q1, v0, v1) = (&self.q[k], &self.q[k + 1], &self.qd[k], &self.qd[k + 1]);
        let mut q = vec![0.0; dof];
        let mut v = vec![0.0; dof];
        for i in 0..dof {
            q[i] = h00 * q0[i] + h10 * h * v0[i] + h01 * q1[i] + h11 * h * v1[i];
            v[i] = (d00 * q0[i] + d10 * h * v0[i] + d01 * q1[i] + d11 * h * v1[i]) / h;
        }
        (q, v)
    }
}

/// Options of [`Arm::plan_palm_path_with`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlanOptions {
    /// Fraction of the URDF velocity limits a joint may use.
    pub velocity_fraction: f64,
    /// Rate of the null-space motion that keeps the arm away from limits and singularities
    /// \[1/s\] (the null-space gain per sample is this times `dt`).
    pub null_space_rate: f64,
    /// Fail if the manipulability along the path drops below this.
    pub min_manipulability: f64,
    /// The IK options for every sample (the null-space gain and iterations are set per sample).
    pub ik: IkOptions,
}

impl Default for PlanOptions {
    fn default() -> Self {
        PlanOptions {
            velocity_fraction: 0.5,
            null_space_rate: 2.0,
            min_manipulability: 0.005,
            ik: IkOptions::default(),
        }
    }
}

impl Arm {
    /// Plan joint motion for palm `waypoints` (`base_from_palm`, one every `dt` seconds) from the
    /// configuration `seed` (the arm's current joints): see [`Arm::plan_palm_path_with`].
    pub fn plan_palm_path(
        &self,
        waypoints: &[Isometry3<f64>],
        dt: f64,
        seed: &[f64],
    ) -> Result<JointTrajectory> {
        self.plan_palm_path_with(waypoints, dt, seed, &PlanOptions::default())
    }

    /// Plan joint motion for the palm path `palm_at(t)` (`base_from_palm`) over
    /// `[0, duration]`, sampled every `dt` (shortened so the last sample falls on `duration`).
    pub fn plan_palm_motion(
        &self,
        palm_at: impl Fn(f64) -> Isometry3<f64>,
        duration: f64,
        dt: f64,
        seed: &[f64],
    ) -> Result<JointTrajectory> {
        if !(dt > 0.0 && duration >= 0.0 && duration.is_finite()) {
            return Err(ArmError::Invalid(format!(
                "palm motion needs dt > 0 and a finite duration >= 0 (dt {dt}, duration {duration})"
            )));
        }
        let n = ((duration / dt).ceil() as usize).max(1);
        let h = duration / n as f64;
        let h = if h > 0.0 { h } else { dt };
        let waypoints: Vec<Isometry3<f64>> = (0..=n).map(|k| palm_at(k as f64 * h)).collect();
        self.plan_palm_path(&waypoints, h, seed)
    }

    /// Plan joint motion for palm `waypoints` spaced `dt` apart.
    ///
    /// The first waypoint is solved from `seed` with no null-space motion, so the trajectory
    /// starts at the solution nearest the seed; each later one is solved from the previous
    /// solution with one bounded null-space step (`null_space_rate * dt` of the descent
    /// direction) and then polished to the IK tolerances. Fails if a waypoint is unreachable, if
    /// a joint would exceed `velocity_fraction` of its limit ([`ArmError::VelocityLimit`] says
    /// how much slower to go), or if manipulability drops below `min_manipulability`.
    pub fn plan_palm_path_with(
        &self,
        waypoints: &[Isometry3<f64>],
        dt: f64,
        seed: &[f64],
        o: &PlanOptions,
    ) -> Result<JointTrajectory> {
        if waypoints.is_empty() {
            return Err(ArmError::Invalid("empty palm path".into()));
        }
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(ArmError::Invalid(format!(
                "time step {dt} must be positive"
            )));
        }
        let dof = self.dof();
        let vmax = self.velocity_limits();
        let mut first = o.ik;
        first.null_space_iterations = 0;
        let mut follow = o.ik;
        follow.null_space_iterations = 1;
        follow.null_space_gain = o.null_space_rate * dt;
        follow.max_joint_step = f64::INFINITY;

        let mut q: Vec<Vec<f64>> = Vec::with_capacity(waypoints.len());
        let mut manip = Vec::with_capacity(waypoints.len());
        let mut residual: (f64, f64) = (0.0, 0.0);
        let mut prev = seed.to_vec();
        for (k, w) in waypoints.iter().enumerate() {
            let opts = if k == 0 { &first } else { &follow };
            let sol = self.ik_with(w, &prev, opts)?;
            residual.0 = residual.0.max(sol.position_error);
            residual.1 = residual.1.max(sol.rotation_error);
            let t = k as f64 * dt;
            if sol.manipulability < o.min_manipulability {
                return Err(ArmError::Singular {
                    time: t,
                    manipulability: sol.manipulability,
                    threshold: o.min_manipulability,
                });
            }
            if k > 0 {
                let mut worst: Option<(usize, f64)> = None;
                for i in 0..dof {
                    let speed = (sol.q[i] - prev[i]).abs() / dt;
                    let ratio = speed / (vmax[i] * o.velocity_fraction);
                    if ratio > 1.0 && worst.is_none_or(|(_, r)| ratio > r) {
                        worst = Some((i, ratio));
                    }
                }
                if let Some((i, ratio)) = worst {
                    return Err(ArmError::VelocityLimit {
                        joint: i,
                        time: t,
                        speed: (sol.q[i] - prev[i]).abs() / dt,
                        limit: vmax[i] * o.velocity_fraction,
                        fraction: o.velocity_fraction,
                        factor: ratio,
                    });
                }
            }
            manip.push(sol.manipulability);
            prev = sol.q.clone();
            q.push(sol.q);
        }
        let n = q.len();
        let mut qd = vec![vec![0.0; dof]; n];
        if n > 1 {
            for (k, v) in qd.iter_mut().enumerate() {
                let (a, b) = (k.saturating_sub(1), (k + 1).min(n - 1));
                for (i, vi) in v.iter_mut().enumerate() {
                    *vi = (q[b][i] - q[a][i]) / ((b - a) as f64 * dt);
                }
            }
        }
        Ok(JointTrajectory {
            dt,
            q,
            qd,
            palm: waypoints.to_vec(),
            manipulability: manip,
            velocity_limits: vmax,
            ik_residual: residual,
        })
    }
}
