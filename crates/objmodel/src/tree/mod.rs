//! The object description tree (paper Fig. 2): the object's contact features — edges and
//! faces — each with its geometry in the object frame, the demonstrations that support it, its
//! uncertainty, and its dynamic models.
//!
//! Learning is incremental: [`Tree::add`] fuses a classified demonstration into the tree. Each
//! feature keeps its per-demonstration observations, and its estimate is recomputed from them:
//!
//! * an edge is the information-weighted mean line of its observations
//!   ([`LineStats`](crate::geometry::LineStats)), with the
//!   covariance of that mean: the larger of the propagated one and the between-demonstration
//!   scatter divided by the number of demonstrations; then conditioned on the planes of the
//!   faces it joins as the rests and the other demonstrations measure them
//!   (`tree/edge_faces.rs`; its own estimate kept as [`Edge::observed`]);
//! * a face's normal is the weighted mean of its observations' normals (their signs aligned), its
//!   offset the weighted mean of the offsets that are known, with the mean's sigma widened by
//!   the Birge ratio `√(χ²/(N-1))` when the offsets scatter beyond their own sigmas;
//! * a pendulum's φ is the inverse-variance weighted mean of its demonstrations' φ, its sigma
//!   likewise widened by the Birge ratio (not by their unweighted scatter: three palm onsets
//!   known to 0.2° keep that precision beside falls known to 3°).
//!
//! An observation joins an existing feature when a χ² test at level [`MATCH_ALPHA`] cannot tell
//! them apart, with both covariances plus a per-demonstration systematic error
//! ([`SYSTEMATIC_POINT_M`], [`SYSTEMATIC_DIRECTION_RAD`]); otherwise it starts a new feature.
//! Distinct edges of a polyhedron differ by centimetres or tens of degrees, far outside that gate.
//!
//! The JSON schema is documented in `docs/tree-schema.md`; its version is [`VERSION`].

use crate::classify::Kind;
use crate::edge::EdgeObservation;
use crate::face::FaceObservation;
use crate::noise::NoiseModel;
use crate::observation::Observation;
use crate::shape::{LearntFace, Shape};

mod checks;
mod com;
mod com_conflicts;
mod com_planes;
mod contradiction;
mod derived;
mod edge;
mod edge_faces;
mod face;
mod file;
mod flight_com;
mod flights;
mod landing;
mod landing_edges;
mod pendulum_fusion;
mod pendulums;
mod rolls_off_shape;
mod support;
mod tolerances;
mod unconfirmed;
mod unlocated;
mod unlocated_offset;
mod withheld_edge;
pub use com_conflicts::{com_without_conflicts, ComConflict};
pub use com_planes::{
    com_from, com_from_planes, CentreOfMass, ComPlane, ComPoint, UNKNOWN_PHI_SIGMA_RAD,
};
pub use contradiction::Contradiction;
pub use edge::{Edge, EdgeEstimate};
pub use face::{Evidence, Face};
pub use flight_com::FlightCom;
pub use pendulums::{Pendulum, PendulumObservation};
use serde::{Deserialize, Serialize};
pub(crate) use tolerances::{angle, matrix, rows};
pub use tolerances::{
    CONDITION_MIN, MATCH_ALPHA, SAME_FACE_RAD, SYSTEMATIC_DIRECTION_RAD, SYSTEMATIC_POINT_M,
};
pub use unlocated::{max_offset_sigma, FACE_OFFSET_MATCH_M, LOCATED_ALPHA};
pub use unlocated_offset::UnlocatedOffset;
pub use withheld_edge::WithheldEdge;

/// Schema name written into every tree file.
pub const SCHEMA: &str = "objmodel.tree";
/// Schema version.
pub const VERSION: u32 = 1;
/// How [`Tree::add`] took a demonstration.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Added {
    /// Its name in the tree: its own, or `NAME#k` when another demonstration with other poses
    /// already had that name.
    pub name: String,
    /// The demonstration with the same poses that it replaced, if any.
    pub replaced: Option<String>,
}

impl Added {
    /// What a report should tell of it, if anything unusual happened.
    pub fn note(&self, own_name: &str) -> Option<String> {
        match &self.replaced {
            Some(old) if old == own_name => None,
            Some(old) => Some(format!(
                "the same poses as '{old}', already in the model: replaced it (a \
                 demonstration is counted once)"
            )),
            None if self.name != own_name => Some(format!(
                "another demonstration named '{own_name}' (other poses) is in the model: this \
                 one is '{}'",
                self.name
            )),
            None => None,
        }
    }
}

