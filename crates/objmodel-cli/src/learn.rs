//! `objmodel learn`: learn (or update) an object description tree from demonstration files,
//! through the library's pipeline (`objmodel::learn`).

use crate::bag::{is_bag_path, BagArgs, DemoSource};
use crate::opts::{palm_for, ClassifyOpts};
use anyhow::{bail, Context, Result};
use objmodel::classify::{Config, Kind};
use objmodel::format::is_palm_file;
use objmodel::learn::Learner;
use objmodel::observation::Observation;
use objmodel::tree::Tree;
use std::path::{Path, PathBuf};

/// Arguments of `objmodel learn`.
#[derive(clap::Args)]
pub struct LearnArgs {
    /// Demonstration files (TUM or CSV; OptiTrack Motive takes, with --object if they hold
    /// several rigid bodies), or ROS 2 bags (.mcap, or bag folders; with --object).
    /// NAME.palm.* files are taken as the palms of NAME.*.
    #[arg(required = true)]
    pub demos: Vec<PathBuf>,
    /// Write the tree to this file (atomically).
    #[arg(short, long, conflicts_with = "into")]
    pub output: Option<PathBuf>,
    /// Fuse the demonstrations into this existing tree file, and write it back (atomically).
    /// A missing file starts an empty tree.
    #[arg(long)]
    pub into: Option<PathBuf>,
    /// The palm trajectory, for a single instrumented demonstration; for bags, the palm's
    /// topic or tf frame (e.g. palm_link); for Motive takes (with --object), the palm's rigid
    /// body in each.
    #[arg(long)]
    pub palm: Option<PathBuf>,
    /// Print the tree as JSON on standard output instead of a summary.
    #[arg(long)]
    pub json: bool,
    /// Do not check the gravity given against the demonstrations (their rests' vertical and
    /// their flights' fall): for a gravity known to be right that the check refuses.
    #[arg(long)]
    pub no_gravity_check: bool,
    /// The support's height [m] along -gravity, in the frame the poses are given in, when it
    /// is known (a tracked table; a frame whose origin is on the floor: 0). Every rest on the
    /// support then gives the face it rests on its offset, and the object its shape, without
    /// an edge rolled over on the support. Kept in the model file (`--into`) once given
    #[arg(long, value_name = "M", allow_negative_numbers = true)]
    pub support_height: Option<f64>,
    /// How well [m] the support's height is known: its measurement, its flatness and its level
    /// where the object rests
    #[arg(
        long,
        value_name = "M",
        default_value_t = 1e-3,
        requires = "support_height"
    )]
    pub support_sigma: f64,
    /// Learn from the demonstrations that can be read, and print the error of each that
    /// cannot (a file, a line and the problem, as without this option), instead of stopping
    /// at the first: the model is written from the others, and the exit status is still an
    /// error's (2).
    #[arg(long)]
    pub keep_going: bool,
    #[command(flatten)]
    pub bag: BagArgs,
    #[command(flatten)]
    pub opts: ClassifyOpts,
}

/// The sources of the demonstration files given on the command line: each object file with
/// its palm (`--palm`, or NAME.palm.* beside it); palm files given among them are skipped.
pub fn sources(demos: &[PathBuf], palm: Option<&Path>) -> Result<Vec<(PathBuf, Option<PathBuf>)>> {
    let objects: Vec<&PathBuf> = demos.iter().filter(|d| !is_palm_file(d)).collect();
    if objects.is_empty() {
        bail!("no demonstration files (only palm files were given)");
    }
    if palm.is_some() && objects.len() > 1 {
        bail!(
            "--palm names the palm of a single demonstration, but {} were given",
            objects.len()
        );
    }
    Ok(objects
        .into_iter()
        .map(|d| (d.clone(), palm_for(d, palm, false)))
        .collect())
}

/// The sources of the demonstrations given on the command line: bags with the selection of
/// `bag` and `--palm` (a topic or frame, the same for every bag), Motive takes' rigid bodies
/// where --object names the object's (and `--palm` the palm's, in each), pose files as
/// [`sources`] says (bags and files may not be mixed).
pub fn demo_sources(
    demos: &[PathBuf],
    palm: Option<&Path>,
    bag: &BagArgs,
) -> Result<Vec<DemoSource>> {
    let bags = demos.iter().filter(|d| is_bag_path(d)).count();
    if bags == 0 {
        bag.check_files()?;
        if bag.object.is_some() {
            // Motive takes: --palm names the palm's rigid body in each.
            return Ok(demos
                .iter()
                .map(|d| bag.file_source(d, palm, || None))
                .collect());
        }
        return Ok(sources(demos, palm)?
            .into_iter()
            .map(|(object, palm)| DemoSource::Files { object, palm })
            .collect());
    }
    if bags < demos.len() {
        bail!("give either bags (.mcap) or pose files, not both");
    }
    demos
        .iter()
        .map(|d| {
            Ok(DemoSource::Bag {
                path: d.clone(),
                selection: bag.selection(d, palm)?,
            })
        })
        .collect()
}

/// Learn every demonstration file into `tree` through the library's pipeline, printing each
/// one's warnings; returns their reports.
pub fn learn_into(
    tree: &mut Tree,
    demos: &[PathBuf],
    palm: Option<&Path>,
    config: &Config,
) -> Result<Vec<Observation>> {
    let sources = demo_sources(demos, palm, &BagArgs::default())?;
    learn_sources_into(tree, &sources, &Learner::new(*config))
}

