//! The classification settings from Python arguments: `gravity` and the command line's
//! threshold options as keyword arguments (`alpha=1e-3`, `min_rest=1.0`, ...).

use crate::error::err;
use nalgebra::Vector3;
use objmodel::classify::{Config, Method};
use objmodel::noise::NoiseModel;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The numeric keyword arguments accepted besides `gravity`, `method` and `length_unit` (the
/// positions' unit, `"m"`, `"cm"` or `"mm"`): the command line's options of the same names
/// (`objmodel classify --help`).
pub const OPTIONS: [&str; 16] = [
    "alpha",
    "outlier_alpha",
    "rest_window",
    "min_rest",
    "noise_position",
    "noise_rotation",
    "palm_noise_position",
    "palm_noise_rotation",
    "edge_tolerance",
    "edge_tolerance_angle",
    "contact_depth",
    "max_axis_tilt",
    "r_palm",
    "pitch_threshold",
    "axis_angle_threshold",
    "normal_angle_threshold",
];

/// A 3-vector from any sequence of three finite numbers; `what` names it in errors.
pub fn vec3(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vector3<f64>> {
    let v: Vec<f64> = obj
        .extract()
        .map_err(|_| err(format!("{what} must be three numbers, e.g. (0, 0, -1)")))?;
    if v.len() != 3 || v.iter().any(|x| !x.is_finite()) {
        return Err(err(format!(
            "{what} must be three finite numbers, got {v:?}"
        )));
    }
    Ok(Vector3::new(v[0], v[1], v[2]))
}

/// The `gravity` argument: gravity in the tracking frame as three numbers (any length but
/// zero), the command line's text (`"0,0,-1"`, `"none"`), or `None` when unknown. Default
/// `(0, 0, -1)`: z up.
#[derive(Clone, Copy, Debug)]
pub struct Gravity(pub Option<Vector3<f64>>);

impl Default for Gravity {
    fn default() -> Self {
        Gravity(Some(Vector3::new(0.0, 0.0, -1.0)))
    }
}

impl<'a, 'py> FromPyObject<'a, 'py> for Gravity {
    type Error = PyErr;

    fn extract(obj: pyo3::Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        if obj.is_none() {
            return Ok(Gravity(None));
        }
        if let Ok(s) = obj.extract::<String>() {
            return objmodel::args::gravity(&s)
                .map(Gravity)
                .map_err(|e| err(e.0));
        }
        let g = vec3(&obj, "gravity")?;
        if g.norm() == 0.0 {
            return Err(err("gravity must not be zero (use None if unknown)"));
        }
        Ok(Gravity(Some(g)))
    }
}

/// The configuration of `gravity`, `method` and the options in `kwargs`, checked as the
/// command line checks its options.
pub fn config(
    gravity: Gravity,
    method: &str,
    kwargs: Option<&Bound<'_, PyDict>>,
) -> PyResult<Config> {
    let mut c = Config {
        method: match method {
            "robust" => Method::Robust,
            "paper" => Method::Paper,
            m => {
                return Err(err(format!(
                    "method must be \"robust\" or \"paper\", not {m:?}"
                )))
            }
        },
        ..Config::default()
    };
    c.gravity = gravity.0;
    let mut noise = [None; 4];
    if let Some(kw) = kwargs {
        for (k, v) in kw.iter() {
            let k: String = k.extract()?;
            if k == "length_unit" {
                let unit: String = v
                    .extract()
                    .map_err(|_| err("length_unit must be \"m\", \"cm\" or \"mm\""))?;
                c.length_unit = Some(unit.parse().map_err(err)?);
                continue;
            }
            if !OPTIONS.contains(&k.as_str()) {
                return Err(pyo3::exceptions::PyTypeError::new_err(format!(
                    "unexpected keyword argument '{k}'; the options are length_unit and the \
                     thresholds {}",
                    OPTIONS.join(", ")
                )));
            }
            let x: f64 = v
                .extract()
                .map_err(|_| err(format!("{k} must be a number")))?;
            set(&mut c, &k, x, &mut noise)?;
        }
    }
    c.robust.noise =
        NoiseModel::from_options(("noise_position", noise[0]), ("noise_rotation", noise[1]))
            .map_err(err)?;
    c.robust.palm_noise = NoiseModel::from_options(
        ("palm_noise_position", noise[2]),
        ("palm_noise_rotation", noise[3]),
    )
    .map_err(err)?;
    if c.robust.palm_noise.is_some() && c.robust.noise.is_none() {
        return Err(err(
            "palm_noise_position and palm_noise_rotation need noise_position and \
             noise_rotation (without them the noise of the motion relative to the palm is \
             estimated from it)",
        ));
    }
    Ok(c)
}

/// Set option `k` to `x`, checked.
fn set(c: &mut Config, k: &str, x: f64, noise: &mut [Option<f64>; 4]) -> PyResult<()> {
    let probability = ["alpha", "outlier_alpha"];
    let positive = [
        "rest_window",
        "r_palm",
        "pitch_threshold",
        "axis_angle_threshold",
        "normal_angle_threshold",
    ];
    if probability.contains(&k) && !(x > 0.0 && x < 1.0) {
        return Err(err(format!("{k} must be a probability in (0, 1), got {x}")));
    }
    if positive.contains(&k) && !(x > 0.0 && x.is_finite()) {
        return Err(err(format!("{k} must be positive, got {x}")));
    }
    if ["contact_depth", "edge_tolerance"].contains(&k) && !(x >= 0.0 && x.is_finite()) {
        return Err(err(format!(
            "{k} must be zero or positive (metres), got {x}"
        )));
    }
    match k {
        "alpha" => c.robust.alpha = x,
        "outlier_alpha" => c.robust.outlier_alpha = x,
        "rest_window" => c.robust.rest_window_s = x,
        "min_rest" => c.robust.min_rest_s = x,
        "noise_position" => noise[0] = Some(x),
        "noise_rotation" => noise[1] = Some(x),
        "palm_noise_position" => noise[2] = Some(x),
        "palm_noise_rotation" => noise[3] = Some(x),
        "edge_tolerance" => c.robust.edge_tolerance_m = x,
        "edge_tolerance_angle" => c.robust.edge_tolerance_rad = x,
        "contact_depth" => c.robust.contact_depth_m = x,
        "max_axis_tilt" => c.robust.max_axis_tilt_rad = x,
        "r_palm" => c.paper.r_palm = x,
        "pitch_threshold" => c.paper.pitch = x,
        "axis_angle_threshold" => c.paper.axis_angle = x,
        _ => c.paper.normal_angle = x,
    }
    Ok(())
}
