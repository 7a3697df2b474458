//! Checks of a line's values (finite, unit quaternion, increasing time), and the messages for
//! people when a line is wrong.

use super::csv;
use super::reader::{Mode, State, COLUMNS};
use super::tum::{tum_field, TumScan};
use super::QUAT_NORM_TOLERANCE;
use crate::trajectory::StampedPose;
use crate::{Error, Result};
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};

impl State {
    /// Check values (finite, unit quaternion, increasing time) and build the pose.
    #[inline]
    pub(super) fn pose(&mut self, v: &[f64; 8], line: &[u8]) -> Result<StampedPose> {
        match self.accept(v, false) {
            Some(p) => Ok(p),
            None => Err(self.bad_values(v, line)),
        }
    }

    /// [`State::pose`] without the error: the pose, or `None` (and no change) if a check
    /// fails. `finite`: the caller knows that all values are finite, which skips that test.
    #[inline(always)]
    pub(super) fn accept(&mut self, v: &[f64; 8], finite: bool) -> Option<StampedPose> {
        let [t, tx, ty, tz, qx, qy, qz, qw] = *v;
        debug_assert!(!finite || v.iter().all(|x| x.is_finite()));
        // x * 0 is 0 for a finite x and NaN otherwise: one test for all eight values.
        let finite = finite || v.iter().fold(0.0, |a, &x| a + x * 0.0) == 0.0;
        let norm = (qx * qx + qy * qy + qz * qz + qw * qw).sqrt();
        let ok = finite && (norm - 1.0).abs() <= QUAT_NORM_TOLERANCE && t > self.prev_t;
        if !ok {
            return None;
        }
        self.prev_t = t;
        self.prev_line = self.line_no;
        self.pose_line = self.line_no;
        // Normalise without touching the sign: q and -q stay distinct here.
        let rot = UnitQuaternion::new_unchecked(Quaternion::new(qw, qx, qy, qz) / norm);
        Some(StampedPose::new(
            t,
            Isometry3::from_parts(Translation3::new(tx, ty, tz), rot),
        ))
    }

    /// The error for values that failed the checks in [`State::pose`].
    #[cold]
    #[inline(never)]
    fn bad_values(&self, v: &[f64; 8], line: &[u8]) -> Error {
        if v.iter().any(|x| !x.is_finite()) {
            return self.not_finite(v, line);
        }
        let norm = Quaternion::new(v[7], v[4], v[5], v[6]).norm();
        if norm.is_nan() || norm == 0.0 || (norm - 1.0).abs() > QUAT_NORM_TOLERANCE {
            return self.bad_norm(v, norm);
        }
        self.bad_time(v[0], self.prev_t, self.prev_line)
    }

    #[cold]
    fn not_finite(&self, v: &[f64; 8], line: &[u8]) -> Error {
        let k = v.iter().position(|x| !x.is_finite()).unwrap_or(0);
        let what = if v[k].is_nan() { "NaN" } else { "infinite" };
        let text = match &self.mode {
            Mode::Csv(h) => {
                let col = h.column_of(k);
                let mut f = csv::Fields::new(line);
                (0..=col).filter_map(|_| f.next_field()).last()
            }
            _ => tum_field(line, k),
        };
        let quoted = text
            .map(|(a, b)| format!(" ({})", quote(&line[a..b])))
            .unwrap_or_default();
        self.err(format!(
            "{} is {what}{quoted}; every value must be a finite number",
            COLUMNS[k]
        ))
    }

    #[cold]
    fn bad_norm(&self, v: &[f64; 8], norm: f64) -> Error {
        let q = format!(
            "({}, {}, {}, {})",
            num(v[4]),
            num(v[5]),
            num(v[6]),
            num(v[7])
        );
        if norm == 0.0 {
            self.err(format!(
                "quaternion (qx qy qz qw) = {q} is zero, which is no rotation"
            ))
        } else {
            self.err(format!(
                "quaternion (qx qy qz qw) = {q} has norm {}, which differs from 1 by more \
                 than the tolerance {QUAT_NORM_TOLERANCE}",
                num(norm)
            ))
        }
    }

    #[cold]
    fn bad_time(&self, t: f64, pt: f64, pl: usize) -> Error {
        let l = self.line_no;
        let how = if t == pt { "repeats" } else { "goes back from" };
        let (t, pt) = (num(t), num(pt));
        self.err(format!(
            "timestamp {t} on line {l} {how} timestamp {pt} on line {pl} \
             (timestamps must strictly increase)"
        ))
    }

    #[cold]
    pub(super) fn tum_error(&self, scan: &TumScan, s: &[u8]) -> Error {
        let count = scan.count;
        if count != 8 {
            let mut msg =
                format!("expected 8 columns (timestamp tx ty tz qx qy qz qw), found {count}");
            if s.contains(&b',') {
                msg.push_str(
                    " (the line has commas: a CSV file needs a header line naming the columns, \
                     e.g. timestamp,tx,ty,tz,qx,qy,qz,qw)",
                );
            }
            return self.err(msg);
        }
        let (k, a, b) = scan.bad.unwrap_or((0, 0, 0));
        self.err(not_a_number(k + 1, k, &s[a..b]))
    }
}

/// A number for messages: plain (shortest round trip) unless very large or very small.
fn num(x: f64) -> String {
    let a = x.abs();
    if a != 0.0 && !(1e-5..1e16).contains(&a) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// `"text"`, shortened if long, for messages.
pub(crate) fn quote(field: &[u8]) -> String {
    let text = String::from_utf8_lossy(field);
    if text.chars().count() > 40 {
        format!("\"{}...\"", text.chars().take(40).collect::<String>())
    } else {
        format!("\"{text}\"")
    }
}

#[cold]
pub(super) fn not_a_number(col: usize, role: usize, field: &[u8]) -> String {
    let name = COLUMNS[role];
    if field.is_empty() {
        format!("column {col} ({name}) is empty; expected a number")
    } else {
        format!("column {col} ({name}): {} is not a number", quote(field))
    }
}
