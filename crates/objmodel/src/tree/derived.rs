//! What the tree derives from its shape and centre of mass: the inertia, the friction evidence
//! and the predicted pendulums beside the observed ones.

use super::Tree;
use nalgebra::Matrix3;

impl Tree {
    /// The centre of mass the shape's properties are taken about: the learnt one when it lies
    /// inside the shape, else (or without one) the shape's centroid at uniform density.
    pub fn mass_centre(&self) -> Option<nalgebra::Vector3<f64>> {
        let shape = self.shape.as_ref()?;
        let inside = |c: &nalgebra::Vector3<f64>| shape.outside(c).is_none_or(|(d, _)| d <= 0.0);
        Some(match &self.com {
            Some(c) if inside(&c.point) => c.point,
            _ => crate::mass::uniform(shape).centroid,
        })
    }

    /// Recompute `inertia`, `friction` and `predictions`.
    pub(super) fn refit_mass_properties(&mut self) {
        self.friction = crate::friction::evidence(self);
        self.inertia = None;
        self.predictions = Vec::new();
        let (Some(shape), Some(centre)) = (self.shape.as_ref(), self.mass_centre()) else {
            return;
        };
        self.inertia = Some(crate::inertia::learn(self, shape, &centre));
        if let Some(com) = &self.com {
            let cov = com.covariance_matrix().unwrap_or_else(Matrix3::zeros);
            let mut predicted = crate::prediction::uncertain(shape, &com.point, &cov);
            crate::prediction::observed_beside(self, &mut predicted);
            self.predictions = predicted;
        }
    }
}
