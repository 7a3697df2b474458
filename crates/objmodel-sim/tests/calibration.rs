//! The learner's sigmas against the simulator's truth, on a small dataset: instrumented and
//! direct topples and slides of four boxes at the "real" tracker noise, each learnt alone.
//! The full table over the standard dataset is `objmodel calibrate` (docs/calibration.md).

use objmodel::classify::Config;
use objmodel_sim::calibration::{samples, table, Quantity};
use objmodel_sim::dataset::{standard_dataset, write_dataset};
use objmodel_sim::noise::TrackerNoise;
use objmodel_sim::SceneKind;

#[test]
fn errors_over_sigmas_are_those_of_honest_sigmas() {
    let dir = tempfile::tempdir().unwrap();
    let mut plan = standard_dataset(true);
    plan.kinds = vec![
        SceneKind::InstrumentedTopple,
        SceneKind::Topple,
        SceneKind::Slide,
    ];
    plan.noises = vec![TrackerNoise::real()];
    plan.seeds = vec![1, 2];
    plan.mocap_kinds.clear();
    plan.tosses = 0;
    write_dataset(dir.path(), &plan, &mut |_| {}).unwrap();
    let all = samples(dir.path(), &Config::default()).unwrap();
    let rows = table(&all);
    for q in [
        Quantity::Phi,
        Quantity::EdgePoint,
        Quantity::EdgeDirection,
        Quantity::FaceOffset,
    ] {
        let r = rows
            .iter()
            .find(|r| r.set == "demo" && r.quantity == q)
            .unwrap_or_else(|| panic!("no {} sample", q.as_str()));
        // An honest median is `honest_median_z`; with a dozen samples its estimate scatters
        // by about a third of it, and sigmas too small by half or too large by three times
        // fail.
        assert!(
            r.median_z > 0.3 * r.honest_median_z && r.median_z < 1.7 * r.honest_median_z,
            "{}: median |error|/sigma {:.2} over {} (honest {:.2})",
            q.as_str(),
            r.median_z,
            r.n,
            r.honest_median_z
        );
        assert!(
            r.max_z < 5.0,
            "{}: {:.1} sigma at {}",
            q.as_str(),
            r.max_z,
            r.worst
        );
    }
    // A face normal's σ holds the support's level (1°) as a prior: the simulator's table is
    // level, so the σ is larger than its errors, by design; it must still cover them.
    for q in [Quantity::FaceNormal, Quantity::RestFaceNormal] {
        let r = rows
            .iter()
            .find(|r| r.set == "demo" && r.quantity == q)
            .unwrap_or_else(|| panic!("no {} sample", q.as_str()));
        assert!(
            r.median_z < 1.7 * r.honest_median_z && r.max_z < 5.0,
            "{}: median {:.2}, max {:.1}",
            q.as_str(),
            r.median_z,
            r.max_z
        );
    }
}
