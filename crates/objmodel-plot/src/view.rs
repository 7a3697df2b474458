//! The learnt object in 3D: one HTML page that needs nothing but a browser with WebGL, no
//! network. Into the template `assets/view.html` go three.js (the bundle
//! `assets/three/three.bundle.min.js`, built from the npm registry's `three` by
//! `assets/three/update.sh`, see `assets/three/README.md`) and the data: the
//! [`ModelDrawing`] of the tree, the legend, and the demonstrations to play back.
//!
//! The page reports its own state in `<pre id="objmodel-status" data-state=...>`: `drawn` once
//! the model is on the screen, `error` when anything failed; every script error, unhandled
//! rejection and `console.error` is written into `<pre id="objmodel-errors">` too, visibly.
//! With `#selftest` in its address, the page also checks itself after drawing: it hovers over
//! the centre of mass (or the first vertex) and writes the picked feature's id into
//! `data-picked`, and plays the first demonstration to its middle and writes `data-playback`.

use crate::feature::Known;
use crate::model::ModelDrawing;
use crate::PlotError;
use objmodel::tree::Tree;
use objmodel::Demonstration;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// The three.js bundle, a classic script that defines the global `THREE`.
static THREE_JS: &str = include_str!("../assets/three/three.bundle.min.js");
/// The page template.
static TEMPLATE: &str = include_str!("../assets/view.html");
/// three.js's version in the bundle (`assets/three/package.json`).
pub const THREE_VERSION: &str = "0.187.0";
/// At most this many poses of a demonstration go into the page (evenly chosen), so that a long
/// recording does not make it large.
pub const MAX_PLAYBACK_FRAMES: usize = 3000;

#[derive(Serialize)]
struct Legend {
    known: Known,
    colour: String,
    meaning: &'static str,
}

/// Poses over time: times \[s\], positions \[m\], quaternions `[x, y, z, w]`.
#[derive(Serialize)]
struct Poses {
    t: Vec<f64>,
    p: Vec<[f64; 3]>,
    q: Vec<[f64; 4]>,
}

#[derive(Serialize)]
struct Playback {
    name: String,
    object: Poses,
    palm: Option<Poses>,
}

#[derive(Serialize)]
struct PageData<'a> {
    title: &'a str,
    three_version: &'static str,
    drawing: ModelDrawing,
    legend: Vec<Legend>,
    demos: Vec<Playback>,
}

/// At most [`MAX_PLAYBACK_FRAMES`] of `poses`, evenly spread, first and last kept.
fn poses(poses: &[objmodel::StampedPose]) -> Poses {
    let n = poses.len();
    let keep: Vec<usize> = if n <= MAX_PLAYBACK_FRAMES {
        (0..n).collect()
    } else {
        (0..MAX_PLAYBACK_FRAMES)
            .map(|i| i * (n - 1) / (MAX_PLAYBACK_FRAMES - 1))
            .collect()
    };
    let r = |x: f64| (x * 1e6).round() / 1e6;
    Poses {
        t: keep.iter().map(|&i| r(poses[i].t)).collect(),
        p: keep
            .iter()
            .map(|&i| {
                let v = poses[i].pose.translation.vector;
                [r(v.x), r(v.y), r(v.z)]
            })
            .collect(),
        q: keep
            .iter()
            .map(|&i| {
                let q = poses[i].pose.rotation;
                [r(q.i), r(q.j), r(q.k), r(q.w)]
            })
            .collect(),
    }
}

/// The 3D view of `tree` as one self-contained HTML page titled `title`; `demos` (their
/// `world_from_object` poses, and the palm's when instrumented) can be played back on it.
pub fn page(tree: &Tree, title: &str, demos: &[Demonstration]) -> String {
    let data = PageData {
        title,
        three_version: THREE_VERSION,
        drawing: ModelDrawing::from_tree(tree),
        legend: Known::ALL
            .iter()
            .map(|k| {
                let [r, g, b] = k.rgb();
                Legend {
                    known: *k,
                    colour: format!("#{r:02x}{g:02x}{b:02x}"),
                    meaning: k.meaning(),
                }
            })
            .collect(),
        demos: demos
            .iter()
            .filter(|d| !d.object.is_empty())
            .map(|d| Playback {
                name: d.name.clone(),
                object: poses(&d.object),
                palm: d.palm.as_deref().filter(|p| !p.is_empty()).map(poses),
            })
            .collect(),
    };
    // Inside <script>, "<" only ever appears in JSON strings, where \u003c means the same.
    let json = serde_json::to_string(&data)
        .expect("plain data serialises")
        .replace('<', "\\u003c");
    let title = title
        .replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;");
    TEMPLATE
        .replacen("@TITLE@", &title, 1)
        .replacen("/*@THREE_JS@*/", THREE_JS, 1)
        .replacen("@DATA_JSON@", &json, 1)
}

pub(crate) fn write(
    tree: &Tree,
    title: &str,
    demos: &[Demonstration],
    path: &Path,
) -> Result<PathBuf, PlotError> {
    crate::common::ensure_dir(path)?;
    crate::common::write_atomic(path, page(tree, title, demos).as_bytes())?;
    Ok(path.to_path_buf())
}
