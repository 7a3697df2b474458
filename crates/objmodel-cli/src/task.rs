//! `objmodel task`: the Fig. 1 loop on the simulated Panda: per random box, the default policy,
//! and if it fails one demonstration, learning, and the planned topple.

use anyhow::Result;
use nalgebra::{Isometry3, Point3, Vector3};
use objmodel_sim::task::{run_task, speed, BoxOutcome, TaskConfig, ToppleRun};
use serde_json::json;

/// Arguments of `objmodel task`.
#[derive(clap::Args)]
pub struct TaskArgs {
    /// Number of random boxes.
    #[arg(long, default_value_t = 20)]
    pub boxes: usize,
    /// Seed of the draw.
    #[arg(long, default_value_t = 7)]
    pub seed: u64,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Skip the planning-speed comparison (a bisection with the full simulation).
    #[arg(long)]
    pub no_speed: bool,
    /// Write pictures (palm and box angles over time with the topple marked; a side view in the
    /// plane normal to the edge at several instants) for the first `--plot-boxes` boxes here.
    #[arg(long)]
    pub plots: Option<std::path::PathBuf>,
    /// How many boxes to draw pictures for.
    #[arg(long, default_value_t = 3)]
    pub plot_boxes: usize,
}

fn hull(mut pts: Vec<[f64; 2]>) -> Vec<[f64; 2]> {
    pts.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let mut lower: Vec<[f64; 2]> = Vec::new();
    for &p in &pts {
        while lower.len() >= 2 && cross(lower[lower.len() - 2], lower[lower.len() - 1], p) <= 0.0 {
            lower.pop();
        }
        lower.push(p);
    }
    let mut upper: Vec<[f64; 2]> = Vec::new();
    for &p in pts.iter().rev() {
        while upper.len() >= 2 && cross(upper[upper.len() - 2], upper[upper.len() - 1], p) <= 0.0 {
            upper.pop();
        }
        upper.push(p);
    }
    lower.pop();
    upper.pop();
    lower.extend(upper);
    lower
}

/// Angles over time and the side view of one attempt.
fn plot_attempt(
    dir: &std::path::Path,
    stem: &str,
    title: &str,
    run: &ToppleRun,
    half: &Vector3<f64>,
    phi: Option<f64>,
) -> Result<Vec<std::path::PathBuf>> {
    use objmodel_plot::{AngleSeries, Fig8, Outline, SideView};
    let ser = |label: &str, f: &dyn Fn(&objmodel_sim::task::SeriesPoint) -> f64| AngleSeries {
        label: label.into(),
        t: run.series.iter().map(|p| p.t).collect(),
        angle_rad: run.series.iter().map(f).collect(),
    };
    let mut marks = Vec::new();
    if let Some(tl) = run.t_level {
        marks.push(("palm levels".to_string(), tl, run.palm_tilt_reached));
    }
    if let Some(tt) = run.t_topple {
        if let Some(p) = run.series.iter().find(|p| p.t >= tt - 1e-9) {
            marks.push(("topple detected".to_string(), p.t, p.box_world));
        }
    }
    let fig = Fig8 {
        title: title.to_string(),
        series: vec![
            ser("palm tilt (commanded)", &|p| p.palm_commanded),
            ser("palm tilt (encoders)", &|p| p.palm),
            ser("box tilt in the world (tracked)", &|p| p.box_world),
            ser("box tilt relative to the palm (tracked)", &|p| p.box_rel),
        ],
        onset_t: run.t_level,
        phi_rad: phi,
        marks,
    };
    let mut out = Vec::new();
    let (svg, png) = objmodel_plot::plot_angles(&fig, &dir.join(format!("{stem}_angles")))?;
    out.push(svg);
    out.push(png);
    // Side view in the plane normal to the tilt axis.
    let u = Vector3::from(run.axis_world).normalize();
    let z = Vector3::z();
    let h = z.cross(&u).try_normalize(1e-9).unwrap_or(Vector3::x());
    let v = u.cross(&h);
    let p0 = Vector3::from(run.axis_point_world);
    let proj = |p: Point3<f64>| [h.dot(&(p.coords - p0)), v.dot(&(p.coords - p0))];
    let corners = |iso: &Isometry3<f64>, hx: f64, hy: f64, z0: f64, z1: f64| {
        let mut pts = Vec::new();
        for sx in [-hx, hx] {
            for sy in [-hy, hy] {
                for sz in [z0, z1] {
                    pts.push(proj(iso * Point3::new(sx, sy, sz)));
                }
            }
        }
        hull(pts)
    };
    let end = run.snapshots.last().map_or(0.0, |s| s.t);
    let mut instants = vec![0.0];
    match run.t_level {
        Some(tl) => instants.extend([0.5 * tl, tl, tl + 0.1, tl + 0.2, tl + 0.35, end]),
        None => instants.extend([0.5 * end, end]),
    }
    let mut frames = Vec::new();
    for t in instants {
        let Some(s) = run
            .snapshots
            .iter()
            .min_by(|a, b| (a.t - t).abs().total_cmp(&(b.t - t).abs()))
        else {
            continue;
        };
        frames.push((
            s.t,
            vec![
                Outline {
                    label: "palm".into(),
                    points: corners(&s.world_from_palm, 0.1, 0.1, -0.01, 0.0),
                },
                Outline {
                    label: "box".into(),
                    points: corners(&s.world_from_box, half.x, half.y, -half.z, half.z),
                },
            ],
        ));
    }
    let sv = SideView {
        title: format!("{title}: side view normal to the tilt axis"),
        frames,
    };
    let (svg, png) = objmodel_plot::plot_side_view(&sv, &dir.join(format!("{stem}_side")))?;
    out.push(svg);
    out.push(png);
    Ok(out)
}

