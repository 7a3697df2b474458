//! `objmodel demo`: the main job on built-in data. A box with a weight inside is simulated
//! (rapier) being toppled over several edges on a tilting palm and directly, slid and carried,
//! all tracked with realistic noise; the object description tree is learnt from those files;
//! the toppling pictures (Fig. 8) and a plan for the robot are written to a report folder with
//! a summary page.

use crate::learn::learn_into;
use crate::plot::fig8;
use anyhow::{Context, Result};
use objmodel::classify::Config;
use objmodel::skill::{plan, PlanRequest};
use objmodel::tree::Tree;
use objmodel_sim::dataset::standard_boxes;
use objmodel_sim::{simulate, write_demo, SceneKind, TrackerNoise};
use std::fmt::Write as _;
use std::path::PathBuf;

/// Arguments of `objmodel demo`.
#[derive(clap::Args)]
pub struct DemoArgs {
    /// Report folder.
    #[arg(short, long, default_value = "report")]
    pub output: PathBuf,
    /// Random seed of the built-in data.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Boxes for the Fig. 1 task on the simulated arm (0 skips it; `objmodel task` runs more).
    #[arg(long, default_value_t = 3)]
    pub task_boxes: usize,
}

/// Run `objmodel demo`.
pub fn run(a: &DemoArgs) -> Result<()> {
    let demos = a.output.join("demos");
    let spec = standard_boxes()
        .into_iter()
        .find(|b| b.name == "weighted")
        .context("the built-in box")?;
    let noise = TrackerNoise::real();
    let scenes = [
        SceneKind::InstrumentedTopple,
        SceneKind::InstrumentedTopple,
        SceneKind::InstrumentedTopple,
        SceneKind::Topple,
        SceneKind::Topple,
        SceneKind::Slide,
        SceneKind::General,
    ];
    let mut files = Vec::new();
    for (i, kind) in scenes.iter().enumerate() {
        let seed = a.seed * 100 + i as u64;
        let d = simulate(*kind, &spec, &noise, seed)
            .with_context(|| format!("simulating {}", kind.name()))?;
        let name = format!("{}_{}_{seed}", spec.name, kind.name());
        let f = write_demo(&demos, &name, &d)?;
        files.push(f.tum);
    }
    println!("simulated {} demonstrations of a {:.2}x{:.2}x{:.2} m box with an offset CoM (rapier, `real` tracking noise) in {}", files.len(), spec.dims[0], spec.dims[1], spec.dims[2], demos.display());

    let config = Config::default();
    let mut tree = Tree::default();
    let reports = learn_into(&mut tree, &files, None, &config)?;
    let cs: Vec<_> = reports.iter().map(|r| &r.classification).collect();
    let tree_path = a.output.join("tree.json");
    tree.save(&tree_path)?;

    // The learnt object: the paper's Fig. 9a, and in 3D with the demonstrations to play back.
    let (model_svg, _) =
        objmodel_plot::plot_model(&tree, "the learnt box (Fig. 9a)", &a.output.join("model"))?;
    let played = files
        .iter()
        .map(|f| objmodel::format::read_demonstration(f, None))
        .collect::<objmodel::Result<Vec<_>>>()?;
    let view = objmodel_plot::write_view(
        &tree,
        "objmodel demo: the learnt box",
        &played,
        &a.output.join("view.html"),
    )?;

    // Fig. 8 for every topple.
    let plots = a.output.join("plots");
    let mut images = Vec::new();
    for r in &reports {
        let c = &r.classification;
        for d in &r.dynamics {
            let stem = c.name.trim_end_matches(".tum");
            let (_, png) = objmodel_plot::plot_angles(
                &fig8(&c.name, d),
                &plots.join(format!("{stem}.angles")),
            )
            .map_err(|e| anyhow::anyhow!("{e}"))?;
            images.push((c.name.clone(), png, d.phi));
        }
    }

    // A plan for the box resting on the palm as in the first demonstration.
    let first = cs[0];
    let (palm_from_object, gravity_in_palm) =
        crate::plan::at_first_poses(&files[0], None, &config.gravity.context("gravity")?)?;
    let planned = plan(
        &tree,
        &PlanRequest {
            palm_from_object,
            towards: None,
            gravity_in_palm,
            margin: None,
        },
    );

    let summary = crate::text::tree(&tree);
    let mut html = String::from("<!doctype html><meta charset=utf-8><title>objmodel demo</title><style>body{font-family:sans-serif;max-width:70em;margin:2em auto}td,th{padding:2px 8px;text-align:left}img{max-width:100%}</style>");
    let _ = write!(html, "<h1>objmodel demo</h1><p>{} demonstrations of a box with a weight inside, simulated with rapier and tracked with 1 mm / 0.5° noise, dropped frames, sign flips and tag mirror flips.</p>", files.len());
    html += "<h2>Demonstrations</h2><table><tr><th>file</th><th>kind</th><th>frames</th><th>tag flips rejected</th></tr>";
    for c in &cs {
        let _ = write!(
            html,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            c.name,
            c.kind.as_str(),
            c.frames,
            c.outliers
        );
    }
    let _ = write!(html, "</table><h2>Object description tree</h2><pre>{}</pre><p><a href=\"tree.json\">tree.json</a> (schema: docs/tree-schema.md)</p>", summary);
    let rel = |p: &PathBuf| p.strip_prefix(&a.output).unwrap_or(p).display().to_string();
    let _ = write!(html, "<h2>The learnt object in 3D</h2><p>Drag to turn it, hover over a feature for its support and uncertainty, play a demonstration back (<a href=\"{v}\">{v}</a> on its own; offline, three.js inside).</p><iframe src=\"{v}\" title=\"the learnt object in 3D\" style=\"width:100%;height:820px;border:1px solid #ccc\"></iframe>", v = rel(&view));
    let _ = write!(html, "<h2>The learnt object (Fig. 9a)</h2><p>Each feature coloured by how it is known: seen in the demonstrations, inferred from seen ones, unknown, or contradicted; hover for details.</p><object data=\"{m}\" type=\"image/svg+xml\" style=\"max-width:100%\"><img src=\"{m}\" alt=\"the learnt object\"></object>", m = rel(&model_svg));
    match &planned {
        Ok(p) => {
            let _ = write!(html, "<h2>Plan</h2><p>For the box as it rests on the palm in {}: tilt the palm by {:.1}° about the line through [{:.3}, {:.3}, {:.3}] m along [{:.3}, {:.3}, {:.3}] (palm frame); edge {}, φ = {:.1}°.</p>", first.name, p.tilt.to_degrees(), p.axis_point.x, p.axis_point.y, p.axis_point.z, p.axis_direction.x, p.axis_direction.y, p.axis_direction.z, p.edge, p.phi.to_degrees());
        }
        Err(e) => {
            let _ = write!(html, "<h2>Plan</h2><p>No plan: {e}</p>");
        }
    }
    html += "<h2>Toppling (Fig. 8)</h2>";
    for (name, png, phi) in &images {
        let rel = png.strip_prefix(&a.output).unwrap_or(png);
        let _ = write!(
            html,
            "<h3>{name}: φ = {}</h3><img src=\"{}\">",
            phi.map_or("?".into(), |p| format!("{:.2}°", p.to_degrees())),
            rel.display()
        );
    }
    // The Fig. 1 loop on the simulated arm: default policy, demonstration, learnt plan.
    if a.task_boxes > 0 {
        let task_dir = a.output.join("task");
        println!("the task on the simulated Panda ({} boxes): default policy, a demonstration (another where one does not locate the edge), the learnt plan", a.task_boxes);
        crate::task::run(&crate::task::TaskArgs {
            boxes: a.task_boxes,
            seed: a.seed,
            json: false,
            no_speed: true,
            plots: Some(task_dir.clone()),
            plot_boxes: a.task_boxes,
        })?;
        let mut pngs: Vec<PathBuf> = std::fs::read_dir(&task_dir)
            .map(|d| {
                d.filter_map(|e| e.ok().map(|e| e.path()))
                    .filter(|p| p.extension().is_some_and(|x| x == "png"))
                    .collect()
            })
            .unwrap_or_default();
        pngs.sort();
        html += "<h2>The task on the simulated arm (Fig. 1, Fig. 5)</h2><p>Each box: the default policy (a fixed 10° tilt) first, then an instrumented demonstration (another, up to three, where one does not locate the edge well enough to be taught), learning, and the planned topple. Run <code>objmodel task --boxes 20</code> for the success rates.</p>";
        for png in &pngs {
            let rel = png.strip_prefix(&a.output).unwrap_or(png);
            let _ = write!(
                html,
                "<h3>{}</h3><img src=\"{}\">",
                rel.file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_default(),
                rel.display()
            );
        }
    }
    let index = a.output.join("index.html");
    objmodel::format::write_atomic(&index, html.as_bytes())?;

    for c in &cs {
        println!("  {}: {}", c.name, c.kind.as_str());
    }
    print!("{summary}");
    match planned {
        Ok(p) => println!(
            "plan for the box on the palm: tilt {:.1} deg about edge {} (phi {:.1} deg)",
            p.tilt.to_degrees(),
            p.edge,
            p.phi.to_degrees()
        ),
        Err(e) => println!("no plan: {e}"),
    }
    println!(
        "wrote {}, {} plots and {}",
        tree_path.display(),
        images.len(),
        index.display()
    );
    Ok(())
}
