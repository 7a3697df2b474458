//! `objmodel classify` and `objmodel learn`.

use crate::opts::ClassifyOpts;
use anyhow::{bail, Context, Result};
use objmodel::classify::{classify_files, Classification, Config, Kind, Label};
use objmodel::format::{is_palm_file, palm_path_for};
use objmodel::tree::Tree;
use std::path::{Path, PathBuf};

/// Arguments of `objmodel classify`.
#[derive(clap::Args)]
pub struct ClassifyArgs {
    /// The demonstration: a TUM (`t tx ty tz qx qy qz qw`) or CSV pose file of the object.
    /// A file NAME.palm.tum (or .palm.csv) beside NAME.tum is read as its palm.
    pub demo: PathBuf,
    /// The palm's (tool plate's) trajectory, for an instrumented demonstration.
    #[arg(long)]
    pub palm: Option<PathBuf>,
    /// Ignore a NAME.palm.tum file beside the demonstration.
    #[arg(long)]
    pub no_palm: bool,
    /// Print one JSON object (with "kind": "topple", "slide" or "general") instead of a summary.
    #[arg(long)]
    pub json: bool,
    /// Also print the per-frame labels (runs of frames with one label).
    #[arg(long)]
    pub frames: bool,
    #[command(flatten)]
    pub opts: ClassifyOpts,
}

/// Arguments of `objmodel learn`.
#[derive(clap::Args)]
pub struct LearnArgs {
    /// Demonstration files (TUM or CSV). NAME.palm.* files are taken as the palms of NAME.*.
    #[arg(required = true)]
    pub demos: Vec<PathBuf>,
    /// Write the tree to this file (atomically).
    #[arg(short, long, conflicts_with = "into")]
    pub output: Option<PathBuf>,
    /// Fuse the demonstrations into this existing tree file, and write it back (atomically).
    /// A missing file starts an empty tree.
    #[arg(long)]
    pub into: Option<PathBuf>,
    /// The palm trajectory, for a single instrumented demonstration.
    #[arg(long)]
    pub palm: Option<PathBuf>,
    /// Print the tree as JSON on standard output instead of a summary.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub opts: ClassifyOpts,
}

fn palm_for(demo: &Path, explicit: Option<&Path>, ignore: bool) -> Option<PathBuf> {
    match explicit {
        Some(p) => Some(p.to_path_buf()),
        None if ignore => None,
        None => palm_path_for(demo),
    }
}

fn v3(v: &nalgebra::Vector3<f64>) -> String {
    format!("[{:+.4}, {:+.4}, {:+.4}]", v.x, v.y, v.z)
}

fn summary(c: &Classification, frames: bool) -> String {
    let mut s = format!(
        "{}: {} ({} method{})\n  {} frames, {} rejected as tag flips; votes: topple {}, slide {}, general {}\n",
        c.name,
        c.kind.as_str(),
        match c.method {
            objmodel::classify::Method::Robust => "robust",
            objmodel::classify::Method::Paper => "paper",
        },
        if c.instrumented { ", relative to the palm" } else { "" },
        c.frames,
        c.outliers,
        c.votes.topple,
        c.votes.slide,
        c.votes.general
    );
    for w in &c.warnings {
        s += &format!("  warning: {w}\n");
    }
    if let Some(n) = c.noise {
        s += &format!(
            "  tracking noise (estimated): {:.2} mm, {:.2} deg per axis\n",
            n.sigma_position * 1e3,
            n.sigma_rotation.to_degrees()
        );
    }
    for (i, seg) in c.segments.iter().enumerate() {
        s += &format!(
            "  segment {i}: {:.2}-{:.2} s, {}, up to {:.1} deg\n",
            seg.t_start,
            seg.t_end,
            seg.kind.as_str(),
            seg.max_angle.to_degrees()
        );
        if let Some(e) = &seg.edge {
            s += &format!(
                "    edge: point {} m, direction {}, ±{:.2} mm, ±{:.2} deg ({} frames)\n",
                v3(&e.line.point),
                v3(&e.line.direction),
                e.sigma_point() * 1e3,
                e.sigma_direction().to_degrees(),
                e.frames
            );
        }
        if let Some(f) = &seg.face {
            s += &format!(
                "    face normal {}{}, ±{:.2} deg\n",
                v3(&f.normal),
                if f.sign_known {
                    " (outward)"
                } else {
                    " (sign unknown)"
                },
                f.sigma_normal().to_degrees()
            );
        }
    }
    if frames {
        s += "  frames:\n";
        for r in &c.labels {
            let label = match r.label {
                Label::Rest => "rest",
                Label::Outlier => "outlier",
                Label::Still => "still",
                Label::Topple => "topple",
                Label::Slide => "slide",
                Label::General => "general",
                Label::Landing => "landing",
                Label::Unlabelled => "unlabelled",
            };
            s += &format!(
                "    {:>6}-{:<6} {:>8.3}-{:<8.3} s  {label}\n",
                r.first, r.last, r.t_start, r.t_end
            );
        }
    }
    s
}

