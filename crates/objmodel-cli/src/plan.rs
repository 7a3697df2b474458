//! `objmodel plan`: the toppling skill's parameters from a learnt tree.

use crate::opts::parse_vec3;
use anyhow::{bail, Context, Result};
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};
use objmodel::skill::{plan, PlanRequest};
use objmodel::tree::Tree;
use std::path::PathBuf;

/// Arguments of `objmodel plan`.
#[derive(clap::Args)]
pub struct PlanArgs {
    /// The learnt tree (written by `objmodel learn -o`).
    #[arg(long)]
    pub model: PathBuf,
    /// The object's tracked pose in the palm frame, `palm_from_object`, as
    /// "tx ty tz qx qy qz qw" (metres; quaternion x y z w). Palm frame: origin on the palm's
    /// surface, z its normal.
    #[arg(long, allow_hyphen_values = true)]
    pub object_in_palm: String,
    /// Preferred toppling direction in the palm frame, "dx,dy,dz"; without it, the edge
    /// easiest to topple (smallest tilt) is chosen.
    #[arg(long, allow_hyphen_values = true)]
    pub towards: Option<String>,
    /// Gravity in the palm frame, "gx,gy,gz" (default: a level palm, -z).
    #[arg(long, default_value = "0,0,-1", allow_hyphen_values = true)]
    pub gravity_in_palm: String,
    /// Margin past phi [rad] (default 2° + 3 σ_phi).
    #[arg(long)]
    pub margin: Option<f64>,
    /// Print the plan as one JSON object.
    #[arg(long)]
    pub json: bool,
}

fn parse_pose(s: &str) -> Result<Isometry3<f64>> {
    let v: Vec<f64> = s
        .split(|c: char| c.is_whitespace() || c == ',')
        .filter(|x| !x.is_empty())
        .map(str::parse::<f64>)
        .collect::<Result<_, _>>()
        .with_context(|| format!("--object-in-palm '{s}' is not 7 numbers"))?;
    if v.len() != 7 || v.iter().any(|x| !x.is_finite()) {
        bail!(
            "--object-in-palm needs 7 finite numbers \"tx ty tz qx qy qz qw\", got {}",
            v.len()
        );
    }
    let q = Quaternion::new(v[6], v[3], v[4], v[5]);
    let norm = q.norm();
    if (norm - 1.0).abs() > objmodel::format::QUAT_NORM_TOLERANCE {
        bail!(
            "--object-in-palm quaternion has norm {norm}, more than {} from 1",
            objmodel::format::QUAT_NORM_TOLERANCE
        );
    }
    Ok(Isometry3::from_parts(
        Translation3::new(v[0], v[1], v[2]),
        UnitQuaternion::from_quaternion(q),
    ))
}

/// Run `objmodel plan`.
pub fn run(a: &PlanArgs) -> Result<()> {
    let tree = Tree::load(&a.model)?;
    let req = PlanRequest {
        palm_from_object: parse_pose(&a.object_in_palm)?,
        towards: a
            .towards
            .as_deref()
            .map(parse_vec3)
            .transpose()
            .context("--towards")?,
        gravity_in_palm: parse_vec3(&a.gravity_in_palm).context("--gravity-in-palm")?,
        margin: a.margin,
    };
    let p = plan(&tree, &req)?;
    if a.json {
        crate::out(&(serde_json::to_string_pretty(&p)? + "\n"))
    } else {
        let v = |x: &nalgebra::Vector3<f64>| format!("[{:+.4}, {:+.4}, {:+.4}]", x.x, x.y, x.z);
        crate::out(&format!(
            "tilt the palm by {:.2} deg about the line through {} m along {} (palm frame)\n  edge {}, phi {:.2} deg, margin {:.2} deg, already tilted {:.2} deg; the object falls towards {}\n",
            p.tilt.to_degrees(),
            v(&p.axis_point),
            v(&p.axis_direction),
            p.edge,
            p.phi.to_degrees(),
            p.margin.to_degrees(),
            p.current_tilt.to_degrees(),
            v(&p.topple_direction)
        ))
    }
}
