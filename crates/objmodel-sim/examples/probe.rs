//! Run every scene once for a box and print the key truth numbers (a quick look, not a test).
//!
//! `cargo run -p objmodel-sim --example probe -- [seed]`
use objmodel_sim::dataset::standard_boxes;
use objmodel_sim::{simulate_clean, SceneKind, SimOptions};
use std::time::Instant;

fn main() {
    let seed: u64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    for b in standard_boxes() {
        for kind in SceneKind::ALL {
            let t0 = Instant::now();
            match simulate_clean(kind, &b, seed, &SimOptions::default()) {
                Ok(d) => {
                    let t = &d.truth;
                    println!(
                        "{:9} {:12} dur {:5.2}s wall {:5.2}s phi {:6.2} start {:6.3} palm {:6.2} pivot_end {:?} left {:?} slip {:.2e} segs {}",
                        b.name,
                        kind.name(),
                        t.duration,
                        t0.elapsed().as_secs_f64(),
                        t.phi_deg.unwrap_or(f64::NAN),
                        t.topple_start.unwrap_or(f64::NAN),
                        t.palm_tilt_at_start_deg.unwrap_or(f64::NAN),
                        t.pivot_end,
                        t.left_edge,
                        t.pivot_slip.unwrap_or(f64::NAN),
                        t.segments.iter().map(|s| format!("{}[{:.2},{:.2}]", s.label, s.t0, s.t1)).collect::<Vec<_>>().join(" ")
                    );
                }
                Err(e) => println!("{:9} {:12} ERROR {e}", b.name, kind.name()),
            }
        }
    }
}
