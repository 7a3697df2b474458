//! A tracker that filters its output (exponential smoothing, as many do) makes the noise
//! correlated from frame to frame; the noise estimate must still hold.

use objmodel::classify::{classify, Config};
use objmodel::synth::{self, SynthBox, SynthNoise, ToppleParams};
use rand::{rngs::StdRng, Rng, SeedableRng};
#[test]
fn filtered_tracker() {
    for (alpha, allowed) in [(1.0, 0), (0.6, 2)] {
        let mut wrong = vec![];
        for kind in 0..4 {
            for seed in 0..10u64 {
                let mut rng = StdRng::seed_from_u64(9000 + 100 * kind as u64 + seed);
                let b = SynthBox::random(&mut rng);
                let side = rng.random_range(0..4);
                let noise = SynthNoise {
                    tag_flip: 0.0,
                    sign_flip: 0.0,
                    drop: 0.0,
                    ..SynthNoise::REAL
                };
                let mut d = match kind {
                    0 => synth::topple(
                        &b,
                        &ToppleParams {
                            side,
                            ..Default::default()
                        },
                        &noise,
                        30.0,
                        seed,
                    ),
                    1 => synth::instrumented_topple(&b, side, 0.2, &noise, 30.0, seed),
                    2 => synth::slide(&b, &noise, 30.0, seed),
                    _ => synth::general(&b, &noise, 30.0, seed),
                };
                for traj in std::iter::once(&mut d.demo.object).chain(d.demo.palm.iter_mut()) {
                    for k in 1..traj.len() {
                        let prev = traj[k - 1].pose;
                        let cur = traj[k].pose;
                        traj[k].pose = prev.lerp_slerp(&cur, alpha);
                    }
                }
                let c = classify(&d.demo, &Config::default()).unwrap();
                if c.kind != d.truth.kind {
                    wrong.push((kind, seed, c.kind));
                }
            }
        }
        eprintln!("alpha {alpha}: {} wrong {:?}", wrong.len(), wrong);
        assert!(wrong.len() <= allowed, "smoothing {alpha}: {wrong:?}");
    }
}
