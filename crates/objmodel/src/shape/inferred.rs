//! A face never seen, inferred opposite a seen one (see the [parent module](super)): parallel
//! to it, with the centre of mass halfway between them.
//!
//! Halfway holds for uniform density; a box with a weight inside has its centre of mass
//! anywhere between its faces (the simulator's `weighted` box: 20 mm off the middle of 80 mm).
//! The inferred face's σ holds that: the centre of mass is taken to lie at a fraction `u` of
//! the thickness `T` from the seen face, `u = ½ ± `[`COM_FRACTION_SIGMA`] (uniformly anywhere
//! in the middle half), so that `T = h / u` (`h` its height above the seen face) is known to
//! `4 h σ_u` (0.58 `h`), besides the seen face's offset and the centre of mass's own σ.

use super::{reconstruct, Incomplete, LearntFace, Shape};
use nalgebra::Vector3;

/// The id of the face inferred opposite the learnt face `id`.
pub fn opposite_id(id: &str) -> String {
    format!("{id}-opposite")
}

/// Learnt faces whose normals are this close to opposite directions \[rad\] (20°) are taken
/// for opposite faces, and an open direction this close to a missing face's normal is that
/// face's.
pub const OPPOSITE_RAD: f64 = 0.349_065_850_398_865_9;

/// Standard deviation of where, as a fraction of the thickness between two opposite faces, an
/// object's centre of mass lies: uniformly anywhere in the middle half (`0.5 / √12`).
pub const COM_FRACTION_SIGMA: f64 = 0.144_337_567_297_406_43;

/// The shape of [`reconstruct`], closed where it is open by inferring each unseen face whose
/// opposite was seen, from the centre of mass `com` (object frame \[m\], with its standard
/// deviation \[m\]) under the assumption of the module documentation. Without a centre of mass,
/// or where no seen face lies opposite an open direction, it stays [`Incomplete`].
pub fn reconstruct_inferring(
    learnt: &[LearntFace],
    com: Option<(Vector3<f64>, f64)>,
) -> Result<Shape, Incomplete> {
    let towards = match reconstruct(learnt) {
        Err(Incomplete::Open { towards }) => towards,
        other => return other,
    };
    let Some((c, sigma_c)) = com else {
        return Err(Incomplete::Open { towards });
    };
    let cos = OPPOSITE_RAD.cos();
    let seen = |f: &&LearntFace| f.outward && f.offset.is_some();
    let mut inferred: Vec<LearntFace> = Vec::new();
    for u in &towards {
        let covered = |n: &Vector3<f64>| n.dot(u) > cos;
        if inferred.iter().any(|f| covered(&f.normal)) {
            continue;
        }
        let Some(opposite) = learnt
            .iter()
            .filter(seen)
            .filter(|f| f.normal.dot(u) < -cos)
            .max_by(|a, b| (-a.normal.dot(u)).total_cmp(&-b.normal.dot(u)))
        else {
            continue;
        };
        let d = opposite.offset.expect("a seen face");
        let height = d - opposite.normal.dot(&c);
        if height <= 0.0 {
            continue; // the CoM is not inside the seen face: nothing to mirror
        }
        inferred.push(LearntFace {
            id: opposite_id(&opposite.id),
            normal: -opposite.normal,
            outward: true,
            offset: Some(2.0 * height - d),
            offset_sigma_m: (opposite.offset_sigma_m.powi(2)
                + 4.0 * sigma_c * sigma_c
                + (4.0 * height * COM_FRACTION_SIGMA).powi(2))
            .sqrt(),
            normal_sigma_rad: opposite.normal_sigma_rad,
        });
    }
    if inferred.is_empty() {
        return Err(Incomplete::Open { towards });
    }
    let all: Vec<LearntFace> = learnt
        .iter()
        .cloned()
        .chain(inferred.iter().cloned())
        .collect();
    let mut shape = reconstruct(&all)?;
    for f in &mut shape.faces {
        if let Some(i) = inferred.iter().find(|i| i.id == f.id) {
            let of = f.id.trim_end_matches("-opposite");
            let why = format!(
                "face {} was never seen: inferred parallel to its opposite face {of}, with the \
                 centre of mass halfway between them (uniform density along their normal; \
                 its σ lets the centre of mass lie anywhere in the middle half), offset {:.4} \
                 m ± {:.1} mm",
                f.id,
                f.offset,
                i.offset_sigma_m * 1e3
            );
            f.inferred = Some(why.clone());
            shape.assumptions.push(why);
        }
    }
    Ok(shape)
}

