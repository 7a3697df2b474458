//! The toppling task on the simulated arm (paper Fig. 1 and Fig. 5): the palm holds a box and
//! must topple it onto an adjacent face by tilting.
//!
//! * [`execute_tilt`] / [`execute_plan`]: rotate the palm slowly about a line in the palm frame
//!   (IK through [`crate::arm::Arm::plan_palm_motion`], joint motors track), watch the
//!   **tracked** tag pose (the simulated tag with [`TrackerNoise::real`] noise at 30 Hz, through
//!   [`Tracker`]) and stop when the box has toppled (its tilt relative to the palm about the axis
//!   exceeds 45° in 3 consecutive tracked frames), then bring the palm back level.
//! * [`default_policy`]: what the robot does without a model: 10° about the palm's `x` axis
//!   through its centre, and back.
//! * [`assess`]: success from the tracked pose only: at rest, on the adjacent face towards the
//!   goal (the face that pointed down is now ~horizontal, the old down direction moved to the
//!   goal side), and on the palm.
//! * [`run`](mod@run): the Fig. 1 loop over random boxes (try, fail, ask for one demonstration,
//!   learn, plan, try again); [`speed`]: planning time against a search with the full simulation.
//!
//! Hidden simulator state is only read for the `truth` fields of the reports, never to decide.

pub mod run;
pub mod speed;

pub use run::{run_task, BoxOutcome, TaskConfig, TaskReport, MAX_DEMOS};

use crate::arm::{ArmError, ArmSim, PlanOptions, TrackingError};
use crate::noise::TrackerNoise;
use nalgebra::{Isometry3, Point3, Translation3, Unit, UnitQuaternion, Vector3};
use objmodel::geometry::angle_about;
use objmodel::skill::Plan;
use objmodel::StampedPose;
use rand::rngs::StdRng;
use rand::SeedableRng;
use rapier3d_f64::prelude::RigidBodyHandle;
use serde::{Deserialize, Serialize};

/// Palm half extents in its plane \[m\] (the shipped URDF's 0.20 x 0.20 m palm).
pub const PALM_HALF: f64 = 0.10;

/// Options of the skill and of the success test.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SkillOptions {
    /// Peak palm rotation rate while tilting \[rad/s\] (quasi-static; 4°/s).
    pub tilt_rate: f64,
    /// Peak palm rotation rate while levelling again \[rad/s\] (20°/s).
    pub return_rate: f64,
    /// Box tilt relative to the palm about the axis that counts as toppled \[rad\] (45°).
    pub topple_angle: f64,
    /// Box tilt relative to the palm at which the box is past its balance and the palm starts
    /// levelling \[rad\] (5°): levelling about the same edge line does not stop the topple, and
    /// the box then lands on a nearly level palm instead of tumbling down a tilted one.
    pub level_angle: f64,
    /// Consecutive tracked frames beyond `topple_angle` needed (3).
    pub consecutive: usize,
    /// Time to keep the palm at the full tilt waiting for a topple \[s\].
    pub hold: f64,
    /// If the box has not toppled after the planned tilt and `hold`, keep tilting slowly by at
    /// most this much more \[rad\] (8°; closed loop on the tracked pose, for a φ learnt too small).
    pub extra_tilt: f64,
    /// Time to let the box settle after levelling \[s\].
    pub settle: f64,
    /// Time step of the palm path given to IK \[s\].
    pub plan_dt: f64,
    /// Tracker rate \[Hz\].
    pub rate_hz: f64,
    /// Tracking noise.
    pub noise: TrackerNoise,
}

impl Default for SkillOptions {
    fn default() -> Self {
        SkillOptions {
            tilt_rate: 4f64.to_radians(),
            return_rate: 120f64.to_radians(),
            topple_angle: 45f64.to_radians(),
            level_angle: 5f64.to_radians(),
            consecutive: 3,
            hold: 1.0,
            extra_tilt: 8f64.to_radians(),
            settle: 1.0,
            plan_dt: 0.04,
            rate_hz: 30.0,
            noise: TrackerNoise::real(),
        }
    }
}

/// The tracker: the box's tag pose with noise at a fixed rate.
pub struct Tracker {
    noise: TrackerNoise,
    rng: StdRng,
    box_from_tag: Isometry3<f64>,
    /// The tracked box body.
    pub body: RigidBodyHandle,
    period: f64,
    next: f64,
}