/// What the tree remembers of each demonstration.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DemoRecord {
    /// Name.
    pub name: String,
    /// Its kind.
    pub kind: Kind,
    /// Frames read.
    pub frames: u64,
    /// Frames rejected as outliers.
    pub outliers: u64,
    /// Whether it was instrumented (palm tracked).
    pub instrumented: bool,
    /// Noise the tests used.
    pub noise: Option<NoiseModel>,
    /// Fingerprint of its poses ([`Observation::fingerprint`]); absent in older files.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fingerprint: Option<String>,
    /// The friction it showed by sliding on the tilting palm, if it did
    /// ([`crate::dynamics::palm_slide`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub palm_slide: Option<crate::dynamics::PalmSlide>,
}

/// The object description tree.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Tree {
    /// Always [`SCHEMA`].
    pub schema: String,
    /// Schema version, [`VERSION`].
    pub version: u32,
    /// The frame everything is expressed in.
    pub frame: String,
    /// Edges.
    pub edges: Vec<Edge>,
    /// Faces.
    pub faces: Vec<Face>,
    /// Demonstrations learnt from, in order.
    pub demos: Vec<DemoRecord>,
    /// The centre of mass, when the pendulums or the flights determine it (`tree/com.rs`).
    #[serde(default)]
    pub com: Option<CentreOfMass>,
    /// The object's shape, when the faces with known offsets close one ([`crate::shape`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shape: Option<Shape>,
    /// Features that contradict each other beyond their uncertainty ([`Tree::contradictions`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub contradictions: Vec<Contradiction>,
    /// The inertia, from the pendulums where they determine it, else the shape's at uniform
    /// density ([`crate::inertia`]); with a shape.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inertia: Option<crate::inertia::LearntInertia>,
    /// What the demonstrations tell of the friction ([`crate::friction`]), if anything.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<crate::friction::FrictionEvidence>,
    /// The pendulum of every (resting face, edge) pair that the shape and the CoM predict, with
    /// its uncertainty and the observed one beside it where one was demonstrated
    /// ([`crate::prediction`]); with a shape and a learnt CoM.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub predictions: Vec<crate::prediction::PredictedPendulum>,
    /// The rests reached after a flight ([`crate::landing`]), each of which teaches its face
    /// once a landing of another demonstration agrees with it (`confirmed`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub landings: Vec<crate::landing::Landing>,
    /// The demonstrations' measurements of the support's height ([`crate::support`]): the
    /// edges they turned about on it; and the height the user gave, if any.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub supports: Vec<crate::support::SupportObservation>,
    /// The support's height, when the user gave it or at least two demonstrations measured it
    /// and agree; it gives the confirmed landings' faces their offsets (and, given, every rest's
    /// on the support).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub support: Option<crate::support::SupportHeight>,
    /// The centres of mass the demonstrations' flights measured, each under its demonstration
    /// (`tree/flights.rs`); pooled into `com`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub flights: Vec<FlightCom>,
    /// Edges held back: the faces the landings show contradict them
    /// (`tree/landing_edges.rs`). They are not in `edges`, the shape or the plans.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub withheld_edges: Vec<WithheldEdge>,
}

impl Default for Tree {
    fn default() -> Self {
        Self {
            schema: SCHEMA.to_string(),
            version: VERSION,
            frame: "object: the tracked frame attached to the object (the frame whose pose the demonstration files give)".to_string(),
            edges: Vec::new(),
            faces: Vec::new(),
            demos: Vec::new(),
            com: None,
            shape: None,
            contradictions: Vec::new(),
            inertia: None,
            friction: None,
            predictions: Vec::new(),
            landings: Vec::new(),
            supports: Vec::new(),
            support: None,
            flights: Vec::new(),
            withheld_edges: Vec::new(),
        }
    }
}