/// The classification's warnings about its input, on standard error, each with its file.
fn print_warnings(demo: &Path, c: &Classification) {
    for w in &c.warnings {
        eprintln!("warning: {}: {w}", demo.display());
    }
}

/// Run `objmodel classify`.
pub fn run_classify(a: &ClassifyArgs) -> Result<()> {
    let config = a.opts.config()?;
    let palm = palm_for(&a.demo, a.palm.as_deref(), a.no_palm);
    let c = classify_files(&a.demo, palm.as_deref(), &config)?;
    if a.json {
        print_warnings(&a.demo, &c);
        let mut v = serde_json::to_value(&c)?;
        v["file"] = serde_json::json!(a.demo.display().to_string());
        v["palm_file"] = serde_json::json!(palm.map(|p| p.display().to_string()));
        crate::out(&(serde_json::to_string_pretty(&v)? + "\n"))?;
    } else {
        crate::out(&summary(&c, a.frames))?;
    }
    Ok(())
}

/// Classify every demonstration file and fuse it into `tree`; returns the classifications.
pub fn learn_into(
    tree: &mut Tree,
    demos: &[PathBuf],
    palm: Option<&Path>,
    config: &Config,
) -> Result<Vec<Classification>> {
    let objects: Vec<&PathBuf> = demos.iter().filter(|d| !is_palm_file(d)).collect();
    if objects.is_empty() {
        bail!("no demonstration files (only palm files were given)");
    }
    if palm.is_some() && objects.len() > 1 {
        bail!(
            "--palm names the palm of a single demonstration, but {} were given",
            objects.len()
        );
    }
    let mut out = Vec::new();
    for d in objects {
        let p = palm_for(d, palm, false);
        let c = classify_files(d, p.as_deref(), config)?;
        print_warnings(d, &c);
        tree.add(&c);
        if let Some(dynamics) = dynamics_of(d, p.as_deref(), &c, config)? {
            tree.add_dynamics(&c, &dynamics);
        }
        out.push(c);
    }
    Ok(out)
}

/// Largest demonstration file [bytes] whose dynamics are analysed (this step holds the poses
/// in memory; the geometry is learnt streaming whatever the size).
pub const MAX_DYNAMICS_BYTES: u64 = 64 << 20;

/// The dynamics (pendulums) of a classified demonstration's topples, when gravity is known and
/// the file is small enough to hold in memory.
pub fn dynamics_of(
    demo: &Path,
    palm: Option<&Path>,
    c: &Classification,
    config: &Config,
) -> Result<Option<Vec<objmodel::dynamics::ToppleDynamics>>> {
    let Some(g) = config.gravity else {
        return Ok(None);
    };
    if c.topples.is_empty()
        || std::fs::metadata(demo).map_or(true, |m| m.len() > MAX_DYNAMICS_BYTES)
    {
        return Ok(None);
    }
    let d = objmodel::format::read_demonstration(demo, palm)?;
    Ok(Some(objmodel::dynamics::analyse(&d, c, &g)))
}

