//! A demonstration in memory made ready to classify: its palm on the object's clock, its
//! stamps in seconds and its positions in metres, with warnings of what was converted.

use super::Learner;
use crate::format::{
    conversion_warning, detect_time_unit_of, to_metres, to_seconds, LengthUnit, TimeUnit,
};
use crate::trajectory::Demonstration;
use std::borrow::Cow;

impl Learner {
    /// `demo` with its palm on the object's clock, its stamps in seconds and its positions in
    /// metres, and the warnings of what was converted.
    pub(super) fn prepared<'d>(
        &self,
        demo: &'d Demonstration,
    ) -> (Cow<'d, Demonstration>, Vec<String>) {
        let (demo, warnings) = self.in_seconds(demo);
        let mut demo = self.in_metres(demo);
        let offset = self.config.clocks.palm_time_offset_s;
        if offset != 0.0 {
            if let Some(palm) = demo.to_mut().palm.as_mut() {
                palm.iter_mut().for_each(|p| p.t += offset);
            }
        }
        (demo, warnings)
    }

    /// `demo` with its positions in metres: scaled by the unit the configuration gives
    /// ([`Config::length_unit`]; poses in memory and bags declare none).
    pub(super) fn in_metres<'d>(&self, mut demo: Cow<'d, Demonstration>) -> Cow<'d, Demonstration> {
        if let Some(u) = self.config.length_unit.filter(|&u| u != LengthUnit::Metres) {
            let d = demo.to_mut();
            to_metres(&mut d.object, u);
            if let Some(palm) = d.palm.as_mut() {
                to_metres(palm, u);
            }
        }
        demo
    }

    /// `demo` with its stamps in seconds (each stream's unit recognised, if the configuration
    /// asks), and the warnings of what was converted.
    fn in_seconds<'d>(&self, demo: &'d Demonstration) -> (Cow<'d, Demonstration>, Vec<String>) {
        let mut demo = Cow::Borrowed(demo);
        let mut warnings = Vec::new();
        if !self.config.clocks.detect_time_unit {
            return (demo, warnings);
        }
        let object_unit = detect_time_unit_of(&demo.object);
        if object_unit != TimeUnit::Seconds {
            to_seconds(&mut demo.to_mut().object, object_unit);
            warnings.push(conversion_warning("object", object_unit));
        }
        let palm_unit = demo.palm.as_deref().map(detect_time_unit_of);
        if let Some(u) = palm_unit.filter(|&u| u != TimeUnit::Seconds) {
            if let Some(palm) = demo.to_mut().palm.as_mut() {
                to_seconds(palm, u);
            }
            warnings.push(conversion_warning("palm", u));
        }
        (demo, warnings)
    }
}