fn line(i: usize, b: &BoxOutcome) -> String {
    let att = |a: &objmodel_sim::task::run::Attempt| {
        format!(
            "{} (tilt {:.1} deg, reached {:.1} deg{})",
            if a.success { "ok" } else { "FAIL" },
            a.tilt_deg,
            a.palm_tilt_reached_deg,
            if a.topple_detected {
                ", topple seen"
            } else {
                ""
            }
        )
    };
    format!(
        "{:>3} {:.3}x{:.3}x{:.3} m {:.2} kg mu {:.2} phi {:.1} deg | default {} | {}{} | {}",
        i,
        b.dims[0],
        b.dims[1],
        b.dims[2],
        b.mass,
        b.friction,
        b.phi_true_deg,
        att(&b.default),
        b.phi_learnt_deg
            .map(|p| format!("learnt phi {p:.1} deg, "))
            .unwrap_or_default(),
        b.planned
            .as_ref()
            .map(|a| format!("planned {}", att(a)))
            .unwrap_or_else(|| "no planned attempt".into()),
        b.reason
    )
}

/// Run `objmodel task`.
pub fn run(a: &TaskArgs) -> Result<()> {
    let cfg = TaskConfig {
        boxes: a.boxes,
        seed: a.seed,
        ..TaskConfig::default()
    };
    let t = std::time::Instant::now();
    let rep = run_task(&cfg, |i, b| eprintln!("{}", line(i, b)))?;
    let elapsed = t.elapsed().as_secs_f64();
    let speed = if a.no_speed {
        None
    } else {
        rep.boxes.iter().find_map(|b| {
            let (tree, req) = b.learnt.as_ref()?;
            let tr = b.trial.as_ref()?;
            eprintln!(
                "planning speed: bisection with the full simulation on {} ...",
                b.name
            );
            speed::compare(
                tree,
                req,
                &tr.spec,
                tr.axis,
                tr.sign,
                20000,
                0.25f64.to_radians(),
            )
            .ok()
        })
    };
    let mut pictures = Vec::new();
    if let Some(dir) = &a.plots {
        for b in rep.boxes.iter().take(a.plot_boxes) {
            let Some(tr) = &b.trial else { continue };
            let half = tr.spec.half_extents();
            let phi = b.plan.as_ref().map(|p| p.phi);
            let attempts = [
                ("default", Some(&b.default)),
                ("planned", b.planned.as_ref()),
            ];
            for (which, att) in attempts {
                let Some(run) = att.and_then(|x| x.run.as_ref()) else {
                    continue;
                };
                let title = format!("{} {which} attempt", b.name);
                let ph = if which == "planned" { phi } else { None };
                pictures.extend(plot_attempt(
                    dir,
                    &format!("{}_{which}", b.name),
                    &title,
                    run,
                    &half,
                    ph,
                )?);
            }
        }
        eprintln!(
            "wrote {} picture files to {}",
            pictures.len(),
            dir.display()
        );
    }
    let pct = |k: usize| 100.0 * k as f64 / rep.trials.max(1) as f64;
    if a.json {
        let mut v = serde_json::to_value(&rep)?;
        v["planning_speed"] = json!(speed);
        v["wall_s"] = json!(elapsed);
        v["pictures"] = json!(pictures);
        crate::output::out(&format!("{}\n", serde_json::to_string_pretty(&v)?))?;
        return Ok(());
    }
    let mut s = String::new();
    for (i, b) in rep.boxes.iter().enumerate() {
        s.push_str(&line(i, b));
        s.push('\n');
    }
    s.push_str(&format!(
        "\n{} boxes ({} draws excluded by the admissibility rule)\n\
         default policy:            {}/{} ({:.0}%)\n\
         after one demonstration:   {}/{} ({:.0}%)  [{} demonstrations, {} planned successes]\n\
         with up to {} demonstrations: {}/{} ({:.0}%)\n\
         palm tracking error:       max {:.3} mm, {:.4} deg\n",
        rep.trials,
        rep.excluded_draws,
        rep.success_default,
        rep.trials,
        pct(rep.success_default),
        rep.success_after_one_demo,
        rep.trials,
        pct(rep.success_after_one_demo),
        rep.demonstrations,
        rep.success_planned,
        objmodel_sim::task::MAX_DEMOS,
        rep.success_default + rep.success_planned,
        rep.trials,
        pct(rep.success_default + rep.success_planned),
        rep.max_tracking_mm,
        rep.max_tracking_deg
    ));
    if let Some(sp) = &speed {
        s.push_str(&format!(
            "planning speed:            skill::plan {:.2} us (phi {:.2} deg); simulation bisection {:.2} s, {} probes (phi {:.2} deg); ratio {:.2e}\n",
            sp.plan_us, sp.plan_phi_deg, sp.search_s, sp.probes, sp.search_phi_deg, sp.ratio
        ));
    }
    s.push_str(&format!("wall time {elapsed:.1} s\n"));
    crate::output::out(&s)
}
