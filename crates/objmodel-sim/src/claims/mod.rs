//! Issue 19's claim, measured on a simulated data set: each box's demonstrations at one noise
//! level learnt together, the model exported as URDF and MJCF, and the learnt object compared
//! with the true box: its corners, its centre of mass, and the palm tilt at which it starts to
//! topple ([`crate::onset`]) resting on each face of the true box and tilted towards each of
//! that face's four edges, in rapier (the URDF read back, [`crate::urdf_body`]) and in MuJoCo
//! (the MJCF, `tests/mujoco/tilt_onset.py`), each against the true box in the same simulator.
//!
//! The learnt body gets the true mass and friction: kinematics cannot tell them, and the claim
//! is about what the demonstrations teach (shape, CoM, inertia).

pub mod table;

use crate::dataset::Manifest;
use crate::onset::{onset, tipping_angle, Onset};
use crate::rigid::RigidModel;
use crate::spec::{BoxFace, BoxSpec};
use anyhow::{bail, Context, Result};
use nalgebra::{Matrix3, Point3, Vector3};
use objmodel::export::{box_fit, mjcf::mjcf, urdf::urdf, Body};
use objmodel::learn::{Config, Learner, Source};
use objmodel::shape::{reconstruct, LearntFace};
use objmodel::tree::Tree;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The claim's bound on the onset tilt error \[deg\].
pub const ONSET_DEG: f64 = 1.0;
/// The claim's bound on the corner and CoM errors \[m\].
pub const POSITION_M: f64 = 3e-3;
/// How far past the later quasi-static angle the palm tilts before giving up \[rad\] (4°).
pub const BEYOND_RAD: f64 = 0.069_813_170_079_773_18;

/// The learnt and the true box on the tilting palm, resting on one face, tilted one way.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct FaceOnset {
    /// The face of the true box it rests on, in box axes (`-z`, `+x`, ...).
    pub face: String,
    /// The box axis the tilt carries it towards.
    pub toward: String,
    /// Quasi-static tipping angles of the true and the learnt body \[deg\].
    pub phi_deg: [f64; 2],
    /// The model's own standard deviation of its φ for this (face, edge) pair \[deg\]: the
    /// tree's prediction's, propagated from the shape and the CoM's covariance (absent without
    /// a learnt CoM or a matching prediction).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub phi_sigma_deg: Option<f64>,
    /// Whether the true box slides before it tips (`tan φ > μ`): no claim there.
    pub slides_first: bool,
    /// Whether the true box tips before it slides by less than the claim's own tolerance:
    /// its φ within [`ONSET_DEG`] below the friction angle `atan μ`. A learnt φ within the
    /// claim can then slide where the true box tips (and which of the two a simulator
    /// registers first depends on its contact model), so the claim does not decide it.
    #[serde(default)]
    pub at_friction_limit: bool,
    /// Onsets in rapier: the true box, the learnt body (from its URDF).
    pub rapier: [Onset; 2],
    /// Onsets in MuJoCo (from the MJCF files), when MuJoCo was run.
    pub mujoco: Option<[Onset; 2]>,
}

/// `learnt − true` onset tilt \[deg\] when both toppled.
pub fn onset_error_deg(pair: &[Onset; 2]) -> Option<f64> {
    match pair {
        [Onset::Topples(t), Onset::Topples(l)] => Some((l - t).to_degrees()),
        _ => None,
    }
}

/// Whether the claim holds for a pair: where the true box topples, the learnt one does too,
/// within [`ONSET_DEG`].
pub fn onset_claim(pair: &[Onset; 2]) -> bool {
    match pair[0] {
        Onset::Topples(_) => onset_error_deg(pair).is_some_and(|d| d.abs() <= ONSET_DEG),
        _ => true,
    }
}

