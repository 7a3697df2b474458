//! The Fig. 1 loop: per random box, the default policy; if it fails, a demonstration, learning,
//! a planned topple (another demonstration, up to [`MAX_DEMOS`], where the model cannot plan
//! yet: one demonstration at `real` noise may locate its edge too loosely to be taught).
//!
//! **Which boxes.** Boxes are drawn with edges 6-20 cm, mass 0.2-1.5 kg, CoM offset up to 30%
//! of each half extent, friction 0.6-1.0 and a randomly placed tag. Each box stands on its `-z`
//! face, and the task is to topple it towards the palm's `-y` side over one of its four bottom
//! edges (chosen at random among the admissible ones; the box is yawed so that edge faces `-y`,
//! ±15°). A draw is excluded, before anything is simulated, when no edge is admissible by this
//! rule (geometry and friction only, never outcomes):
//!
//! * friction: `μ ≥ 1.15 tan φ` with `μ = min(μ_box, μ_palm = 0.9)`, so the box tips before it
//!   slides (the instrumented demonstration scene's rule);
//! * `φ ≤ 30°` ([`MAX_PHI_TASK`]): steeper boxes land hard and tumble;
//! * size: the box starts with its uphill side 1 cm from the palm's `+y` border, and after the
//!   topple (lying on the adjacent face, from the downhill edge outwards) its centre must lie at
//!   least [`LANDED_INSIDE`] = 3 cm inside the `-y` border and it may not overhang that border
//!   ([`MAX_OVERHANG`] = 0); its footprint must fit across the palm (`x`) with 1 cm to
//!   spare. (A box overhanging the border lands on it while the palm levels and tumbles off.)
//!
//! **The demonstration** is the instrumented scene ([`crate::scenes::instrumented::run_with`],
//! as in [`crate::simulate`] with `SceneKind::InstrumentedTopple`) of the same box (same
//! [`crate::BoxSpec`], same tag mount), resting on the same `-z` face, tilted by the simulated user
//! towards the same edge, tracked with `real` noise.
//!
//! **Counts.** `success_default`: boxes the default policy toppled correctly;
//! `success_after_one_demo`: boxes toppled correctly with at most one demonstration (the default
//! success, or the planned attempt after one demonstration); `success_planned`: planned attempts
//! that succeeded, after however many demonstrations (`demonstrations` counts them all).

use super::{
    assess, attempt_truth, default_policy, execute_plan, goal_direction, observe, robust_pose,
    Assessment, AttemptTruth, SkillOptions, ToppleRun, Tracker, PALM_HALF,
};
use crate::arm::{Arm, ArmSim, ArmSimOptions};
use crate::demo::{truth_of, CleanDemo, SimDemo, SimOptions};
use crate::scenes::{edge_lever, instrumented};
use crate::spec::{BoxSpec, TagMount};
use crate::{SceneKind, SimError, TrackerNoise};
use nalgebra::Vector3;
use objmodel::classify::Config;
use objmodel::learn::{Learner, Source};
use objmodel::skill::{plan, Plan, PlanRequest};
use objmodel::tree::Tree;
use objmodel::Demonstration;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use serde::{Deserialize, Serialize};

/// After the topple the box centre must be this far inside the palm's border \[m\].
pub const LANDED_INSIDE: f64 = 0.03;
/// After the topple the box may overhang the palm's border by at most this much \[m\].
pub const MAX_OVERHANG: f64 = 0.0;

/// Largest tipping angle admitted \[rad\] (30°): steeper boxes land hard and tumble on a
/// 20 cm palm, and the simulated user's demonstration on the plate often fails above it too
/// (the scene's own limit is 36°, [`instrumented::MAX_PHI`]).
pub const MAX_PHI_TASK: f64 = std::f64::consts::FRAC_PI_6;

/// Friction of the shipped palm (see [`ArmSimOptions`]).
const PALM_MU: f64 = 0.9;

/// Task configuration.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct TaskConfig {
    /// Number of boxes.
    pub boxes: usize,
    /// Seed of the draw.
    pub seed: u64,
    /// Skill options.
    pub skill: SkillOptions,
}

impl Default for TaskConfig {
    fn default() -> Self {
        TaskConfig {
            boxes: 20,
            seed: 7,
            skill: SkillOptions::default(),
        }
    }
}

