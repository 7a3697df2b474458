//! `objmodel classify`: is a demonstration a topple, a slide or a general motion, and why.

use crate::learn::palm_for;
use crate::opts::ClassifyOpts;
use anyhow::Result;
use objmodel::learn::{Learner, Source};
use std::path::PathBuf;

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

/// Run `objmodel classify`.
pub fn run(a: &ClassifyArgs) -> Result<()> {
    let config = a.opts.config()?;
    let palm = palm_for(&a.demo, a.palm.as_deref(), a.no_palm);
    let source = Source::Files {
        object: &a.demo,
        palm: palm.as_deref(),
    };
    let c = Learner::new(config).classify(&source)?;
    if c.segments.is_empty() {
        anyhow::bail!(
            "{}: {}",
            a.demo.display(),
            objmodel::learn::nothing_to_learn(&c)
        );
    }
    if a.json {
        crate::text::print_warnings(&a.demo, &c);
        let mut v = serde_json::to_value(&c)?;
        v["file"] = serde_json::json!(a.demo.display().to_string());
        v["palm_file"] = serde_json::json!(palm.map(|p| p.display().to_string()));
        crate::out(&(serde_json::to_string_pretty(&v)? + "\n"))?;
    } else {
        crate::out(&crate::text::classification(&c, a.frames))?;
    }
    Ok(())
}
