//! The claims as a Markdown report: a summary line per box, then every tilting-palm
//! experiment.

use super::{onset_claim, onset_error_deg, BoxClaims, FaceOnset, ONSET_DEG, POSITION_M};
use crate::onset::Onset;

fn onset_cell(o: &Onset) -> String {
    match o {
        Onset::Topples(t) => format!("{:.2}", t.to_degrees()),
        Onset::Slides(t) => format!("slides {:.1}", t.to_degrees()),
        Onset::Neither => "none".into(),
    }
}

fn pair_cells(p: Option<&[Onset; 2]>) -> String {
    match p {
        None => "| – | – | – ".into(),
        Some(p) => format!(
            "| {} | {} | {} ",
            onset_cell(&p[0]),
            onset_cell(&p[1]),
            onset_error_deg(p).map_or("–".into(), |d| format!("{d:+.2}"))
        ),
    }
}

/// Worst |onset error| \[deg\] and how many experiments (of those where the true box topples)
/// meet the claim, over `pairs`.
fn summary<'a>(pairs: impl Iterator<Item = &'a [Onset; 2]>) -> (f64, usize, usize) {
    let (mut worst, mut ok, mut n) = (0.0f64, 0, 0);
    for p in pairs {
        if !matches!(p[0], Onset::Topples(_)) {
            continue;
        }
        n += 1;
        ok += onset_claim(p) as usize;
        worst = worst.max(onset_error_deg(p).map_or(f64::INFINITY, f64::abs));
    }
    (worst, ok, n)
}

/// The experiments the onset claim is about: a face the box can rest on without sliding,
/// tilted one way (not those where `tan φ > μ`: quasi-statically the true box slides first;
/// which of slide and topple a simulator registers first there depends on its contact model;
/// nor those where it tips less than [`ONSET_DEG`] before its friction angle, which a φ within
/// the claim does not decide: `FaceOnset::at_friction_limit`).
pub fn claimed(b: &BoxClaims) -> impl Iterator<Item = &super::FaceOnset> {
    b.onsets
        .iter()
        .filter(|o| !o.slides_first && !o.at_friction_limit)
}

/// Whether every claim holds for `b`: corners and CoM within [`POSITION_M`], and every onset
/// it makes ([`claimed`]) where the true box topples within [`ONSET_DEG`] in each simulator
/// that ran.
pub fn holds(b: &BoxClaims) -> bool {
    b.error.is_none()
        && b.corner_error_m <= POSITION_M
        && b.com_error_m <= POSITION_M
        && claimed(b).all(|o| onset_claim(&o.rapier) && o.mujoco.as_ref().is_none_or(onset_claim))
}

/// The per-box summary table.
pub fn summary_table(boxes: &[BoxClaims]) -> String {
    let mut s = String::from(
        "| box | demos | shape | corners [mm] | CoM [mm] | CoM from | rapier onset | MuJoCo onset | all claims |\n\
         |---|---|---|---|---|---|---|---|---|\n",
    );
    for b in boxes {
        if let Some(e) = &b.error {
            s += &format!(
                "| {} | {} | – | – | – | – | – | – | no model: {e} |\n",
                b.name, b.demos
            );
            continue;
        }
        let (wr, okr, nr) = summary(claimed(b).map(|o| &o.rapier));
        let mj: Vec<&[Onset; 2]> = claimed(b).filter_map(|o| o.mujoco.as_ref()).collect();
        let mujoco = if mj.is_empty() {
            "not run".to_string()
        } else {
            let (wm, okm, nm) = summary(mj.into_iter());
            format!("{wm:.2}°, {okm}/{nm}")
        };
        s += &format!(
            "| {} | {} | {} | {:.2} | {:.2} | {} | {wr:.2}°, {okr}/{nr} | {mujoco} | {} |\n",
            b.name,
            b.demos,
            b.shape,
            b.corner_error_m * 1e3,
            b.com_error_m * 1e3,
            if b.com_learnt {
                "pendulums"
            } else {
                "centroid"
            },
            if holds(b) { "yes" } else { "**no**" },
        );
    }
    for b in boxes.iter().filter(|b| !b.assumptions.is_empty()) {
        s += &format!(
            "\n{}'s shape assumes: {}\n",
            b.name,
            b.assumptions.join("; ")
        );
    }
    s
}

