//! The pendulum fitted to a topple's fall: from the onset (instrumented) or from the earliest
//! start consistent with a free pendulum (direct: before it, the pusher drives the object), to
//! the last pivot frame; its φ's σ as the data show it.

use super::budget::Budget;
use super::series::AngleSeries;
use super::{passes_with, PENDULUM_TOLERANCE_RAD};
use crate::pendulum::{self, FallFit, Onset};

/// The fall's fit over `series` up to `last_pivot`: from `onset` when there is one (starting
/// the search at `phi_onset`), else scanning the start back towards `first_pivot`; `None` when
/// no window passes its χ² test. `sigma` is the rotation noise.
pub(super) fn fit(
    series: &AngleSeries,
    first_pivot: usize,
    last_pivot: usize,
    onset: Option<Onset>,
    phi_onset: Option<f64>,
    sigma: f64,
    budget: &Budget,
) -> Option<FallFit> {
    let sigma_fit = (sigma * sigma + PENDULUM_TOLERANCE_RAD * PENDULUM_TOLERANCE_RAD).sqrt();
    let fit_from = |k0: usize, phi0: f64| {
        pendulum::fit_fall(
            &series.t[k0..=last_pivot],
            &series.object[k0..=last_pivot],
            sigma_fit,
            phi0,
        )
    };
    // A fall that is not a free pendulum within the noise teaches no φ.
    let passes = |f: &FallFit| passes_with(f, 4);
    let fall = match onset {
        Some(o) => {
            let k0 = series.t.partition_point(|&t| t < o.t);
            (k0 + 6 <= last_pivot)
                .then(|| fit_from(k0, phi_onset.unwrap_or(series.object[k0])))
                .flatten()
                .filter(passes)
        }
        None => {
            // Scanning the start back from the end of the pivot: the earliest start whose fit
            // passes the χ² test and lies past that fit's own balance point (ψ >= φ). Before
            // balance a pusher may still be driving the object at a steady rate, and a free
            // pendulum fitted through those frames lowers φ (by 0.6° on exact rapier pushes,
            // 3° at 1 mm / 0.5° noise; in MuJoCo 19 of 20 low); past it the object falls away
            // from the pusher. (docs/calibration.md: what this leaves.)
            let mut best = None;
            let mut k0 = last_pivot.saturating_sub(6);
            while k0 >= first_pivot && k0 + 6 <= last_pivot {
                match fit_from(k0, series.object[k0]) {
                    Some(f) if passes(&f) && best.is_some() && series.object[k0] < f.phi => break,
                    Some(f) if passes(&f) => best = Some(f),
                    _ if best.is_some() => break,
                    _ => {}
                }
                if k0 == 0 {
                    break;
                }
                k0 -= 1;
            }
            best
        }
    };
    // Its φ's sigma as the data show it (the jackknife; see `pendulum::jackknife`), and the
    // resting normal's error that is common to every sample (see `budget`).
    fall.map(|f| {
        let k0 = series.t.partition_point(|&t| t < f.t_start);
        let mut f = pendulum::jackknife_fall(
            &series.t[k0..=last_pivot],
            &series.object[k0..=last_pivot],
            f,
        );
        f.phi_sigma = (f.phi_sigma.powi(2) + budget.resting_normal()).sqrt();
        f
    })
}
