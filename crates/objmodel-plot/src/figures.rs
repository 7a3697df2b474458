//! What the figures are drawn from: the angle series of the paper's Fig. 8, a demonstration's
//! side view and outlines.

/// One angle signal sampled over time, for [`Fig8`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct AngleSeries {
    /// Name shown in the legend, e.g. `"box angle relative to palm"`.
    pub label: String,
    /// Sample times (s); same length as `angle_rad`.
    pub t: Vec<f64>,
    /// Angle at each sample (rad); plotted in degrees.
    pub angle_rad: Vec<f64>,
}

/// Data for the paper's Fig. 8: angles over time around a topple.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Fig8 {
    /// Figure title, drawn above the chart.
    pub title: String,
    /// Angle signals, overlaid on one chart (e.g. box angle relative to the palm, palm tilt).
    pub series: Vec<AngleSeries>,
    /// Time of the topple onset (s): drawn as a dashed vertical line.
    pub onset_t: Option<f64>,
    /// CoM angle φ from the edge (rad): drawn as a dashed horizontal line.
    pub phi_rad: Option<f64>,
    /// Marked points `(label, t [s], angle [rad])`: drawn as red dots with their label
    /// and value, e.g. the box and palm angles at the onset.
    pub marks: Vec<(String, f64, f64)>,
}

/// A closed polygon in the plane of a [`SideView`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Outline {
    /// Name of the body, e.g. `"box"` or `"palm"`; outlines with the same label get the same
    /// colour in every panel.
    pub label: String,
    /// Vertices `[horizontal, vertical]` (m) in the plane normal to the edge, vertical pointing
    /// up; the polygon is closed (the last vertex joins the first).
    pub points: Vec<[f64; 2]>,
}

/// Data for the paper's Fig. 5: body outlines in the plane normal to an edge at several
/// instants.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SideView {
    /// Figure title, drawn above the panels.
    pub title: String,
    /// One panel per entry: the time (s) and the outlines at that time.
    pub frames: Vec<(f64, Vec<Outline>)>,
}