/// One box's measurements.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct BoxClaims {
    /// The box.
    pub name: String,
    /// Demonstrations learnt.
    pub demos: usize,
    /// Why no model could be built, if none could.
    pub error: Option<String>,
    /// What the shape assumes beyond the data (inferred faces).
    pub assumptions: Vec<String>,
    /// The learnt shape: "box", or "N faces" when it is not one.
    pub shape: String,
    /// Largest distance of a true corner from the nearest learnt one \[m\].
    pub corner_error_m: f64,
    /// Distance of the learnt CoM from the true one \[m\].
    pub com_error_m: f64,
    /// Whether the CoM came from the pendulums (else the shape's centroid).
    pub com_learnt: bool,
    /// The tilting-palm experiments.
    pub onsets: Vec<FaceOnset>,
}

/// The true box of `spec` as an export body, in the tag frame (for its MJCF).
pub fn truth_body(spec: &BoxSpec) -> Body {
    let tag_from_box = spec.tag_from_box();
    let centre = (tag_from_box * Point3::origin()).coords;
    let faces: Vec<LearntFace> = BoxFace::ALL
        .iter()
        .map(|f| {
            let n = tag_from_box.rotation * f.normal();
            LearntFace {
                id: face_name(*f),
                normal: n,
                outward: true,
                offset: Some(n.dot(&centre) + spec.half_extents()[f.axis_sign().0]),
                offset_sigma_m: 0.0,
                normal_sigma_rad: 0.0,
            }
        })
        .collect();
    let shape = reconstruct(&faces).expect("a box closes");
    let r = tag_from_box.rotation.to_rotation_matrix();
    Body {
        box_fit: box_fit(&shape),
        shape,
        mass_kg: spec.mass,
        com: (tag_from_box * spec.com_box()).coords,
        inertia: r.matrix()
            * Matrix3::from_diagonal(&spec.principal_inertia())
            * r.matrix().transpose(),
        friction: spec.friction,
        notes: vec![format!("the true box '{}' of the data set", spec.name)],
    }
}

fn face_name(f: BoxFace) -> String {
    let (k, s) = f.axis_sign();
    format!("{}{}", if s > 0.0 { '+' } else { '-' }, ['x', 'y', 'z'][k])
}

/// Which of a box's demonstrations [`learn_boxes`] learns.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DemoSet {
    /// All of them.
    All,
    /// Those that start with the box upright (none turned onto another face).
    Upright,
    /// Those without a tracked palm: the pushes, slides, carries and tosses, no instrumented
    /// topple.
    WithoutPalm,
}

impl DemoSet {
    /// Whether the set holds the demonstration `m`.
    pub fn holds(self, m: &crate::dataset::ManifestEntry) -> bool {
        match self {
            DemoSet::All => true,
            DemoSet::Upright => m.turned.is_none(),
            DemoSet::WithoutPalm => !m.instrumented,
        }
    }
}

