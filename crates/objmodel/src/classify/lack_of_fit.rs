//! Split-half lack of fit: how far a part's feature, fitted to the first and to the second
//! half of its frames, moves beyond what the frames' noise explains. A contact that changes
//! while the object moves (a pivot that slips, a slide whose last frames already tip over an
//! edge) moves the later frames' fits one way; their scatter divided by their number does not
//! say so, because the moves are one trajectory, not independent errors. The excess (method
//! of moments, zero when negative) is added to the feature's covariance, so that its σ stays
//! honest.

use super::block::Block;
use super::msac::slide_normal;
use crate::geometry::{Line, LineStats, PlaneStats};
use nalgebra::{Matrix3, Vector3};

/// Per-axis variance \[m²\] of an edge's point beyond what its frames' noise explains: the
/// split-half lack of fit of the rotation-about-a-fixed-edge model.
///
/// With `order` the edge's blocks in time order, cut once where their summed point weight
/// reaches half (a cut chosen before looking at the data, so that the statistic has its null
/// distribution), the weighted mean axis points before and after differ by `d` (normal to the
/// line). Under a fixed edge `E|d|² = 2 s²`, `s² = 1/W_before + 1/W_after + (σ_ref Δ(1/c))²` per
/// axis (as in [`super::analysis`]'s change-point trimming). A pivot that moves while the object turns (a soft
/// contact whose edge sinks and rises, an edge that slips on the support past the balance
/// point: on MuJoCo's tilting palm the edge point moves 0.3 mm in the first 20° and 1-3 mm
/// after 40°) moves the axes of the later frames, which weigh the most, and the mean line with
/// them; the frames' scatter divided by their number does not say so, because the moves are
/// one trajectory, not independent errors. The excess `|d|²/2 - s²` (method of moments, zero
/// when negative) is that systematic error per axis: it is added to the edge point's
/// covariance, so that its σ stays honest where the pivot moved.
pub(super) fn systematic_point_var(
    blocks: &[Block],
    order: &[usize],
    line: &Line,
    sigma_ref: f64,
) -> f64 {
    let mut total = PointSums::default();
    order.iter().for_each(|&i| total.add(&blocks[i].line));
    if total.sw <= 0.0 || order.len() < 2 {
        return 0.0;
    }
    let u = line.direction;
    let p_mat = nalgebra::Matrix3::identity() - u * u.transpose();
    let mut before = PointSums::default();
    for &i in &order[..order.len() - 1] {
        before.add(&blocks[i].line);
        if before.sw >= 0.5 * total.sw {
            break;
        }
    }
    let (wb, wa) = (before.sw, total.sw - before.sw);
    if wb <= 0.0 || wa <= 0.0 {
        return 0.0;
    }
    let d = p_mat * (before.swr / wb - (total.swr - before.swr) / wa);
    let dc = before.sw_inv_chord / wb - (total.sw_inv_chord - before.sw_inv_chord) / wa;
    let s2 = 1.0 / wb + 1.0 / wa + (sigma_ref * dc).powi(2);
    (0.5 * d.norm_squared() - s2).max(0.0)
}

/// Per-axis variance \[rad²\] of an edge's direction beyond what its frames' noise explains:
/// the split-half lack of fit of the rotation-about-a-fixed-edge model, as
/// [`systematic_point_var`] for its point.
///
/// With `order` the edge's blocks in time order, cut once where their summed direction weight
/// reaches half, the principal directions of the axes before and after differ by `d` (normal
/// to the line). Under a fixed edge `E|d|² = 2 s²`, `s² = 1/A_before + 1/A_after + (σ_ref
/// Δ(1/c))²` per axis: each half's formal variance, and the reference orientation's error
/// `σ_ref` \[rad\], common to both halves, which turns the axis of a rotation by θ by about
/// `1/c` of itself (`c = 2 sin(θ/2)`; the halves' mean `1/c` taken with the point weights). A
/// pivot that slips while the object turns turns the axis of the later frames with it: on
/// rapier pushes at exact poses, an axis turned 1.2-2.5° within the resting face as the pivot
/// slipped 0.3-0.7 mm, and came out 6 σ off. The excess `|d|²/2 - s²` (zero when negative) is
/// that systematic error per axis. It widens the taught edge's σ, but not the σ with which
/// the edge is tested for level (`classify::analysis`): a slipping pivot turns the axis within
/// the level plane, and an axis that turns out of it (a twist, a corner pivot) is no edge.
pub(super) fn systematic_direction_var(
    blocks: &[Block],
    order: &[usize],
    line: &Line,
    sigma_ref: f64,
) -> f64 {
    if order.len() < 2 {
        return 0.0;
    }
    let (total, before, after) = split_half(blocks, order, |b| &b.line, LineStats::merge, |s| s.sa);
    if total.sa <= 0.0 || before.sa <= 0.0 || after.sa <= 0.0 || before.sw <= 0.0 || after.sw <= 0.0
    {
        return 0.0;
    }
    let u = line.direction;
    let direction = |s: &LineStats| {
        let v = crate::geometry::sym_eigen(&s.sauu).1[2];
        if v.dot(&u) < 0.0 {
            -v
        } else {
            v
        }
    };
    let p_mat = Matrix3::identity() - u * u.transpose();
    let d = p_mat * (direction(&before) - direction(&after));
    let dc = before.sw_inv_chord / before.sw - after.sw_inv_chord / after.sw;
    let s2 = 1.0 / before.sa + 1.0 / after.sa + (sigma_ref * dc).powi(2);
    (0.5 * d.norm_squared() - s2).max(0.0)
}

