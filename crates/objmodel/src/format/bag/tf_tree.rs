//! The tf tree of a bag: every frame's transform from its parent (`parent_from_child`), static
//! (`/tf_static`: one pose, valid at all times) or dynamic (`/tf`: poses over time), and the
//! transform between any two connected frames at a time, composed along the tree.
//!
//! A dynamic edge is interpolated between its poses around the time asked (slerp of the
//! rotation, linear in the translation) and is unknown outside its first and last stamps (no
//! extrapolation, as in tf2).

use crate::trajectory::StampedPose;
use nalgebra::Isometry3;
use std::collections::HashMap;

/// One frame's transform from its parent.
#[derive(Clone, Debug, Default)]
pub struct Edge {
    /// The frame.
    pub child: String,
    /// Its parent.
    pub parent: String,
    /// `parent_from_child`, if published on `/tf_static`.
    pub fixed: Option<Isometry3<f64>>,
    /// `parent_from_child` over time, from `/tf`, sorted by stamp (after [`TfTree::finish`]).
    pub poses: Vec<StampedPose>,
    /// Topic it was published on (the first, if several).
    pub topic: String,
    /// Poses dropped because another had the same stamp ([`TfTree::finish`]).
    pub duplicates: usize,
}

impl Edge {
    /// Whether it changes over time (published on `/tf`).
    pub fn is_dynamic(&self) -> bool {
        self.fixed.is_none()
    }

    /// `parent_from_child` at `t`; `None` outside a dynamic edge's stamps.
    pub fn at(&self, t: f64) -> Option<Isometry3<f64>> {
        if let Some(f) = self.fixed {
            return Some(f);
        }
        let p = &self.poses;
        let i = p.partition_point(|x| x.t < t);
        if i < p.len() && p[i].t == t {
            return Some(p[i].pose);
        }
        if i == 0 || i >= p.len() {
            return None;
        }
        let (a, b) = (&p[i - 1], &p[i]);
        Some(interpolate(&a.pose, &b.pose, (t - a.t) / (b.t - a.t)))
    }
}

/// A path through the tree: edges, each used forwards (`parent_from_child`) or inverted.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Chain {
    /// (edge index, inverted), in the order their transforms are multiplied.
    pub steps: Vec<(usize, bool)>,
}

/// The tf tree (see the module's documentation).
#[derive(Clone, Debug, Default)]
pub struct TfTree {
    edges: Vec<Edge>,
    by_child: HashMap<Vec<u8>, usize>,
}

impl TfTree {
    /// Add a transform `parent_from_child` stamped `t`, static or not, published on `topic`.
    /// A frame has one parent: a transform naming another is an error (its message).
    pub fn insert(
        &mut self,
        parent: &[u8],
        child: &[u8],
        t: f64,
        pose: Isometry3<f64>,
        is_static: bool,
        topic: &str,
    ) -> Result<(), String> {
        let i = match self.by_child.get(child) {
            Some(&i) => i,
            None => {
                self.edges.push(Edge {
                    child: String::from_utf8_lossy(child).into_owned(),
                    parent: String::from_utf8_lossy(parent).into_owned(),
                    topic: topic.to_string(),
                    ..Edge::default()
                });
                self.by_child.insert(child.to_vec(), self.edges.len() - 1);
                self.edges.len() - 1
            }
        };
        let e = &mut self.edges[i];
        if e.parent.as_bytes() != parent {
            return Err(format!(
                "frame '{}' has two parents in tf, '{}' and '{}' (tf allows one)",
                e.child,
                e.parent,
                String::from_utf8_lossy(parent)
            ));
        }
        if is_static {
            e.fixed = Some(pose);
        } else {
            e.poses.push(StampedPose::new(t, pose));
        }
        Ok(())
    }

    /// Sort every dynamic edge by stamp and keep one pose per stamp (the last received).
    /// Returns how many duplicates were dropped. An edge both static and dynamic is static.
    pub fn finish(&mut self) -> usize {
        let mut dropped = 0;
        for e in &mut self.edges {
            if e.fixed.is_some() {
                e.poses.clear();
            }
            e.duplicates = sort_dedup(&mut e.poses);
            dropped += e.duplicates;
        }
        dropped
    }

    /// The edges.
    pub fn edges(&self) -> &[Edge] {
        &self.edges
    }

    /// The edge whose child is `frame`.
    pub fn edge_of(&self, frame: &str) -> Option<usize> {
        self.by_child.get(frame.as_bytes()).copied()
    }

    /// Whether `frame` is in the tree (as a child or a parent).
    pub fn contains(&self, frame: &str) -> bool {
        self.edge_of(frame).is_some() || self.edges.iter().any(|e| e.parent == frame)
    }

    /// `frame` and its ancestors, up to the root.
    fn ancestors(&self, frame: &str) -> Vec<(String, Option<usize>)> {
        let mut out = vec![];
        let mut f = frame.to_string();
        loop {
            let e = self.edge_of(&f);
            out.push((f.clone(), e));
            match e {
                // A cycle (a corrupt tree) ends the walk.
                Some(i) if out.len() <= self.edges.len() => f = self.edges[i].parent.clone(),
                _ => return out,
            }
        }
    }

    /// The root of `frame`'s tree.
    pub fn root(&self, frame: &str) -> String {
        self.ancestors(frame).pop().map(|a| a.0).unwrap_or_default()
    }

