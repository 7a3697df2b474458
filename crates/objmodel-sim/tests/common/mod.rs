//! What several test files share: rapier tosses of a standard box.

use objmodel::noise::NoiseModel;
use objmodel::Demonstration;
use objmodel_sim::dataset::standard_boxes;
use objmodel_sim::demo::{clean_demo, run_scene};
use objmodel_sim::noise::TrackerNoise;
use objmodel_sim::truth::BoxFeatures;
use objmodel_sim::{SceneKind, SimOptions};
use rand::{rngs::StdRng, SeedableRng};

/// `n` tosses of the first standard box at one noise level (`"mocap"`: drawn motion-capture
/// noise at 240 Hz; otherwise the "real" camera preset at 30 Hz): the demonstrations, the box's
/// features, and the noise a user of the camera gives (a 30 Hz toss cannot measure it: its
/// first frames measure the motion, and its short rests are too short).
pub fn tosses(level: &str, n: u64) -> (Vec<Demonstration>, BoxFeatures, Option<NoiseModel>) {
    let spec = &standard_boxes()[0];
    let mut demos = Vec::new();
    let mut features = None;
    let mut given = None;
    for seed in 1..=n {
        let out = run_scene(SceneKind::Toss, spec, seed, &SimOptions::default()).expect("runs");
        let mut rng = StdRng::seed_from_u64(seed);
        let (noise, rate) = match level {
            "mocap" => (TrackerNoise::mocap_drawn(&mut rng), 240.0),
            _ => (TrackerNoise::real(), 30.0),
        };
        let opts = SimOptions {
            rate_hz: rate,
            ..SimOptions::default()
        };
        if level != "mocap" {
            given = Some(noise.sigma);
        }
        let clean = clean_demo(SceneKind::Toss, spec, seed, &out, &opts).expect("truth");
        let sim = clean.with_noise(&noise);
        features = Some(sim.truth.features.clone());
        demos.push(Demonstration {
            name: format!("toss_{level}_{seed}"),
            object: sim.object.clone(),
            palm: None,
        });
    }
    (demos, features.expect("at least one toss"), given)
}