impl Tracker {
    /// Track `body` (a box with tag `box_from_tag`) from the simulation's current time.
    pub fn new(
        sim: &ArmSim,
        body: RigidBodyHandle,
        box_from_tag: Isometry3<f64>,
        o: &SkillOptions,
        seed: u64,
    ) -> Tracker {
        Tracker {
            noise: o.noise.clone(),
            rng: StdRng::seed_from_u64(seed ^ 0x7261_636b),
            box_from_tag,
            body,
            period: 1.0 / o.rate_hz,
            next: sim.t,
        }
    }

    /// After a step: the tracked `world_from_tag` if a frame is due now and not dropped.
    pub fn poll(&mut self, sim: &ArmSim) -> Option<StampedPose> {
        if sim.t + 1e-9 < self.next {
            return None;
        }
        while self.next <= sim.t + 1e-9 {
            self.next += self.period;
        }
        let clean = StampedPose {
            t: sim.t,
            pose: sim.body_pose(self.body) * self.box_from_tag,
        };
        self.noise.apply(&[clean], &mut self.rng).into_iter().next()
    }
}

/// The palm pose the robot knows from its joint encoders: `world_from_palm`.
pub fn encoder_palm(sim: &ArmSim) -> Isometry3<f64> {
    sim.world_from_base * sim.arm.fk(&sim.joint_positions())
}

/// A robust mean of poses: per-axis median position, and the medoid rotation (the sample with
/// the smallest summed angle to the others), so mirror flips and outliers do not pull it.
pub fn robust_pose(poses: &[Isometry3<f64>]) -> Option<Isometry3<f64>> {
    if poses.is_empty() {
        return None;
    }
    let med = |k: usize| {
        let mut v: Vec<f64> = poses.iter().map(|p| p.translation.vector[k]).collect();
        v.sort_by(|a, b| a.total_cmp(b));
        v[v.len() / 2]
    };
    let rot = poses
        .iter()
        .map(|p| {
            let s: f64 = poses.iter().map(|q| p.rotation.angle_to(&q.rotation)).sum();
            (s, p.rotation)
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|x| x.1)?;
    Some(Isometry3::from_parts(
        Translation3::new(med(0), med(1), med(2)),
        rot,
    ))
}

/// Step the simulation for `seconds`, collecting tracked `palm_from_tag` poses (palm from the
/// encoders).
pub fn observe(sim: &mut ArmSim, tracker: &mut Tracker, seconds: f64) -> Vec<Isometry3<f64>> {
    let end = sim.t + seconds;
    let mut out = Vec::new();
    while sim.t < end - 0.5 * sim.dt {
        sim.step();
        if let Some(f) = tracker.poll(sim) {
            out.push(encoder_palm(sim).inverse() * f.pose);
        }
    }
    out
}

/// One sample of an attempt's time series (for plots).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SeriesPoint {
    /// Time since the attempt started \[s\].
    pub t: f64,
    /// Commanded palm tilt about the axis \[rad\].
    pub palm_commanded: f64,
    /// Palm tilt about the axis from the encoders \[rad\].
    pub palm: f64,
    /// Tracked box tilt relative to the palm about the axis \[rad\] (noisy).
    pub box_rel: f64,
    /// Tracked box tilt in the world about the axis \[rad\] (palm + relative).
    pub box_world: f64,
}

/// What one tilt did.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ToppleRun {
    /// Whether the tracked pose showed a topple.
    pub toppled: bool,
    /// Time of the detection since the attempt started \[s\].
    pub t_topple: Option<f64>,
    /// Time the palm started levelling because the box was past its balance \[s\].
    pub t_level: Option<f64>,
    /// Commanded palm tilt when the topple was detected (or the most it tilted) \[rad\].
    pub palm_tilt_reached: f64,
    /// The tilt asked for \[rad\].
    pub tilt_asked: f64,
    /// Worst palm tracking error during the attempt.
    pub tracking_position_m: f64,
    /// Worst palm tracking error during the attempt \[rad\].
    pub tracking_angle_rad: f64,
    /// Tracked `palm_from_tag` before the attempt.
    #[serde(skip)]
    pub palm_from_tag0: Option<Isometry3<f64>>,
    /// The tilt axis and point in the world at the start.
    pub axis_world: [f64; 3],
    /// A point of the tilt axis in the world at the start \[m\].
    pub axis_point_world: [f64; 3],
    /// Time series.
    pub series: Vec<SeriesPoint>,
    /// Simulated palm and box poses at every tracker instant (hidden state: for pictures only).
    #[serde(skip)]
    pub snapshots: Vec<Snapshot>,
}

