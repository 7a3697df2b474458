//! Time a scene's physics against its truth (contact modes):
//! `cargo run --release -p objmodel-sim --example modes_cost -- session`.
use objmodel_sim::dataset::standard_boxes;
use objmodel_sim::demo::{clean_demo, run_scene};
use objmodel_sim::{SceneKind, SimOptions};

fn main() {
    let kind =
        SceneKind::from_name(&std::env::args().nth(1).unwrap_or("session".into())).expect("a kind");
    let opts = SimOptions::default();
    let (mut sim, mut truth, mut secs) = (0.0, 0.0, 0.0);
    for spec in standard_boxes() {
        let t = std::time::Instant::now();
        let Ok(out) = run_scene(kind, &spec, 1, &opts) else {
            continue;
        };
        sim += t.elapsed().as_secs_f64();
        let t = std::time::Instant::now();
        let d = clean_demo(kind, &spec, 1, &out, &opts).expect("truth");
        truth += t.elapsed().as_secs_f64();
        secs += d.truth.duration;
    }
    println!(
        "{}: {secs:.0} s simulated; physics {sim:.2} s, truth {truth:.2} s",
        kind.name()
    );
}