/// A drawn trial: the box, the edge to topple (downhill box axis and sign), its pose on the palm.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Trial {
    /// The box.
    pub spec: BoxSpec,
    /// Downhill box axis (0 = x, 1 = y).
    pub axis: usize,
    /// Its sign.
    pub sign: f64,
    /// Position of the box centre on the palm \[m\].
    pub position: [f64; 2],
    /// Yaw on the palm \[rad\].
    pub yaw: f64,
    /// True tipping angle about that edge \[rad\].
    pub phi_true: f64,
    /// Draws rejected before this one by the admissibility rule.
    pub rejected_before: usize,
}

/// Footprint half extents of a box yawed by `yaw` along the palm's x and y.
fn footprint(h: &Vector3<f64>, yaw: f64) -> (f64, f64) {
    let (s, c) = yaw.sin_cos();
    (h.x * c.abs() + h.y * s.abs(), h.x * s.abs() + h.y * c.abs())
}

/// Draw an admissible trial (see the module docs for the rule).
pub fn draw_trial<R: Rng>(rng: &mut R, name: &str) -> Trial {
    let mut rejected = 0;
    loop {
        let dims = [
            rng.random_range(0.06..0.20),
            rng.random_range(0.06..0.20),
            rng.random_range(0.06..0.20),
        ];
        let mass = rng.random_range(0.2..1.5);
        let com = [
            rng.random_range(-0.3..0.3) * dims[0] / 2.0,
            rng.random_range(-0.3..0.3) * dims[1] / 2.0,
            rng.random_range(-0.3..0.3) * dims[2] / 2.0,
        ];
        let friction = rng.random_range(0.6..1.0);
        let mut spec = BoxSpec::new(name, dims, mass).with_com(com);
        spec.friction = friction;
        spec.tag = TagMount::random(rng);
        let jitter = rng.random_range(-15f64..15.0).to_radians();
        let x_frac: f64 = rng.random_range(-1.0..1.0);
        let h = spec.half_extents();
        let mu = friction.min(PALM_MU);
        let mut options = Vec::new();
        for axis in 0..2 {
            for sign in [1.0, -1.0] {
                let (d, hc) = edge_lever(&spec, axis, sign);
                let phi = d.atan2(hc);
                if mu < 1.15 * phi.tan() || phi > MAX_PHI_TASK {
                    continue;
                }
                // yaw turning the box direction sign*e_axis onto the palm's -y
                let heading = if axis == 0 {
                    if sign > 0.0 {
                        0.0
                    } else {
                        std::f64::consts::PI
                    }
                } else {
                    sign * std::f64::consts::FRAC_PI_2
                };
                let yaw = -std::f64::consts::FRAC_PI_2 - heading + jitter;
                let (ex, ey) = footprint(&h, yaw);
                let y = PALM_HALF - 0.01 - ey;
                // after the topple the centre is about h_e + c beyond the start centre
                let edge = y - h[axis];
                let landed = edge - h.z;
                let far = edge - 2.0 * h.z;
                if landed < -(PALM_HALF - LANDED_INSIDE)
                    || far < -(PALM_HALF + MAX_OVERHANG)
                    || ex > PALM_HALF - 0.01
                {
                    continue;
                }
                let x_room = (PALM_HALF - 0.01 - ex).clamp(0.0, 0.02);
                options.push((axis, sign, yaw, [x_frac * x_room, y], phi));
            }
        }
        if options.is_empty() {
            rejected += 1;
            continue;
        }
        let (axis, sign, yaw, position, phi_true) = options[rng.random_range(0..options.len())];
        return Trial {
            spec,
            axis,
            sign,
            position,
            yaw,
            phi_true,
            rejected_before: rejected,
        };
    }
}

/// The simulated user's instrumented demonstration of `spec` toppled towards its box direction
/// `sign · e_axis`, tracked with `noise`.
pub fn demonstrate(
    spec: &BoxSpec,
    axis: usize,
    sign: f64,
    noise: &TrackerNoise,
    seed: u64,
) -> crate::Result<SimDemo> {
    let opts = SimOptions::default();
    let mut rng = StdRng::seed_from_u64(seed ^ 0x0de0_0de0);
    let tilt = instrumented::Tilt {
        axis,
        sign,
        rate: rng.random_range(2f64..5.0).to_radians(),
        pivot: [rng.random_range(-0.03..0.03), rng.random_range(-0.03..0.03)],
        max_tilt: 80f64.to_radians(),
    };
    let out = instrumented::run_with(spec, spec.friction, &tilt, &opts.physics, &mut rng)?;
    let truth = truth_of(SceneKind::InstrumentedTopple, spec, seed, &out, &opts)?;
    let (object, palm) = crate::demo::tracked(&out, spec, opts.rate_hz);
    let clean = CleanDemo {
        kind: SceneKind::InstrumentedTopple,
        object,
        palm: Some(palm),
        truth,
    };
    Ok(clean.with_noise(noise))
}

