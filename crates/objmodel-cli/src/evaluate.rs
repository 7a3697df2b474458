//! `objmodel evaluate`: the learner against a simulated dataset's ground truth.

use crate::opts::ClassifyOpts;
use anyhow::{Context, Result};
use std::path::PathBuf;

/// Arguments of `objmodel evaluate`.
#[derive(clap::Args)]
pub struct EvaluateArgs {
    /// Dataset folder (written by `objmodel dataset`, with manifest.json).
    pub data: PathBuf,
    /// Print the per-demonstration results as JSON instead of the tables.
    #[arg(long)]
    pub json: bool,
    /// Also write the tables (Markdown) to this file.
    #[arg(long)]
    pub markdown: Option<PathBuf>,
    #[command(flatten)]
    pub opts: ClassifyOpts,
}

/// The line after which `evaluate --markdown` writes its tables: what comes before it in the
/// file (a hand-written header) is kept.
pub const MARKER: &str = "<!-- objmodel evaluate: the tables below are generated -->";

/// The Markdown page with the generated `tables`: the existing page's text up to its
/// [`MARKER`] line, or the whole existing page and the marker after it, then the tables.
pub fn splice(existing: Option<&str>, tables: &str) -> String {
    let head = match existing {
        None => String::new(),
        Some(text) => match text.find(MARKER) {
            Some(at) => text[..at].to_string(),
            None if text.trim().is_empty() => String::new(),
            None => format!("{}\n\n", text.trim_end()),
        },
    };
    format!("{head}{MARKER}\n\n{tables}")
}

/// Write `tables` into the Markdown page `p` after its hand-written header (see [`splice`]).
pub fn write_page(p: &std::path::Path, tables: &str) -> Result<()> {
    let existing = match std::fs::read_to_string(p) {
        Ok(text) => Some(text),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
        Err(e) => return Err(e).with_context(|| format!("reading {}", p.display())),
    };
    let page = splice(existing.as_deref(), tables);
    objmodel::format::write_atomic(p, page.as_bytes())?;
    Ok(())
}

/// Run `objmodel evaluate`.
pub fn run(a: &EvaluateArgs) -> Result<()> {
    let config = a.opts.config()?;
    let e = objmodel_sim::eval::evaluate(&a.data, &config)
        .with_context(|| format!("evaluating {}", a.data.display()))?;
    let md = e.markdown();
    if let Some(p) = &a.markdown {
        write_page(p, &md)?;
    }
    if a.json {
        crate::output::out(&(serde_json::to_string_pretty(&e)? + "\n"))
    } else {
        crate::output::out(&md)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A hand-written header survives any number of runs; only the tables change.
    #[test]
    fn the_header_is_kept() {
        let header = "# My results\n\nWritten by hand.\n";
        let first = splice(Some(header), "| a |\n");
        assert!(first.starts_with(header));
        assert!(first.ends_with("| a |\n"));
        let second = splice(Some(&first), "| b |\n");
        assert!(second.starts_with(header));
        assert!(second.ends_with("| b |\n"));
        assert!(!second.contains("| a |"));
        assert_eq!(second.matches(MARKER).count(), 1);
        assert_eq!(splice(None, "| c |\n"), format!("{MARKER}\n\n| c |\n"));
    }
}