/// Learn every demonstration of `sources` into `tree` with `learner`, printing each one's
/// warnings; returns their reports.
pub fn learn_sources_into(
    tree: &mut Tree,
    sources: &[DemoSource],
    learner: &Learner,
) -> Result<Vec<Observation>> {
    Ok(learn_sources(tree, sources, learner, false)?.0)
}

/// [`learn_sources_into`]; with `keep_going`, of the demonstrations that can be read
/// ([`Learner::learn_readable`]), each left out printed with its error. Returns the reports
/// and how many were left out.
fn learn_sources(
    tree: &mut Tree,
    sources: &[DemoSource],
    learner: &Learner,
    keep_going: bool,
) -> Result<(Vec<Observation>, usize)> {
    let bar = crate::progress::bar(sources.len() as u64);
    let wrapped: Vec<_> = sources.iter().map(|s| s.source()).collect();
    let progress = |k: usize| {
        if let Some(next) = sources.get(k + 1) {
            bar.set_message(next.path().display().to_string());
        }
        bar.inc(1);
    };
    let learnt = match keep_going {
        true => learner.learn_readable(tree, &wrapped, progress),
        false => learner
            .learn_with_progress(tree, &wrapped, progress)
            .map(|r| (r, Vec::new())),
    };
    bar.finish_and_clear();
    let (reports, left_out) = learnt?;
    for l in &left_out {
        eprintln!("error: {} (left out: --keep-going)", l.error);
    }
    // Kept out by the gravity check: the caller fails with the reason, and only that.
    if reports.iter().all(|r| r.not_learnt.is_none()) {
        print_all_warnings(&reports);
    }
    Ok((reports, left_out.len()))
}

/// Print the reports' warnings, each demonstration's own under its name, and a warning that
/// every one of several demonstrations was given (the gravity check's) once.
fn print_all_warnings(reports: &[Observation]) {
    let shared = |w: &String| {
        reports.len() > 1
            && reports
                .iter()
                .all(|r| r.classification.warnings.contains(w))
    };
    if let Some(first) = reports.first() {
        for w in first.classification.warnings.iter().filter(|w| shared(w)) {
            eprintln!("warning: all {} demonstrations: {w}", reports.len());
        }
    }
    for r in reports {
        let c = &r.classification;
        for w in c.warnings.iter().filter(|w| !shared(w)) {
            eprintln!("warning: {}: {w}", c.name);
        }
    }
}

/// Run `objmodel learn`.
pub fn run(a: &LearnArgs) -> Result<()> {
    let config = a.opts.config()?;
    let mut learner = Learner::new(config);
    if a.no_gravity_check {
        learner = learner.without_gravity_check();
    }
    if let Some(h) = a.support_height {
        learner = learner
            .with_support(h, a.support_sigma)
            .with_context(|| format!("--support-height {h} --support-sigma {}", a.support_sigma))?;
    }
    let learnt = |tree: &mut Tree| -> objmodel::Result<_> {
        let (reports, left_out) = demo_sources(&a.demos, a.palm.as_deref(), &a.bag)
            .and_then(|sources| learn_sources(tree, &sources, &learner, a.keep_going))
            .map_err(|e| objmodel::Error::Data(format!("{e:#}")))?;
        // Kept out by the gravity check: an error that says which gravity to give.
        if let Some(why) = reports.iter().find_map(|r| r.not_learnt.as_ref()) {
            return Err(objmodel::Error::Data(format!(
                "{} demonstrations {why} (for a gravity known to be right: --no-gravity-check)",
                reports.len()
            )));
        }
        let changed = reports.iter().any(|r| r.learnt());
        Ok(((reports, tree.clone(), left_out), changed))
    };
    // Into a model file: read, learn and write it under its lock, and leave it as it was when
    // nothing was learnt. Otherwise: a new tree, written where -o says.
    let (reports, tree, left_out, wrote) = match &a.into {
        Some(model) => {
            let (reports, tree, left_out) = Tree::update(model, learnt)?;
            let wrote = reports.iter().any(|r| r.learnt());
            (reports, tree, left_out, wrote.then_some(model))
        }
        None => {
            let ((reports, tree, left_out), _) = learnt(&mut Tree::default())?;
            if let Some(out) = &a.output {
                tree.save(out)
                    .with_context(|| format!("writing {}", out.display()))?;
            }
            (reports, tree, left_out, a.output.as_ref())
        }
    };
    if a.json {
        crate::output::out(&(tree.to_json() + "\n"))?;
    } else {
        for c in reports.iter().map(|r| &r.classification) {
            let n_edges = c.edges().count();
            eprintln!(
                "{}: {}{}",
                c.name,
                c.kind.as_str(),
                if c.kind == Kind::Topple {
                    format!(" ({n_edges} topple(s))")
                } else {
                    String::new()
                }
            );
        }
        crate::output::out(&crate::text::tree(&tree))?;
        match (wrote, &a.into) {
            (Some(out), _) => println!("wrote {}", out.display()),
            (None, Some(model)) => println!("nothing learnt: {} left as it was", model.display()),
            (None, None) => {}
        }
    }
    if left_out > 0 {
        let what = if left_out == 1 {
            "1 demonstration".to_string()
        } else {
            format!("{left_out} demonstrations")
        };
        bail!(
            "{what} could not be read and left out (the errors above); the model holds the others"
        );
    }
    Ok(())
}