#[cfg(test)]
mod tests {
    use super::super::tests_support::box_faces as turned_box;
    use super::super::ShapeFace;
    use super::*;
    use nalgebra::UnitQuaternion;

    fn box_faces(c: Vector3<f64>) -> Vec<LearntFace> {
        turned_box(c, &UnitQuaternion::identity(), &Vector3::new(0.2, 0.1, 0.3))
    }

    /// A box missing its +x face, with its centre of mass: the face is inferred where the
    /// uniform box has it, marked so with its assumption and a sigma above the seen faces':
    /// the centre of mass's and the density's (a quarter of the box's thickness, 0.2 m, in 1 σ
    /// where the centre of mass lies halfway). Without a CoM, or missing both x faces, it
    /// stays open.
    #[test]
    fn an_unseen_face_is_inferred_opposite_a_seen_one() {
        let c = Vector3::new(0.02, -0.03, 0.1);
        let full = reconstruct(&box_faces(c)).unwrap();
        let mut faces = box_faces(c);
        faces.remove(0); // +x
        let s = reconstruct_inferring(&faces, Some((c, 2e-3))).unwrap();
        assert_eq!(s.vertices.len(), 8);
        for v in &full.vertices {
            assert!(s.vertices.iter().any(|w| (v - w).norm() < 1e-12), "{v}");
        }
        let inferred: Vec<&ShapeFace> = s.faces.iter().filter(|f| f.inferred.is_some()).collect();
        assert_eq!(inferred.len(), 1);
        assert_eq!(inferred[0].id, opposite_id("f1"));
        assert!(inferred[0].normal.x > 0.999);
        let density = 4.0 * 0.1 * COM_FRACTION_SIGMA;
        let expected = (4.0 * 2e-3 * 2e-3 + density * density).sqrt();
        let own = faces[0].offset_sigma_m;
        assert!(
            (inferred[0].offset_sigma_m - (expected * expected + own * own).sqrt()).abs() < 1e-12,
            "{} vs {expected}",
            inferred[0].offset_sigma_m
        );
        assert!(inferred[0].offset_sigma_m > 0.05 && inferred[0].offset_sigma_m < 0.06);
        assert_eq!(s.assumptions.len(), 1);
        assert!(s.assumptions[0].contains("uniform density"));
        // The seen faces keep their own sigma and no mark.
        assert!(s.faces.iter().filter(|f| f.inferred.is_none()).count() == 5);
        // A CoM 1 cm towards -x puts the inferred face 2 cm nearer.
        let s = reconstruct_inferring(&faces, Some((c - Vector3::x() * 0.01, 2e-3))).unwrap();
        assert!((s.extents[1].x - (c.x + 0.1 - 0.02)).abs() < 1e-12);
        // Without a CoM, or without the opposite face, it stays open.
        assert!(matches!(
            reconstruct_inferring(&faces, None),
            Err(Incomplete::Open { .. })
        ));
        faces.remove(0); // -x
        assert!(matches!(
            reconstruct_inferring(&faces, Some((c, 2e-3))),
            Err(Incomplete::Open { .. })
        ));
        // A closed shape is returned as it is.
        assert_eq!(
            reconstruct_inferring(&box_faces(c), Some((c, 1.0))),
            Ok(full)
        );
    }
}
