use objmodel::classify::{classify, Config};
use objmodel::synth::{self, SynthBox, SynthNoise, ToppleParams};
use rand::{rngs::StdRng, SeedableRng};
fn main() {
    let seed: u64 = std::env::args().nth(1).unwrap().parse().unwrap();
    let mut rng = StdRng::seed_from_u64(300 + seed);
    let b = SynthBox::random(&mut rng);
    let d = synth::topple(&b, &ToppleParams { side: (seed % 4) as usize, push_s: 60.0, ..Default::default() }, &SynthNoise::REAL, 30.0, seed);
    let c = classify(&d.demo, &Config::default()).unwrap();
    for r in &c.labels { println!("{:?} {:.2}-{:.2} {} seg {:?}", r.label, r.t_start, r.t_end, r.frames, r.segment); }
    for s in &c.segments { println!("seg {:.2}-{:.2} {:?} {:?} max {:.3}", s.t_start, s.t_end, s.kind, s.votes, s.max_angle); }
    println!("truth {:?}", d.truth.edge);
    for e in c.edges() { println!("edge {:?} frames {}", e.line, e.frames); }
}
