//! `objmodel dataset`: the standard simulated dataset (boxes x scenes x noise levels), with a
//! manifest.

use anyhow::{bail, Context, Result};
use objmodel_sim::dataset::{standard_dataset, with_tosses};
use objmodel_sim::noise::TrackerNoise;
use objmodel_sim::write_dataset;
use std::path::PathBuf;

/// Arguments of `objmodel dataset`.
#[derive(clap::Args, Debug)]
#[command(after_help = "\
Writes, for each standard box (one with an offset centre of mass) x each kind (topple,
instrumented, slide, general, compound) x each seed, the demo at three noise levels (clean,
real, noisy) — NAME.tum, NAME.palm.tum, NAME.truth.json — and OUT/manifest.json listing them.
Besides: topple-then-slide compounds, one long session per box and tosses (box thrown onto a
table), and motion-capture versions (noise 0.1-0.5 mm, 0.05-0.3 deg, 120-240 Hz) of the
instrumented topples, compounds, sessions and tosses. Every truth file lists the contact mode
of each interval (`modes`) and the box's faces and edges (`features`); see docs/dataset.md.")]
pub struct DatasetArgs {
    /// Output folder (created if needed).
    #[arg(short, long, default_value = "data")]
    pub output: PathBuf,
    /// A small set: 4 boxes, 1 seed and the original five kinds only (no compounds
    /// topple-then-slide, sessions or tosses unless --tosses).
    #[arg(long)]
    pub quick: bool,
    /// Tosses in all, spread over the boxes in turn, each also at motion-capture noise
    /// (default 15, none with --quick); e.g. `--tosses 500` for the toss benchmark.
    #[arg(long)]
    pub tosses: Option<usize>,
    /// Noise levels, comma-separated: `clean`, `real`, `noisy` (the default: all three),
    /// and `camera` (noise larger along the line of sight and correlated between frames, as
    /// a camera's is). The motion-capture versions are made
    /// whatever the levels.
    #[arg(long, value_delimiter = ',', default_values_t = TrackerNoise::PRESETS.map(String::from),
          value_parser = ["clean", "real", "noisy", "camera"])]
    pub noise: Vec<String>,
    /// Correlation of consecutive frames' noise (0 to below 1, first-order autoregressive) at
    /// every level asked for, in place of the level's own (0, or 0.5 for `camera`).
    #[arg(long, value_name = "RHO")]
    pub correlation: Option<f64>,
    /// How many times larger the noise is along the camera's line of sight and in tilts out
    /// of the image (1 to 10) at every level asked for, in place of the level's own (1, or 3
    /// for `camera`).
    #[arg(long, value_name = "K")]
    pub sight_ratio: Option<f64>,
    /// Worker threads (default: up to 2).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Print the manifest summary as JSON on stdout.
    #[arg(long)]
    pub json: bool,
}

/// Run `objmodel dataset`.
pub fn run(a: &DatasetArgs) -> Result<()> {
    let mut plan = standard_dataset(a.quick);
    if let Some(n) = a.tosses {
        plan = with_tosses(plan, n);
    }
    plan.noises = a
        .noise
        .iter()
        .map(|n| {
            let mut noise = TrackerNoise::preset(n).context("unknown noise level")?;
            noise.correlation = a.correlation.unwrap_or(noise.correlation);
            noise.sight_ratio = a.sight_ratio.unwrap_or(noise.sight_ratio);
            noise.validate().context("--correlation or --sight-ratio")?;
            Ok(noise)
        })
        .collect::<Result<_>>()?;
    if let Some(t) = a.threads {
        if t == 0 {
            bail!("--threads must be at least 1");
        }
        plan.threads = t;
    }
    let bar = crate::progress::bar(0);
    let mut progress = |p: &objmodel_sim::Progress| {
        bar.set_length(p.total as u64);
        bar.set_position(p.done as u64);
        bar.set_message(p.name.clone());
    };
    let manifest = write_dataset(&a.output, &plan, &mut progress)
        .with_context(|| format!("writing the data set into {}", a.output.display()))?;
    bar.finish_and_clear();
    if a.json {
        let v = serde_json::json!({
            "manifest": a.output.join("manifest.json"),
            "demos": manifest.demos.len(),
            "failures": manifest.failures,
            "seconds": manifest.seconds,
            "simulated_seconds": manifest.simulated_seconds,
        });
        println!("{}", serde_json::to_string_pretty(&v)?);
    } else {
        println!(
            "{} demos in {} ({:.0} s simulated in {:.1} s)",
            manifest.demos.len(),
            a.output.join("manifest.json").display(),
            manifest.simulated_seconds,
            manifest.seconds
        );
        for (cell, why) in &manifest.failures {
            println!("  not made: {cell}: {why}");
        }
    }
    Ok(())
}
