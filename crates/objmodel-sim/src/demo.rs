//! Simulate a demonstration and write it as a tracker would have: `NAME.tum` (the tag),
//! `NAME.palm.tum` (the palm, instrumented demos only) and `NAME.truth.json`.

use crate::events::{face_in_tag, rest_face, segments, topple_events};
use crate::noise::TrackerNoise;
use crate::scenes::{self, SceneOutput};
use crate::spec::BoxSpec;
use crate::truth::{arr, PoseJson, Truth};
use crate::world::PhysicsParams;
use crate::{Result, SceneKind, SimError};
use objmodel::StampedPose;
use rand::rngs::StdRng;
use rand::SeedableRng;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Output and physics rates.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SimOptions {
    /// Tracker output rate \[Hz\] (30 by default).
    pub rate_hz: f64,
    /// Physics settings (960 Hz steps by default).
    pub physics: PhysicsParams,
    /// The downhill edge of an instrumented topple, as an index (taken modulo their number)
    /// into the bottom edges its box can topple over on the palm, in the order +x, -x, +y, -y;
    /// `None` (the default): drawn at random. The standard data set gives seed `s` the edge
    /// `s - 1` (`s + 1` turned), so that its three seeds tilt towards three different edges:
    /// random edges often repeat one plane through the CoM (opposite edges from opposite
    /// faces give the same one) and leave the CoM to the pushes.
    #[serde(default)]
    pub edge: Option<usize>,
}

impl Default for SimOptions {
    fn default() -> Self {
        SimOptions {
            rate_hz: 30.0,
            physics: PhysicsParams::default(),
            edge: None,
        }
    }
}

/// A noise-free demonstration: exact tag (and palm) poses at the output rate, and the truth.
#[derive(Debug, Clone)]
pub struct CleanDemo {
    /// The kind of scene.
    pub kind: SceneKind,
    /// Exact `world_from_tag` poses.
    pub object: Vec<StampedPose>,
    /// Exact `world_from_palm` poses (instrumented only).
    pub palm: Option<Vec<StampedPose>>,
    /// The truth (its `noise` field says "clean").
    pub truth: Truth,
}

/// A demonstration as a tracker reports it, with the exact version beside it.
#[derive(Debug, Clone)]
pub struct SimDemo {
    /// The kind of scene.
    pub kind: SceneKind,
    /// Tracked `world_from_tag` poses, with noise.
    pub object: Vec<StampedPose>,
    /// Tracked `world_from_palm` poses, with noise (instrumented only).
    pub palm: Option<Vec<StampedPose>>,
    /// Exact `world_from_tag` poses at every output instant (dropped frames included).
    pub object_clean: Vec<StampedPose>,
    /// Exact `world_from_palm` poses (instrumented only).
    pub palm_clean: Option<Vec<StampedPose>>,
    /// What really happened.
    pub truth: Truth,
}

/// Simulate one demonstration of `kind` with default options.
pub fn simulate(
    kind: SceneKind,
    spec: &BoxSpec,
    noise: &TrackerNoise,
    seed: u64,
) -> Result<SimDemo> {
    simulate_with(kind, spec, noise, seed, &SimOptions::default())
}

/// Simulate one demonstration of `kind` and add tracking noise.
pub fn simulate_with(
    kind: SceneKind,
    spec: &BoxSpec,
    noise: &TrackerNoise,
    seed: u64,
    opts: &SimOptions,
) -> Result<SimDemo> {
    noise.validate()?;
    Ok(simulate_clean(kind, spec, seed, opts)?.with_noise(noise))
}

fn kind_salt(kind: SceneKind) -> u64 {
    match kind {
        SceneKind::Topple => 0x1111,
        SceneKind::InstrumentedTopple => 0x2222,
        SceneKind::Slide => 0x3333,
        SceneKind::General => 0x4444,
        SceneKind::Compound => 0x5555,
        SceneKind::ToppleSlide => 0x6666,
        SceneKind::Toss => 0x7777,
        SceneKind::Session => 0x8888,
    }
}

/// Run the scene of `kind` for `seed` and compute its truth; no noise yet.
pub fn simulate_clean(
    kind: SceneKind,
    spec: &BoxSpec,
    seed: u64,
    opts: &SimOptions,
) -> Result<CleanDemo> {
    let out = run_scene(kind, spec, seed, opts)?;
    clean_demo(kind, spec, seed, &out, opts)
}