    /// The path giving `target_from_source`; `None` if the two are not connected.
    pub fn chain(&self, target: &str, source: &str) -> Option<Chain> {
        let up_t = self.ancestors(target);
        let up_s = self.ancestors(source);
        let (jt, js) = up_t
            .iter()
            .enumerate()
            .find_map(|(jt, (f, _))| up_s.iter().position(|(g, _)| g == f).map(|js| (jt, js)))?;
        // target_from_common = inverse of the edges from the target up; then common_from_source
        // = the source side's edges from the top down.
        let mut steps: Vec<(usize, bool)> = up_t[..jt]
            .iter()
            .map(|(_, e)| (e.expect("a frame below the common one has a parent"), true))
            .collect();
        steps.extend(
            up_s[..js]
                .iter()
                .rev()
                .map(|(_, e)| (e.expect("a frame below the common one has a parent"), false)),
        );
        Some(Chain { steps })
    }

    /// The transform of `chain` at `t`; `None` if a dynamic edge on it has no pose around `t`.
    pub fn at(&self, chain: &Chain, t: f64) -> Option<Isometry3<f64>> {
        let mut out = Isometry3::identity();
        for &(i, inverted) in &chain.steps {
            let e = self.edges[i].at(t)?;
            out *= if inverted { e.inverse() } else { e };
        }
        Some(out)
    }

    /// A description of every frame for error messages: `child <- parent (static)` or
    /// `child <- parent (N poses on /tf)`.
    pub fn describe(&self) -> Vec<String> {
        let mut v: Vec<String> = self
            .edges
            .iter()
            .map(|e| match e.fixed {
                Some(_) => format!("{} <- {} (static)", e.child, e.parent),
                None => format!(
                    "{} <- {} ({} poses on {})",
                    e.child,
                    e.parent,
                    e.poses.len(),
                    e.topic
                ),
            })
            .collect();
        v.sort();
        v
    }
}

/// Sort poses by stamp and keep one per stamp (the last received); returns how many were
/// dropped.
pub fn sort_dedup(poses: &mut Vec<StampedPose>) -> usize {
    let n = poses.len();
    if poses.windows(2).any(|w| w[1].t <= w[0].t) {
        poses.sort_by(|a, b| a.t.total_cmp(&b.t));
        // Of equal stamps, the last received (a stable sort keeps arrival order) wins.
        let mut out: Vec<StampedPose> = Vec::with_capacity(n);
        for p in poses.drain(..) {
            match out.last_mut() {
                Some(last) if last.t == p.t => *last = p,
                _ => out.push(p),
            }
        }
        *poses = out;
    }
    n - poses.len()
}

/// The pose a fraction `s` of the way from `a` to `b`: slerp of the rotation (the shorter
/// way), linear in the translation.
pub fn interpolate(a: &Isometry3<f64>, b: &Isometry3<f64>, s: f64) -> Isometry3<f64> {
    Isometry3::from_parts(
        a.translation.vector.lerp(&b.translation.vector, s).into(),
        a.rotation.slerp(&b.rotation, s),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Translation3, UnitQuaternion};

    fn pose(x: f64, yaw: f64) -> Isometry3<f64> {
        Isometry3::from_parts(
            Translation3::new(x, 0.5 * x, 1.0),
            UnitQuaternion::from_euler_angles(0.1, 0.2, yaw),
        )
    }

    /// world -> cam (static), cam -> tag (dynamic), world -> base (static), base -> palm
    /// (dynamic): palm_from_tag composed along the tree is the product of the four, the
    /// dynamic ones interpolated, and unknown outside their stamps.
    #[test]
    fn transforms_compose_along_the_tree() {
        let mut tf = TfTree::default();
        let (wc, wb) = (pose(0.3, 1.0), pose(-0.2, -0.4));
        tf.insert(b"world", b"cam", 0.0, wc, true, "/tf_static")
            .unwrap();
        tf.insert(b"world", b"base", 0.0, wb, true, "/tf_static")
            .unwrap();
        for k in [2, 0, 1] {
            let t = k as f64;
            tf.insert(b"cam", b"tag", t, pose(0.1 * t, 0.3 * t), false, "/tf")
                .unwrap();
            tf.insert(
                b"base",
                b"palm",
                t + 0.5,
                pose(0.2 * t, -0.1 * t),
                false,
                "/tf",
            )
            .unwrap();
        }
        assert_eq!(tf.finish(), 0);
        assert_eq!(tf.root("tag"), "world");
        let chain = tf.chain("palm", "tag").unwrap();
        assert_eq!(chain.steps.len(), 4);
        let t = 1.25;
        let cam_tag = interpolate(&pose(0.1, 0.3), &pose(0.2, 0.6), 0.25);
        let base_palm = interpolate(&pose(0.0, 0.0), &pose(0.2, -0.1), 0.75);
        let want = base_palm.inverse() * wb.inverse() * wc * cam_tag;
        let got = tf.at(&chain, t).unwrap();
        assert!((got.translation.vector - want.translation.vector).norm() < 1e-12);
        assert!(got.rotation.angle_to(&want.rotation) < 1e-12);
        assert!(
            tf.at(&chain, 0.2).is_none(),
            "before the palm's first stamp"
        );
        assert!(tf.at(&chain, 2.1).is_none(), "after the tag's last stamp");
        assert!(tf.chain("tag", "elsewhere").is_none());
        // A second parent is refused.
        assert!(tf
            .insert(b"base", b"tag", 3.0, pose(0.0, 0.0), false, "/tf")
            .is_err());
    }
}