/// A short human summary of a tree.
pub fn tree_summary(tree: &Tree) -> String {
    let mut s = format!(
        "{} demonstrations, {} edges, {} faces (object frame)\n",
        tree.demos.len(),
        tree.edges.len(),
        tree.faces.len()
    );
    for e in &tree.edges {
        s += &format!(
            "  {}: point {} m, direction {}, ±{:.2} mm, ±{:.2} deg, {} demos\n",
            e.id,
            v3(&e.point),
            v3(&e.direction),
            e.sigma_point_m * 1e3,
            e.sigma_direction_rad.to_degrees(),
            e.n_support
        );
    }
    for e in &tree.edges {
        for p in &e.pendulums {
            s += &format!(
                "  {} pendulum, resting on {}: phi {} ±{:.2} deg, I/(m l_p) {}, {} demos\n",
                e.id,
                v3(&p.resting_face_normal),
                p.phi
                    .map_or("?".into(), |x| format!("{:.2}", x.to_degrees())),
                p.phi_sigma.unwrap_or(f64::NAN).to_degrees(),
                p.inertia_ratio_m
                    .map_or("?".into(), |x| format!("{:.3} m", x)),
                p.observations.len()
            );
        }
    }
    if let Some(com) = &tree.com {
        s += &format!(
            "  centre of mass: {} m (from {} pendulums, rms {:.1} mm)\n",
            v3(&com.point),
            com.pendulums,
            com.rms_residual_m * 1e3
        );
    }
    for f in &tree.faces {
        let off = f.offset.map_or("offset unknown".to_string(), |o| {
            format!(
                "offset {o:+.4} m ±{:.2} mm",
                f.offset_sigma_m.unwrap_or(0.0) * 1e3
            )
        });
        s += &format!(
            "  {}: normal {}, {off}, ±{:.2} deg, {} demos ({} slides, {} rests)\n",
            f.id,
            v3(&f.normal),
            f.sigma_normal_rad.to_degrees(),
            f.n_support,
            f.evidence.slide,
            f.evidence.rest
        );
    }
    s
}

/// Run `objmodel learn`.
pub fn run_learn(a: &LearnArgs) -> Result<()> {
    let config = a.opts.config()?;
    let mut tree = match &a.into {
        Some(p) if p.exists() => Tree::load(p)?,
        _ => Tree::default(),
    };
    let cs = learn_into(&mut tree, &a.demos, a.palm.as_deref(), &config)?;
    if let Some(out) = a.output.as_ref().or(a.into.as_ref()) {
        tree.save(out)
            .with_context(|| format!("writing {}", out.display()))?;
    }
    if a.json {
        crate::out(&(tree.to_json() + "\n"))?;
    } else {
        for c in &cs {
            let n_edges = c.edges().count();
            eprintln!(
                "{}: {}{}",
                c.name,
                c.kind.as_str(),
                if c.kind == Kind::Topple {
                    format!(" ({n_edges} topple(s))")
                } else {
                    String::new()
                }
            );
        }
        crate::out(&tree_summary(&tree))?;
        if let Some(out) = a.output.as_ref().or(a.into.as_ref()) {
            println!("wrote {}", out.display());
        }
    }
    Ok(())
}

/// Arguments of `objmodel evaluate`.
#[derive(clap::Args)]
pub struct EvaluateArgs {
    /// Dataset folder (written by `objmodel dataset`, with manifest.json).
    pub data: PathBuf,
    /// Print the per-demonstration results as JSON instead of the tables.
    #[arg(long)]
    pub json: bool,
    /// Also write the tables (Markdown) to this file.
    #[arg(long)]
    pub markdown: Option<PathBuf>,
    #[command(flatten)]
    pub opts: ClassifyOpts,
}

