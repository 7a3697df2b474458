//! Demonstrations of two different objects learnt into one tree are caught by the consistency
//! checks (issue 19, item 8), and one object's own demonstrations raise none.

use objmodel::classify::Config;
use objmodel::learn::{Learner, Source};
use objmodel::synth::{self, SynthBox, SynthNoise};
use objmodel::tree::Tree;
use rand::rngs::StdRng;
use rand::SeedableRng;

fn learn(tree: &mut Tree, b: &SynthBox, tag: &str, seed: u64) {
    let learner = Learner::new(Config::default());
    for mut d in synth::topples_over_every_face(b, &SynthNoise::REAL, seed) {
        d.demo.name = format!("{tag}-{}", d.demo.name);
        learner.learn(tree, &[Source::Memory(&d.demo)]).unwrap();
    }
}

#[test]
fn two_boxes_in_one_tree_contradict_each_other() {
    let mut caught = 0;
    for seed in 1..=4u64 {
        let a = SynthBox::random(&mut StdRng::seed_from_u64(100 + seed));
        let b = SynthBox::random(&mut StdRng::seed_from_u64(200 + seed));
        for (b, name) in [(&a, "a"), (&b, "b")] {
            let mut alone = Tree::default();
            learn(&mut alone, b, name, seed);
            assert!(
                alone.contradictions.is_empty(),
                "box {name} (seed {seed}) alone: {:?}",
                alone.contradictions
            );
        }
        let mut both = Tree::default();
        learn(&mut both, &a, "a", seed);
        learn(&mut both, &b, "b", seed);
        if !both.contradictions.is_empty() {
            caught += 1;
        }
    }
    assert_eq!(caught, 4, "two boxes fused without a contradiction");
}
