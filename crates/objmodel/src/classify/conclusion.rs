//! What a demonstration's segments teach together: each segment's analysis
//! ([`super::analysis`]), the votes, and the topples grouped by edge.

use super::analysis::{analyse_segment, edge_observation};
use super::block::runs;
use super::segments::Segmented;
use super::{Classification, Kind, Method, Segment, Votes};
use crate::geometry::LineStats;

/// The classification of a segmented demonstration (the robust method's result).
pub(super) fn conclude(
    mut segmented: Segmented,
    name: &str,
    instrumented: bool,
    frames: u64,
) -> Classification {
    let config0 = segmented.config;
    let alpha = config0.robust.alpha;
    // The fits use the noise in force (given or estimated).
    let mut config = config0;
    config.robust.noise = segmented.noise;
    let mut segments = Vec::with_capacity(segmented.segments.len());
    let mut votes = Votes::default();
    let mut warnings = Vec::new();
    for (i, seg) in segmented.segments.iter().enumerate() {
        let (s, warning) = analyse_segment(
            i,
            instrumented,
            seg,
            &mut segmented.blocks,
            &config,
            alpha,
            name,
        );
        warnings.extend(warning);
        votes.add(s.kind, 0);
        for (k, n) in [
            (Kind::Topple, s.votes.topple),
            (Kind::Slide, s.votes.slide),
            (Kind::General, s.votes.general),
        ] {
            votes.add(k, n);
        }
        segments.push(s);
    }
    let topples = group_topples(&segments, alpha, name);
    let paper_edge = topples
        .iter()
        .max_by_key(|t| t.edge.frames)
        .and_then(|t| t.edge.paper_line);
    let mut c = Classification {
        name: name.to_string(),
        kind: votes.winner().unwrap_or(Kind::General),
        method: Method::Robust,
        instrumented,
        frames,
        outliers: segmented.outliers,
        votes,
        noise: segmented.noise,
        noise_given: config0.robust.noise.is_some(),
        segments,
        topples,
        labels: runs(&segmented.blocks),
        paper_edge,
        gravity_doubted: !warnings.is_empty(),
        warnings,
        ..Default::default()
    };
    c.fill_parts();
    c
}

/// Group the topple segments of a demonstration by edge. The line of a topple is fixed in the
/// object, so per-frame line statistics of different segments (different reference poses) are
/// directly comparable: a segment joins a group when the likelihood-ratio statistic
/// `χ²(pooled) - χ²(group) - χ²(segment)`, each about its own mean line, is below the χ²₄
/// quantile at `alpha` (4 = the parameters of a line). A topple that paused half way (or a
/// quasi-static one slow enough to pass for rest now and then) thus stays one topple.
pub(crate) fn group_topples(segments: &[Segment], alpha: f64, demo: &str) -> Vec<super::Topple> {
    let threshold = crate::stats::chi2_threshold(4.0, alpha);
    let own = |s: &LineStats| s.mean().map_or(0.0, |l| s.chi2(&l));
    let mut groups: Vec<(Vec<usize>, LineStats, super::LargestRotation)> = Vec::new();
    for (i, seg) in segments.iter().enumerate() {
        let (Kind::Topple, Some(best)) = (seg.kind, seg.topple_best) else {
            continue;
        };
        let s = &seg.topple_stats;
        let joinable = groups
            .iter_mut()
            .map(|g| {
                let mut pooled = g.1;
                pooled.merge(s);
                (own(&pooled) - own(&g.1) - own(s), g)
            })
            .filter(|(lr, _)| *lr < threshold)
            .min_by(|a, b| a.0.total_cmp(&b.0));
        match joinable {
            Some((_, g)) => {
                g.0.push(i);
                g.1.merge(s);
                if best.0 > g.2 .0 {
                    g.2 = best;
                }
            }
            None => groups.push((vec![i], *s, best)),
        }
    }
    groups
        .into_iter()
        .filter_map(|(idx, stats, best)| {
            let mut edge = edge_observation(&stats, best, demo)?;
            // The largest systematic errors of its segments' pivots (one trajectory each: they
            // do not average down over segments).
            let largest = |var: fn(&Segment) -> f64| {
                idx.iter().map(|&i| var(&segments[i])).fold(0.0, f64::max)
            };
            edge.add_systematic_point_var(largest(|s| s.topple_systematic_var));
            edge.add_systematic_direction_var(largest(|s| s.topple_systematic_direction_var));
            idx.iter()
                .filter_map(|&i| segments[i].support_constraint.as_ref())
                .for_each(|c| edge.condition_on(c));
            // The contact's depth, as its segments measured it (the same contact in each).
            let depth = idx
                .iter()
                .filter_map(|&i| segments[i].edge.as_ref())
                .map(|e| e.common_point_cov)
                .max_by(|a, b| a.trace().total_cmp(&b.trace()));
            if let Some(depth) = depth {
                edge.add_common_point_cov(&depth);
            }
            Some(super::Topple {
                resting_normal_before: segments[idx[0]].resting_normal_before,
                // The face after only when the topple lasts to the rest (landing aside): after
                // another motion, the rest is not where the topple ended.
                resting_normal_after: Some(&segments[*idx.last().unwrap()])
                    .filter(|s| s.arrives_on_support)
                    .and_then(|s| s.resting_normal_after),
                segments: idx,
                edge,
            })
        })
        .collect()
}
