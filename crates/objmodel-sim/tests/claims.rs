//! Issue 19's claim on the standard data set (all demonstrations of each box at realistic
//! noise learnt together; docs/model-claims.md): every box gets a closed model, its CoM and its
//! corners within 3 mm, and, put on a tilting palm, it starts to topple within 1° of the true
//! box wherever the claim is made (a face the box rests on without sliding, tilted towards each
//! edge), in rapier and in MuJoCo. The experiment itself is checked too: the true box starts to
//! topple within half a degree of its quasi-static angle, in rapier and in MuJoCo, and the two
//! simulators agree on the learnt body within half a degree; and where the learnt φ misses,
//! the model's own σ for it covers the miss.

use objmodel_sim::claims::{learn_boxes, measure_box, table, DemoSet, POSITION_M};
use objmodel_sim::onset::Onset;

/// The Python with MuJoCo (`OBJMODEL_PYTHON`, else `python3`), or None (a failure when
/// `OBJMODEL_REQUIRE_MUJOCO` is set).
fn python_with_mujoco() -> Option<String> {
    let python = std::env::var("OBJMODEL_PYTHON").unwrap_or_else(|_| "python3".into());
    let ok = std::process::Command::new(&python)
        .args(["-c", "import mujoco"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !ok && std::env::var_os("OBJMODEL_REQUIRE_MUJOCO").is_some() {
        panic!("{python} cannot import mujoco, and OBJMODEL_REQUIRE_MUJOCO is set");
    }
    ok.then_some(python)
}

#[test]
fn learnt_models_of_the_standard_boxes_meet_the_claims() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    let plan = objmodel_sim::standard_dataset(false);
    objmodel_sim::write_dataset(&data, &plan, &mut |_| {}).unwrap();
    let python = python_with_mujoco();
    if python.is_none() {
        eprintln!("no Python with mujoco: MuJoCo not run (set OBJMODEL_PYTHON)");
    }
    let work = dir.path().join("work");
    for (spec, tree, demos) in learn_boxes(&data, "real", DemoSet::All).unwrap() {
        let c = measure_box(&spec, &tree, demos, python.as_deref(), &work).unwrap();
        eprintln!(
            "{}: corners {:.2} mm, CoM {:.2} mm",
            c.name,
            c.corner_error_m * 1e3,
            c.com_error_m * 1e3
        );
        assert!(c.error.is_none(), "{}: {:?}", c.name, c.error);
        assert!(c.com_error_m <= POSITION_M, "{}", c.name);
        assert!(c.corner_error_m <= POSITION_M, "{}", c.name);
        for o in table::claimed(&c) {
            let mut pairs = vec![("rapier", &o.rapier)];
            pairs.extend(o.mujoco.as_ref().map(|m| ("MuJoCo", m)));
            for (sim, pair) in pairs {
                assert!(
                    objmodel_sim::claims::onset_claim(pair),
                    "{} on {} towards {} in {sim}: true {:?}, learnt {:?}",
                    c.name,
                    o.face,
                    o.toward,
                    pair[0],
                    pair[1]
                );
            }
        }
        // Where the learnt φ misses the true one, the model says so: its own σ (from the shape
        // and the CoM's covariance) covers the miss within 3σ, for every pair where the true
        // box topples.
        let mut with_sigma = 0;
        for o in c
            .onsets
            .iter()
            .filter(|o| matches!(o.rapier[0], Onset::Topples(_)))
        {
            let Some(s) = o.phi_sigma_deg else { continue };
            with_sigma += 1;
            let miss = o.phi_deg[1] - o.phi_deg[0];
            assert!(
                miss.abs() <= 3.0 * s,
                "{} {} towards {}: learnt φ {:.2}° is {miss:+.2}° off, beyond 3 × its σ {s:.2}°",
                c.name,
                o.face,
                o.toward,
                o.phi_deg[1]
            );
        }
        assert!(with_sigma > 0, "{}: no predicted φ with a σ", c.name);
        // The true box tips at its quasi-static angle in both simulators, where it can tip
        // before it slides (where `tan φ > μ` it slides, and a simulator may register the
        // slide's first rotation as a topple at the friction angle: MuJoCo did, at 49.8° for
        // the weighted box's 54.0°).
        for o in c.onsets.iter().filter(|o| !o.slides_first) {
            let phi = o.phi_deg[0].to_radians();
            let mut pairs = vec![("rapier", o.rapier)];
            pairs.extend(o.mujoco.map(|m| ("MuJoCo", m)));
            for (sim, pair) in &pairs {
                if let Onset::Topples(t) = pair[0] {
                    assert!(
                        (t - phi).abs() < 0.5f64.to_radians(),
                        "{} {} towards {} in {sim}: true box at {t} rad, quasi-static {phi}",
                        c.name,
                        o.face,
                        o.toward
                    );
                }
            }
            // The learnt body tips alike in both simulators, except within 1° of the friction
            // angle, where which of a slide and a topple comes first, and when, is the contact
            // model's (the rows the claims leave undecided, `table::claimed`).
            if let (Some(m), [_, Onset::Topples(r)], false) =
                (o.mujoco, o.rapier, o.at_friction_limit)
            {
                if let Onset::Topples(t) = m[1] {
                    assert!((t - r).abs() < 0.5f64.to_radians(), "{} {}", c.name, o.face);
                }
            }
        }
    }
}
