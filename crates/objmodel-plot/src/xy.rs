//! Generic x-y line plot.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::common::{
    colour, de, finite_runs, legend_line, render, span, tick_formatter, DrawResult, Figure, FONT,
    GRID_BOLD, GRID_LIGHT,
};
use crate::PlotError;

pub(crate) fn plot(
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[(String, Vec<(f64, f64)>)],
    base: &Path,
) -> Result<(PathBuf, PathBuf), PlotError> {
    render(
        base,
        &Xy {
            title,
            x_label,
            y_label,
            series,
        },
    )
}

struct Xy<'a> {
    title: &'a str,
    x_label: &'a str,
    y_label: &'a str,
    series: &'a [(String, Vec<(f64, f64)>)],
}

impl Figure for Xy<'_> {
    fn size(&self) -> (u32, u32) {
        (1200, 750)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult {
        let points = || self.series.iter().flat_map(|(_, p)| p.iter().copied());
        let (x0, x1) = span(points().map(|p| p.0), 0.02);
        let (y0, y1) = span(points().map(|p| p.1), 0.06);

        let mut chart = ChartBuilder::on(root)
            .caption(self.title, (FONT, 30))
            .margin(20)
            .margin_right(36)
            .x_label_area_size(64)
            .y_label_area_size(100)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(de)?;
        let x_fmt = tick_formatter(x0, x1, 12);
        let y_fmt = tick_formatter(y0, y1, 10);
        chart
            .configure_mesh()
            .x_label_formatter(&x_fmt)
            .y_label_formatter(&y_fmt)
            .x_desc(self.x_label)
            .y_desc(self.y_label)
            .axis_desc_style((FONT, 22))
            .label_style((FONT, 18))
            .bold_line_style(GRID_BOLD)
            .light_line_style(GRID_LIGHT)
            .x_labels(12)
            .y_labels(10)
            .draw()
            .map_err(de)?;

        let mut any_legend = false;
        for (i, (label, pts)) in self.series.iter().enumerate() {
            let style = colour(i).stroke_width(3);
            for (k, run) in finite_runs(pts.iter().copied()).into_iter().enumerate() {
                // A lone point would be invisible as a line: give it a dot.
                let ann = if run.len() == 1 {
                    chart
                        .draw_series(run.into_iter().map(|p| Circle::new(p, 4, style.filled())))
                        .map_err(de)?
                } else {
                    chart.draw_series(LineSeries::new(run, style)).map_err(de)?
                };
                if k == 0 && !label.is_empty() {
                    ann.label(label.as_str()).legend(legend_line(style));
                    any_legend = true;
                }
            }
        }
        if any_legend {
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperRight)
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
