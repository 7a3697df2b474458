//! `objmodel classify`: is a demonstration a topple, a slide or a general motion, and why.

use crate::bag::{single_source, BagArgs, DemoSource};
use crate::opts::ClassifyOpts;
use anyhow::Result;
use objmodel::learn::Learner;
use std::path::PathBuf;

/// Arguments of `objmodel classify`.
#[derive(clap::Args)]
pub struct ClassifyArgs {
    /// The demonstration: a TUM (`t tx ty tz qx qy qz qw`) or CSV pose file of the object, or a
    /// ROS 2 bag (.mcap, or a bag folder; with --object).
    /// A file NAME.palm.tum (or .palm.csv) beside NAME.tum is read as its palm.
    pub demo: PathBuf,
    /// The palm's (tool plate's) trajectory, for an instrumented demonstration; for a bag,
    /// the palm's topic or tf frame; for a Motive take (with --object), its rigid body.
    #[arg(long)]
    pub palm: Option<PathBuf>,
    /// Ignore a NAME.palm.tum file beside the demonstration.
    #[arg(long)]
    pub no_palm: bool,
    /// Print one JSON object (with "kind": "topple", "slide" or "general") instead of a summary
    /// (a bag cut by --split: one JSON array of them).
    #[arg(long)]
    pub json: bool,
    /// Also print the per-frame labels (runs of frames with one label).
    #[arg(long)]
    pub frames: bool,
    #[command(flatten)]
    pub bag: BagArgs,
    #[command(flatten)]
    pub opts: ClassifyOpts,
}

/// Run `objmodel classify`.
pub fn run(a: &ClassifyArgs) -> Result<()> {
    let config = a.opts.config()?;
    let source = single_source(&a.demo, a.palm.as_deref(), a.no_palm, &a.bag)?;
    let palm = match &source {
        DemoSource::Files { palm, .. } => palm.clone(),
        DemoSource::Take { path, palm, .. } => palm.as_ref().map(|_| path.clone()),
        DemoSource::Bag { .. } => None,
    };
    let learner = Learner::new(config);
    let is_bag = matches!(source, DemoSource::Bag { .. });
    let all: Vec<_> = if is_bag {
        learner
            .observe_all(&source.source())?
            .into_iter()
            .map(|o| o.classification)
            .collect()
    } else {
        vec![learner.classify(&source.source())?]
    };
    let mut json = Vec::new();
    for c in &all {
        if c.segments.is_empty() && all.len() == 1 {
            anyhow::bail!(
                "{}: {}",
                a.demo.display(),
                objmodel::learn::nothing_to_learn(c)
            );
        }
        if a.json {
            crate::text::print_warnings(&a.demo, c);
            let mut v = serde_json::to_value(c)?;
            v["file"] = serde_json::json!(a.demo.display().to_string());
            v["palm_file"] = serde_json::json!(palm.as_ref().map(|p| p.display().to_string()));
            if let DemoSource::Take { object, palm, .. } = &source {
                v["rigid_bodies"] = serde_json::json!({ "object": object, "palm": palm });
            }
            if let DemoSource::Bag { selection, .. } = &source {
                v["bag"] = serde_json::json!({
                    "object": selection.object,
                    "palm": selection.palm,
                    "reference": selection.reference,
                });
            }
            json.push(v);
        } else {
            crate::output::out(&crate::text::classification(c, a.frames))?;
        }
    }
    if a.json {
        let v = if a.bag.split.is_some() {
            serde_json::Value::Array(json)
        } else {
            json.remove(0)
        };
        crate::output::out(&(serde_json::to_string_pretty(&v)? + "\n"))?;
    }
    Ok(())
}
