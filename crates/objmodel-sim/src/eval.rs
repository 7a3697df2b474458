//! Measuring the learner against the simulator's ground truth: classification accuracy per kind
//! and noise level, edge errors per demonstration and after fusing, face normal errors.

use crate::dataset::Manifest;
use crate::truth::Truth;
use nalgebra::Vector3;
use objmodel::classify::{Config, Kind};
use objmodel::learn::{Learner, Source};
use objmodel::observation::Observation;
use objmodel::tree::Tree;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::Path;

/// One demonstration's result.
#[derive(Clone, Debug, Serialize)]
pub struct DemoResult {
    /// Demo name.
    pub name: String,
    /// Scene (topple, instrumented, slide, general, compound).
    pub scene: String,
    /// Box name.
    pub r#box: String,
    /// Noise preset.
    pub noise: String,
    /// True kind.
    pub truth: String,
    /// Learnt kind.
    pub kind: String,
    /// Whether the learnt kind is right (for a compound: a topple about the true edge was found).
    pub correct: bool,
    /// Edge direction error \[deg\], for demos with an edge.
    pub edge_direction_deg: Option<f64>,
    /// Edge position error \[mm\]: distance between learnt and true points closest to the origin.
    pub edge_position_mm: Option<f64>,
    /// Face normal error \[deg\] (sign included), for slides (slide and compound scenes).
    pub face_normal_deg: Option<f64>,
    /// φ error \[deg\] of the palm-at-onset estimate (instrumented).
    pub phi_onset_deg: Option<f64>,
    /// φ error \[deg\] of the pendulum-on-palm fit (instrumented).
    pub phi_support_deg: Option<f64>,
    /// φ error \[deg\] of the pendulum fit to the fall.
    pub phi_fall_deg: Option<f64>,
    /// φ error \[deg\] of the combined estimate that goes into the tree.
    pub phi_deg: Option<f64>,
    /// Onset time error \[s\] against the simulator's topple start (instrumented).
    pub onset_s: Option<f64>,
    /// Inertia ratio `I_e/(m l_p)` \[m\] fitted to the fall, and its truth for the box.
    pub inertia_ratio_m: Option<(f64, f64)>,
}

/// Errors of one fused edge.
#[derive(Clone, Debug, Serialize)]
pub struct FusedResult {
    /// Box name.
    pub r#box: String,
    /// Noise preset.
    pub noise: String,
    /// Demonstrations fused into the edge.
    pub support: usize,
    /// Direction error \[deg\].
    pub direction_deg: f64,
    /// Position error \[mm\].
    pub position_mm: f64,
    /// Held back as too loosely located to be taught (`objmodel::tree::unlocated`): not in
    /// the table's errors, counted beside them.
    pub held_back: bool,
}

/// The whole evaluation.
#[derive(Clone, Debug, Serialize)]
pub struct Evaluation {
    /// Per demonstration.
    pub demos: Vec<DemoResult>,
    /// Per fused edge.
    pub fused: Vec<FusedResult>,
    /// Centre-of-mass errors per box and noise level.
    pub coms: Vec<ComResult>,
    /// Precision of the features learnt per scene kind and noise level.
    pub precision: Vec<crate::eval_precision::PrecisionRow>,
}

/// The CoM learnt from all topples of a box.
#[derive(Clone, Debug, Serialize)]
pub struct ComResult {
    /// Box name.
    pub r#box: String,
    /// Noise preset.
    pub noise: String,
    /// Pendulums used.
    pub pendulums: usize,
    /// Distance from the true CoM \[mm\].
    pub error_mm: f64,
}

fn v(a: [f64; 3]) -> Vector3<f64> {
    Vector3::new(a[0], a[1], a[2])
}

fn line_angle_deg(a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    a.cross(b).norm().atan2(a.dot(b).abs()).to_degrees()
}

fn edge_errors(
    tree_or_obs: impl Iterator<Item = (Vector3<f64>, Vector3<f64>)>,
    truth: &Truth,
) -> Option<(f64, f64)> {
    let e = truth.edge?;
    let (tp, td) = (v(e.point), v(e.direction));
    tree_or_obs
        .map(|(p, d)| (line_angle_deg(&d, &td), (p - tp).norm() * 1e3))
        .min_by(|a, b| (a.0 + a.1).total_cmp(&(b.0 + b.1)))
}

/// The manifest of the dataset in `dir`; an error names the file.
pub(crate) fn read_manifest(dir: &Path) -> anyhow::Result<Manifest> {
    let path = dir.join("manifest.json");
    let text = std::fs::read_to_string(&path).map_err(|e| {
        anyhow::anyhow!(
            "{}: {e} (a dataset written by `objmodel dataset`?)",
            path.display()
        )
    })?;
    serde_json::from_str(&text).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))
}