/// Simulated poses at one instant (for pictures, never for decisions).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Snapshot {
    /// Time since the attempt started \[s\].
    pub t: f64,
    /// `world_from_palm`.
    pub world_from_palm: Isometry3<f64>,
    /// `world_from_box`.
    pub world_from_box: Isometry3<f64>,
}

fn smooth(s: f64) -> f64 {
    let s = s.clamp(0.0, 1.0);
    s * s * (3.0 - 2.0 * s)
}

/// The palm pose (`base_from_palm`) after rotating `start` by `theta` about the line through
/// `p` along `u` (base frame).
pub fn rotate_about(
    start: &Isometry3<f64>,
    p: &Vector3<f64>,
    u: &Unit<Vector3<f64>>,
    theta: f64,
) -> Isometry3<f64> {
    let r = UnitQuaternion::from_axis_angle(u, theta);
    Isometry3::from_parts(
        Translation3::from(p + r * (start.translation.vector - p)),
        r * start.rotation,
    )
}

/// Tilt the palm by up to `tilt` \[rad\] about the line through `axis_point` along
/// `axis_direction` (palm frame at the start, right-hand rule), watching the tracked box; stop
/// at a detected topple, and bring the palm back level (to its start pose).
pub fn execute_tilt(
    sim: &mut ArmSim,
    tracker: &mut Tracker,
    axis_point: &Vector3<f64>,
    axis_direction: &Vector3<f64>,
    tilt: f64,
    extra: f64,
    o: &SkillOptions,
) -> Result<ToppleRun, ArmError> {
    let arm = sim.arm.clone();
    // The box on the palm before moving.
    let frames = observe(sim, tracker, 0.5);
    let p_t0 = robust_pose(&frames);
    let q0 = sim.targets().0.to_vec();
    let start = arm.fk(&q0);
    let u_palm = Unit::new_normalize(*axis_direction);
    let p_b = (start * Point3::from(*axis_point)).coords;
    let u_b = Unit::new_normalize(start.rotation * u_palm.into_inner());
    let wfb = sim.world_from_base;
    let n0_w = (wfb * start).rotation * Vector3::z();
    let u_w = wfb.rotation * u_b.into_inner();

    let t1 = (1.5 * tilt.abs() / o.tilt_rate).max(1.0);
    let t2 = 1.5 * extra.abs() / o.tilt_rate;
    let angle = |t: f64| {
        if t <= t1 + o.hold || t2 <= 0.0 {
            tilt * smooth(t / t1)
        } else {
            tilt + extra * tilt.signum() * smooth((t - t1 - o.hold) / t2)
        }
    };
    let t_tilt = t1 + if t2 > 0.0 { o.hold + t2 } else { 0.0 };
    let path = |t: f64| rotate_about(&start, &p_b, &u_b, angle(t));
    let tr = arm.plan_palm_motion(path, t_tilt, o.plan_dt, &q0)?;
    sim.follow(tr);
    let t_start = sim.t;
    let mut worst = TrackingError::default();
    let mut series = Vec::new();
    let mut snapshots = Vec::new();
    let snap = |sim: &ArmSim, body: RigidBodyHandle| Snapshot {
        t: sim.t - t_start,
        world_from_palm: sim.palm_pose(),
        world_from_box: sim.body_pose(body),
    };
    let mut count = 0usize;
    let mut count_topple = 0usize;
    let mut t_topple = None;
    let mut t_level = None;
    let mut theta_now;
    let record = |sim: &ArmSim, f: &StampedPose, cmd: f64, series: &mut Vec<SeriesPoint>| {
        let wp = encoder_palm(sim);
        let palm = angle_about(&u_w, &n0_w, &(wp.rotation * Vector3::z()));
        let box_rel = p_t0.map_or(0.0, |p0| {
            let r = (wp.inverse() * f.pose).rotation * p0.rotation.inverse();
            angle_about(u_palm.as_ref(), &Vector3::z(), &(r * Vector3::z()))
        });
        let pt = SeriesPoint {
            t: sim.t - t_start,
            palm_commanded: cmd,
            palm,
            box_rel,
            box_world: palm + box_rel,
        };
        series.push(pt);
        pt
    };
    loop {
        sim.step();
        worst = worst.max(sim.tracking_error());
        let el = sim.t - t_start;
        theta_now = angle(el);
        if let Some(f) = tracker.poll(sim) {
            snapshots.push(snap(sim, tracker.body));
            let pt = record(sim, &f, theta_now, &mut series);
            if pt.box_rel.abs() > o.level_angle {
                count += 1;
            } else {
                count = 0;
            }
            if count >= o.consecutive {
                t_level = Some(el);
                break;
            }
        }
        if el > t_tilt + o.hold {
            break;
        }
    }
    // Level the palm again.
    let theta_d = theta_now;
    let q_now = sim.targets().0.to_vec();
    let mut t_ret = (1.5 * theta_d.abs() / o.return_rate).max(0.15);
    let tr = loop {
        let n = ((t_ret / 0.01).ceil() as usize).max(2);
        let h = t_ret / n as f64;
        let way: Vec<Isometry3<f64>> = (0..=n)
            .map(|k| {
                rotate_about(
                    &start,
                    &p_b,
                    &u_b,
                    theta_d * (1.0 - smooth(k as f64 / n as f64)),
                )
            })
            .collect();
        let fast = PlanOptions {
            velocity_fraction: 0.9,
            ..PlanOptions::default()
        };
        match arm.plan_palm_path_with(&way, h, &q_now, &fast) {
            Err(ArmError::VelocityLimit { factor, .. }) if t_ret < 20.0 => {
                t_ret *= factor.max(1.01) * 1.05
            }
            r => break r?,
        }
    };
    sim.follow(tr);
    let end = sim.t + t_ret + o.settle;
    let t_ret0 = sim.t;
    while sim.t < end {
        sim.step();
        worst = worst.max(sim.tracking_error());
        let cmd = theta_d * (1.0 - smooth((sim.t - t_ret0) / t_ret));
        if let Some(f) = tracker.poll(sim) {
            snapshots.push(snap(sim, tracker.body));
            let pt = record(sim, &f, cmd, &mut series);
            if pt.box_rel.abs() > o.topple_angle {
                count_topple += 1;
            } else {
                count_topple = 0;
            }
            if count_topple >= o.consecutive && t_topple.is_none() {
                t_topple = Some(sim.t - t_start);
            }
        }
    }
    let pw = wfb * Point3::from(p_b);
    Ok(ToppleRun {
        toppled: t_topple.is_some(),
        t_topple,
        t_level,
        palm_tilt_reached: theta_d,
        tilt_asked: tilt,
        tracking_position_m: worst.position,
        tracking_angle_rad: worst.angle,
        palm_from_tag0: p_t0,
        axis_world: u_w.into(),
        axis_point_world: pw.coords.into(),
        series,
        snapshots,
    })
}

