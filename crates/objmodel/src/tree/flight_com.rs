//! One flight's centre of mass as the tree keeps it (`tree/flights.rs` pools them).

use super::tolerances::{matrix, rows};
use crate::flight::ComEstimate;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// The centre of mass one flight of a demonstration measured.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FlightCom {
    /// The demonstration.
    pub demo: String,
    /// The point that fell with gravity, object frame \[m\].
    pub point: Vector3<f64>,
    /// Its covariance \[m²\], rows.
    pub covariance: [[f64; 3]; 3],
    /// How the point moves with the gravity it was measured under, `∂point/∂g` \[s²\], rows
    /// (`FlightFit::com_gravity_sensitivity`).
    pub gravity_sensitivity: [[f64; 3]; 3],
    /// Frames of the flight.
    pub frames: usize,
}

impl FlightCom {
    /// The flight's measurement as the pooling takes it.
    pub fn estimate(&self) -> ComEstimate {
        ComEstimate {
            point: self.point,
            covariance: matrix(&self.covariance),
            gravity_sensitivity: matrix(&self.gravity_sensitivity),
            frames: self.frames,
        }
    }

    /// A flight's measurement, under the demonstration `demo`.
    pub fn of(demo: &str, e: &ComEstimate) -> Self {
        Self {
            demo: demo.to_string(),
            point: e.point,
            covariance: rows(&e.covariance),
            gravity_sensitivity: rows(&e.gravity_sensitivity),
            frames: e.frames,
        }
    }
}
