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

/// Run `objmodel classify`.
pub fn run_classify(a: &ClassifyArgs) -> Result<()> {
    let config = a.opts.config()?;
    let palm = palm_for(&a.demo, a.palm.as_deref(), a.no_palm);
    let c = classify_files(&a.demo, palm.as_deref(), &config)?;
    if a.json {
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
        tree.add(&c);
        out.push(c);
    }
    Ok(out)
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
