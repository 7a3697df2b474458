//! `objmodel plan`: the toppling skill's parameters from a learnt tree.

use crate::opts::parse_vec3;
use anyhow::{bail, Context, Result};
use nalgebra::{Isometry3, Vector3};
use objmodel::skill::{plan, PlanRequest};
use objmodel::tree::Tree;
use std::path::{Path, PathBuf};

/// Arguments of `objmodel plan`.
#[derive(clap::Args)]
pub struct PlanArgs {
    /// The learnt tree (written by `objmodel learn -o`).
    #[arg(long)]
    pub model: PathBuf,
    /// The object's tracked pose in the palm frame, `palm_from_object`, as
    /// "tx ty tz qx qy qz qw" (metres; quaternion x y z w). Palm frame: origin on the palm's
    /// surface, z its normal.
    #[arg(
        long,
        allow_hyphen_values = true,
        required_unless_present = "from_demo",
        conflicts_with = "from_demo"
    )]
    pub object_in_palm: Option<String>,
    /// Take the object's pose on the palm, and gravity in the palm frame, from the first
    /// poses of an instrumented demonstration: this object file and its palm file
    /// (NAME.palm.tum beside it, or --palm).
    #[arg(long)]
    pub from_demo: Option<PathBuf>,
    /// The palm file of --from-demo.
    #[arg(long, requires = "from_demo")]
    pub palm: Option<PathBuf>,
    /// Gravity in the tracking frame of --from-demo, "gx,gy,gz".
    #[arg(
        long,
        default_value = "0,0,-1",
        allow_hyphen_values = true,
        requires = "from_demo"
    )]
    pub gravity: String,
    /// Preferred toppling direction in the palm frame, "dx,dy,dz"; without it, the edge
    /// easiest to topple (smallest tilt) is chosen.
    #[arg(long, allow_hyphen_values = true)]
    pub towards: Option<String>,
    /// Gravity in the palm frame, "gx,gy,gz" (default: a level palm, -z).
    #[arg(
        long,
        default_value = "0,0,-1",
        allow_hyphen_values = true,
        conflicts_with = "from_demo"
    )]
    pub gravity_in_palm: String,
    /// Margin past phi [rad] (default 2° + 3 σ_phi).
    #[arg(long)]
    pub margin: Option<f64>,
    /// Print the plan as one JSON object.
    #[arg(long)]
    pub json: bool,
}

/// The `--object-in-palm` pose ([`objmodel::args::pose_xyz_xyzw`]).
fn parse_pose(s: &str) -> Result<Isometry3<f64>> {
    Ok(objmodel::args::pose_xyz_xyzw(s)?)
}

/// `palm_from_object` and gravity in the palm frame at the first poses of an instrumented
/// demonstration (`demo` and its palm file), gravity being `gravity` in the tracking frame.
pub fn at_first_poses(
    demo: &Path,
    palm: Option<&Path>,
    gravity: &Vector3<f64>,
) -> Result<(Isometry3<f64>, Vector3<f64>)> {
    let palm = match palm {
        Some(p) => p.to_path_buf(),
        None => objmodel::format::palm_path_for(demo).with_context(|| {
            format!(
                "{}: no palm file beside it (NAME.palm.tum); give --palm",
                demo.display()
            )
        })?,
    };
    let d = objmodel::format::read_demonstration(demo, Some(&palm))?;
    let (Some(object), Some(world_from_palm)) =
        (d.object.first(), d.palm.as_ref().and_then(|p| p.first()))
    else {
        bail!("{}: no poses", demo.display());
    };
    Ok((
        world_from_palm.pose.inverse() * object.pose,
        world_from_palm.pose.rotation.inverse() * gravity,
    ))
}

/// Run `objmodel plan`.
pub fn run(a: &PlanArgs) -> Result<()> {
    let tree = Tree::load(&a.model)?;
    let (palm_from_object, gravity_in_palm) = match (&a.from_demo, &a.object_in_palm) {
        (Some(demo), _) => {
            let gravity = parse_vec3(&a.gravity).context("--gravity")?;
            at_first_poses(demo, a.palm.as_deref(), &gravity)?
        }
        (None, Some(pose)) => (
            parse_pose(pose)?,
            parse_vec3(&a.gravity_in_palm).context("--gravity-in-palm")?,
        ),
        (None, None) => bail!("give --object-in-palm or --from-demo"),
    };
    let req = PlanRequest {
        palm_from_object,
        towards: a
            .towards
            .as_deref()
            .map(parse_vec3)
            .transpose()
            .context("--towards")?,
        gravity_in_palm,
        margin: a.margin,
    };
    let p = plan(&tree, &req)?;
    if a.json {
        crate::output::out(&(serde_json::to_string_pretty(&p)? + "\n"))
    } else {
        let v = |x: &nalgebra::Vector3<f64>| format!("[{:+.4}, {:+.4}, {:+.4}]", x.x, x.y, x.z);
        let edge = if p.predicted {
            format!(
                "{} (faces resting/landing; no one demonstrated it: phi predicted from the \
                 shape and the CoM, ±{:.2} deg)",
                p.edge,
                p.phi_sigma.unwrap_or(f64::NAN).to_degrees()
            )
        } else {
            p.edge.clone()
        };
        crate::output::out(&format!(
            "tilt the palm by {:.2} deg about the line through {} m along {} (palm frame)\n  edge {}, phi {:.2} deg, margin {:.2} deg, already tilted {:.2} deg; the object falls towards {}\n",
            p.tilt.to_degrees(),
            v(&p.axis_point),
            v(&p.axis_direction),
            edge,
            p.phi.to_degrees(),
            p.margin.to_degrees(),
            p.current_tilt.to_degrees(),
            v(&p.topple_direction)
        ))
    }
}
