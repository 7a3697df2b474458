//! The paper's Fig. 5: outlines in the plane normal to the edge, one panel per instant.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::common::{
    colour, de, render, tick_formatter, DrawResult, Figure, FONT, GRID_BOLD, GRID_LIGHT,
};
use crate::{PlotError, SideView};

pub(crate) fn plot(v: &SideView, base: &Path) -> Result<(PathBuf, PathBuf), PlotError> {
    render(base, &Layout::new(v))
}

/// Space around the grid of panels (px).
const OUTER: u32 = 16;
/// Height of the figure title band (px).
const TITLE_H: u32 = 56;
/// Height of the legend band (px).
const LEGEND_H: u32 = 40;
/// Height of each panel's caption band (px).
const CAP_H: u32 = 34;
/// Chart margin inside a panel (px).
const MARGIN: u32 = 10;
/// Left (tick labels and axis name) and bottom label areas of a panel (px).
const Y_AREA: u32 = 84;
const X_AREA: u32 = 58;

/// Sizes worked out once so that [`Figure::size`] and [`Figure::draw`] agree.
struct Layout<'a> {
    view: &'a SideView,
    /// Distinct outline labels, in order of first appearance; index = colour.
    labels: Vec<&'a str>,
    ncols: u32,
    nrows: u32,
    panel_w: u32,
    panel_h: u32,
    /// Data bounds (padded) `[x0, x1, y0, y1]` (m), before fitting to the panel's aspect.
    bounds: [f64; 4],
}

impl<'a> Layout<'a> {
    fn new(view: &'a SideView) -> Self {
        let mut labels: Vec<&str> = Vec::new();
        for o in view.frames.iter().flat_map(|(_, os)| os) {
            if !labels.contains(&o.label.as_str()) {
                labels.push(&o.label);
            }
        }
        let n = view.frames.len().max(1) as u32;
        let ncols = match n {
            0..=4 => n,
            5..=6 => 3,
            _ => 4,
        };
        let nrows = n.div_ceil(ncols);

        let (mut x0, mut x1, mut y0, mut y1) = (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        );
        for p in view
            .frames
            .iter()
            .flat_map(|(_, os)| os.iter().flat_map(|o| o.points.iter()))
        {
            if p[0].is_finite() && p[1].is_finite() {
                x0 = x0.min(p[0]);
                x1 = x1.max(p[0]);
                y0 = y0.min(p[1]);
                y1 = y1.max(p[1]);
            }
        }
        let bounds = if x0 > x1 {
            [-0.1, 0.1, -0.1, 0.1]
        } else {
            // Same absolute padding on both axes; a minimum extent of 1 mm.
            let pad = (0.08 * (x1 - x0).max(y1 - y0)).max(5e-4);
            [x0 - pad, x1 + pad, y0 - pad, y1 + pad]
        };

        // Plot area shaped like the data (within limits), so little of it is left empty.
        let plot_w: u32 = if ncols == 1 { 640 } else { 380 };
        let aspect = (bounds[3] - bounds[2]) / (bounds[1] - bounds[0]);
        let plot_h =
            (plot_w as f64 * aspect).clamp(0.35 * plot_w as f64, 1.6 * plot_w as f64) as u32;
        Layout {
            view,
            labels,
            ncols,
            nrows,
            panel_w: plot_w + Y_AREA + 2 * MARGIN,
            panel_h: CAP_H + plot_h + X_AREA + 2 * MARGIN,
            bounds,
        }
    }

    fn label_colour(&self, label: &str) -> RGBColor {
        colour(self.labels.iter().position(|l| *l == label).unwrap_or(0))
    }

    /// Ranges covering `bounds`, widened along one axis so that a metre spans as many pixels
    /// horizontally as vertically in a plot area of `w` × `h` pixels.
    fn equal_aspect_ranges(&self, (w, h): (u32, u32)) -> ((f64, f64), (f64, f64)) {
        let [x0, x1, y0, y1] = self.bounds;
        let (w, h) = (w.max(1) as f64, h.max(1) as f64);
        let m_per_px = ((x1 - x0) / w).max((y1 - y0) / h);
        let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
        let (hw, hh) = (0.5 * m_per_px * w, 0.5 * m_per_px * h);
        ((cx - hw, cx + hw), (cy - hh, cy + hh))
    }

