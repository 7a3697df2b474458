//! A camera tracker's noise is correlated from frame to frame (it filters its poses), and a
//! short demonstration holds few windows to measure that correlation on. Taking the noise as
//! independent wherever those few windows cannot prove the correlation makes every test too
//! strict: this palm topple (the standard camera set's, its tracker holding its pose for
//! 0.23 s once, so that its correlation of about 0.5 measured 3.96 standard errors above white
//! noise where the test asked 4.14) showed motion at rest on the palm, and taught an edge
//! 7.7 mm off at ±1.1 mm. The learner now tests with the long-run noise of the correlation
//! as measured, without a significance test (`learn::tracker_noise::correlated_noise`); with
//! the test put back, this fails.

mod common;

use common::{data, truth_edge};
use objmodel::learn::{Config, Learner, Source};

#[test]
fn a_correlation_few_windows_cannot_prove_still_widens_the_tests() {
    let name = "camera_held_instrumented";
    let (object, palm) = (
        data(&format!("{name}.tum")),
        data(&format!("{name}.palm.tum")),
    );
    let c = Learner::new(Config::default())
        .classify(&Source::Files {
            object: &object,
            palm: Some(&palm),
        })
        .unwrap();
    assert!(
        c.warnings
            .iter()
            .any(|w| w.contains("object's tracking noise") && w.contains("correlated")),
        "{:?}",
        c.warnings
    );
    let truth = truth_edge(name);
    let edges: Vec<_> = c.edges().collect();
    assert!(!edges.is_empty(), "{c:?}");
    for e in edges {
        let off = truth.distance_to(&e.line.point);
        let sigma = e.point_cov.symmetric_eigenvalues().max().sqrt();
        assert!(
            off < 3.0 * sigma,
            "edge {:.1} mm off the truth at ±{:.1} mm",
            off * 1e3,
            sigma * 1e3
        );
    }
}
