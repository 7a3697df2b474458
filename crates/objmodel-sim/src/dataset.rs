//! The standard data set: several boxes (one with an offset centre of mass) × every kind of
//! demonstration × three noise levels × a few seeds, with a `manifest.json`; and the messy
//! scenes of issue 20 (topple-then-slide compounds, long sessions, tosses), some of them also
//! at motion-capture noise and rate.
//!
//! Each (box, kind, seed) is simulated once; the noise levels are drawn on the same clean
//! trajectory, so noise (and, for motion capture, the tracking rate) is the only difference
//! between them.

use crate::demo::{clean_demo, run_scene, tracked, write_demo, CleanDemo, SimOptions};
use crate::noise::TrackerNoise;
use crate::spec::{BoxFace, BoxSpec, TagMount};
use crate::turned::Turn;
use crate::{Result, SceneKind, SimError};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What to generate.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DatasetPlan {
    /// The boxes.
    pub boxes: Vec<BoxSpec>,
    /// The kinds of demonstration.
    pub kinds: Vec<SceneKind>,
    /// The noise levels.
    pub noises: Vec<TrackerNoise>,
    /// Seeds per (box, kind) cell.
    pub seeds: Vec<u64>,
    /// Kinds also demonstrated with each box turned onto another face ([`Turn`]): the scenes
    /// start every box on its `-z` face, so without them no demonstration shows its top face,
    /// nor the faces of edges too steep to topple over from there, and the learnt shape stays
    /// open.
    #[serde(default)]
    pub turned: Vec<(Turn, SceneKind)>,
    /// Rates.
    pub options: SimOptions,
    /// Whether the instrumented topples of seed `s` tilt towards the downhill edge `s - 1`
    /// (`s + 1` with the box turned; see [`SimOptions::edge`]) rather than a random one
    /// (`options.edge`).
    #[serde(default)]
    pub edges_by_seed: bool,
    /// Worker threads (scenes run in parallel).
    pub threads: usize,
    /// Messy scenes made for every box besides `kinds`: each kind with its number of seeds
    /// (seeds 1..=n).
    #[serde(default)]
    pub messy: Vec<(SceneKind, usize)>,
    /// Tosses in all: toss `k` (1..=tosses) throws box `(k − 1) mod boxes` with seed `k`.
    #[serde(default)]
    pub tosses: usize,
    /// Kinds also written at motion-capture noise ([`TrackerNoise::mocap_drawn`]: sigmas drawn
    /// per demo) and rate (one of [`TrackerNoise::MOCAP_RATES`] drawn per demo), named
    /// `..._mocap_...`, besides `noises`.
    #[serde(default)]
    pub mocap_kinds: Vec<SceneKind>,
}

/// The standard boxes, each with its own tag sticker:
///
/// | name | dims \[m\] | mass \[kg\] | CoM offset \[m\] | μ |
/// |---|---|---|---|---|
/// | tall | 0.10 × 0.10 × 0.20 | 0.6 | 0 | 0.8 |
/// | brick | 0.09 × 0.07 × 0.13 | 0.45 | 0 | 1.0 |
/// | slab | 0.12 × 0.06 × 0.10 | 0.4 | 0 | 0.9 |
/// | weighted | 0.08 × 0.08 × 0.16 | 0.8 | (0.015, 0, −0.02) | 0.9 |
/// | post | 0.06 × 0.07 × 0.22 | 0.35 | (0, 0.008, 0.03) | 0.7 |
pub fn standard_boxes() -> Vec<BoxSpec> {
    let tag = |face, o0, o1, yaw_deg: f64| TagMount {
        face,
        offset: [o0, o1],
        yaw: yaw_deg.to_radians(),
    };
    vec![
        BoxSpec::new("tall", [0.10, 0.10, 0.20], 0.6)
            .with_friction(0.8)
            .with_tag(tag(BoxFace::PosX, 0.004, -0.003, 17.0)),
        BoxSpec::new("brick", [0.09, 0.07, 0.13], 0.45)
            .with_friction(1.0)
            .with_tag(tag(BoxFace::NegY, -0.003, 0.005, -25.0)),
        BoxSpec::new("slab", [0.12, 0.06, 0.10], 0.4)
            .with_friction(0.9)
            .with_tag(tag(BoxFace::PosY, 0.005, 0.002, 8.0)),
        BoxSpec::new("weighted", [0.08, 0.08, 0.16], 0.8)
            .with_com([0.015, 0.0, -0.02])
            .with_friction(0.9)
            .with_tag(tag(BoxFace::NegX, -0.002, -0.004, 33.0)),
        BoxSpec::new("post", [0.06, 0.07, 0.22], 0.35)
            .with_com([0.0, 0.008, 0.03])
            .with_friction(0.7)
            .with_tag(tag(BoxFace::PosX, 0.003, 0.006, -12.0)),
    ]
}