    fn draw_panel<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        t: f64,
        outlines: &[crate::Outline],
    ) -> DrawResult {
        let caption = if t.is_finite() {
            format!("t = {t:.3} s")
        } else {
            "t = ?".to_owned()
        };
        let (w, _) = area.dim_in_pixel();
        area.draw(&Text::new(
            caption,
            (w as i32 / 2 + Y_AREA as i32 / 2, CAP_H as i32 / 2 + 4),
            (FONT, 21)
                .into_font()
                .color(&BLACK)
                .pos(Pos::new(HPos::Center, VPos::Center)),
        ))
        .map_err(de)?;
        let (_, h) = area.dim_in_pixel();
        let chart_area = area
            .clone()
            .shrink((0, CAP_H), (w, h.saturating_sub(CAP_H)));

        let builder = || {
            let mut b = ChartBuilder::on(&chart_area);
            b.margin(MARGIN)
                .x_label_area_size(X_AREA)
                .y_label_area_size(Y_AREA);
            b
        };
        // Measure the plotting area (building without a caption draws nothing), then fit ranges.
        let probe = builder()
            .build_cartesian_2d(0.0..1.0, 0.0..1.0)
            .map_err(de)?;
        let (xr, yr) = self.equal_aspect_ranges(probe.plotting_area().dim_in_pixel());
        drop(probe);

        let mut chart = builder()
            .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)
            .map_err(de)?;
        let x_fmt = tick_formatter(xr.0, xr.1, 6);
        let y_fmt = tick_formatter(yr.0, yr.1, 6);
        chart
            .configure_mesh()
            .x_label_formatter(&x_fmt)
            .y_label_formatter(&y_fmt)
            .x_desc("horizontal [m]")
            .y_desc("vertical [m]")
            .axis_desc_style((FONT, 20))
            .label_style((FONT, 17))
            .bold_line_style(GRID_BOLD)
            .light_line_style(GRID_LIGHT)
            .x_labels(6)
            .y_labels(6)
            .draw()
            .map_err(de)?;

        for o in outlines {
            let c = self.label_colour(&o.label);
            let pts: Vec<(f64, f64)> = o
                .points
                .iter()
                .filter(|p| p[0].is_finite() && p[1].is_finite())
                .map(|p| (p[0], p[1]))
                .collect();
            if pts.len() >= 3 {
                chart
                    .draw_series(std::iter::once(Polygon::new(
                        pts.clone(),
                        c.mix(0.22).filled(),
                    )))
                    .map_err(de)?;
            }
            if let Some(&first) = pts.first() {
                let mut ring = pts;
                ring.push(first);
                chart
                    .draw_series(std::iter::once(PathElement::new(ring, c.stroke_width(3))))
                    .map_err(de)?;
            }
        }
        Ok(())
    }

    fn draw_legend<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> DrawResult {
        let font = (FONT, 19).into_font().color(&BLACK);
        let mut x = (OUTER + Y_AREA) as i32;
        let y = LEGEND_H as i32 / 2;
        for (i, label) in self.labels.iter().enumerate() {
            let c = colour(i);
            let shown = if label.is_empty() { "(unnamed)" } else { label };
            area.draw(&Rectangle::new(
                [(x, y - 9), (x + 28, y + 9)],
                c.mix(0.22).filled(),
            ))
            .map_err(de)?;
            area.draw(&Rectangle::new(
                [(x, y - 9), (x + 28, y + 9)],
                c.stroke_width(3),
            ))
            .map_err(de)?;
            area.draw(&Text::new(
                shown.to_owned(),
                (x + 38, y),
                font.pos(Pos::new(HPos::Left, VPos::Center)),
            ))
            .map_err(de)?;
            let (tw, _) = area.estimate_text_size(shown, &font).map_err(de)?;
            x += 38 + tw as i32 + 36;
        }
        Ok(())
    }
}

impl Figure for Layout<'_> {
    fn size(&self) -> (u32, u32) {
        (
            2 * OUTER + self.ncols * self.panel_w,
            TITLE_H + LEGEND_H + self.nrows * self.panel_h + OUTER,
        )
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult {
        let (w, h) = root.dim_in_pixel();
        root.draw(&Text::new(
            self.view.title.clone(),
            (w as i32 / 2, TITLE_H as i32 / 2 + 4),
            (FONT, 30)
                .into_font()
                .color(&BLACK)
                .pos(Pos::new(HPos::Center, VPos::Center)),
        ))
        .map_err(de)?;

        if self.view.frames.is_empty() {
            root.draw(&Text::new(
                "no frames".to_owned(),
                (w as i32 / 2, h as i32 / 2),
                (FONT, 24)
                    .into_font()
                    .color(&BLACK.mix(0.6))
                    .pos(Pos::new(HPos::Center, VPos::Center)),
            ))
            .map_err(de)?;
            return Ok(());
        }

        let legend = root.clone().shrink((0, TITLE_H), (w, LEGEND_H));
        self.draw_legend(&legend)?;

        for (i, (t, outlines)) in self.view.frames.iter().enumerate() {
            let (r, c) = (i as u32 / self.ncols, i as u32 % self.ncols);
            let panel = root.clone().shrink(
                (
                    OUTER + c * self.panel_w,
                    TITLE_H + LEGEND_H + r * self.panel_h,
                ),
                (self.panel_w, self.panel_h),
            );
            self.draw_panel(&panel, *t, outlines)?;
        }
        Ok(())
    }
}