/// Run the scene of `kind` for `seed`: its full-rate record.
pub fn run_scene(
    kind: SceneKind,
    spec: &BoxSpec,
    seed: u64,
    opts: &SimOptions,
) -> Result<SceneOutput> {
    spec.validate()?;
    if !(opts.rate_hz > 0.0 && opts.rate_hz <= opts.physics.step_hz) {
        return Err(SimError::InvalidSpec(format!(
            "output rate {} Hz must be positive and at most the physics rate {} Hz",
            opts.rate_hz, opts.physics.step_hz
        )));
    }
    let mut rng = StdRng::seed_from_u64(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ kind_salt(kind));
    let p = &opts.physics;
    Ok(match kind {
        SceneKind::Topple => scenes::topple::run(spec, p, &mut rng)?,
        SceneKind::InstrumentedTopple => scenes::instrumented::run(spec, p, opts.edge, &mut rng)?,
        SceneKind::Slide => scenes::slide::run(spec, p, &mut rng)?,
        SceneKind::General => scenes::general::run(spec, p, &mut rng)?,
        SceneKind::Compound => scenes::compound::run(spec, p, &mut rng)?,
        SceneKind::ToppleSlide => scenes::topple_slide::run(spec, p, &mut rng)?,
        SceneKind::Toss => scenes::toss::run(spec, p, &mut rng)?,
        SceneKind::Session => scenes::session::run(spec, p, &mut rng)?,
    })
}

/// The clean demonstration of a finished scene, tracked at `opts.rate_hz`, with its truth.
pub fn clean_demo(
    kind: SceneKind,
    spec: &BoxSpec,
    seed: u64,
    out: &SceneOutput,
    opts: &SimOptions,
) -> Result<CleanDemo> {
    let truth = truth_of(kind, spec, seed, out, opts)?;
    let (object, palm) = tracked(out, spec, opts.rate_hz);
    let palm = out.script.palm.then_some(palm);
    Ok(CleanDemo {
        kind,
        object,
        palm,
        truth,
    })
}

/// What a tracker at `rate_hz` sees of a finished scene: the tag's pose (`world_from_tag`) and
/// the support's (the palm's), at the physics sample nearest each tracker frame.
pub fn tracked(
    out: &SceneOutput,
    spec: &BoxSpec,
    rate_hz: f64,
) -> (Vec<StampedPose>, Vec<StampedPose>) {
    let box_from_tag = spec.box_from_tag();
    let n_out = (out.samples.last().map_or(0.0, |s| s.t) * rate_hz).floor() as usize + 1;
    (0..n_out)
        .map(|k| {
            let t = k as f64 / rate_hz;
            let i = ((t * out.step_hz).round() as usize).min(out.samples.len() - 1);
            let s = &out.samples[i];
            (
                StampedPose {
                    t,
                    pose: s.world_from_box * box_from_tag,
                },
                StampedPose {
                    t,
                    pose: s.world_from_support,
                },
            )
        })
        .unzip()
}

