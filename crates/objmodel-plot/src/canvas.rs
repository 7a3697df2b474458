//! A list of 2-D shapes in pixels, written as an SVG by hand (each shape one element that
//! says what it draws: `data-kind`, `data-id`, `data-known`, with a `<title>` shown on hover)
//! and drawn with plotters into a PNG, so both files show the same picture.

use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::fmt::Write as _;

use crate::common::{de, DrawResult, Figure, FONT};

/// What a shape is, for the SVG's `data-` attributes and its hover text.
#[derive(Clone, Debug, Default)]
pub(crate) struct Tag {
    /// `data-kind`.
    pub kind: &'static str,
    /// `data-id`.
    pub id: String,
    /// `data-known`.
    pub known: &'static str,
    /// Hover text.
    pub title: String,
}

/// One shape.
#[derive(Clone, Debug)]
pub(crate) enum Shape2 {
    /// A filled polygon.
    Polygon {
        points: Vec<(f64, f64)>,
        fill: [u8; 3],
        opacity: f64,
    },
    /// A straight line, solid or dashed.
    Line {
        a: (f64, f64),
        b: (f64, f64),
        colour: [u8; 3],
        width: f64,
        dashed: bool,
    },
    /// A filled circle with a dark outline.
    Circle {
        centre: (f64, f64),
        r: f64,
        fill: [u8; 3],
    },
    /// Text, anchored at its left (or middle, when `middle`) baseline.
    Text {
        at: (f64, f64),
        text: String,
        colour: [u8; 3],
        size: f64,
        middle: bool,
    },
}

/// A picture: its size in pixels and its shapes, drawn in order.
#[derive(Clone, Debug, Default)]
pub(crate) struct Canvas {
    pub width: u32,
    pub height: u32,
    pub items: Vec<(Shape2, Tag)>,
}

fn rgb(c: [u8; 3]) -> String {
    format!("rgb({},{},{})", c[0], c[1], c[2])
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

impl Canvas {
    /// Adds a shape.
    pub fn push(&mut self, shape: Shape2, tag: Tag) {
        self.items.push((shape, tag));
    }

    /// The picture as an SVG document.
    pub fn svg(&self) -> String {
        let mut s = format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\">\n<rect x=\"0\" y=\"0\" width=\"{w}\" height=\"{h}\" fill=\"white\"/>\n",
            w = self.width,
            h = self.height
        );
        for (shape, tag) in &self.items {
            let mut attrs = String::new();
            if !tag.kind.is_empty() {
                let _ = write!(
                    attrs,
                    " data-kind=\"{}\" data-id=\"{}\" data-known=\"{}\"",
                    tag.kind,
                    esc(&tag.id),
                    tag.known
                );
            }
            let (open, name) = match shape {
                Shape2::Polygon {
                    points,
                    fill,
                    opacity,
                } => {
                    let pts: Vec<String> =
                        points.iter().map(|(x, y)| format!("{x:.2},{y:.2}")).collect();
                    (
                        format!(
                            "<polygon{attrs} points=\"{}\" fill=\"{}\" fill-opacity=\"{opacity}\" stroke=\"none\"",
                            pts.join(" "),
                            rgb(*fill)
                        ),
                        "polygon",
                    )
                }
                Shape2::Line {
                    a,
                    b,
                    colour,
                    width,
                    dashed,
                } => (
                    format!(
                        "<line{attrs} x1=\"{:.2}\" y1=\"{:.2}\" x2=\"{:.2}\" y2=\"{:.2}\" stroke=\"{}\" stroke-width=\"{width}\" stroke-linecap=\"round\"{}",
                        a.0,
                        a.1,
                        b.0,
                        b.1,
                        rgb(*colour),
                        if *dashed { " stroke-dasharray=\"8 5\"" } else { "" }
                    ),
                    "line",
                ),
                Shape2::Circle { centre, r, fill } => (
                    format!(
                        "<circle{attrs} cx=\"{:.2}\" cy=\"{:.2}\" r=\"{r}\" fill=\"{}\" stroke=\"rgb(40,40,40)\" stroke-width=\"1\"",
                        centre.0,
                        centre.1,
                        rgb(*fill)
                    ),
                    "circle",
                ),
                Shape2::Text {
                    at,
                    text,
                    colour,
                    size,
                    middle,
                } => {
                    let _ = writeln!(
                        s,
                        "<text{attrs} x=\"{:.2}\" y=\"{:.2}\" font-family=\"sans-serif\" font-size=\"{size}\" fill=\"{}\"{}>{}</text>",
                        at.0,
                        at.1,
                        rgb(*colour),
                        if *middle { " text-anchor=\"middle\"" } else { "" },
                        esc(text)
                    );
                    continue;
                }
            };
            s += &open;
            if tag.title.is_empty() {
                s += "/>\n";
            } else {
                let _ = writeln!(s, "><title>{}</title></{name}>", esc(&tag.title));
            }
        }
        s += "</svg>\n";
        s
    }
}

fn colour(c: [u8; 3]) -> RGBColor {
    RGBColor(c[0], c[1], c[2])
}

fn px(p: (f64, f64)) -> (i32, i32) {
    (p.0.round() as i32, p.1.round() as i32)
}

impl Figure for Canvas {
    fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult {
        for (shape, _) in &self.items {
            match shape {
                Shape2::Polygon {
                    points,
                    fill,
                    opacity,
                } => root
                    .draw(&Polygon::new(
                        points.iter().copied().map(px).collect::<Vec<_>>(),
                        colour(*fill).mix(*opacity).filled(),
                    ))
                    .map_err(de)?,
                Shape2::Line {
                    a,
                    b,
                    colour: c,
                    width,
                    dashed,
                } => {
                    let style = colour(*c).stroke_width(width.round().max(1.0) as u32);
                    if *dashed {
                        root.draw(&DashedPathElement::new(vec![px(*a), px(*b)], 8, 5, style))
                            .map_err(de)?
                    } else {
                        root.draw(&PathElement::new(vec![px(*a), px(*b)], style))
                            .map_err(de)?
                    }
                }
                Shape2::Circle { centre, r, fill } => {
                    let r = r.round() as i32;
                    root.draw(&Circle::new(px(*centre), r, colour(*fill).filled()))
                        .map_err(de)?;
                    root.draw(&Circle::new(px(*centre), r, RGBColor(40, 40, 40)))
                        .map_err(de)?;
                }
                Shape2::Text {
                    at,
                    text,
                    colour: c,
                    size,
                    middle,
                } => {
                    let h = if *middle { HPos::Center } else { HPos::Left };
                    let style = (FONT, *size)
                        .into_font()
                        .color(&colour(*c))
                        .pos(Pos::new(h, VPos::Bottom));
                    root.draw(&Text::new(text.clone(), px(*at), style))
                        .map_err(de)?;
                }
            }
        }
        Ok(())
    }
}