/// Execute a plan of [`objmodel::skill::plan`] (palm frame) from the current palm pose.
pub fn execute_plan(
    sim: &mut ArmSim,
    tracker: &mut Tracker,
    plan: &Plan,
    o: &SkillOptions,
) -> Result<ToppleRun, ArmError> {
    execute_tilt(
        sim,
        tracker,
        &plan.axis_point,
        &plan.axis_direction,
        plan.tilt,
        o.extra_tilt,
        o,
    )
}

/// The default policy, with no model: tilt 10° about the palm's `x` axis through its centre
/// (its `-y` side goes down), and back.
pub fn default_policy(
    sim: &mut ArmSim,
    tracker: &mut Tracker,
    o: &SkillOptions,
) -> Result<ToppleRun, ArmError> {
    execute_tilt(
        sim,
        tracker,
        &Vector3::zeros(),
        &Vector3::x(),
        DEFAULT_TILT,
        0.0,
        o,
    )
}

/// The default policy's tilt \[rad\] (10°).
pub const DEFAULT_TILT: f64 = std::f64::consts::PI / 18.0;

/// The direction (palm frame) in which the task wants the box toppled: `-y`, the side the
/// default policy lowers.
pub fn goal_direction() -> Vector3<f64> {
    -Vector3::y()
}