/// Learn from one demonstration through the library's pipeline ([`objmodel::learn`]), with
/// the simulated world's gravity; returns its kind.
pub fn learn(tree: &mut Tree, demo: &SimDemo, name: &str) -> objmodel::Result<String> {
    let d = Demonstration {
        name: name.to_string(),
        object: demo.object.clone(),
        palm: demo.palm.clone(),
    };
    let config = Config {
        gravity: Some(Vector3::from(crate::world::GRAVITY)),
        ..Config::default()
    };
    let reports = Learner::new(config).learn(tree, &[Source::Memory(&d)])?;
    Ok(reports[0].classification.kind.as_str().to_string())
}

/// One attempt's record.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Attempt {
    /// Success (from the tracked pose).
    pub success: bool,
    /// Why not.
    pub reason: String,
    /// Tilt asked for \[deg\].
    pub tilt_deg: f64,
    /// Palm tilt when the topple was detected, or the most it tilted \[deg\].
    pub palm_tilt_reached_deg: f64,
    /// Topple detected from the tracked pose.
    pub topple_detected: bool,
    /// The success test's detail.
    pub assessment: Option<Assessment>,
    /// Hidden truth, for the log.
    pub truth: Option<AttemptTruth>,
    /// Worst palm tracking error \[mm\].
    pub tracking_mm: f64,
    /// Worst palm tracking error \[deg\].
    pub tracking_deg: f64,
    /// The run (series), not serialised in the summary.
    #[serde(skip)]
    pub run: Option<ToppleRun>,
}

/// Per-box detail.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct BoxOutcome {
    /// Box name.
    pub name: String,
    /// Edge lengths \[m\].
    pub dims: [f64; 3],
    /// Mass \[kg\].
    pub mass: f64,
    /// CoM offset \[m\].
    pub com: [f64; 3],
    /// Friction.
    pub friction: f64,
    /// Box centre on the palm \[m\].
    pub position: [f64; 2],
    /// Yaw on the palm \[deg\].
    pub yaw_deg: f64,
    /// True φ of the intended edge \[deg\].
    pub phi_true_deg: f64,
    /// Learnt φ \[deg\].
    pub phi_learnt_deg: Option<f64>,
    /// The default attempt.
    pub default: Attempt,
    /// Classification of the demonstration, if one was asked for.
    pub demo_kind: Option<String>,
    /// Demonstrations the simulated user botched (the box fell off the plate) and redid before
    /// the ones given to the learner.
    pub demo_user_retries: usize,
    /// Demonstrations given to the learner (0 where the default policy succeeded).
    #[serde(default)]
    pub demonstrations: usize,
    /// Why the model could not plan, after each demonstration that did not suffice.
    #[serde(default)]
    pub asked_again: Vec<String>,
    /// The plan, if one was made.
    pub plan: Option<Plan>,
    /// The planned attempt.
    pub planned: Option<Attempt>,
    /// Success of the default policy.
    pub success_default: bool,
    /// Success with at most one demonstration.
    pub success_after_one_demo: bool,
    /// Outcome in words.
    pub reason: String,
    /// The trial (for re-runs), not serialised.
    #[serde(skip)]
    pub trial: Option<Trial>,
    /// The learnt tree and the plan request, not serialised.
    #[serde(skip)]
    pub learnt: Option<(Tree, PlanRequest)>,
}

/// The loop's report.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct TaskReport {
    /// Boxes tried.
    pub trials: usize,
    /// Default-policy successes.
    pub success_default: usize,
    /// Successes with at most one demonstration.
    pub success_after_one_demo: usize,
    /// Demonstrations given, over all boxes.
    pub demonstrations: usize,
    /// Planned attempts that succeeded.
    pub success_planned: usize,
    /// Draws excluded by the admissibility rule.
    pub excluded_draws: usize,
    /// Worst palm tracking error over all attempts \[mm\].
    pub max_tracking_mm: f64,
    /// Worst palm tracking error over all attempts \[deg\].
    pub max_tracking_deg: f64,
    /// Per box.
    pub boxes: Vec<BoxOutcome>,
}