/// The frames' point-weighted mean of `1/c` (`c = 2 sin(θ/2)`): by this factor the error of
/// the reference pose the frames are measured from, common to every frame, moves and turns the
/// axis of their rotation (as in [`systematic_point_var`] and [`systematic_direction_var`]).
/// An edge's point and direction are off by `σ_ref` times it, per axis (for the point, the
/// reference's position and orientation error at the point \[m\]; for the direction, its
/// orientation error \[rad\]), and neither the frames' scatter shows that nor their number
/// averages it down. Small for a reference that is the mean of a rest (σ/√n); for a rest held
/// at one frame's pose (`crate::onset`), one frame's noise. Zero without point weight.
pub(super) fn mean_inv_chord(blocks: &[Block], order: &[usize]) -> f64 {
    let mut total = PointSums::default();
    order.iter().for_each(|&i| total.add(&blocks[i].line));
    if total.sw <= 0.0 {
        return 0.0;
    }
    total.sw_inv_chord / total.sw
}

/// The parts of [`LineStats`] that the change-point trimming tests, summed as
/// [`LineStats::merge`] sums them.
#[derive(Clone, Copy, Default)]
pub(super) struct PointSums {
    pub n: f64,
    pub sw: f64,
    pub swr: Vector3<f64>,
    pub sw_inv_chord: f64,
}

impl PointSums {
    #[inline]
    pub fn add(&mut self, s: &LineStats) {
        self.n += s.n;
        self.sw += s.sw;
        self.swr += s.swr;
        self.sw_inv_chord += s.sw_inv_chord;
    }
}

/// Per-axis variance \[rad²\] of a slide's face normal `n` beyond what its frames' noise
/// explains: the split-half lack of fit of the planar-motion model.
///
/// With `order` the slide's blocks in time order, cut once where their frames reach half, the
/// normals fitted to the frames before and after (each with the slide's prior `down`, the
/// level support, as the slide's own normal has it: a straight push determines its normal in
/// one direction only, and a half without the prior can turn freely in the other) differ by
/// `d` (normal to `n`). Under planar motion `E|d|² ≤ tr C_before + tr C_after`, the traces of
/// the two normals' covariances (less where the shared prior correlates them). A slide
/// whose last frames already tip over an edge (a push that ends in a roll) turns the later
/// normals towards that edge: on a session of the standard data set a slide's normal came out
/// 1.8° off at a σ of 0.34°, its second half turned towards the edge it then rolled over. The
/// excess `(|d|² - tr C_before - tr C_after) / 2` per axis is that systematic error.
pub(super) fn systematic_normal_var(
    blocks: &[Block],
    order: &[usize],
    n: &Vector3<f64>,
    down: Option<&Vector3<f64>>,
) -> f64 {
    if order.len() < 2 {
        return 0.0;
    }
    let (_, before, after) = split_half(blocks, order, |b| &b.plane, PlaneStats::merge, |s| s.n);
    let half = |s: &PlaneStats| -> Option<(Vector3<f64>, Matrix3<f64>)> {
        let s = slide_normal(s, down);
        let m = s.normal()?.into_inner();
        let m = if m.dot(n) < 0.0 { -m } else { m };
        let c = s.normal_covariance(&m);
        c.iter().all(|x| x.is_finite()).then_some((m, c))
    };
    let (Some((nb, cb)), Some((na, ca))) = (half(&before), half(&after)) else {
        return 0.0;
    };
    let p = Matrix3::identity() - n * n.transpose();
    let d = p * (nb - na);
    (0.5 * (d.norm_squared() - cb.trace() - ca.trace())).max(0.0)
}

