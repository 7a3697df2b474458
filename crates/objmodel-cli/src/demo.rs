//! `objmodel demo`: the main job on built-in data.

use crate::learn::{learn_into, tree_summary};
use crate::synth_cmd::{make, write_demo};
use anyhow::Result;
use objmodel::classify::Config;
use objmodel::synth::{SynthBox, SynthNoise};
use objmodel::tree::Tree;
use rand::{rngs::StdRng, SeedableRng};
use std::path::PathBuf;

/// Arguments of `objmodel demo`.
#[derive(clap::Args)]
pub struct DemoArgs {
    /// Report folder.
    #[arg(short, long, default_value = "report")]
    pub output: PathBuf,
    /// Random seed of the built-in data.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

/// Run `objmodel demo`.
pub fn run(a: &DemoArgs) -> Result<()> {
    let demos = a.output.join("demos");
    let b = SynthBox::random(&mut StdRng::seed_from_u64(a.seed));
    let mut files = Vec::new();
    for (i, (kind, side)) in [
        ("topple", 0),
        ("topple", 1),
        ("instrumented", 2),
        ("slide", 0),
        ("general", 0),
        ("topple", 0),
        ("topple", 1),
    ]
    .iter()
    .enumerate()
    {
        let d = make(kind, &b, *side, &SynthNoise::REAL, a.seed * 100 + i as u64);
        write_demo(&demos, &d)?;
        files.push(demos.join(format!("{}.tum", d.demo.name)));
    }
    println!(
        "wrote {} demonstrations of one box (kinematic generator, real tracking noise) to {}",
        files.len(),
        demos.display()
    );
    let mut tree = Tree::default();
    let cs = learn_into(&mut tree, &files, None, &Config::default())?;
    for c in &cs {
        println!("  {}: {}", c.name, c.kind.as_str());
    }
    let out = a.output.join("tree.json");
    tree.save(&out)?;
    crate::out(&tree_summary(&tree))?;
    println!("wrote {}", out.display());
    Ok(())
}