/// The standard plan: 5 boxes × 5 kinds × (clean, real, noisy) × 3 seeds; the topples again
/// with each box upside down (direct and instrumented), standing on either `x` end (direct)
/// and on its `+x` end (instrumented), each left out for a box that cannot topple so; the
/// instrumented topples of the three seeds towards three different edges
/// ([`DatasetPlan::edges_by_seed`]); and besides: topple-then-slide compounds (2
/// seeds per box), one session per box, 3 tosses per box, and motion-capture versions of the
/// instrumented topples, both compounds, the sessions and the tosses. `quick` keeps 4 boxes,
/// 1 seed, no turned boxes and only the original five kinds. [`with_tosses`] sets the tosses
/// (with `quick` too).
pub fn standard_dataset(quick: bool) -> DatasetPlan {
    let mut boxes = standard_boxes();
    if quick {
        boxes.truncate(4);
    }
    DatasetPlan {
        boxes,
        kinds: SceneKind::ALL.to_vec(),
        noises: TrackerNoise::PRESETS
            .iter()
            .filter_map(|n| TrackerNoise::preset(n))
            .collect(),
        seeds: if quick { vec![1] } else { vec![1, 2, 3] },
        turned: if quick {
            Vec::new()
        } else {
            vec![
                (Turn::UpsideDown, SceneKind::Topple),
                (Turn::UpsideDown, SceneKind::InstrumentedTopple),
                (Turn::OnPosX, SceneKind::Topple),
                (Turn::OnPosX, SceneKind::InstrumentedTopple),
                (Turn::OnNegX, SceneKind::Topple),
            ]
        },
        options: SimOptions::default(),
        edges_by_seed: true,
        threads: std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1)
            .min(2),
        messy: if quick {
            vec![]
        } else {
            vec![(SceneKind::ToppleSlide, 2), (SceneKind::Session, 1)]
        },
        tosses: if quick { 0 } else { 15 },
        mocap_kinds: if quick {
            vec![SceneKind::Toss]
        } else {
            vec![
                SceneKind::InstrumentedTopple,
                SceneKind::Compound,
                SceneKind::ToppleSlide,
                SceneKind::Toss,
                SceneKind::Session,
            ]
        },
    }
}

/// `plan` with `n` tosses in all (see [`DatasetPlan::tosses`]).
pub fn with_tosses(mut plan: DatasetPlan, n: usize) -> DatasetPlan {
    plan.tosses = n;
    plan
}

/// One demo in the manifest.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ManifestEntry {
    /// File stem.
    pub name: String,
    /// Scene kind name (topple, instrumented, slide, general, compound).
    pub scene: String,
    /// Truth kind (topple, slide, general, compound).
    pub kind: String,
    /// How the box was turned from standing on its bottom (`-z`) face, if it was.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub turned: Option<Turn>,
    /// Whether a palm was tracked.
    pub instrumented: bool,
    /// Box name.
    pub r#box: String,
    /// Noise preset name.
    pub noise: String,
    /// Seed actually used (a failed scene is retried with another seed).
    pub seed: u64,
    /// Tag trajectory file, relative to the manifest.
    pub tum: String,
    /// Palm trajectory file, if any.
    pub palm: Option<String>,
    /// Truth file.
    pub truth: String,
    /// Number of written object poses.
    pub frames: usize,
    /// Duration \[s\].
    pub duration: f64,
    /// Tracking rate \[Hz\].
    #[serde(default)]
    pub rate_hz: f64,
}

/// `manifest.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// Schema version.
    pub version: u32,
    /// The boxes.
    pub boxes: Vec<BoxSpec>,
    /// The noise models.
    pub noises: Vec<TrackerNoise>,
    /// Every demo written.
    pub demos: Vec<ManifestEntry>,
    /// Cells that failed even after retries, with the reason.
    pub failures: Vec<(String, String)>,
    /// Wall-clock generation time \[s\].
    pub seconds: f64,
    /// Simulated time \[s\] (each clean run counted once).
    pub simulated_seconds: f64,
}