/// Run `objmodel evaluate`.
pub fn run_evaluate(a: &EvaluateArgs) -> Result<()> {
    let config = a.opts.config()?;
    let e = objmodel_sim::eval::evaluate(&a.data, &config)
        .with_context(|| format!("evaluating {}", a.data.display()))?;
    let md = e.markdown();
    if let Some(p) = &a.markdown {
        objmodel::format::write_atomic(p, md.as_bytes())?;
    }
    if a.json {
        crate::out(&(serde_json::to_string_pretty(&e)? + "\n"))
    } else {
        crate::out(&md)
    }
}

/// Arguments of `objmodel plot`.
#[derive(clap::Args)]
pub struct PlotArgs {
    /// The demonstration (TUM or CSV; NAME.palm.tum beside it is its palm).
    pub demo: PathBuf,
    /// The palm's trajectory, for an instrumented demonstration.
    #[arg(long)]
    pub palm: Option<PathBuf>,
    /// Output folder for NAME.angles.svg and NAME.angles.png.
    #[arg(short, long, default_value = "plots")]
    pub output: PathBuf,
    #[command(flatten)]
    pub opts: ClassifyOpts,
}

/// Run `objmodel plot`: the paper's Fig. 8 for a demonstration.
pub fn run_plot(a: &PlotArgs) -> Result<()> {
    let config = a.opts.config()?;
    let palm = palm_for(&a.demo, a.palm.as_deref(), false);
    let c = classify_files(&a.demo, palm.as_deref(), &config)?;
    let Some(dynamics) = dynamics_of(&a.demo, palm.as_deref(), &c, &config)? else {
        bail!(
            "{}: no topple to plot (kind: {}), or gravity unknown",
            a.demo.display(),
            c.kind.as_str()
        );
    };
    for (i, d) in dynamics.iter().enumerate() {
        let stem = c.name.trim_end_matches(".tum").trim_end_matches(".csv");
        let path = a.output.join(if dynamics.len() > 1 {
            format!("{stem}.topple{i}.angles")
        } else {
            format!("{stem}.angles")
        });
        let (svg, png) = objmodel_plot::plot_angles(&fig8(&c.name, d), &path)
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        crate::out(&format!("{}\n{}\n", svg.display(), png.display()))?;
        if let Some(phi) = d.phi {
            let onset = d.onset.map_or(String::new(), |o| {
                format!(", onset at {:.3} s", o.t - d.series.t[0])
            });
            crate::out(&format!(
                "  phi {:.2} deg ±{:.2}{onset}\n",
                phi.to_degrees(),
                d.phi_sigma.unwrap_or(f64::NAN).to_degrees()
            ))?;
        }
    }
    Ok(())
}

/// The Fig. 8 description of one topple's dynamics (times from the first frame).
pub fn fig8(name: &str, d: &objmodel::dynamics::ToppleDynamics) -> objmodel_plot::Fig8 {
    let t0 = d.series.t.first().copied().unwrap_or(0.0);
    let t: Vec<f64> = d.series.t.iter().map(|x| x - t0).collect();
    let mut series = vec![objmodel_plot::AngleSeries {
        label: "object tilt ψ about the edge".into(),
        t: t.clone(),
        angle_rad: d.series.object.clone(),
    }];
    let mut marks = Vec::new();
    if !d.series.palm.is_empty() {
        series.push(objmodel_plot::AngleSeries {
            label: "palm tilt".into(),
            t: t.clone(),
            angle_rad: d.series.palm.clone(),
        });
        let rel: Vec<f64> = d
            .series
            .object
            .iter()
            .zip(&d.series.palm)
            .map(|(a, b)| a - b)
            .collect();
        series.push(objmodel_plot::AngleSeries {
            label: "object relative to palm".into(),
            t,
            angle_rad: rel,
        });
        if let (Some(o), Some(p)) = (d.onset, d.phi_onset) {
            marks.push(("palm at onset".to_string(), o.t - t0, p));
        }
    }
    objmodel_plot::Fig8 {
        title: format!("{name}: tilt about the learnt edge"),
        series,
        onset_t: d.onset.map(|o| o.t - t0),
        phi_rad: d.phi,
        marks,
    }
}
