//! The learnt inertia as the tree keeps it: the matrix about the centre of mass per kilogram,
//! where each moment came from, and the moments the pendulums gave (computed in
//! [`super::learn`]).

use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

/// Where the inertia came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum InertiaSource {
    /// Every moment from the pendulums.
    Pendulums,
    /// Some moments from the pendulums, the others from the shape at uniform density.
    PendulumsAndUniformDensity,
    /// The shape at uniform density.
    UniformDensity,
}

/// The moment about one axis through the CoM.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AxisMoment {
    /// The axis (unit, object frame).
    pub direction: Vector3<f64>,
    /// Moment per kg \[m²\].
    pub moment_per_kg: f64,
    /// Its standard deviation \[m²\] (the pendulums' scatter over their number), when two or
    /// more pendulums give it.
    pub sigma_per_kg: Option<f64>,
    /// Pendulum observations about edges along it.
    pub pendulums: usize,
    /// Whether `moment_per_kg` is theirs (else the uniform shape's).
    #[serde(default)]
    pub from_pendulums: bool,
    /// Their mean moment per kg \[m²\], when there are any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pendulum_moment_per_kg: Option<f64>,
    /// Why their moment was not used, when it was not.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub not_used: Option<String>,
}

/// The learnt inertia.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LearntInertia {
    /// Inertia tensor per kg about the CoM \[m²\] (times the mass in kg: kg m²), object axes,
    /// rows.
    pub per_kg: [[f64; 3]; 3],
    /// Where it came from.
    pub source: InertiaSource,
    /// The moments about the box's axes (a box), or the pendulums' edge directions.
    pub axes: Vec<AxisMoment>,
    /// What it assumes.
    pub note: String,
}

impl LearntInertia {
    /// The tensor per kg as a matrix.
    pub fn matrix(&self) -> Matrix3<f64> {
        Matrix3::from_fn(|i, j| self.per_kg[i][j])
    }
}
