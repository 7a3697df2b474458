//! The legend of the paper's Fig. 9a ([`crate::fig9a`]): the colours' meanings, the symbols,
//! the counts, the notes on what is unknown, and the object frame's axes.

use nalgebra::Vector3;

use crate::canvas::{Canvas, Shape2, Tag};
use crate::feature::{FeatureKind, Known};
use crate::fig9a_view::{View, INK, LEFT, ORIGIN_GREEN, SIDE, TOP};
use crate::model::ModelDrawing;

/// The object frame's axes, small, in the lower left corner.
pub(crate) fn axes(c: &mut Canvas, view: &View) {
    let o = (LEFT + 40.0, TOP + SIDE - 30.0);
    for (i, name) in ["x", "y", "z"].iter().enumerate() {
        let u = Vector3::ith(i, 1.0);
        let b = (
            o.0 + 32.0 * view.right.dot(&u),
            o.1 - 32.0 * view.up.dot(&u),
        );
        c.push(
            Shape2::Line {
                a: o,
                b,
                colour: INK,
                width: 1.5,
                dashed: false,
            },
            Tag::default(),
        );
        c.push(
            Shape2::Text {
                at: (b.0 + 2.0, b.1 + 4.0),
                text: name.to_string(),
                colour: INK,
                size: 13.0,
                middle: false,
            },
            Tag::default(),
        );
    }
}

/// Words of `s` in lines of at most `width` characters.
fn wrap(s: &str, width: usize) -> Vec<String> {
    let mut lines: Vec<String> = vec![String::new()];
    for w in s.split_whitespace() {
        let last = lines.last_mut().expect("never empty");
        if !last.is_empty() && last.chars().count() + 1 + w.chars().count() > width {
            lines.push(w.to_string());
        } else {
            if !last.is_empty() {
                last.push(' ');
            }
            last.push_str(w);
        }
    }
    lines
}

/// The colours' meanings, the symbols, and the notes.
pub(crate) fn legend(c: &mut Canvas, d: &ModelDrawing) {
    let x = LEFT + SIDE + 20.0;
    let mut y = TOP + 20.0;
    let line = |c: &mut Canvas, y: f64, s: &str, colour| {
        c.push(
            Shape2::Text {
                at: (x, y),
                text: s.to_string(),
                colour,
                size: 13.0,
                middle: false,
            },
            Tag::default(),
        );
    };
    for k in Known::ALL {
        c.push(
            Shape2::Polygon {
                points: vec![
                    (x, y - 11.0),
                    (x + 14.0, y - 11.0),
                    (x + 14.0, y + 1.0),
                    (x, y + 1.0),
                ],
                fill: k.rgb(),
                opacity: 1.0,
            },
            Tag::default(),
        );
        c.push(
            Shape2::Text {
                at: (x + 20.0, y),
                text: k.meaning().to_string(),
                colour: INK,
                size: 13.0,
                middle: false,
            },
            Tag::default(),
        );
        y += 22.0;
    }
    y += 8.0;
    for (s, k, dashed) in [
        ("learnt edge (a topple about it)", Known::Seen, false),
        ("edge of the shape, not demonstrated", Known::Inferred, true),
    ] {
        c.push(
            Shape2::Line {
                a: (x, y - 5.0),
                b: (x + 24.0, y - 5.0),
                colour: k.rgb(),
                width: if dashed { 2.0 } else { 4.0 },
                dashed,
            },
            Tag::default(),
        );
        c.push(
            Shape2::Text {
                at: (x + 30.0, y),
                text: s.into(),
                colour: INK,
                size: 13.0,
                middle: false,
            },
            Tag::default(),
        );
        y += 22.0;
    }
    c.push(
        Shape2::Circle {
            centre: (x + 12.0, y - 5.0),
            r: 4.0,
            fill: Known::Inferred.rgb(),
        },
        Tag::default(),
    );
    line(c, y, "      vertex (where three faces meet)", INK);
    y += 22.0;
    c.push(
        Shape2::Circle {
            centre: (x + 12.0, y - 5.0),
            r: 7.0,
            fill: Known::Seen.rgb(),
        },
        Tag::default(),
    );
    line(c, y, "      centre of mass (pendulums, flights)", INK);
    y += 22.0;
    c.push(
        Shape2::Circle {
            centre: (x + 12.0, y - 5.0),
            r: 5.0,
            fill: ORIGIN_GREEN,
        },
        Tag::default(),
    );
    line(c, y, "      object frame origin (the tag)", INK);
    y += 30.0;
    let count = |k: FeatureKind, known: Option<Known>| {
        d.features
            .iter()
            .filter(|f| f.kind == k && known.is_none_or(|q| f.known == q))
            .count()
    };
    let summary = format!(
        "{} faces, {} edges ({} learnt), {} vertices",
        count(FeatureKind::Face, None),
        count(FeatureKind::Edge, None),
        count(FeatureKind::Edge, None) - count(FeatureKind::Edge, Some(Known::Inferred)),
        count(FeatureKind::Vertex, None)
    );
    for l in wrap(&summary, 40) {
        line(c, y, &l, INK);
        y += 18.0;
    }
    for n in &d.notes {
        y += 6.0;
        for l in wrap(n, 40) {
            line(c, y, &l, Known::Unknown.rgb());
            y += 18.0;
        }
    }
}
