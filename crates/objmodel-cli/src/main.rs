//! `objmodel`: learn object description trees from pose demonstrations, and use them.
//!
//! A thin front end: argument parsing and printing. The work is done by the `objmodel`
//! library (learning) and `objmodel-sim` (simulation).

// The argument structs' doc comments are the command-line help (clap), read in a terminal:
// their units in brackets ("Window [s]") are text, not links to items.
#![allow(rustdoc::broken_intra_doc_links)]

mod bag;
mod calibrate;
mod classify;
mod dataset;
mod demo;
mod evaluate;
mod export;
mod learn;
mod opts;
mod output;
mod plan;
mod plot;
mod progress;
mod simulate;
mod synth;
mod task;
mod text;
mod view;

use clap::{Parser, Subcommand};
use output::out_bytes;
use std::process::ExitCode;

/// Learn models of objects (edges, faces, dynamics) from demonstrations in which they are
/// toppled, slid or moved, after Sanan, Bretan & Heck, IROS 2019.
#[derive(Parser)]
#[command(
    name = "objmodel",
    version,
    propagate_version = true,
    after_help = "Commands that classify (classify, learn, evaluate) take --gravity gx,gy,gz (the direction of gravity in the tracking frame; default 0,0,-1, i.e. z up) or --gravity none; see `objmodel classify --help` for every threshold."
)]
struct Cli {
    /// No progress bars (they are shown on standard error only when it is a terminal).
    #[arg(long, short, global = true)]
    quiet: bool,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Tell whether a demonstration is a topple, a slide or a general motion, and why.
    Classify(classify::ClassifyArgs),
    /// Learn (or update) an object description tree from demonstrations.
    Learn(learn::LearnArgs),
    /// Run the whole story on built-in data: demonstrations, learning, a report.
    Demo(demo::DemoArgs),
    /// Write synthetic (kinematic) demonstrations with ground truth.
    Synth(synth::SynthArgs),
    /// Simulate one demonstration with rapier physics (demo files plus ground truth).
    Simulate(simulate::SimulateArgs),
    /// Write the standard simulated dataset (boxes x kinds x noise levels, with a manifest).
    Dataset(dataset::DatasetArgs),
    /// Measure the learner on a simulated dataset against its ground truth.
    Evaluate(evaluate::EvaluateArgs),
    /// Check that the learner's sigmas are honest, against a simulated dataset's ground
    /// truth: error / sigma of every learnt quantity, per noise level.
    Calibrate(calibrate::CalibrateArgs),
    /// Plot a topple's tilt angles over time with the onset and φ (the paper's Fig. 8).
    Plot(plot::PlotArgs),
    /// Write the learnt object as a simulation model: MJCF (MuJoCo) and URDF, with its shape,
    /// centre of mass, inertia and the mass you give.
    Export(export::ExportArgs),
    /// Show a learnt tree in 3D: one offline HTML page (turn it with the mouse, hover for each
    /// feature's support and uncertainty, play demonstrations back), and the paper's Fig. 9a.
    View(view::ViewArgs),
    /// Plan a topple on the palm from a learnt tree: the tilt axis and angle.
    Plan(plan::PlanArgs),
    /// Run the toppling task on the simulated arm: default policy, one demonstration, planned topple.
    Task(task::TaskArgs),
    /// Print a shell completion script: `objmodel completions bash > ~/.local/share/bash-completion/completions/objmodel`.
    Completions {
        /// The shell.
        shell: clap_complete::Shell,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    progress::set_quiet(cli.quiet);
    let result = match &cli.command {
        Command::Classify(a) => classify::run(a),
        Command::Learn(a) => learn::run(a),
        Command::Demo(a) => demo::run(a),
        Command::Synth(a) => synth::run(a),
        Command::Simulate(a) => simulate::run(a),
        Command::Dataset(a) => dataset::run(a),
        Command::Evaluate(a) => evaluate::run(a),
        Command::Calibrate(a) => calibrate::run(a),
        Command::Plot(a) => plot::run(a),
        Command::Plan(a) => plan::run(a),
        Command::Export(a) => export::run(a),
        Command::View(a) => view::run(a),
        Command::Task(a) => task::run(a),
        Command::Completions { shell } => {
            use clap::CommandFactory;
            let mut out = Vec::new();
            clap_complete::generate(*shell, &mut Cli::command(), "objmodel", &mut out);
            out_bytes(&out)
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) if is_broken_pipe(&e) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("objmodel: error: {e:#}");
            ExitCode::from(2)
        }
    }
}

/// A reader of our output went away (`objmodel ... | head`): not an error.
fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}
