//! People's text: summaries of classifications and trees, and warnings, for standard error
//! and standard output (JSON goes through serde).

use objmodel::classify::{Classification, Label};
use objmodel::format::LengthUnit;
use objmodel::tree::Tree;
use std::path::Path;

pub fn v3(v: &nalgebra::Vector3<f64>) -> String {
    format!("[{:+.4}, {:+.4}, {:+.4}]", v.x, v.y, v.z)
}

/// A human summary of a classification; with `frames`, its per-frame label runs too.
pub fn classification(c: &Classification, frames: bool) -> String {
    let mut s = format!(
        "{}: {} ({} method{})\n  {} frames, {} rejected as tag flips{}; votes: topple {}, slide {}, general {}\n",
        c.name,
        c.kind.as_str(),
        match c.method {
            objmodel::classify::Method::Robust => "robust",
            objmodel::classify::Method::Paper => "paper",
        },
        if c.instrumented { ", relative to the palm" } else { "" },
        c.frames,
        c.outliers - c.held_frames,
        if c.held_frames > 0 {
            format!(" and {} as held poses", c.held_frames)
        } else {
            String::new()
        },
        c.votes.topple,
        c.votes.slide,
        c.votes.general
    );
    for w in &c.warnings {
        s += &format!("  warning: {w}\n");
    }
    if let Some(u) = c.length_unit.filter(|&u| u != LengthUnit::Metres) {
        s += &format!("  positions read in {u}, converted to metres\n");
    }
    if let Some(n) = c.noise {
        // Relative to a palm, given noise is propagated from both trackers' noise.
        s += &format!(
            "  tracking noise{} ({}): {:.2} mm, {:.2} deg per axis\n",
            if c.instrumented {
                " of the motion relative to the palm"
            } else {
                ""
            },
            match (c.noise_given, c.instrumented, c.noise_shared) {
                (true, true, _) => "from the noise given",
                (true, false, _) => "given",
                (false, _, Some(_)) => "measured on the rests of the demonstrations learnt with it",
                (false, _, None) => "estimated",
            },
            n.sigma_position * 1e3,
            n.sigma_rotation.to_degrees()
        );
    }
    for (i, seg) in c.segments.iter().enumerate() {
        s += &format!(
            "  segment {i}: {:.2}-{:.2} s, {}, up to {:.1} deg\n",
            seg.t_start,
            seg.t_end,
            seg.kind.as_str(),
            seg.max_angle.to_degrees()
        );
        if let Some(e) = &seg.edge {
            s += &format!(
                "    edge: point {} m, direction {}, ±{:.2} mm, ±{:.2} deg ({} frames)\n",
                v3(&e.line.point),
                v3(&e.line.direction),
                e.sigma_point() * 1e3,
                e.sigma_direction().to_degrees(),
                e.frames
            );
            s += &loose(e.bounds(0.95), "      ");
        }
        if let Some(f) = &seg.face {
            s += &format!(
                "    face normal {}{}, ±{:.2} deg\n",
                v3(&f.normal),
                if f.sign_known {
                    " (outward)"
                } else {
                    " (sign unknown)"
                },
                f.sigma_normal().to_degrees()
            );
        }
        if let Some(w) = &seg.withheld {
            s += &format!("    {w}\n");
        }
        if let Some(w) = &seg.remeasured {
            s += &format!("    {w}\n");
        }
    }
    for r in &c.rolls {
        let e = &r.edge;
        s += &format!(
            "  roll {:.2}-{:.2} s, {:.1} deg: edge point {} m, direction {}, ±{:.2} mm, ±{:.2} deg \
             ({} frames){}\n",
            r.t_start,
            r.t_end,
            r.turn.to_degrees(),
            v3(&e.line.point),
            v3(&e.line.direction),
            e.sigma_point() * 1e3,
            e.sigma_direction().to_degrees(),
            e.frames,
            if r.taught { ", taught" } else { "" }
        );
    }
    for r in &c.rolls_rejected {
        s += &format!(
            "  no roll {:.2}-{:.2} s, {:.1} deg about a fixed line ({} frames): {}\n",
            r.t_start,
            r.t_end,
            r.turn.to_degrees(),
            r.frames,
            r.why
        );
    }
    if c.parts.len() > 1 {
        s += "  parts:\n";
        for p in &c.parts {
            let kind = serde_json::to_value(p.kind)
                .ok()
                .and_then(|v| v.as_str().map(str::to_string))
                .unwrap_or_default();
            s += &format!(
                "    {:.2}-{:.2} s  {kind}{}{}{}\n",
                p.t_start,
                p.t_end,
                if p.taught.is_empty() {
                    String::new()
                } else {
                    format!(", taught {}", p.taught.join(", "))
                },
                p.withheld
                    .as_ref()
                    .map_or(String::new(), |w| format!(" ({w})")),
                p.com_estimate.as_ref().map_or(String::new(), |e| format!(
                    ", centre of mass {} ±{:.1} mm (object frame, from {} frames)",
                    v3(&e.point),
                    1e3 * e.covariance.symmetric_eigenvalues().max().max(0.0).sqrt(),
                    e.frames
                ))
            );
        }
    }
    for f in c.rest_faces() {
        s += &format!(
            "  rest on the support: face normal {} (outward), ±{:.2} deg ({} frames)\n",
            v3(&f.normal),
            f.sigma_normal().to_degrees(),
            f.frames
        );
    }
    if frames {
        s += "  frames:\n";
        for r in &c.labels {
            let label = match r.label {
                Label::Rest => "rest",
                Label::Outlier => "outlier",
                Label::Still => "still",
                Label::Topple => "topple",
                Label::Slide => "slide",
                Label::General => "general",
                Label::Landing => "landing",
                Label::Unlabelled => "unlabelled",
                Label::Flight => "flight",
                Label::Impact => "impact",
                Label::Roll => "roll",
                Label::Creep => "creep",
            };
            s += &format!(
                "    {:>6}-{:<6} {:>8.3}-{:<8.3} s  {label}\n",
                r.first, r.last, r.t_start, r.t_end
            );
        }
    }
    s
}