/// Progress report: `done` of `total` scenes finished, the last one's name.
#[derive(Debug, Clone)]
pub struct Progress {
    /// Scenes finished.
    pub done: usize,
    /// Scenes planned.
    pub total: usize,
    /// Name of the scene just finished.
    pub name: String,
}

/// A cell's demos and simulated duration, or why it could not be made.
type CellOutcome = std::result::Result<(Vec<ManifestEntry>, f64), String>;
type CellResult = (usize, CellOutcome);

/// The noise levels and tracking rates of one cell: the plan's levels at its rate, then for a
/// [`DatasetPlan::mocap_kinds`] kind motion capture with drawn sigmas and rate.
fn cell_noises(plan: &DatasetPlan, kind: SceneKind, seed: u64) -> Vec<(TrackerNoise, f64)> {
    let mut v: Vec<(TrackerNoise, f64)> = plan
        .noises
        .iter()
        .map(|n| (n.clone(), plan.options.rate_hz))
        .collect();
    if plan.mocap_kinds.contains(&kind) {
        let mut rng = StdRng::seed_from_u64(seed ^ 0x006d_6f63_6170 ^ (kind as u64) << 40);
        let rates = TrackerNoise::MOCAP_RATES;
        let rate = rates[rng.random_range(0..rates.len())];
        v.push((TrackerNoise::mocap_drawn(&mut rng), rate));
    }
    v
}

fn run_cell(
    dir: &Path,
    plan: &DatasetPlan,
    b: &BoxSpec,
    kind: SceneKind,
    seed: u64,
    turn: Option<Turn>,
) -> CellOutcome {
    let turned;
    let (b, stem) = match turn {
        Some(t) => {
            turned = t.apply(b);
            (&turned, format!("{}_{}-{}", b.name, kind.name(), t.name()))
        }
        None => (b, format!("{}_{}", b.name, kind.name())),
    };
    let mut last_err = String::new();
    for attempt in 0..4u64 {
        let s = seed + 1000 * attempt;
        let options = SimOptions {
            // A turned box starts two edges further on: the edges diagonally opposite the
            // upright box's would put the same plane through a centred CoM.
            edge: if plan.edges_by_seed {
                Some((seed as usize).saturating_sub(1) + if turn.is_some() { 2 } else { 0 })
            } else {
                plan.options.edge
            },
            ..plan.options
        };
        let out = match run_scene(kind, b, s, &options) {
            Ok(out) => out,
            // Not every box can do every kind turned (a box too wide to topple standing on its
            // end): that cell is left out.
            Err(SimError::InvalidSpec(_)) if turn.is_some() => return Ok((Vec::new(), 0.0)),
            Err(SimError::InvalidSpec(m)) => return Err(m),
            Err(e) => {
                last_err = format!("seed {s}: {e}");
                continue;
            }
        };
        let mut entries = Vec::new();
        let mut clean_at: Vec<(f64, CleanDemo)> = Vec::new();
        let mut duration = 0.0;
        for (noise, rate) in cell_noises(plan, kind, seed) {
            if !clean_at.iter().any(|(r, _)| *r == rate) {
                let made = match clean_at.first() {
                    // Another rate of the same run: the same truth, tracked anew.
                    Some((_, first)) => {
                        let (object, palm) = tracked(&out, b, rate);
                        let mut truth = first.truth.clone();
                        truth.rate_hz = rate;
                        Ok(CleanDemo {
                            kind,
                            object,
                            palm: out.script.palm.then_some(palm),
                            truth,
                        })
                    }
                    None => {
                        let opts = SimOptions {
                            rate_hz: rate,
                            ..options
                        };
                        clean_demo(kind, b, s, &out, &opts)
                    }
                };
                match made {
                    Ok(c) => clean_at.push((rate, c)),
                    Err(e) => {
                        last_err = format!("seed {s}: {e}");
                        break;
                    }
                }
            }
            let Some((_, clean)) = clean_at.iter().find(|(r, _)| *r == rate) else {
                break;
            };
            duration = clean.truth.duration;
            let name = format!("{stem}_{}_s{seed}", noise.name);
            let demo = clean.with_noise(&noise);
            let files = write_demo(dir, &name, &demo).map_err(|e| e.to_string())?;
            let rel = |p: &PathBuf| {
                p.file_name()
                    .map(|f| f.to_string_lossy().into_owned())
                    .unwrap_or_default()
            };
            entries.push(ManifestEntry {
                name,
                scene: kind.name().into(),
                kind: kind.truth_kind().into(),
                turned: turn,
                instrumented: demo.truth.instrumented,
                r#box: b.name.clone(),
                noise: noise.name.clone(),
                seed: s,
                tum: rel(&files.tum),
                palm: files.palm.as_ref().map(rel),
                truth: rel(&files.truth),
                frames: demo.object.len(),
                duration: demo.truth.duration,
                rate_hz: rate,
            });
        }
        if entries.len() == cell_noises(plan, kind, seed).len() {
            return Ok((entries, duration));
        }
    }
    Err(last_err)
}

