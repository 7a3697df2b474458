//! `objmodel view`: the learnt object in 3D, one offline HTML page (three.js inlined), and on
//! request the paper's Fig. 9a (SVG and PNG). The page is made by `objmodel_plot::write_view`.

use anyhow::{Context, Result};
use objmodel::format::{is_palm_file, read_demonstration};
use objmodel::tree::Tree;
use std::path::PathBuf;

/// Arguments of `objmodel view`.
#[derive(clap::Args)]
pub struct ViewArgs {
    /// The learnt tree (written by `objmodel learn -o`).
    pub model: PathBuf,
    /// The page to write (default: the model's name with .html).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Demonstrations (TUM or CSV; NAME.palm.tum beside one is its palm, and is not played
    /// as a demonstration of its own) to play back on the page, in the object's recorded poses.
    #[arg(long, num_args = 1..)]
    pub demos: Vec<PathBuf>,
    /// Also draw the paper's Fig. 9a to STEM.svg and STEM.png.
    #[arg(long, value_name = "STEM")]
    pub figure: Option<PathBuf>,
    /// The page's title (default: the model file's name).
    #[arg(long)]
    pub title: Option<String>,
}

/// Run `objmodel view`.
pub fn run(a: &ViewArgs) -> Result<()> {
    let tree = Tree::load(&a.model)?;
    let demos = a
        .demos
        .iter()
        .filter(|d| !is_palm_file(d))
        .map(|d| read_demonstration(d, None))
        .collect::<objmodel::Result<Vec<_>>>()?;
    let title = a.title.clone().unwrap_or_else(|| {
        a.model
            .file_name()
            .map_or("learnt object".into(), |s| s.to_string_lossy().into_owned())
    });
    let out = a
        .output
        .clone()
        .unwrap_or_else(|| a.model.with_extension("html"));
    let page = objmodel_plot::write_view(&tree, &title, &demos, &out)
        .with_context(|| format!("writing the 3D view of {}", a.model.display()))?;
    eprintln!(
        "wrote {} ({} kB; {} demonstration(s) to play back): open it in a browser",
        page.display(),
        std::fs::metadata(&page).map_or(0, |m| m.len() / 1024),
        demos.len()
    );
    if let Some(stem) = &a.figure {
        let (svg, png) = objmodel_plot::plot_model(&tree, &title, stem)?;
        eprintln!("wrote {} and {}", svg.display(), png.display());
    }
    Ok(())
}