/// The classification's warnings about its input, on standard error, each with its file.
pub fn print_warnings(demo: &Path, c: &Classification) {
    for w in &c.warnings {
        eprintln!("warning: {}: {w}", demo.display());
    }
}

/// Where an edge's σ leaves it farther from its estimate than an edge of the object may be
/// (5 mm, 3°) one time in twenty, its 95% `bounds` (\[m\], \[rad\]) on a line of their own,
/// so that no one takes it for located; else nothing.
fn loose((r, a): (f64, f64), indent: &str) -> String {
    if r <= objmodel::edge::EDGE_MATCH_M && a <= objmodel::edge::EDGE_MATCH_RAD {
        return String::new();
    }
    format!(
        "{indent}(within {:.1} mm and {:.1} deg of this at 95%, by its σ: more demonstrations of \
         this edge would locate it better)\n",
        r * 1e3,
        a.to_degrees()
    )
}

/// `n` and `thing`, plural where `n` is not 1 ("1 demo", "3 demos").
fn count(n: usize, thing: &str) -> String {
    format!("{n} {thing}{}", if n == 1 { "" } else { "s" })
}

/// A short human summary of a tree.
pub fn tree(tree: &Tree) -> String {
    let mut s = format!(
        "{} demonstrations, {} edges, {} faces (object frame)\n",
        tree.demos.len(),
        tree.edges.len(),
        tree.faces.len()
    );
    for e in &tree.edges {
        s += &format!(
            "  {}: point {} m, direction {}, ±{:.2} mm, ±{:.2} deg, {}\n",
            e.id,
            v3(&e.point),
            v3(&e.direction),
            e.sigma_point_m * 1e3,
            e.sigma_direction_rad.to_degrees(),
            count(e.n_support, "demo")
        );
        s += &loose(e.bounds(0.95), "    ");
    }
    for e in &tree.edges {
        for p in &e.pendulums {
            s += &format!(
                "  {} pendulum, resting on {}: phi {} ±{:.2} deg, I/(m l_p) {}, {}\n",
                e.id,
                v3(&p.resting_face_normal),
                p.phi
                    .map_or("?".into(), |x| format!("{:.2}", x.to_degrees())),
                p.phi_sigma.unwrap_or(f64::NAN).to_degrees(),
                p.inertia_ratio_m
                    .map_or("?".into(), |x| format!("{:.3} m", x)),
                count(p.observations.len(), "demo")
            );
        }
    }
    if let Some(com) = &tree.com {
        let sigma = com.sigma_m.map_or(String::new(), |x| {
            format!("±{:.1} mm (worst axis), ", x * 1e3)
        });
        let rms = if com.pendulums > 0 {
            format!(", planes' rms {:.1} mm", com.rms_residual_m * 1e3)
        } else {
            String::new()
        };
        s += &format!(
            "  centre of mass: {} m {sigma}(from {}{rms})\n",
            v3(&com.point),
            com.learnt_from(),
        );
    }
    for f in &tree.faces {
        let off = f.offset.map_or("offset unknown".to_string(), |o| {
            format!(
                "offset {o:+.4} m ±{:.2} mm",
                f.offset_sigma_m.unwrap_or(0.0) * 1e3
            )
        });
        let landings = match f.evidence.landing {
            0 => String::new(),
            n => format!(", {}", count(n, "landing")),
        };
        s += &format!(
            "  {}: normal {}, {off}, ±{:.2} deg, {} ({}, {}{landings})\n",
            f.id,
            v3(&f.normal),
            f.sigma_normal_rad.to_degrees(),
            count(f.n_support, "demo"),
            count(f.evidence.slide, "slide"),
            count(f.evidence.rest, "rest")
        );
    }
    if let Some(sp) = &tree.support {
        let from = if sp.given {
            "given".to_string()
        } else {
            format!(
                "measured by {} edges on it in {} demonstrations",
                sp.observations, sp.demos
            )
        };
        s += &format!(
            "  support: height {:+.4} m ±{:.2} mm ({from})\n",
            sp.height,
            sp.sigma_m * 1e3
        );
    }
    match tree.reconstruct_shape() {
        Ok(shape) => {
            s += &format!(
                "  shape: closed, {} faces, {} vertices, extents {} to {} m\n",
                shape.faces.len(),
                shape.vertices.len(),
                v3(&shape.extents[0]),
                v3(&shape.extents[1])
            );
            for (id, why) in &shape.left_out {
                s += &format!("    {id} left out: {why}\n");
            }
            for a in &shape.assumptions {
                s += &format!("    assumed: {a}\n");
            }
        }
        Err(e) => s += &format!("  shape: not closed yet: {e}\n"),
    }
    if let Some(i) = &tree.inertia {
        let ev = i.matrix().symmetric_eigenvalues();
        s += &format!(
            "  inertia per kg about the CoM: principal {:.2}, {:.2}, {:.2} cm² ({})\n",
            ev[0] * 1e4,
            ev[1] * 1e4,
            ev[2] * 1e4,
            i.note
        );
    }
    if let Some(f) = &tree.friction {
        s += &format!("  friction: {}\n", f.note);
    }
    if !tree.predictions.is_empty() {
        s += "  predicted pendulums (shape and CoM), resting face -> landing face: phi, l_p; \
              observed beside\n";
    }
    for q in &tree.predictions {
        let sd = |x: Option<f64>, k: f64| x.map_or(String::new(), |x| format!(" ±{:.2}", x * k));
        let observed = q.observed.as_ref().map_or(String::new(), |o| {
            format!(
                "; observed {}: phi {:.2}{} deg{}",
                o.edge,
                o.phi.to_degrees(),
                sd(o.phi_sigma, 180.0 / std::f64::consts::PI),
                o.phi_z
                    .map_or(String::new(), |z| format!(" ({z:+.1} sigma)"))
            )
        });
        s += &format!(
            "    {} -> {}: phi {:.2}{} deg, l_p {:.1}{} mm{observed}\n",
            q.resting_face,
            q.landing_face,
            q.phi.to_degrees(),
            sd(q.phi_sigma, 180.0 / std::f64::consts::PI),
            q.l_p * 1e3,
            sd(q.l_p_sigma, 1e3),
        );
    }
    for w in tree.unlocated_edges() {
        s += &format!("  held back: {}\n", w.why);
    }
    for c in &tree.contradictions {
        s += &format!("  contradiction: {}\n", c.what);
    }
    s
}