/// The trees learnt from the data set in `dir`: per box, its demonstrations in `set` at
/// `noise`.
pub fn learn_boxes(dir: &Path, noise: &str, set: DemoSet) -> Result<Vec<(BoxSpec, Tree, usize)>> {
    let manifest: Manifest = serde_json::from_str(
        &std::fs::read_to_string(dir.join("manifest.json"))
            .with_context(|| format!("reading {}", dir.join("manifest.json").display()))?,
    )?;
    let learner = Learner::new(Config::default());
    let mut out = Vec::new();
    for spec in &manifest.boxes {
        let mut tree = Tree::default();
        let demos: Vec<_> = manifest
            .demos
            .iter()
            .filter(|m| m.r#box == spec.name && m.noise == noise)
            .filter(|m| set.holds(m))
            .collect();
        for m in &demos {
            let object = dir.join(&m.tum);
            let palm = m.palm.as_ref().map(|p| dir.join(p));
            // A demonstration the learner rejects teaches nothing; the others still count.
            let _ = learner.learn(
                &mut tree,
                &[Source::Files {
                    object: &object,
                    palm: palm.as_deref(),
                }],
            );
        }
        out.push((spec.clone(), tree, demos.len()));
    }
    Ok(out)
}

/// Measure one box: its learnt `tree` against `spec`, in rapier and, with `python` (a Python
/// with the `mujoco` package), in MuJoCo; `work` is a folder for the exported files.
pub fn measure_box(
    spec: &BoxSpec,
    tree: &Tree,
    demos: usize,
    python: Option<&str>,
    work: &Path,
) -> Result<BoxClaims> {
    let mut claims = BoxClaims {
        name: spec.name.clone(),
        demos,
        error: None,
        assumptions: vec![],
        shape: String::new(),
        corner_error_m: f64::NAN,
        com_error_m: f64::NAN,
        com_learnt: false,
        onsets: vec![],
    };
    let body = match Body::from_tree(tree, spec.mass, Some(spec.friction)) {
        Ok(b) => b,
        Err(e) => {
            claims.error = Some(e.to_string());
            return Ok(claims);
        }
    };
    claims.assumptions = body.shape.assumptions.clone();
    claims.shape = match body.box_fit {
        Some(_) => "box".into(),
        None => format!("{} faces", body.shape.faces.len()),
    };
    claims.com_learnt = body.notes.iter().any(|n| n.contains("learnt from"));
    std::fs::create_dir_all(work)?;
    // The learnt body as rapier sees it: its URDF, read back.
    let (u, mesh) = urdf(&body, &spec.name, &format!("{}.obj", spec.name));
    let urdf_path = work.join(format!("{}.urdf", spec.name));
    std::fs::write(&urdf_path, u)?;
    if let Some(m) = mesh {
        std::fs::write(work.join(format!("{}.obj", spec.name)), m)?;
    }
    let learnt = crate::urdf_body::read(&urdf_path, spec.friction)?;
    let truth_b = truth_body(spec);
    let truth = RigidModel::of_body(&truth_b);
    let learnt_corners = learnt.corners();
    claims.corner_error_m = truth
        .corners()
        .iter()
        .map(|c| {
            learnt_corners
                .iter()
                .map(|l| (l - c).norm())
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max);
    claims.com_error_m = (learnt.com - truth.com).norm();

    // The learnt body's faces as it collides: a box's own axes, else the shape's faces.
    let learnt_normals: Vec<Vector3<f64>> = match &learnt.geometry {
        crate::rigid::Geometry::Cuboid { body_from_box, .. } => (0..6)
            .map(|i| {
                body_from_box.rotation * Vector3::ith(i / 2, if i % 2 == 0 { 1.0 } else { -1.0 })
            })
            .collect(),
        crate::rigid::Geometry::Hull { .. } => body.shape.faces.iter().map(|f| f.normal).collect(),
    };
    let tag_from_box = spec.tag_from_box();
    let mut experiments = Vec::new();
    for f in BoxFace::ALL {
        let n = tag_from_box.rotation * f.normal();
        let n_l = learnt_normals
            .iter()
            .copied()
            .max_by(|a, b| a.dot(&n).total_cmp(&b.dot(&n)))
            .expect("a closed shape has faces");
        for toward in BoxFace::ALL {
            if toward.axis_sign().0 == f.axis_sign().0 {
                continue;
            }
            let e = tag_from_box.rotation * toward.normal();
            let phi_t = tipping_angle(&truth, &n, &e);
            let e_l = (e - n_l * n_l.dot(&e)).normalize();
            let phi_l = tipping_angle(&learnt, &n_l, &e_l);
            let (low, beyond) = (phi_t.min(phi_l), (phi_t - phi_l).abs() + BEYOND_RAD);
            let rapier = [
                onset(&truth, &n, &e, spec.friction, low, beyond),
                onset(&learnt, &n_l, &e_l, spec.friction, low, beyond),
            ];
            experiments.push((n, e, n_l, e_l, low, beyond));
            claims.onsets.push(FaceOnset {
                face: face_name(f),
                toward: face_name(toward),
                phi_deg: [phi_t.to_degrees(), phi_l.to_degrees()],
                phi_sigma_deg: predicted_sigma(tree, &n_l, &e_l).map(f64::to_degrees),
                slides_first: phi_t.tan() > spec.friction,
                at_friction_limit: phi_t.tan() <= spec.friction
                    && spec.friction.atan() - phi_t < ONSET_DEG.to_radians(),
                rapier,
                mujoco: None,
            });
        }
    }
    if let Some(python) = python {
        let truth_xml = work.join(format!("{}-truth.xml", spec.name));
        let learnt_xml = work.join(format!("{}.xml", spec.name));
        std::fs::write(&truth_xml, mjcf(&truth_b, &spec.name))?;
        std::fs::write(&learnt_xml, mjcf(&body, &spec.name))?;
        let learnt_model = RigidModel::of_body(&body);
        let v = |x: &Vector3<f64>| [x.x, x.y, x.z];
        let mut list = Vec::new();
        for (n, e, n_l, e_l, low, beyond) in &experiments {
            for (name, m, n, e) in [("truth", &truth, n, e), ("learnt", &learnt_model, n_l, e_l)] {
                list.push(serde_json::json!({
                    "model": name, "n": v(n), "e": v(e), "mu": spec.friction,
                    "phi": low, "beyond": beyond,
                    "corners": m.corners().iter().map(v).collect::<Vec<_>>(), "com": v(&m.com),
                }));
            }
        }
        let job = serde_json::json!({
            "models": {"truth": truth_xml, "learnt": learnt_xml},
            "experiments": list,
        });
        let job_path = work.join(format!("{}-tilt.json", spec.name));
        std::fs::write(&job_path, serde_json::to_string(&job)?)?;
        let out = std::process::Command::new(python)
            .arg(mujoco_script())
            .arg(&job_path)
            .output()
            .with_context(|| format!("running {python}"))?;
        if !out.status.success() {
            bail!(
                "MuJoCo's tilt experiment failed: {}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
        let results: Vec<Onset> = serde_json::from_slice::<Vec<MujocoOnset>>(&out.stdout)?
            .into_iter()
            .map(Onset::from)
            .collect();
        for (o, pair) in claims.onsets.iter_mut().zip(results.chunks(2)) {
            o.mujoco = Some([pair[0], pair[1]]);
        }
    }
    Ok(claims)
}

/// The standard deviation \[rad\] of the tree's predicted φ for resting on the face of
/// outward normal `n` and toppling towards the horizontal `toward`: the prediction whose
/// resting face is `n` (within 10°) and whose landing face is the one most nearly facing
/// `toward`.
fn predicted_sigma(tree: &Tree, n: &Vector3<f64>, toward: &Vector3<f64>) -> Option<f64> {
    let shape = tree.shape.as_ref()?;
    let normal = |id: &str| shape.faces.iter().find(|f| f.id == id).map(|f| f.normal);
    tree.predictions
        .iter()
        .filter(|p| p.resting_normal.dot(n) > 10f64.to_radians().cos())
        .filter_map(|p| Some((p, normal(&p.landing_face)?.dot(toward))))
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .filter(|(_, c)| *c > 0.9)
        .and_then(|(p, _)| p.phi_sigma)
}

/// The Python script that runs the experiment in MuJoCo.
pub fn mujoco_script() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/mujoco/tilt_onset.py")
}

#[derive(Deserialize)]
struct MujocoOnset {
    what: String,
    tilt_rad: Option<f64>,
}

impl From<MujocoOnset> for Onset {
    fn from(m: MujocoOnset) -> Onset {
        match (m.what.as_str(), m.tilt_rad) {
            ("topples", Some(t)) => Onset::Topples(t),
            ("slides", Some(t)) => Onset::Slides(t),
            _ => Onset::Neither,
        }
    }
}