/// The success test, from tracked poses.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Assessment {
    /// Success: at rest, on the adjacent face towards the goal, on the palm.
    pub success: bool,
    /// Why not (or "ok").
    pub reason: String,
    /// How far the resting face turned \[deg\] (median over frames; 90 for a topple).
    pub face_change_deg: f64,
    /// Tracked tag position on the palm (median) \[m\].
    pub tag_in_palm: [f64; 3],
    /// Fraction of frames that pass every test.
    pub pass_fraction: f64,
}

/// Judge from 0.6 s of tracked frames (stepping the simulation) whether the box rests on the
/// adjacent face in `goal` (palm frame), on the palm. `palm_from_tag0` is the tracked pose
/// before the attempt.
pub fn assess(
    sim: &mut ArmSim,
    tracker: &mut Tracker,
    palm_from_tag0: &Isometry3<f64>,
    goal: &Vector3<f64>,
) -> Assessment {
    let frames = observe(sim, tracker, 0.6);
    let down0 = palm_from_tag0.rotation.inverse() * -Vector3::z();
    let goal = goal.normalize();
    let mut pass = 0usize;
    let mut changes = Vec::new();
    let (mut n_rest, mut n_face, mut n_dir, mut n_palm) = (0, 0, 0, 0);
    let Some(med) = robust_pose(&frames) else {
        return Assessment {
            success: false,
            reason: "no tracked frames".into(),
            face_change_deg: f64::NAN,
            tag_in_palm: [f64::NAN; 3],
            pass_fraction: 0.0,
        };
    };
    for f in &frames {
        let down = f.rotation.inverse() * -Vector3::z();
        let change = down.angle(&down0).to_degrees();
        changes.push(change);
        let rest = (f.translation.vector - med.translation.vector).norm() < 0.005
            && f.rotation.angle_to(&med.rotation) < 5f64.to_radians();
        let face = (70.0..110.0).contains(&change);
        let dir = (palm_from_tag0.rotation * down).dot(&goal) > 45f64.to_radians().cos();
        let p = f.translation.vector;
        let on = p.x.abs() <= PALM_HALF && p.y.abs() <= PALM_HALF && p.z > -0.01 && p.z < 0.3;
        n_rest += rest as usize;
        n_face += face as usize;
        n_dir += dir as usize;
        n_palm += on as usize;
        pass += (rest && face && dir && on) as usize;
    }
    changes.sort_by(|a, b| a.total_cmp(b));
    let n = frames.len();
    let frac = pass as f64 / n as f64;
    let ok = |k: usize| k as f64 >= 0.7 * n as f64;
    let change = changes[n / 2];
    let reason = if !ok(n_palm) {
        "the box is not on the palm".to_string()
    } else if !ok(n_rest) {
        "the box is not at rest".to_string()
    } else if change < 20.0 {
        "the box did not topple (still on its first face)".to_string()
    } else if !ok(n_face) {
        format!("the box tumbled: its resting face turned by {change:.0} deg, not 90")
    } else if !ok(n_dir) {
        "the box toppled onto a face other than the intended one".to_string()
    } else if !ok(pass) {
        "the tracked frames do not agree".to_string()
    } else {
        "ok".to_string()
    };
    Assessment {
        success: reason == "ok",
        reason,
        face_change_deg: change,
        tag_in_palm: med.translation.vector.into(),
        pass_fraction: frac,
    }
}

/// Hidden-state truth after an attempt, for logging only.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct AttemptTruth {
    /// Box face (box frame outward normal) now facing the palm.
    pub down_face: [f64; 3],
    /// Angle between the first and the current down faces \[deg\].
    pub face_change_deg: f64,
    /// The box touches the palm and no other part of the arm.
    pub touches_palm_only: bool,
    /// Box centre in the palm frame \[m\].
    pub centre_in_palm: [f64; 3],
}

/// The truth now, given the palm-frame down face at the start `down0_box` (box frame).
pub fn attempt_truth(
    sim: &ArmSim,
    body: RigidBodyHandle,
    down0_box: &Vector3<f64>,
) -> AttemptTruth {
    let pb = sim.palm_pose().inverse() * sim.body_pose(body);
    let down = pb.rotation.inverse() * -Vector3::z();
    let face = crate::spec::BoxFace::closest_to(&down).normal();
    AttemptTruth {
        down_face: face.into(),
        face_change_deg: down.angle(down0_box).to_degrees(),
        touches_palm_only: sim.touches_palm_only(body),
        centre_in_palm: pb.translation.vector.into(),
    }
}