/// The truth of the dataset's demonstration `m` (in `dir`), and what `learner` makes of it.
pub(crate) fn observe(
    dir: &Path,
    learner: &Learner,
    m: &crate::dataset::ManifestEntry,
) -> anyhow::Result<(Truth, Observation)> {
    let truth: Truth = serde_json::from_str(&std::fs::read_to_string(dir.join(&m.truth))?)?;
    let palm = m.palm.as_ref().map(|p| dir.join(p));
    let observation = learner.observe(&Source::Files {
        object: &dir.join(&m.tum),
        palm: palm.as_deref(),
    })?;
    Ok((truth, observation))
}

/// Evaluate the learner on the dataset in `dir` (with `manifest.json`).
pub fn evaluate(dir: &Path, config: &Config) -> anyhow::Result<Evaluation> {
    let manifest = read_manifest(dir)?;
    let mut demos = Vec::new();
    let mut groups: BTreeMap<(String, String), Vec<(Observation, Truth)>> = BTreeMap::new();
    let learner = Learner::new(*config);
    let mut by_scene: BTreeMap<(String, String, String), (Vec<Observation>, _)> = BTreeMap::new();
    for m in &manifest.demos {
        let (truth, observation) = observe(dir, &learner, m)?;
        let c = &observation.classification;
        let edge = edge_errors(c.edges().map(|e| (e.line.point, e.line.direction)), &truth);
        // Slide and compound scenes (a straight push, then a topple) slide on a known face.
        let slid = matches!(truth.kind.as_str(), "slide" | "compound");
        let face_normal_deg = truth.face.filter(|_| slid).and_then(|f| {
            let n = v(f.normal);
            c.segments
                .iter()
                .filter_map(|s| s.face.as_ref())
                .map(|o| o.normal.angle(&n).to_degrees())
                .min_by(|a, b| a.total_cmp(b))
        });
        let (
            mut phi_onset_deg,
            mut phi_support_deg,
            mut phi_fall_deg,
            mut phi_deg,
            mut onset_s,
            mut inertia_ratio_m,
        ) = (None, None, None, None, None, None);
        if let (Some(phi_true), Kind::Topple) = (truth.phi, c.kind) {
            if let Some(d) = observation.dynamics.first() {
                phi_onset_deg = d.phi_onset.map(|p| (p - phi_true).to_degrees());
                phi_support_deg = d.on_support.map(|f| (f.phi - phi_true).to_degrees());
                phi_fall_deg = d.fall.map(|f| (f.phi - phi_true).to_degrees());
                phi_deg = d.phi.map(|p| (p - phi_true).to_degrees());
                onset_s = d.onset.zip(truth.topple_start).map(|(o, ts)| o.t - ts);
                inertia_ratio_m = d
                    .fall
                    .map(|f| (f.inertia_ratio_m, true_inertia_ratio(&truth)));
            }
        }
        let correct = match truth.kind.as_str() {
            "compound" => edge.is_some_and(|(d, p)| d < 5.0 && p < 10.0),
            k => c.kind.as_str() == k,
        };
        demos.push(DemoResult {
            name: m.name.clone(),
            scene: m.scene.clone(),
            r#box: m.r#box.clone(),
            noise: m.noise.clone(),
            truth: truth.kind.clone(),
            kind: c.kind.as_str().to_string(),
            correct,
            edge_direction_deg: edge.map(|e| e.0),
            edge_position_mm: edge.map(|e| e.1),
            face_normal_deg,
            phi_onset_deg,
            phi_support_deg,
            phi_fall_deg,
            phi_deg,
            onset_s,
            inertia_ratio_m,
        });
        by_scene
            .entry((m.scene.clone(), m.r#box.clone(), m.noise.clone()))
            .or_insert_with(|| (Vec::new(), truth.features.clone()))
            .0
            .push(observation.clone());
        if truth.edge.is_some() && c.kind == Kind::Topple {
            groups
                .entry((m.r#box.clone(), m.noise.clone()))
                .or_default()
                .push((observation, truth));
        }
    }
    // Fuse, per box and noise level, all topples; score each true edge against the tree.
    let mut fused = Vec::new();
    let mut coms = Vec::new();
    for ((b, noise), items) in groups {
        let mut tree = Tree::default();
        for (o, _) in &items {
            tree.add(o);
        }
        if let (Some(com), Some((_, t))) = (&tree.com, items.first()) {
            coms.push(ComResult {
                r#box: b.clone(),
                noise: noise.clone(),
                pendulums: com.pendulums,
                error_mm: (com.point - v(t.com)).norm() * 1e3,
            });
        }
        // Each true edge against the estimate its own topples taught (taught, or held back as
        // too loosely located: `objmodel::tree::unlocated`), not the nearest other edge.
        let mut seen: Vec<Vector3<f64>> = Vec::new();
        for (_, t) in &items {
            let key = v(t.edge.unwrap().point);
            if seen.iter().any(|s| (s - key).norm() < 1e-6) {
                continue;
            }
            seen.push(key);
            let demos: Vec<&str> = items
                .iter()
                .filter(|(_, u)| u.edge.is_some_and(|e| (v(e.point) - key).norm() < 1e-6))
                .map(|(o, _)| o.classification.name.as_str())
                .collect();
            let taught_by_them =
                |x: &&objmodel::tree::Edge| x.support.iter().any(|s| demos.contains(&s.as_str()));
            let best = tree
                .edge_estimates()
                .filter(taught_by_them)
                .map(|x| {
                    (
                        x,
                        edge_errors(std::iter::once((x.point, x.direction)), t).unwrap(),
                    )
                })
                .min_by(|a, b| (a.1 .0 + a.1 .1).total_cmp(&(b.1 .0 + b.1 .1)));
            if let Some((x, (d, p))) = best {
                fused.push(FusedResult {
                    r#box: b.clone(),
                    noise: noise.clone(),
                    support: x.n_support,
                    direction_deg: d,
                    position_mm: p,
                    held_back: !tree.edges.iter().any(|e| e.id == x.id),
                });
            }
        }
    }
    let precision = crate::eval_precision::precision_rows(&by_scene);
    Ok(Evaluation {
        demos,
        fused,
        coms,
        precision,
    })
}

/// `I_e/(m l_p)` \[m\] of the true box about its true edge: homogeneous box inertia about the
/// CoM, parallel-axis to the edge (the sim's boxes are homogeneous apart from the CoM offset).
fn true_inertia_ratio(t: &Truth) -> f64 {
    let (Some(e), d) = (t.edge, t.box_dims) else {
        return f64::NAN;
    };
    let u = v(e.direction);
    let com = v(t.com);
    let r = (com - v(e.point)) - u * u.dot(&(com - v(e.point)));
    let l_p = r.norm();
    // Inertia of the box about an axis through the CoM along u, in the box frame: the edge is
    // parallel to one box axis, so use the two other dimensions.
    let btt = v(d);
    let q = &t.box_from_tag;
    let rot = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
        q.quaternion[3],
        q.quaternion[0],
        q.quaternion[1],
        q.quaternion[2],
    ));
    let u_box = rot * u;
    let i_c = (0..3)
        .map(|k| {
            let (a, b) = (btt[(k + 1) % 3], btt[(k + 2) % 3]);
            u_box[k].powi(2) * (a * a + b * b) / 12.0
        })
        .sum::<f64>();
    (i_c + l_p * l_p) / l_p
}

fn median(mut v: Vec<f64>) -> f64 {
    objmodel::stats::median(&mut v).unwrap_or(f64::NAN)
}

fn max(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::NAN, f64::max)
}

impl Evaluation {
    /// The tables as Markdown.
    pub fn markdown(&self) -> String {
        let mut s = String::from("### Classification accuracy (correct / demos)\n\n| scene | clean | real | noisy |\n|---|---|---|---|\n");
        let noises = ["clean", "real", "noisy"];
        for scene in ["topple", "instrumented", "slide", "general", "compound"] {
            s += &format!("| {scene} |");
            for n in noises {
                let d: Vec<&DemoResult> = self
                    .demos
                    .iter()
                    .filter(|d| d.scene == scene && d.noise == n)
                    .collect();
                let ok = d.iter().filter(|d| d.correct).count();
                s += &format!(" {ok}/{} |", d.len());
            }
            s += "\n";
        }
        s += "\nA compound demonstration (a slide that turns into a topple) counts as correct when a topple about its true edge is found (direction within 5°, position within 10 mm).\n\n";
        s += "### Edge errors per demonstration (median / max)\n\n| scene | noise | demos | direction [deg] | position [mm] |\n|---|---|---|---|---|\n";
        for scene in ["topple", "instrumented", "compound"] {
            for n in noises {
                let d: Vec<&DemoResult> = self
                    .demos
                    .iter()
                    .filter(|d| d.scene == scene && d.noise == n && d.edge_direction_deg.is_some())
                    .collect();
                let dir: Vec<f64> = d.iter().filter_map(|d| d.edge_direction_deg).collect();
                let pos: Vec<f64> = d.iter().filter_map(|d| d.edge_position_mm).collect();
                s += &format!(
                    "| {scene} | {n} | {} | {:.3} / {:.3} | {:.2} / {:.2} |\n",
                    d.len(),
                    median(dir.clone()),
                    max(&dir),
                    median(pos.clone()),
                    max(&pos)
                );
            }
        }
        s += "\n### Edges after fusing all topples of a box (median / max over edges)\n\nEach true edge toppled about, against the edge its topples taught; an edge held back as too loosely located to be taught is counted in the last column, not in the errors.\n\n| noise | edges | demos per edge | direction [deg] | position [mm] | held back |\n|---|---|---|---|---|---|\n";
        for n in noises {
            let all = self.fused.iter().filter(|f| f.noise == n);
            let held = all.clone().filter(|f| f.held_back).count();
            let f: Vec<&FusedResult> = all.filter(|f| !f.held_back).collect();
            let dir: Vec<f64> = f.iter().map(|f| f.direction_deg).collect();
            let pos: Vec<f64> = f.iter().map(|f| f.position_mm).collect();
            let sup: Vec<f64> = f.iter().map(|f| f.support as f64).collect();
            s += &format!(
                "| {n} | {} | {:.1} | {:.3} / {:.3} | {:.2} / {:.2} | {held} |\n",
                f.len(),
                median(sup),
                median(dir.clone()),
                max(&dir),
                median(pos.clone()),
                max(&pos)
            );
        }
        s += "\n### φ (CoM angle over the edge) errors, degrees (median |error| / max |error|)\n\n| scene | noise | demos | φ: palm tilt at onset | φ: pendulum on the palm | φ: the fall alone | φ: combined (in the tree) | onset time error [s] |\n|---|---|---|---|---|---|---|---|\n";
        for scene in ["instrumented", "topple"] {
            for n in noises {
                let d: Vec<&DemoResult> = self
                    .demos
                    .iter()
                    .filter(|d| d.scene == scene && d.noise == n)
                    .collect();
                let a: Vec<f64> = d
                    .iter()
                    .filter_map(|d| d.phi_onset_deg.map(f64::abs))
                    .collect();
                let b: Vec<f64> = d
                    .iter()
                    .filter_map(|d| d.phi_fall_deg.map(f64::abs))
                    .collect();
                let sp: Vec<f64> = d
                    .iter()
                    .filter_map(|d| d.phi_support_deg.map(f64::abs))
                    .collect();
                let cb: Vec<f64> = d.iter().filter_map(|d| d.phi_deg.map(f64::abs)).collect();
                let o: Vec<f64> = d.iter().filter_map(|d| d.onset_s.map(f64::abs)).collect();
                let cell = |v: &[f64], p: usize| {
                    if v.is_empty() {
                        "-".to_string()
                    } else {
                        format!(
                            "{:.prec$} / {:.prec$} ({})",
                            median(v.to_vec()),
                            max(v),
                            v.len(),
                            prec = p
                        )
                    }
                };
                s += &format!(
                    "| {scene} | {n} | {} | {} | {} | {} | {} | {} |\n",
                    d.len(),
                    cell(&a, 2),
                    cell(&sp, 2),
                    cell(&b, 2),
                    cell(&cb, 2),
                    cell(&o, 3)
                );
            }
        }
        s += "\n### Centre of mass from the pendulums of all topples of a box\n\n| box | noise | pendulums | CoM error [mm] |\n|---|---|---|---|\n";
        for c in &self.coms {
            s += &format!(
                "| {} | {} | {} | {:.1} |\n",
                c.r#box, c.noise, c.pendulums, c.error_mm
            );
        }
        s += "\n### Face normal errors of slides, in slide and compound scenes (median / max)\n\n| noise | demos | normal [deg] |\n|---|---|---|\n";
        for n in noises {
            let d: Vec<f64> = self
                .demos
                .iter()
                .filter(|d| d.noise == n)
                .filter_map(|d| d.face_normal_deg)
                .collect();
            s += &format!(
                "| {n} | {} | {:.3} / {:.3} |\n",
                d.len(),
                median(d.clone()),
                max(&d)
            );
        }
        s += "\n";
        s += &crate::eval_precision::markdown(
            &self.precision,
            &[
                "topple",
                "instrumented",
                "slide",
                "general",
                "compound",
                "topple_slide",
                "toss",
                "session",
            ],
        );
        s
    }
}
