//! `objmodel simulate`: one physics-simulated demonstration with ground truth (the
//! `objmodel-sim` crate, on rapier3d-f64).

use anyhow::{bail, Context, Result};
use objmodel_sim::{simulate, write_demo, BoxFace, BoxSpec, SceneKind, TagMount, TrackerNoise};
use rand::{rngs::StdRng, SeedableRng};
use std::path::PathBuf;

/// Arguments of `objmodel simulate`.
#[derive(clap::Args, Debug)]
#[command(after_help = "\
Writes OUT/NAME.tum (the tag's poses, as a tracker would), OUT/NAME.palm.tum (instrumented
only: the palm's poses) and OUT/NAME.truth.json (what really happened: edge or face in the tag
frame, resting faces, CoM, tipping angle phi, topple start, segments).

Examples:
  objmodel simulate topple --box 0.1x0.1x0.2 --mass 0.6 --com 0.02,0,0 --noise real --seed 3 -o out/
  objmodel simulate topple --instrumented -o out/
  objmodel simulate slide --noise noisy --json -o out/
  objmodel simulate instrumented --model box.json --mass 0.6 --friction 0.8 -o out/

With --model, the object is the learnt one (its shape, centre of mass and inertia; the mass
and friction given): its tag frame is the model's object frame, so the truth file is in that
frame.")]
pub struct SimulateArgs {
    /// Kind of demonstration: `topple` (a finger pushes the box over on a table),
    /// `instrumented` (the box topples on a tilting, tracked palm), `slide` (a low push slides
    /// and turns it), `general` (it is carried, turned and put down), `compound` (a slide, then
    /// a topple).
    #[arg(value_parser = ["topple", "instrumented", "slide", "general", "compound"])]
    pub kind: String,
    /// Make a `topple` an instrumented one (same as the kind `instrumented`).
    #[arg(long)]
    pub instrumented: bool,
    /// Box edge lengths in metres, `XxYxZ` (Z is up at the start).
    #[arg(long = "box", value_name = "XxYxZ", default_value = "0.1x0.1x0.2")]
    pub dims: String,
    /// Simulate the object of this learnt model (written by `objmodel learn -o`) instead of a
    /// specified box: `--box` and `--com` are then ignored, `--mass` and `--friction` are its
    /// own (demonstrations of poses cannot tell them). Its shape must be closed.
    #[arg(long, value_name = "MODEL.json")]
    pub model: Option<PathBuf>,
    /// Box (or learnt object's) mass [kg].
    #[arg(long, default_value_t = 0.6)]
    pub mass: f64,
    /// Centre of mass offset from the box's geometric centre [m], `X,Y,Z` in box axes.
    #[arg(
        long,
        value_name = "X,Y,Z",
        default_value = "0,0,0",
        allow_hyphen_values = true
    )]
    pub com: String,
    /// Box–table (or palm) friction coefficient (slides use their own low value). Default: 0.8;
    /// with --model, the model's (as `objmodel export` takes it: 0.8, raised above the lower
    /// bound its instrumented topples show).
    #[arg(long)]
    pub friction: Option<f64>,
    /// Tracking noise: `clean` (exact), `real` (1 mm, 0.5 deg, 3% drops, sign and mirror
    /// flips), `noisy` (2 mm, 1 deg, more drops and flips) or `camera` (0.7 mm and 0.3 deg,
    /// three times that along the line of sight and in tilts out of the image, correlated
    /// between frames).
    #[arg(long, default_value = "real", value_parser = ["clean", "real", "noisy", "camera"])]
    pub noise: String,
    /// Random seed of the scene (push height, direction, speed, tilt rate, start pose) and noise.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Seed of the tag sticker's placement: keep it fixed to get several demos of the same
    /// physical box (as the learner's fusion expects).
    #[arg(long, default_value_t = 0)]
    pub tag_seed: u64,
    /// Output folder (created if needed).
    #[arg(short, long, default_value = "out")]
    pub output: PathBuf,
    /// File stem (default: KIND_NOISE_sSEED).
    #[arg(long)]
    pub name: Option<String>,
    /// Print a JSON summary (files and truth) on stdout instead of text.
    #[arg(long)]
    pub json: bool,
}

