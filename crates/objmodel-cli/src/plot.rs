//! `objmodel plot`: a topple's tilt angles over time, its onset and φ (the paper's Fig. 8).

use crate::bag::{single_source, BagArgs};
use crate::opts::ClassifyOpts;
use crate::text::print_warnings;
use anyhow::{bail, Result};
use objmodel::learn::Learner;
use objmodel::observation::Observation;
use std::path::PathBuf;

/// Arguments of `objmodel plot`.
#[derive(clap::Args)]
pub struct PlotArgs {
    /// The demonstration (TUM or CSV; NAME.palm.tum beside it is its palm), or a ROS 2 bag
    /// (with --object).
    pub demo: PathBuf,
    /// The palm's trajectory, for an instrumented demonstration; for a bag, its topic or tf
    /// frame; for a Motive take (with --object), its rigid body.
    #[arg(long)]
    pub palm: Option<PathBuf>,
    /// Output folder for NAME.angles.svg and NAME.angles.png.
    #[arg(short, long, default_value = "plots")]
    pub output: PathBuf,
    #[command(flatten)]
    pub bag: BagArgs,
    #[command(flatten)]
    pub opts: ClassifyOpts,
}

/// Run `objmodel plot`: the paper's Fig. 8 for a demonstration.
pub fn run(a: &PlotArgs) -> Result<()> {
    let config = a.opts.config()?;
    let source = single_source(&a.demo, a.palm.as_deref(), false, &a.bag)?;
    let observations = Learner::new(config).observe_all(&source.source())?;
    let several = observations.len() > 1;
    let mut plotted = 0;
    for o in observations {
        let Observation {
            classification: c,
            dynamics,
            ..
        } = o;
        print_warnings(&a.demo, &c);
        if dynamics.is_empty() {
            if several {
                eprintln!("{}: no topple to plot (kind: {})", c.name, c.kind.as_str());
                continue;
            }
            bail!(
                "{}: no topple to plot (kind: {}), or gravity unknown",
                a.demo.display(),
                c.kind.as_str()
            );
        }
        plotted += 1;
        plot_one(a, &c, &dynamics)?;
    }
    if plotted == 0 {
        bail!(
            "{}: no topple to plot, or gravity unknown",
            a.demo.display()
        );
    }
    Ok(())
}

/// Plot the topples of one demonstration.
fn plot_one(
    a: &PlotArgs,
    c: &objmodel::classify::Classification,
    dynamics: &[objmodel::dynamics::ToppleDynamics],
) -> Result<()> {
    for (i, d) in dynamics.iter().enumerate() {
        let stem = c
            .name
            .trim_end_matches(".tum")
            .trim_end_matches(".csv")
            .replace(".mcap#", "_");
        let stem = stem.trim_end_matches(".mcap");
        let path = a.output.join(if dynamics.len() > 1 {
            format!("{stem}.topple{i}.angles")
        } else {
            format!("{stem}.angles")
        });
        let (svg, png) = objmodel_plot::plot_angles(&fig8(&c.name, d), &path)
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        crate::output::out(&format!("{}\n{}\n", svg.display(), png.display()))?;
        if let Some(phi) = d.phi {
            let onset = d.onset.map_or(String::new(), |o| {
                format!(", onset at {:.3} s", o.t - d.series.t[0])
            });
            crate::output::out(&format!(
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
