//! `objmodel calibrate`: are the learner's sigmas honest? Error / sigma of every learnt
//! quantity against a simulated dataset's ground truth.

use crate::opts::ClassifyOpts;
use anyhow::{Context, Result};
use std::path::PathBuf;

/// Arguments of `objmodel calibrate`.
#[derive(clap::Args)]
pub struct CalibrateArgs {
    /// Dataset folder (written by `objmodel dataset`, with manifest.json).
    pub data: PathBuf,
    /// Print every sample (quantity, set, noise, demonstration or box, error, error/sigma) as
    /// JSON instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Also write the table (Markdown) to this file, after its hand-written header.
    #[arg(long)]
    pub markdown: Option<PathBuf>,
    #[command(flatten)]
    pub opts: ClassifyOpts,
}

/// Run `objmodel calibrate`.
pub fn run(a: &CalibrateArgs) -> Result<()> {
    let config = a.opts.config()?;
    let samples = objmodel_sim::calibration::samples(&a.data, &config)
        .with_context(|| format!("calibrating on {}", a.data.display()))?;
    let md = objmodel_sim::calibration::markdown(&objmodel_sim::calibration::table(&samples));
    if let Some(p) = &a.markdown {
        crate::evaluate::write_page(p, &md)?;
    }
    if a.json {
        crate::output::out(&(serde_json::to_string_pretty(&samples)? + "\n"))
    } else {
        crate::output::out(&md)
    }
}