/// The truth of a finished scene.
pub fn truth_of(
    kind: SceneKind,
    spec: &BoxSpec,
    seed: u64,
    out: &SceneOutput,
    opts: &SimOptions,
) -> Result<Truth> {
    let s = &out.samples;
    let (first, last) = (s.first().expect("samples"), s.last().expect("samples"));
    let (f0, f1) = (rest_face(first), rest_face(last));
    let tag_from_box = spec.tag_from_box();
    let n_tag = |f: crate::BoxFace| arr(&(tag_from_box.rotation * f.normal()));
    let topples = matches!(
        kind,
        SceneKind::Topple | SceneKind::InstrumentedTopple | SceneKind::Compound
    );
    let slides = matches!(kind, SceneKind::Slide | SceneKind::Compound);
    let topple = if topples {
        let t_ref = out.script.second_phase.unwrap_or(out.script.motion_start);
        Some(topple_events(spec, out, t_ref, f0, f1)?)
    } else {
        None
    };
    if slides && !topples && f0 != f1 {
        return Err(SimError::Scene(format!(
            "the sliding box ended on face {f1:?}, not {f0:?}"
        )));
    }
    let instrumented = kind == SceneKind::InstrumentedTopple;
    let deg = |x: f64| x.to_degrees();
    Ok(Truth {
        kind: kind.truth_kind().into(),
        instrumented,
        seed,
        box_name: spec.name.clone(),
        box_dims: spec.dims,
        mass: spec.mass,
        friction: out.script.mu,
        box_from_tag: PoseJson::from(&spec.box_from_tag()),
        com: arr(&(tag_from_box * spec.com_box()).coords),
        box_com: spec.com_offset,
        rest_normal_before: n_tag(f0),
        rest_normal_after: n_tag(f1),
        edge: topple.as_ref().map(|e| e.edge),
        face: slides.then(|| face_in_tag(spec, f0)),
        phi: topple.as_ref().map(|e| e.phi),
        phi_deg: topple.as_ref().map(|e| deg(e.phi)),
        topple_start: topple.as_ref().map(|e| e.onset.1),
        palm_tilt_at_start: topple
            .as_ref()
            .filter(|_| instrumented)
            .map(|e| e.support_tilt),
        palm_tilt_at_start_deg: topple
            .as_ref()
            .filter(|_| instrumented)
            .map(|e| deg(e.support_tilt)),
        pivot_end: topple.as_ref().and_then(|e| e.pivot_end.map(|p| p.0)),
        left_edge: topple.as_ref().and_then(|e| e.pivot_end.map(|p| p.1)),
        pivot_slip: topple.as_ref().map(|e| e.pivot_slip),
        segments: segments(out, kind.truth_kind(), topple.as_ref().map(|e| e.onset.1)),
        duration: last.t,
        rate_hz: opts.rate_hz,
        physics_hz: out.step_hz,
        noise: TrackerNoise::clean(),
        script: out.script.notes.iter().cloned().collect(),
        features: crate::modes::box_features(spec),
        modes: crate::modes::contact_modes(spec, out),
    })
}

impl CleanDemo {
    /// Add tracking noise. The noise stream depends on the truth's seed and the model's name,
    /// so the same demo gets different noise at each level and the same noise every run.
    pub fn with_noise(&self, noise: &TrackerNoise) -> SimDemo {
        let salt: u64 = noise.name.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
            (h ^ b as u64).wrapping_mul(0x100_0000_01b3)
        });
        let mut rng = StdRng::seed_from_u64(self.truth.seed ^ salt);
        let object = noise.apply(&self.object, &mut rng);
        let palm = self.palm.as_ref().map(|p| noise.apply(p, &mut rng));
        let mut truth = self.truth.clone();
        truth.noise = noise.clone();
        SimDemo {
            kind: self.kind,
            object,
            palm,
            object_clean: self.object.clone(),
            palm_clean: self.palm.clone(),
            truth,
        }
    }
}

/// Paths written by [`write_demo`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DemoFiles {
    /// The tag trajectory, TUM format.
    pub tum: PathBuf,
    /// The palm trajectory, TUM format (instrumented only).
    pub palm: Option<PathBuf>,
    /// The ground truth, JSON.
    pub truth: PathBuf,
}

/// Write `dir/NAME.tum`, `dir/NAME.palm.tum` (instrumented) and `dir/NAME.truth.json`, each
/// atomically; creates `dir` if needed.
pub fn write_demo(dir: &Path, name: &str, demo: &SimDemo) -> Result<DemoFiles> {
    std::fs::create_dir_all(dir).map_err(|source| objmodel::Error::Io {
        file: dir.to_path_buf(),
        source,
    })?;
    let t = &demo.truth;
    let header = format!(
        "objmodel-sim {name}: {} demonstration{}, box '{}' {:?} m, {} kg, seed {}, noise '{}'",
        t.kind,
        if t.instrumented {
            " (instrumented)"
        } else {
            ""
        },
        t.box_name,
        t.box_dims,
        t.mass,
        t.seed,
        t.noise.name
    );
    let tum = dir.join(format!("{name}.tum"));
    objmodel::format::write_tum(
        &tum,
        &demo.object,
        &format!("{header}\nworld_from_tag of the tracked tag"),
    )?;
    let palm = match &demo.palm {
        Some(p) => {
            let path = dir.join(format!("{name}.palm.tum"));
            let c = format!(
                "{header}\nworld_from_palm: origin on the palm's top surface, z its normal"
            );
            objmodel::format::write_tum(&path, p, &c)?;
            Some(path)
        }
        None => None,
    };
    let truth = dir.join(format!("{name}.truth.json"));
    objmodel::format::write_atomic(&truth, serde_json::to_string_pretty(t)?.as_bytes())?;
    Ok(DemoFiles { tum, palm, truth })
}