/// A cell's name: box, kind (and turn) and seed.
fn cell_name((b, kind, seed, turn): (&BoxSpec, SceneKind, u64, Option<Turn>)) -> String {
    let turned = turn.map_or(String::new(), |t| format!("-{}", t.name()));
    format!("{}_{}{turned}_s{seed}", b.name, kind.name())
}

/// Generate `plan` into `dir` (created if needed) and write `dir/manifest.json`, calling
/// `progress` after each scene. A cell that cannot be made (an impossible box for a kind, or
/// four failed seeds) is listed in `failures`, not fatal.
pub fn write_dataset(
    dir: &Path,
    plan: &DatasetPlan,
    progress: &mut dyn FnMut(&Progress),
) -> Result<Manifest> {
    std::fs::create_dir_all(dir).map_err(|source| objmodel::Error::Io {
        file: dir.to_path_buf(),
        source,
    })?;
    for n in &plan.noises {
        n.validate()?;
    }
    let start = Instant::now();
    let mut cells = Vec::new();
    for b in &plan.boxes {
        for &kind in &plan.kinds {
            for &seed in &plan.seeds {
                cells.push((b, kind, seed, None));
                for (turn, k) in &plan.turned {
                    if *k == kind {
                        cells.push((b, kind, seed, Some(*turn)));
                    }
                }
            }
        }
    }
    for b in &plan.boxes {
        for &(kind, n) in &plan.messy {
            for seed in 1..=n as u64 {
                cells.push((b, kind, seed, None));
            }
        }
    }
    if !plan.boxes.is_empty() {
        for k in 1..=plan.tosses {
            cells.push((
                &plan.boxes[(k - 1) % plan.boxes.len()],
                SceneKind::Toss,
                k as u64,
                None,
            ));
        }
    }
    let total = cells.len();
    let next = std::sync::atomic::AtomicUsize::new(0);
    let (tx, rx) = std::sync::mpsc::channel::<CellResult>();
    let mut results: Vec<Option<CellOutcome>> = vec![None; total];
    std::thread::scope(|scope| {
        for _ in 0..plan.threads.max(1) {
            let tx = tx.clone();
            let (cells, next) = (&cells, &next);
            scope.spawn(move || loop {
                let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                if i >= cells.len() {
                    break;
                }
                let (b, kind, seed, flipped) = cells[i];
                let _ = tx.send((i, run_cell(dir, plan, b, kind, seed, flipped)));
            });
        }
        drop(tx);
        for (done, (i, r)) in rx.iter().enumerate() {
            results[i] = Some(r);
            progress(&Progress {
                done: done + 1,
                total,
                name: cell_name(cells[i]),
            });
        }
    });
    let mut demos = Vec::new();
    let mut failures = Vec::new();
    let mut simulated = 0.0;
    for (i, r) in results.into_iter().enumerate() {
        match r.expect("every cell reports") {
            Ok((entries, dur)) => {
                demos.extend(entries);
                simulated += dur;
            }
            Err(m) => failures.push((cell_name(cells[i]), m)),
        }
    }
    let manifest = Manifest {
        version: 1,
        boxes: plan.boxes.clone(),
        noises: plan.noises.clone(),
        demos,
        failures,
        seconds: start.elapsed().as_secs_f64(),
        simulated_seconds: simulated,
    };
    objmodel::format::write_atomic(
        &dir.join("manifest.json"),
        serde_json::to_string_pretty(&manifest)?.as_bytes(),
    )?;
    Ok(manifest)
}
