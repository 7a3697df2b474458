//! Print the contact modes of one simulated scene:
//! `cargo run --release -p objmodel-sim --example modes -- toss tall 3`.

use objmodel_sim::dataset::standard_boxes;
use objmodel_sim::{simulate_clean, SceneKind, SimOptions};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let kind = SceneKind::from_name(args.get(1).map_or("toss", |s| s)).expect("a scene kind");
    let name = args.get(2).map_or("tall", |s| s);
    let seeds: Vec<u64> = match args.get(3) {
        Some(s) => s.split(',').map(|x| x.parse().expect("a seed")).collect(),
        None => vec![1],
    };
    let spec = standard_boxes()
        .into_iter()
        .find(|b| b.name == name)
        .expect("a standard box");
    for seed in seeds {
        let t0 = std::time::Instant::now();
        match simulate_clean(kind, &spec, seed, &SimOptions::default()) {
            Ok(d) => {
                println!(
                    "{} {} seed {seed}: {:.2} s simulated in {:.2} s, script {:?}",
                    kind.name(),
                    name,
                    d.truth.duration,
                    t0.elapsed().as_secs_f64(),
                    d.truth.script
                );
                for m in &d.truth.modes {
                    let feat = m
                        .face
                        .as_ref()
                        .map(|f| f.id.clone())
                        .or(m.edge.as_ref().map(|e| e.id.clone()))
                        .unwrap_or_default();
                    println!(
                        "  {:7.3} {:7.3} {:8} {:6} {:12} turn {:7.2} deg travel {:6.1} mm",
                        m.t0,
                        m.t1,
                        m.mode,
                        m.contact,
                        feat,
                        m.turn_deg,
                        m.travel * 1e3
                    );
                }
            }
            Err(e) => println!("{} {} seed {seed}: {e}", kind.name(), name),
        }
    }
}