fn attempt_from(
    r: Result<ToppleRun, crate::arm::ArmError>,
    sim: &mut ArmSim,
    tracker: &mut Tracker,
    down0_box: &Vector3<f64>,
) -> Attempt {
    match r {
        Ok(run) => {
            let a = run
                .palm_from_tag0
                .map(|p0| assess(sim, tracker, &p0, &goal_direction()));
            let truth = attempt_truth(sim, tracker.body, down0_box);
            let (success, reason) = match &a {
                Some(a) => (a.success, a.reason.clone()),
                None => (false, "no tracked frames before the attempt".into()),
            };
            Attempt {
                success,
                reason,
                tilt_deg: run.tilt_asked.to_degrees(),
                palm_tilt_reached_deg: run.palm_tilt_reached.to_degrees(),
                topple_detected: run.toppled,
                assessment: a,
                truth: Some(truth),
                tracking_mm: run.tracking_position_m * 1e3,
                tracking_deg: run.tracking_angle_rad.to_degrees(),
                run: Some(run),
            }
        }
        Err(e) => Attempt {
            success: false,
            reason: format!("arm: {e}"),
            tilt_deg: f64::NAN,
            palm_tilt_reached_deg: f64::NAN,
            topple_detected: false,
            assessment: None,
            truth: None,
            tracking_mm: 0.0,
            tracking_deg: 0.0,
            run: None,
        },
    }
}

/// A fresh arm with the trial's box on the level palm, settled.
pub fn setup(
    arm: &Arm,
    q_up: &[f64],
    trial: &Trial,
    o: &SkillOptions,
    seed: u64,
) -> crate::Result<(ArmSim, Tracker)> {
    let mut sim = ArmSim::new(arm, q_up, &ArmSimOptions::default())
        .map_err(|e| SimError::Scene(format!("arm: {e}")))?;
    let mut pose = ArmSim::on_palm(&trial.spec, trial.position[0], trial.position[1], trial.yaw);
    pose.translation.vector.z += 1e-4;
    let body = sim.add_box_on_palm(&trial.spec, &pose);
    sim.run_for(0.5);
    let tracker = Tracker::new(&sim, body, trial.spec.box_from_tag(), o, seed);
    Ok((sim, tracker))
}

/// The most demonstrations the simulated user gives one box.
pub const MAX_DEMOS: usize = 3;

/// One completed demonstration of the trial's topple. The simulated user may fumble (the box
/// tumbles off the demonstration plate); they then try again, up to 3 times
/// (`out.demo_user_retries` counts them). Only a completed demonstration reaches the learner.
fn demonstrate_once(
    spec: &BoxSpec,
    trial: &Trial,
    seed: u64,
    out: &mut BoxOutcome,
) -> Result<SimDemo, String> {
    let mut last_err = None;
    for k in 0..3u64 {
        match demonstrate(
            spec,
            trial.axis,
            trial.sign,
            &TrackerNoise::real(),
            seed + 7919 * k,
        ) {
            Ok(d) => return Ok(d),
            Err(e) => {
                out.demo_user_retries += 1;
                last_err = Some(e);
            }
        }
    }
    Err(format!(
        "the simulated user could not complete a demonstration: {}",
        last_err.map_or(String::new(), |e| e.to_string())
    ))
}

