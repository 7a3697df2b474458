//! The view of the paper's Fig. 9a ([`crate::fig9a`]): the figure's size and layout, its
//! colours, and the oblique orthographic projection of the object frame onto the page.

use nalgebra::Vector3;

/// Size of the figure (px).
pub(crate) const WIDTH: u32 = 1000;
pub(crate) const HEIGHT: u32 = 720;
/// The drawing's square: left edge, top edge and side (px); the legend is to its right.
pub(crate) const LEFT: f64 = 10.0;
pub(crate) const TOP: f64 = 50.0;
pub(crate) const SIDE: f64 = 660.0;
/// Azimuth and elevation of the direction towards the viewer in the object frame (degrees),
/// unless another view of [`View::choose`] shows the vertices much further apart.
const AZIMUTH_DEG: f64 = -58.0;
const ELEVATION_DEG: f64 = 26.0;
/// The object frame's origin: green, as in the paper.
pub(crate) const ORIGIN_GREEN: [u8; 3] = [44, 160, 44];
pub(crate) const INK: [u8; 3] = [30, 30, 30];

/// An orthographic view: page right, page up and towards the viewer, in the object frame.
pub(crate) struct View {
    pub(crate) right: Vector3<f64>,
    pub(crate) up: Vector3<f64>,
    pub(crate) toward: Vector3<f64>,
    pub(crate) centre: Vector3<f64>,
    pub(crate) scale: f64,
}

impl View {
    /// The view from azimuth `az_deg` and elevation `el_deg`.
    pub(crate) fn new(centre: Vector3<f64>, radius: f64, az_deg: f64, el_deg: f64) -> Self {
        let (az, el) = (az_deg.to_radians(), el_deg.to_radians());
        let toward = Vector3::new(el.cos() * az.cos(), el.cos() * az.sin(), el.sin());
        let right = Vector3::new(-az.sin(), az.cos(), 0.0);
        View {
            up: toward.cross(&right),
            right,
            toward,
            centre,
            scale: (SIDE / 2.0 - 40.0) / radius.max(1e-6),
        }
    }

    /// The default view, or, when it shows a face of the shape (outward `normals`) much more
    /// nearly edge-on than another view does (its smallest `|normal · toward|` below 0.8 of
    /// theirs), the view among azimuths every 15° and elevations 20°, 30°, 40° whose smallest
    /// `|normal · toward|` is largest: no face seen edge-on.
    pub(crate) fn choose(centre: Vector3<f64>, radius: f64, normals: &[Vector3<f64>]) -> Self {
        let open = |v: &View| {
            normals
                .iter()
                .map(|n| n.dot(&v.toward).abs())
                .fold(f64::INFINITY, f64::min)
        };
        let default = View::new(centre, radius, AZIMUTH_DEG, ELEVATION_DEG);
        let base = open(&default);
        let best = (0..24)
            .flat_map(|a| [20.0, 30.0, 40.0].map(|e| (a as f64 * 15.0 - 180.0, e)))
            .map(|(a, e)| View::new(centre, radius, a, e))
            .map(|v| (open(&v), v))
            .max_by(|a, b| a.0.total_cmp(&b.0));
        match best {
            Some((s, v)) if s.is_finite() && base < 0.8 * s => v,
            _ => default,
        }
    }

    /// Pixel position of the object-frame point `p`.
    pub(crate) fn px(&self, p: &[f64; 3]) -> (f64, f64) {
        let r = Vector3::from(*p) - self.centre;
        (
            LEFT + SIDE / 2.0 + self.scale * self.right.dot(&r),
            TOP + SIDE / 2.0 - self.scale * self.up.dot(&r),
        )
    }

    /// Whether the shape (half-spaces `planes`, `radius`) hides the object-frame point `p`: a
    /// step from it towards the viewer, of a twentieth of the radius, is inside every face.
    pub(crate) fn hidden(&self, planes: &[([f64; 3], f64)], radius: f64, p: &[f64; 3]) -> bool {
        let q = Vector3::from(*p) + self.toward * radius * 0.05;
        !planes.is_empty() && planes.iter().all(|(n, d)| Vector3::from(*n).dot(&q) < *d)
    }

    pub(crate) fn depth(&self, p: &[f64; 3]) -> f64 {
        self.toward.dot(&Vector3::from(*p))
    }
}
