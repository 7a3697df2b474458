//! `objmodel export`: the learnt object as a simulation model, MJCF (MuJoCo) and URDF.

use anyhow::{Context, Result};
use objmodel::export::{mjcf::mjcf, urdf::urdf, Body};
use objmodel::format::write_atomic;
use objmodel::tree::Tree;
use std::path::PathBuf;

/// Arguments of `objmodel export`.
#[derive(clap::Args)]
pub struct ExportArgs {
    /// The learnt tree (written by `objmodel learn -o`).
    pub model: PathBuf,
    /// Write the MJCF model (MuJoCo) here.
    #[arg(long, required_unless_present = "urdf")]
    pub mjcf: Option<PathBuf>,
    /// Write the URDF here (a non-box shape goes to NAME.obj beside it).
    #[arg(long)]
    pub urdf: Option<PathBuf>,
    /// The object's mass [kg]. Demonstrations of poses cannot tell it: weigh the object.
    #[arg(long, allow_hyphen_values = true)]
    pub mass: f64,
    /// Coulomb friction coefficient. Default: 0.8, raised to 1.1 x the lower bound the model's
    /// instrumented topples show when that is higher (the tree's `friction`); the notes say
    /// which.
    #[arg(long, allow_hyphen_values = true)]
    pub friction: Option<f64>,
    /// The body's (and model's) name (default: the model file's stem).
    #[arg(long)]
    pub name: Option<String>,
}

/// Run `objmodel export`.
pub fn run(a: &ExportArgs) -> Result<()> {
    let tree = Tree::load(&a.model)?;
    let body = Body::from_tree(&tree, a.mass, a.friction)
        .with_context(|| format!("{}", a.model.display()))?;
    let name = a.name.clone().unwrap_or_else(|| {
        a.model
            .file_stem()
            .map_or("object".into(), |s| s.to_string_lossy().into_owned())
    });
    for n in &body.notes {
        eprintln!("{n}");
    }
    if let Some(p) = &a.mjcf {
        write_atomic(p, mjcf(&body, &name).as_bytes())?;
        println!("wrote {}", p.display());
    }
    if let Some(p) = &a.urdf {
        let mesh = p.with_extension("obj");
        let mesh_name = mesh
            .file_name()
            .map_or("object.obj".into(), |s| s.to_string_lossy().into_owned());
        let (text, obj) = urdf(&body, &name, &mesh_name);
        if let Some(obj) = obj {
            write_atomic(&mesh, obj.as_bytes())?;
            println!("wrote {}", mesh.display());
        }
        write_atomic(p, text.as_bytes())?;
        println!("wrote {}", p.display());
    }
    Ok(())
}
