//! `objmodel synth`: kinematic demonstrations with ground truth.

use anyhow::{Context, Result};
use objmodel::format::write_tum;
use objmodel::synth::{self, SynthBox, SynthDemo, SynthNoise, ToppleParams};
use rand::{rngs::StdRng, SeedableRng};
use std::path::{Path, PathBuf};

/// Arguments of `objmodel synth`.
#[derive(clap::Args)]
pub struct SynthArgs {
    /// What to generate.
    #[arg(value_parser = ["topple", "instrumented", "slide", "straight-slide", "general"])]
    pub kind: String,
    /// Output folder.
    #[arg(short, long, default_value = "synth")]
    pub output: PathBuf,
    /// Number of demonstrations (of one random box).
    #[arg(short, long, default_value_t = 1)]
    pub count: u64,
    /// Random seed.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Tracking noise: `real` (1 mm, 0.5 deg, drops, sign and tag flips) or `clean`.
    #[arg(long, default_value = "real", value_parser = ["real", "clean"])]
    pub noise: String,
    /// Bottom edge to topple about (0..3).
    #[arg(long, default_value_t = 0)]
    pub side: usize,
}

/// Write a synthetic demonstration (object, palm, truth) into `dir`.
pub fn write_demo(dir: &Path, d: &SynthDemo) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let note = "synthetic demonstration (objmodel synth); world_from_object of the tag frame";
    write_tum(
        &dir.join(format!("{}.tum", d.demo.name)),
        &d.demo.object,
        note,
    )?;
    if let Some(p) = &d.demo.palm {
        write_tum(
            &dir.join(format!("{}.palm.tum", d.demo.name)),
            p,
            "palm (tool plate) trajectory, world_from_palm",
        )?;
    }
    let t = &d.truth;
    let truth = serde_json::json!({
        "kind": t.kind,
        "edge": t.edge.map(|e| serde_json::json!({"point": [e.point.x, e.point.y, e.point.z], "direction": [e.direction.x, e.direction.y, e.direction.z]})),
        "face": t.face.map(|(n, o)| serde_json::json!({"normal": [n.x, n.y, n.z], "offset": o})),
        "phi": t.phi,
    });
    objmodel::format::write_atomic(
        &dir.join(format!("{}.truth.json", d.demo.name)),
        serde_json::to_string_pretty(&truth)?.as_bytes(),
    )?;
    Ok(())
}

/// Generate one synthetic demonstration.
pub fn make(kind: &str, b: &SynthBox, side: usize, noise: &SynthNoise, seed: u64) -> SynthDemo {
    match kind {
        "topple" => synth::topple(
            b,
            &ToppleParams {
                side,
                ..Default::default()
            },
            noise,
            30.0,
            seed,
        ),
        "instrumented" => synth::instrumented_topple(b, side, 0.2, noise, 30.0, seed),
        "slide" => synth::slide(b, noise, 30.0, seed),
        "straight-slide" => synth::straight_slide(b, noise, 30.0, seed),
        _ => synth::general(b, noise, 30.0, seed),
    }
}

/// Run `objmodel synth`.
pub fn run(a: &SynthArgs) -> Result<()> {
    let noise = if a.noise == "clean" {
        SynthNoise::CLEAN
    } else {
        SynthNoise::REAL
    };
    let b = SynthBox::random(&mut StdRng::seed_from_u64(a.seed));
    for k in 0..a.count {
        let d = make(&a.kind, &b, a.side, &noise, a.seed * 1000 + k);
        write_demo(&a.output, &d)?;
        println!(
            "{}",
            a.output.join(format!("{}.tum", d.demo.name)).display()
        );
    }
    Ok(())
}