/// The report: `intro` (what was measured, how), the summary, `more` (further sections), then
/// every experiment.
pub fn markdown(intro: &str, boxes: &[BoxClaims], more: &str) -> String {
    let mut s = String::from(intro);
    s += &format!(
        "\n## Per box\n\nClaims: corners and CoM within {:.0} mm, onset within {ONSET_DEG:.0}° \
         of the true box's in the same simulator wherever the true box topples, resting on a face it \
         can rest on without sliding (not the rows marked † below, where `tan φ > μ`: \
         quasi-statically the true box slides first, and which of slide and topple a simulator \
         registers first depends on its contact model; nor the rows marked ‡, where the true \
         box tips less than {ONSET_DEG:.0}° before its friction angle `atan μ`: a learnt φ \
         within the claim may slide there, so the claim does not decide them). Onset columns: \
         worst |learnt − true| \
         [deg] and experiments meeting the claim / experiments where the true box topples.\n\n",
        POSITION_M * 1e3
    );
    s += &summary_table(boxes);
    let (wr, okr, nr) = summary(boxes.iter().flat_map(|b| claimed(b).map(|o| &o.rapier)));
    let (wm, okm, nm) = summary(
        boxes
            .iter()
            .flat_map(|b| claimed(b).filter_map(|o| o.mujoco.as_ref())),
    );
    let within = |b: &&BoxClaims, x: f64| b.error.is_none() && x <= POSITION_M;
    s += &format!(
        "\nIn all: corners within {:.0} mm for {} of {} boxes, CoM for {}; onsets within \
         {ONSET_DEG:.0}° in {okr} of {nr} rapier experiments (worst {wr:.2}°) and {okm} of {nm} \
         MuJoCo ones (worst {wm:.2}°). A worst of inf° means the learnt body slid where the true \
         box toppled.\n",
        POSITION_M * 1e3,
        boxes.iter().filter(|b| within(b, b.corner_error_m)).count(),
        boxes.len(),
        boxes.iter().filter(|b| within(b, b.com_error_m)).count(),
    );
    let (within, judged) = within_two_sigma(boxes);
    s += &format!(
        "\nThe model's own uncertainty: for each (face, edge) pair the tree predicts φ with a \
         standard deviation propagated from its shape and its CoM's covariance (`σ` below). \
         Where the true box topples, the learnt φ is within 2σ of the true box's in {within} \
         of {judged} experiments with a σ (an honest σ: about 95%).\n"
    );
    s += more;
    s += "\n## Every experiment\n\nThe face of the true box it rests on and the box axis the \
          tilt carries it towards; φ: quasi-static tipping angles [deg] of the true box and the \
          learnt body, and the model's σ of its φ; onsets [deg] of the true box, the learnt body and their difference, in \
          each simulator. `slides X`: it slid first, at X°. Rows where the true box's \
          `tan φ > μ` (it must slide first) are marked †, those where it tips within \
          1° of its friction angle ‡.\n\n\
          | box | face | toward | φ true | φ learnt | σ | rapier true | rapier learnt | Δ | MuJoCo true | MuJoCo learnt | Δ |\n\
          |---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for b in boxes {
        for o in &b.onsets {
            s += &row(&b.name, o);
        }
    }
    s
}

/// Of the experiments where the true box topples and the model has a σ for its φ, how many
/// have the learnt φ within 2σ of the true one, and how many there are.
pub fn within_two_sigma(boxes: &[BoxClaims]) -> (usize, usize) {
    let judged: Vec<bool> = boxes
        .iter()
        .flat_map(|b| &b.onsets)
        .filter(|o| matches!(o.rapier[0], Onset::Topples(_)))
        .filter_map(|o| {
            let s = o.phi_sigma_deg?;
            Some((o.phi_deg[1] - o.phi_deg[0]).abs() <= 2.0 * s)
        })
        .collect();
    (judged.iter().filter(|w| **w).count(), judged.len())
}

fn row(name: &str, o: &FaceOnset) -> String {
    format!(
        "| {name} | {}{} | {} | {:.2} | {:.2} | {} {}{}|\n",
        o.face,
        if o.slides_first {
            " †"
        } else if o.at_friction_limit {
            " ‡"
        } else {
            ""
        },
        o.toward,
        o.phi_deg[0],
        o.phi_deg[1],
        o.phi_sigma_deg.map_or("–".into(), |s| format!("{s:.2}")),
        pair_cells(Some(&o.rapier)),
        pair_cells(o.mujoco.as_ref()),
    )
}
