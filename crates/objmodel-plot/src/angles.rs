//! The paper's Fig. 8: angles over time with the onset, φ and marked points.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::common::{
    colour, de, finite_runs, legend_dashes, legend_line, render, span, tick_formatter, DrawResult,
    Figure, FONT, GRID_BOLD, GRID_LIGHT, MARK_RED,
};
use crate::{Fig8, PlotError};

pub(crate) fn plot(fig: &Fig8, base: &Path) -> Result<(PathBuf, PathBuf), PlotError> {
    for s in &fig.series {
        if s.t.len() != s.angle_rad.len() {
            return Err(PlotError::InvalidInput {
                path: base.to_owned(),
                reason: format!(
                    "series {:?} has {} times but {} angles",
                    s.label,
                    s.t.len(),
                    s.angle_rad.len()
                ),
            });
        }
    }
    render(base, &Angles(fig))
}

struct Angles<'a>(&'a Fig8);

impl Figure for Angles<'_> {
    fn size(&self) -> (u32, u32) {
        (1200, 750)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult {
        let fig = self.0;
        let deg = f64::to_degrees;
        let onset = fig.onset_t.filter(|t| t.is_finite());
        let phi_deg = fig.phi_rad.map(deg).filter(|p| p.is_finite());

        let times = fig.series.iter().flat_map(|s| s.t.iter().copied());
        let (t0, t1) = span(
            times.chain(onset).chain(fig.marks.iter().map(|m| m.1)),
            0.02,
        );
        let angles = fig
            .series
            .iter()
            .flat_map(|s| s.angle_rad.iter().map(|&a| deg(a)));
        let (y0, y1) = span(
            angles
                .chain(phi_deg)
                .chain(fig.marks.iter().map(|m| deg(m.2))),
            0.08,
        );

        let mut chart = ChartBuilder::on(root)
            .caption(&fig.title, (FONT, 30))
            .margin(20)
            .margin_right(36)
            .x_label_area_size(64)
            .y_label_area_size(88)
            .build_cartesian_2d(t0..t1, y0..y1)
            .map_err(de)?;
        let x_fmt = tick_formatter(t0, t1, 12);
        let y_fmt = tick_formatter(y0, y1, 10);
        chart
            .configure_mesh()
            .x_label_formatter(&x_fmt)
            .y_label_formatter(&y_fmt)
            .x_desc("time [s]")
            .y_desc("angle [°]")
            .axis_desc_style((FONT, 22))
            .label_style((FONT, 18))
            .bold_line_style(GRID_BOLD)
            .light_line_style(GRID_LIGHT)
            .x_labels(12)
            .y_labels(10)
            .draw()
            .map_err(de)?;

        let mut any_legend = false;
        for (i, s) in fig.series.iter().enumerate() {
            let style = colour(i).stroke_width(3);
            let runs = finite_runs(s.t.iter().copied().zip(s.angle_rad.iter().map(|&a| deg(a))));
            for (k, run) in runs.into_iter().enumerate() {
                let ann = chart.draw_series(LineSeries::new(run, style)).map_err(de)?;
                if k == 0 && !s.label.is_empty() {
                    ann.label(s.label.as_str()).legend(legend_line(style));
                    any_legend = true;
                }
            }
        }

        let ref_style = BLACK.mix(0.75).stroke_width(2);
        if let Some(t) = onset {
            chart
                .draw_series(DashedLineSeries::new([(t, y0), (t, y1)], 10, 6, ref_style))
                .map_err(de)?
                .label(format!("onset  t = {t:.3} s"))
                .legend(legend_dashes(ref_style));
            any_legend = true;
        }
        let phi_style = RGBColor(90, 90, 90).stroke_width(2);
        if let Some(p) = phi_deg {
            chart
                .draw_series(DashedLineSeries::new([(t0, p), (t1, p)], 4, 5, phi_style))
                .map_err(de)?
                .label(format!("φ = {p:.2}°"))
                .legend(legend_dashes(phi_style));
            any_legend = true;
        }

        let mark_font = (FONT, 18).into_font().color(&MARK_RED);
        let mut marks = Vec::new();
        for (label, t, a) in fig
            .marks
            .iter()
            .filter(|(_, t, a)| t.is_finite() && a.is_finite())
        {
            let text = if label.is_empty() {
                format!("{:.2}°", deg(*a))
            } else {
                format!("{label} = {:.2}°", deg(*a))
            };
            let (tw, th) = chart
                .plotting_area()
                .estimate_text_size(&text, &mark_font)
                .map_err(de)?;
            let (tx, ty) = (12, -28);
            marks.push(
                EmptyElement::at((*t, deg(*a)))
                    + Rectangle::new(
                        [(tx - 3, ty - 2), (tx + tw as i32 + 3, ty + th as i32 + 4)],
                        WHITE.mix(0.85).filled(),
                    )
                    + Circle::new((0, 0), 7, MARK_RED.filled())
                    + Circle::new((0, 0), 7, WHITE.stroke_width(1))
                    + Text::new(text, (tx, ty), mark_font.clone()),
            );
        }
        chart.draw_series(marks).map_err(de)?;

        if any_legend {
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperLeft)
                .margin(12)
                .legend_area_size(34)
                .label_font((FONT, 18))
                .background_style(WHITE.mix(0.9))
                .border_style(BLACK.mix(0.5))
                .draw()
                .map_err(de)?;
        }
        Ok(())
    }
}