fn parse_numbers(s: &str, sep: char, n: usize, what: &str) -> Result<Vec<f64>> {
    let parts: Vec<&str> = s.split(sep).map(str::trim).collect();
    if parts.len() != n {
        bail!("{what} '{s}' must be {n} numbers separated by '{sep}'");
    }
    parts
        .iter()
        .map(|p| {
            p.parse::<f64>()
                .with_context(|| format!("{what} '{s}': '{p}' is not a number"))
        })
        .collect()
}

/// The box described by the arguments, with a tag placed by `--tag-seed`.
pub fn box_from_args(a: &SimulateArgs) -> Result<BoxSpec> {
    let d = parse_numbers(&a.dims.to_lowercase(), 'x', 3, "--box")?;
    let c = parse_numbers(&a.com, ',', 3, "--com")?;
    let tag = if a.tag_seed == 0 {
        TagMount {
            face: BoxFace::PosX,
            offset: [0.004, -0.003],
            yaw: 0.3,
        }
    } else {
        TagMount::random(&mut StdRng::seed_from_u64(a.tag_seed))
    };
    let spec = BoxSpec::new("box", [d[0], d[1], d[2]], a.mass)
        .with_com([c[0], c[1], c[2]])
        .with_friction(a.friction.unwrap_or(objmodel::export::DEFAULT_FRICTION))
        .with_tag(tag);
    spec.validate()?;
    Ok(spec)
}

/// The object of the learnt model `path`, with the mass and friction of the arguments (without
/// a friction, the model's: [`objmodel::export::Body::from_tree`]).
pub fn learnt_from_args(path: &std::path::Path, a: &SimulateArgs) -> Result<BoxSpec> {
    let tree = objmodel::tree::Tree::load(path)?;
    let body = objmodel::export::Body::from_tree(&tree, a.mass, a.friction)
        .with_context(|| format!("{}", path.display()))?;
    let spec = objmodel_sim::learnt::learnt_spec(&body, "learnt");
    spec.validate()
        .with_context(|| format!("{}: the learnt object", path.display()))?;
    Ok(spec)
}

/// Run `objmodel simulate`.
pub fn run(a: &SimulateArgs) -> Result<()> {
    let mut kind = SceneKind::from_name(&a.kind).context("unknown kind")?;
    if a.instrumented {
        if kind != SceneKind::Topple && kind != SceneKind::InstrumentedTopple {
            bail!(
                "--instrumented applies to a topple only, not to '{}'",
                a.kind
            );
        }
        kind = SceneKind::InstrumentedTopple;
    }
    let spec = match &a.model {
        Some(path) => learnt_from_args(path, a)?,
        None => box_from_args(a)?,
    };
    let what = match &a.model {
        Some(path) => format!("the object of {}", path.display()),
        None => format!("a {} m box", a.dims),
    };
    let noise = TrackerNoise::preset(&a.noise).context("unknown noise preset")?;
    let demo = simulate(kind, &spec, &noise, a.seed)
        .with_context(|| format!("simulating a {} of {what} (seed {})", kind.name(), a.seed))?;
    let name = a
        .name
        .clone()
        .unwrap_or_else(|| format!("{}_{}_s{}", kind.name(), a.noise, a.seed));
    let files = write_demo(&a.output, &name, &demo)
        .with_context(|| format!("writing into {}", a.output.display()))?;
    if a.json {
        let v =
            serde_json::json!({ "files": files, "frames": demo.object.len(), "truth": demo.truth });
        println!("{}", serde_json::to_string_pretty(&v)?);
        return Ok(());
    }
    let t = &demo.truth;
    println!(
        "{} demonstration, {:.1} s, {} poses at {} Hz",
        kind.name(),
        t.duration,
        demo.object.len(),
        t.rate_hz
    );
    if let (Some(phi), Some(ts)) = (t.phi_deg, t.topple_start) {
        print!("  topples at t = {ts:.2} s over an edge with tipping angle {phi:.1} deg");
        match t.palm_tilt_at_start_deg {
            Some(p) => println!(" (palm tilted {p:.1} deg)"),
            None => println!(),
        }
    }
    println!("  {}", files.tum.display());
    if let Some(p) = &files.palm {
        println!("  {}", p.display());
    }
    println!("  {}", files.truth.display());
    Ok(())
}