impl Tree {
    /// Fuse an analysed demonstration into the tree, geometry and pendulums in one step: each
    /// topple's edge, the faces it rested on before and after, and the pendulum of its
    /// dynamics on that edge; each taught roll's edge ([`crate::roll`]); its landings, whose
    /// faces are taught once another demonstration's landing agrees ([`crate::landing`]).
    ///
    /// A demonstration is identified by its poses ([`Observation::fingerprint`]), not its
    /// name: the same poses again (under any name) replace the earlier ones, so adding a
    /// demonstration twice changes nothing and never counts it twice; other poses under a
    /// name the tree already has are added under a new name (`NAME#2`, ...), so none is lost.
    /// The returned [`Added`] says which.
    pub fn add(&mut self, observation: &Observation) -> Added {
        self.restore_withheld_edges();
        let c = &observation.classification;
        // (A tree written before 2026-12-08 holds the fingerprint without the positions.)
        let fingerprints = [
            &observation.fingerprint,
            &observation.fingerprint_without_positions,
        ];
        let same_poses = self
            .demos
            .iter()
            .find(|d| {
                d.fingerprint
                    .as_ref()
                    .is_some_and(|f| fingerprints.iter().any(|o| o.as_ref() == Some(f)))
            })
            .map(|d| d.name.clone());
        // A name is taken by a demonstration that stays (not the one these poses replace).
        let taken = |n: &str| {
            self.demos
                .iter()
                .any(|d| d.name == n && Some(&d.name) != same_poses.as_ref())
        };
        let name = if taken(&c.name) {
            (2..)
                .map(|k| format!("{}#{k}", c.name))
                .find(|n| !taken(n))
                .expect("a free name")
        } else {
            c.name.clone()
        };
        if let Some(old) = &same_poses {
            self.remove_demo(old);
            // Removing refits the tree, which may hold edges back again (without the poses
            // about to come back): all are judged afresh with them in.
            self.restore_withheld_edges();
        }
        self.demos.push(DemoRecord {
            name: name.clone(),
            kind: c.kind,
            frames: c.frames,
            outliers: c.outliers,
            instrumented: c.instrumented,
            noise: c.noise,
            fingerprint: observation.fingerprint.clone(),
            palm_slide: observation.palm_slide.clone(),
        });
        let slides = c.segments.iter().filter_map(|s| s.face.as_ref());
        for f in slides.chain(c.rest_faces().iter()) {
            self.add_face(FaceObservation {
                demo: name.clone(),
                ..f.clone()
            });
        }
        self.supports
            .extend(c.support_observations().into_iter().map(|o| {
                crate::support::SupportObservation {
                    demo: name.clone(),
                    ..o
                }
            }));
        self.add_flights(&name, c);
        self.add_landings(
            c.landings()
                .into_iter()
                .map(|l| crate::landing::Landing {
                    demo: name.clone(),
                    ..l
                })
                .collect(),
        );
        for (ti, t) in c.topples.iter().enumerate() {
            let edge = EdgeObservation {
                demo: name.clone(),
                ..t.edge.clone()
            };
            let eid = self.add_edge(edge.clone());
            for d in observation.dynamics.iter().filter(|d| d.topple == ti) {
                self.add_pendulum(&eid, &name, t, d);
            }
            for n in [t.resting_normal_before, t.resting_normal_after]
                .into_iter()
                .flatten()
            {
                let fid = self.add_face(FaceObservation::from_rest(&n, &edge));
                let edge = self
                    .edges
                    .iter_mut()
                    .find(|x| x.id == eid)
                    .expect("the edge was just added");
                if !edge.faces.contains(&fid) {
                    edge.faces.push(fid);
                }
            }
        }
        // The rolls' edges (no pendulum: a roll's angles are not measured from a rest).
        for r in c.rolls.iter().filter(|r| r.taught) {
            self.add_edge(EdgeObservation {
                demo: name.clone(),
                ..r.edge.clone()
            });
        }
        self.refit_whole();
        Added {
            name,
            replaced: same_poses,
        }
    }

    fn next_id(prefix: &str, used: impl Iterator<Item = String>) -> String {
        let max = used
            .filter_map(|id| {
                id.strip_prefix(prefix)
                    .and_then(|n| n.parse::<usize>().ok())
            })
            .max();
        format!("{prefix}{}", max.map_or(0, |m| m + 1))
    }

    fn add_edge(&mut self, o: EdgeObservation) -> String {
        let threshold = crate::stats::chi2_threshold(4.0, MATCH_ALPHA);
        let best = self
            .edges
            .iter_mut()
            .map(|e| (e.match_chi2(&o), e))
            .filter(|(c, _)| *c < threshold)
            .min_by(|a, b| a.0.total_cmp(&b.0));
        match best {
            Some((_, e)) => {
                e.observations.push(o);
                e.refit();
                e.id.clone()
            }
            None => {
                // Not the id of an edge held back either (removing a demonstration may withhold
                // one before an edge is added).
                let held = self.withheld_edges.iter().map(|w| w.edge.id.clone());
                let id = Self::next_id("e", self.edges.iter().map(|e| e.id.clone()).chain(held));
                self.edges.push(Edge::new(id.clone(), o));
                id
            }
        }
    }

    fn add_face(&mut self, o: FaceObservation) -> String {
        let dof = if o.offset.is_some() { 3.0 } else { 2.0 };
        let threshold = crate::stats::chi2_threshold(dof, MATCH_ALPHA);
        let best = self
            .faces
            .iter_mut()
            .map(|f| (f.match_chi2(&o), f))
            .filter(|(c, _)| *c < threshold)
            .min_by(|a, b| a.0.total_cmp(&b.0));
        match best {
            Some((_, f)) => {
                f.observations.push(o);
                f.refit();
                f.id.clone()
            }
            None => {
                let id = Self::next_id("f", self.faces.iter().map(|f| f.id.clone()));
                self.faces.push(Face::new(id.clone(), o));
                id
            }
        }
    }

