//! Slides on a tilting palm (`scenes::instrumented::run_slide`): the files of one, tracked at a
//! noise level, for `objmodel classify` / `learn`, and the true friction and slide tilt.
//!
//! ```text
//! cargo run --release -p objmodel-sim --example palm_slide -- OUT_DIR MU NOISE SEED
//! ```

use anyhow::Result;
use objmodel_sim::dataset::standard_boxes;
use objmodel_sim::demo::tracked;
use objmodel_sim::noise::TrackerNoise;
use objmodel_sim::scenes::instrumented::run_slide;
use objmodel_sim::SimOptions;
use rand::{rngs::StdRng, SeedableRng};
use std::path::PathBuf;

fn main() -> Result<()> {
    let mut args = std::env::args().skip(1);
    let out = PathBuf::from(args.next().expect("OUT_DIR"));
    let mu: f64 = args.next().expect("MU").parse()?;
    let noise = TrackerNoise::preset(&args.next().expect("NOISE")).expect("a noise preset");
    let seed: u64 = args.next().expect("SEED").parse()?;
    let spec = standard_boxes().remove((seed % 5) as usize);
    let opts = SimOptions::default();
    let mut rng = StdRng::seed_from_u64(seed);
    let scene = run_slide(&spec, mu, &opts.physics, &mut rng)?;
    let (object, palm) = tracked(&scene, &spec, opts.rate_hz);
    let object = noise.apply(&object, &mut rng);
    let palm = noise.apply(&palm, &mut rng);
    std::fs::create_dir_all(&out)?;
    let name = format!("{}_palmslide-mu{mu}_{}_s{seed}", spec.name, noise.name);
    objmodel::format::write_tum(&out.join(format!("{name}.tum")), &object, &name)?;
    objmodel::format::write_tum(&out.join(format!("{name}.palm.tum")), &palm, &name)?;
    let slide_tilt = scene
        .script
        .notes
        .iter()
        .find(|(k, _)| k == "slide_tilt")
        .map(|(_, v)| v.to_degrees());
    println!(
        "{name}: mu {mu}, atan(mu) {:.2} deg, slide tilt {:?} deg",
        mu.atan().to_degrees(),
        slide_tilt
    );
    Ok(())
}
