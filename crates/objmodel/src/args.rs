//! Values given on the command line as text: a pose (`--object-in-palm`), a 3-vector
//! (`--gravity-in-palm`, `--towards`) and gravity (`--gravity`, which may be `none`).
//!
//! They live in the library, not in the command-line tool, so that they can be tested and
//! fuzzed on their own (`fuzz/fuzz_targets/cli_args.rs`); the tool calls them, and its error
//! messages are these errors' texts.

use crate::format::QUAT_NORM_TOLERANCE;
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion, Vector3};

/// A value on the command line that is not what it should be; the text says which option
/// and why, e.g. `--gravity: '0,0' is not three comma-separated finite numbers`.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct ArgError(pub String);

/// `"x,y,z"` (spaces around the numbers allowed) as a vector of three finite numbers.
pub fn vec3(s: &str) -> Result<Vector3<f64>, ArgError> {
    let v: Vec<f64> = s
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|e| ArgError(format!("'{s}' is not three comma-separated numbers: {e}")))?;
    if v.len() != 3 || v.iter().any(|x| !x.is_finite()) {
        return Err(ArgError(format!(
            "'{s}' is not three comma-separated finite numbers"
        )));
    }
    Ok(Vector3::new(v[0], v[1], v[2]))
}

/// The `--gravity` option: `"gx,gy,gz"` (any length but zero), or `"none"` when it is not
/// known (`None`). Spaces around the whole are ignored.
pub fn gravity(s: &str) -> Result<Option<Vector3<f64>>, ArgError> {
    match s.trim() {
        "none" => Ok(None),
        g => {
            let v = vec3(g).map_err(|e| ArgError(format!("--gravity: {e}")))?;
            if v.norm() == 0.0 {
                return Err(ArgError(
                    "--gravity must not be zero (use \"none\" if unknown)".into(),
                ));
            }
            Ok(Some(v))
        }
    }
}

/// The `--object-in-palm` option: a pose `"tx ty tz qx qy qz qw"` (separated by spaces or
/// commas; metres, quaternion in x y z w order) whose quaternion's norm is within
/// [`QUAT_NORM_TOLERANCE`] of 1 (it is normalised).
pub fn pose_xyz_xyzw(s: &str) -> Result<Isometry3<f64>, ArgError> {
    let v: Vec<f64> = s
        .split(|c: char| c.is_whitespace() || c == ',')
        .filter(|x| !x.is_empty())
        .map(str::parse::<f64>)
        .collect::<Result<_, _>>()
        .map_err(|e| ArgError(format!("--object-in-palm '{s}' is not 7 numbers: {e}")))?;
    if v.len() != 7 || v.iter().any(|x| !x.is_finite()) {
        return Err(ArgError(format!(
            "--object-in-palm needs 7 finite numbers \"tx ty tz qx qy qz qw\", got {}",
            v.len()
        )));
    }
    let q = Quaternion::new(v[6], v[3], v[4], v[5]);
    let norm = q.norm();
    if (norm - 1.0).abs() > QUAT_NORM_TOLERANCE {
        return Err(ArgError(format!(
            "--object-in-palm quaternion has norm {norm}, more than {QUAT_NORM_TOLERANCE} from 1"
        )));
    }
    Ok(Isometry3::from_parts(
        Translation3::new(v[0], v[1], v[2]),
        UnitQuaternion::from_quaternion(q),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The words the command line prints (its tests look for parts of them).
    #[test]
    fn messages() {
        let err = |r: Result<(), ArgError>| r.unwrap_err().0;
        assert_eq!(
            err(vec3("1,x,3").map(drop)),
            "'1,x,3' is not three comma-separated numbers: invalid float literal"
        );
        assert_eq!(
            err(vec3("1,2").map(drop)),
            "'1,2' is not three comma-separated finite numbers"
        );
        assert_eq!(
            err(vec3("1,2,inf").map(drop)),
            "'1,2,inf' is not three comma-separated finite numbers"
        );
        assert_eq!(
            err(gravity(" 1,,2 ").map(drop)),
            "--gravity: '1,,2' is not three comma-separated numbers: cannot parse float from \
             empty string"
        );
        assert_eq!(
            err(gravity("0,0,-0").map(drop)),
            "--gravity must not be zero (use \"none\" if unknown)"
        );
        assert_eq!(
            err(pose_xyz_xyzw("1 2 x").map(drop)),
            "--object-in-palm '1 2 x' is not 7 numbers: invalid float literal"
        );
        assert_eq!(
            err(pose_xyz_xyzw("1 2 3 0 0 0 1 4").map(drop)),
            "--object-in-palm needs 7 finite numbers \"tx ty tz qx qy qz qw\", got 8"
        );
        assert_eq!(
            err(pose_xyz_xyzw("0 0 0 0 0 0 2").map(drop)),
            "--object-in-palm quaternion has norm 2, more than 0.01 from 1"
        );
    }

    #[test]
    fn values() {
        assert_eq!(gravity(" none ").unwrap(), None);
        assert_eq!(
            gravity("0, 1 ,0").unwrap(),
            Some(Vector3::new(0.0, 1.0, 0.0))
        );
        assert_eq!(vec3(" -1e-3,2,3").unwrap(), Vector3::new(-1e-3, 2.0, 3.0));
        let p = pose_xyz_xyzw("0.1,0.2 0.3\t0 0 0.6 0.8").unwrap();
        assert_eq!(p.translation.vector, Vector3::new(0.1, 0.2, 0.3));
        let q = p.rotation.coords;
        assert_eq!([q.x, q.y, q.z, q.w], [0.0, 0.0, 0.6, 0.8]);
        // Within the tolerance: normalised.
        let p = pose_xyz_xyzw("0 0 0 0 0 0 1.005").unwrap();
        assert_eq!(p.rotation.coords.w, 1.0);
    }
}