/// The statistics (`stats` of each block) of all the blocks of `order` (at least 2, in time
/// order), and of those before and after one cut, made before looking at the data where the
/// `weight` of the blocks before it reaches half of all of theirs (at least one block after
/// it): `(total, before, after)`, each merged in time order.
fn split_half<S: Default>(
    blocks: &[Block],
    order: &[usize],
    stats: impl Fn(&Block) -> &S,
    merge: impl Fn(&mut S, &S),
    weight: impl Fn(&S) -> f64,
) -> (S, S, S) {
    let mut total = S::default();
    order
        .iter()
        .for_each(|&i| merge(&mut total, stats(&blocks[i])));
    let mut before = S::default();
    let mut cut = 0;
    for (k, &i) in order[..order.len() - 1].iter().enumerate() {
        merge(&mut before, stats(&blocks[i]));
        cut = k + 1;
        if weight(&before) >= 0.5 * weight(&total) {
            break;
        }
    }
    let mut after = S::default();
    order[cut..]
        .iter()
        .for_each(|&i| merge(&mut after, stats(&blocks[i])));
    (total, before, after)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::classify::block::Phase;
    use rand::{rngs::StdRng, Rng, SeedableRng};
    use rand_distr::{Distribution, Normal};

    /// A slide's blocks (4 frames each, 40 frames): the object turns by up to 0.6 rad about
    /// the normal `n0` while it translates in the plane; from frame `tip_from` on it also
    /// tips about the horizontal `u` by `tip_rate` per frame. Rotation noise `sr` \[rad\],
    /// translation noise 1 mm.
    fn blocks(tip_from: usize, tip_rate: f64, sr: f64, rng: &mut StdRng) -> Vec<Block> {
        let (n0, u, v) = (Vector3::z(), Vector3::x(), Vector3::y());
        let (nr, nt) = (
            Normal::new(0.0, sr).unwrap(),
            Normal::new(0.0, 1e-3).unwrap(),
        );
        let mut out: Vec<Block> = Vec::new();
        for k in 0..40 {
            if k % 4 == 0 {
                out.push(Block::new(k, k as f64, Phase::Moving, Some(0)));
            }
            let tip = tip_rate * k.saturating_sub(tip_from) as f64;
            let omega = n0 * (0.6 * k as f64 / 40.0) + u * tip;
            let omega = omega + Vector3::from_fn(|_, _| nr.sample(rng));
            let t =
                (u * 0.03 + v * 0.01) * (k as f64 / 40.0) + Vector3::from_fn(|_, _| nt.sample(rng));
            out.last_mut().unwrap().plane.add(&omega, &t, sr * sr, 1e-6);
        }
        out
    }

    /// The normal fitted to all the blocks (with the level prior, as a slide's is), its
    /// error against the true `z` in its own covariance's σ, with and without the lack of fit.
    fn z_scores(b: &[Block]) -> (f64, f64) {
        let order: Vec<usize> = (0..b.len()).collect();
        let mut total = PlaneStats::default();
        b.iter().for_each(|x| total.merge(&x.plane));
        let down = Vector3::z();
        let s = slide_normal(&total, Some(&down));
        let n = s.normal().unwrap().into_inner();
        let n = if n.z < 0.0 { -n } else { n };
        let cov = s.normal_covariance(&n);
        let across = Matrix3::identity() - n * n.transpose();
        let e = across * Vector3::z();
        let z = |c: Matrix3<f64>| e.dot(&(c.pseudo_inverse(1e-18).unwrap() * e)).sqrt();
        let sys = systematic_normal_var(b, &order, &n, Some(&down));
        (z(cov), z(cov + across * sys))
    }

    #[test]
    fn a_slide_that_ends_tipping_gets_a_sigma_that_covers_its_error() {
        let mut rng = StdRng::seed_from_u64(3);
        for _ in 0..20 {
            // The last 15 frames tip 0.4° more each: 6° at the end.
            let b = blocks(25, 0.4f64.to_radians(), 1e-3, &mut rng);
            let (without, with) = z_scores(&b);
            assert!(
                without > 5.0,
                "the tipping frames bias the normal: {without:.1} σ"
            );
            assert!(with < 3.0, "the lack of fit covers it: {with:.1} σ");
        }
    }

    #[test]
    fn planar_halves_add_little_beyond_their_noise() {
        let mut rng = StdRng::seed_from_u64(5);
        let mut z = Vec::new();
        let mut unchanged = 0;
        for _ in 0..400 {
            let sr = rng.random_range(2e-3..1e-2);
            let b = blocks(40, 0.0, sr, &mut rng);
            let (without, with) = z_scores(&b);
            unchanged += (with == without) as usize;
            z.push(with);
        }
        z.sort_by(f64::total_cmp);
        // Under the null |d|² exceeds its expectation about a third of the time, and the
        // shared prior makes that rarer; the honest median of a 2-D |error|/σ is 1.18.
        assert!(unchanged >= 200, "{unchanged} of 400 unchanged");
        assert!(
            z[200] > 0.5,
            "median z {:.2}: the σ is not inflated",
            z[200]
        );
        assert!(z[399] < 4.3, "max z {:.2}", z[399]);
    }

    /// An edge's blocks (4 frames each, 80 frames): each frame's axis is `z` plus noise of
    /// `sd` \[rad\] per axis, turned towards `x` within the resting plane by `turn_rate` per
    /// frame from frame `turn_from` on (a pivot that slips as the object falls).
    fn edge_blocks(turn_from: usize, turn_rate: f64, sd: f64, rng: &mut StdRng) -> Vec<Block> {
        let nd = Normal::new(0.0, sd).unwrap();
        let mut out: Vec<Block> = Vec::new();
        for k in 0..80 {
            if k % 4 == 0 {
                out.push(Block::new(k, k as f64, Phase::Moving, Some(0)));
            }
            let turn = turn_rate * k.saturating_sub(turn_from) as f64;
            let u = Vector3::new(turn.sin(), 0.0, turn.cos())
                + Vector3::new(nd.sample(rng), nd.sample(rng), 0.0);
            let r = Vector3::new(0.05, 0.02, 0.0);
            let a = 1.0 / (sd * sd);
            out.last_mut()
                .unwrap()
                .line
                .add(&r, &u.normalize(), 1e8, a, 0.0);
        }
        out
    }

    /// The direction fitted to all the blocks, its error against the true `z` in its own
    /// covariance's σ, without and with the lack of fit.
    fn direction_z_scores(b: &[Block]) -> (f64, f64) {
        let order: Vec<usize> = (0..b.len()).collect();
        let mut total = LineStats::default();
        b.iter().for_each(|x| total.merge(&x.line));
        let line = total.mean().unwrap();
        let line = if line.direction.z < 0.0 {
            Line::through(line.point, -line.direction)
        } else {
            line
        };
        let (_, cov) = total.covariances(&line);
        let u = line.direction;
        let across = Matrix3::identity() - u * u.transpose();
        let e = across * (Vector3::z() - u);
        let z = |c: Matrix3<f64>| e.dot(&(c.pseudo_inverse(1e-18).unwrap() * e)).sqrt();
        let sys = systematic_direction_var(b, &order, &line, 0.0);
        (z(cov), z(cov + across * sys))
    }

    #[test]
    fn an_axis_that_turns_gets_a_sigma_that_covers_its_error() {
        let mut rng = StdRng::seed_from_u64(7);
        for _ in 0..20 {
            // The last 40 frames turn 0.05° more each: 2° at the end.
            let b = edge_blocks(40, 0.05f64.to_radians(), 1e-3, &mut rng);
            let (without, with) = direction_z_scores(&b);
            assert!(without > 5.0, "the turned axes bias it: {without:.1} σ");
            assert!(with < 3.0, "the lack of fit covers it: {with:.1} σ");
        }
    }

    #[test]
    fn a_fixed_axis_adds_little_beyond_its_noise() {
        let mut rng = StdRng::seed_from_u64(9);
        let mut z = Vec::new();
        let mut unchanged = 0;
        for _ in 0..400 {
            let sd = rng.random_range(1e-3..1e-2);
            let (without, with) = direction_z_scores(&edge_blocks(80, 0.0, sd, &mut rng));
            unchanged += (with == without) as usize;
            z.push(with);
        }
        z.sort_by(f64::total_cmp);
        // Under the null |d|²/2 exceeds s² about a third of the time. The honest median of a
        // 2-D |error|/σ is 1.18.
        assert!(unchanged >= 200, "{unchanged} of 400 unchanged");
        assert!(
            z[200] > 0.9 && z[200] < 1.5,
            "median z {:.2}: honest 1.18",
            z[200]
        );
        assert!(z[399] < 4.3, "max z {:.2}", z[399]);
    }
}