/// Run one trial: default attempt, and if it fails, a demonstration (more where the model
/// cannot plan yet), learning and the planned attempt.
pub fn run_trial(
    arm: &Arm,
    q_up: &[f64],
    trial: &Trial,
    o: &SkillOptions,
    seed: u64,
) -> crate::Result<BoxOutcome> {
    let spec = &trial.spec;
    let down0 = -Vector3::z();
    let (mut sim, mut tracker) = setup(arm, q_up, trial, o, seed)?;
    let r = default_policy(&mut sim, &mut tracker, o);
    let default = attempt_from(r, &mut sim, &mut tracker, &down0);
    let mut out = BoxOutcome {
        name: spec.name.clone(),
        dims: spec.dims,
        mass: spec.mass,
        com: spec.com_offset,
        friction: spec.friction,
        position: trial.position,
        yaw_deg: trial.yaw.to_degrees(),
        phi_true_deg: trial.phi_true.to_degrees(),
        phi_learnt_deg: None,
        success_default: default.success,
        success_after_one_demo: default.success,
        reason: if default.success {
            "default policy succeeded".into()
        } else {
            format!("default failed: {}", default.reason)
        },
        default,
        demo_kind: None,
        demo_user_retries: 0,
        demonstrations: 0,
        asked_again: Vec::new(),
        plan: None,
        planned: None,
        trial: Some(trial.clone()),
        learnt: None,
    };
    if out.success_default {
        return Ok(out);
    }
    // If the failed attempt left the box off its first face, the user puts it back.
    let moved = out
        .default
        .assessment
        .as_ref()
        .is_none_or(|a| a.face_change_deg > 20.0 || a.reason.contains("not on the palm"));
    if moved {
        (sim, tracker) = setup(arm, q_up, trial, o, seed ^ 0x55)?;
    }
    let frames = observe(&mut sim, &mut tracker, 0.5);
    let Some(pose) = robust_pose(&frames) else {
        out.reason = format!("{}; no tracked frames to plan from", out.reason);
        return Ok(out);
    };
    let palm = super::encoder_palm(&sim);
    let req = PlanRequest {
        palm_from_object: pose,
        towards: Some(goal_direction()),
        gravity_in_palm: palm.rotation.inverse() * -Vector3::z(),
        margin: None,
    };
    // Ask for a demonstration of the same box, same face, same edge; learn it; plan. Where the
    // model cannot plan yet (one demonstration at this noise may locate its edge too loosely
    // to be taught: `objmodel::tree::unlocated`), ask for another, up to [`MAX_DEMOS`].
    let mut tree = Tree::default();
    let mut why_not = String::new();
    let mut planned = None;
    for n in 0..MAX_DEMOS as u64 {
        let demo = match demonstrate_once(spec, trial, seed + 104_729 * n, &mut out) {
            Ok(d) => d,
            Err(why) => {
                why_not = why;
                continue;
            }
        };
        out.demonstrations += 1;
        let name = match out.demonstrations {
            1 => format!("{}_demo", spec.name),
            k => format!("{}_demo{k}", spec.name),
        };
        match learn(&mut tree, &demo, &name) {
            Ok(k) => out.demo_kind = out.demo_kind.take().or(Some(k)),
            Err(e) => {
                out.reason = format!("{}; learning failed: {e}", out.reason);
                return Ok(out);
            }
        }
        match plan(&tree, &req) {
            Ok(p) => {
                planned = Some(p);
                break;
            }
            Err(e) => {
                why_not = format!("no plan: {e}");
                out.asked_again.push(e.to_string());
            }
        }
    }
    let Some(p) = planned else {
        out.reason = format!("{}; {why_not}", out.reason);
        return Ok(out);
    };
    out.phi_learnt_deg = Some(p.phi.to_degrees());
    out.learnt = Some((tree.clone(), req));
    let r = execute_plan(&mut sim, &mut tracker, &p, o);
    let planned = attempt_from(r, &mut sim, &mut tracker, &down0);
    out.plan = Some(p);
    out.success_after_one_demo = planned.success && out.demonstrations == 1;
    out.reason = if planned.success {
        match out.demonstrations {
            1 => "default failed; planned topple after one demonstration succeeded".into(),
            n => format!("default failed; planned topple after {n} demonstrations succeeded"),
        }
    } else {
        format!("planned attempt failed: {}", planned.reason)
    };
    out.planned = Some(planned);
    Ok(out)
}

/// Run the loop over `cfg.boxes` random boxes; `progress` is told about each box.
pub fn run_task(
    cfg: &TaskConfig,
    mut progress: impl FnMut(usize, &BoxOutcome),
) -> crate::Result<TaskReport> {
    let arm = Arm::panda();
    let q_up = arm
        .palm_up_configuration()
        .map_err(|e| SimError::Scene(format!("arm: {e}")))?;
    let mut rng = StdRng::seed_from_u64(cfg.seed);
    let mut rep = TaskReport {
        trials: 0,
        success_default: 0,
        success_after_one_demo: 0,
        demonstrations: 0,
        success_planned: 0,
        excluded_draws: 0,
        max_tracking_mm: 0.0,
        max_tracking_deg: 0.0,
        boxes: Vec::new(),
    };
    for i in 0..cfg.boxes {
        let trial = draw_trial(&mut rng, &format!("box{i:02}"));
        rep.excluded_draws += trial.rejected_before;
        let seed = cfg.seed.wrapping_mul(1000).wrapping_add(i as u64);
        let o = run_trial(&arm, &q_up, &trial, &cfg.skill, seed)?;
        rep.trials += 1;
        rep.success_default += o.success_default as usize;
        rep.success_after_one_demo += o.success_after_one_demo as usize;
        rep.demonstrations += o.demonstrations;
        rep.success_planned += o.planned.as_ref().is_some_and(|a| a.success) as usize;
        for a in std::iter::once(&o.default).chain(o.planned.as_ref()) {
            rep.max_tracking_mm = rep.max_tracking_mm.max(a.tracking_mm);
            rep.max_tracking_deg = rep.max_tracking_deg.max(a.tracking_deg);
        }
        progress(i, &o);
        rep.boxes.push(o);
    }
    Ok(rep)
}