    /// Remove every observation of the demonstration `name`, and features left without any.
    pub fn remove_demo(&mut self, name: &str) {
        self.restore_withheld_edges();
        self.demos.retain(|d| d.name != name);
        self.edges.retain_mut(|e| {
            e.observations.retain(|o| o.demo != name);
            e.pendulums.retain_mut(|p| {
                p.observations.retain(|o| o.demo != name);
                if !p.observations.is_empty() {
                    p.refit();
                }
                !p.observations.is_empty()
            });
            !e.observations.is_empty()
        });
        self.edges.iter_mut().for_each(Edge::refit);
        let (gone, kept) = std::mem::take(&mut self.landings)
            .into_iter()
            .partition(|l| l.demo == name);
        self.landings = kept;
        self.refit_landings(&gone);
        self.supports.retain(|o| o.demo != name);
        self.flights.retain(|o| o.demo != name);
        self.faces
            .iter_mut()
            .for_each(|f| f.observations.retain(|o| o.demo != name));
        self.prune_faces();
        self.refit_whole();
    }

    /// Drop the faces left without observations (and the edges' references to them), and
    /// refit the others.
    fn prune_faces(&mut self) {
        self.faces.retain(|f| !f.observations.is_empty());
        self.faces.iter_mut().for_each(Face::refit);
        let ids: Vec<String> = self.faces.iter().map(|f| f.id.clone()).collect();
        self.edges
            .iter_mut()
            .for_each(|e| e.faces.retain(|f| ids.contains(f)));
    }

    /// Recompute what depends on all the features: the edges' own estimates, the support's
    /// height and the offsets it gives the landings' faces, the edges conditioned on their
    /// faces (without those the faces they rested on contradict), the centre of mass, the
    /// shape (without the rolls' edges off it) and the contradictions between them.
    fn refit_whole(&mut self) {
        self.edges.iter_mut().for_each(Edge::refit);
        self.withhold_edges_off_landed_faces();
        loop {
            self.refit_support();
            self.withhold_unlocated_offsets();
            let out_of_faces = self.withhold_edges_out_of_their_faces();
            self.condition_edges_on_faces();
            let unlocated = self.withhold_unlocated_edges();
            self.refit_centre_of_mass();
            self.shape = self.reconstruct_shape().ok();
            // An edge withheld takes its measurement of the support's height out with it,
            // which may give the landings' faces their offsets: the shape again.
            if !self.withhold_rolls_off_shape() && !out_of_faces && !unlocated {
                break;
            }
        }
        self.contradictions = self.contradictions();
        self.refit_mass_properties();
    }

    /// The shape of the learnt faces, with a face never seen inferred opposite a seen one from
    /// the centre of mass ([`crate::shape::reconstruct_inferring`]; the CoM's standard
    /// deviation is its `sigma_m` (worst axis), at least [`SYSTEMATIC_POINT_M`]), and
    /// without the faces seen once that cut into the shape of those seen more often or could
    /// not have held the object at rest (`tree/unconfirmed.rs`; listed in its `left_out`).
    pub fn reconstruct_shape(&self) -> Result<Shape, crate::shape::Incomplete> {
        let com = self.com.as_ref().map(|c| {
            (
                c.point,
                c.sigma_m
                    .unwrap_or(c.rms_residual_m)
                    .max(SYSTEMATIC_POINT_M),
            )
        });
        let mut out = self.unconfirmed_cuts(&self.learnt_faces(), com);
        loop {
            let kept: Vec<LearntFace> = self
                .learnt_faces()
                .into_iter()
                .filter(|f| out.iter().all(|(id, _)| *id != f.id))
                .collect();
            let mut shape = crate::shape::reconstruct_inferring(&kept, com)?;
            let unstable = self.unstable_rests(&shape, com);
            if unstable.is_empty() {
                shape.left_out.extend(out);
                return Ok(shape);
            }
            out.extend(unstable);
        }
    }

    /// The faces as the shape takes them.
    pub fn learnt_faces(&self) -> Vec<LearntFace> {
        self.faces
            .iter()
            .map(|f| LearntFace {
                id: f.id.clone(),
                normal: f.normal,
                outward: f.sign_known,
                offset: f.offset,
                offset_sigma_m: f.offset_sigma_m.unwrap_or(0.0),
                normal_sigma_rad: f.sigma_normal_rad,
            })
            .collect()
    }

    /// The tree as pretty JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("the tree serialises")
    }
}
