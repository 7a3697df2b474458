//! Lines and planes, and the sufficient statistics from which they are fitted.
//!
//! Per-frame screw axes are accumulated as weighted sums (no per-frame storage), so a fit over
//! any union of frames is a sum of [`LineStats`] or [`PlaneStats`] followed by a small
//! eigen-problem: this is what keeps the learner's memory independent of the file length.

use nalgebra::{Matrix3, SymmetricEigen, Unit, Vector3};
use serde::{Deserialize, Serialize};

/// An infinite line `{point + λ direction}`, `point` the line's point closest to the origin.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Line {
    /// Point of the line closest to the origin \[m\].
    pub point: Vector3<f64>,
    /// Unit direction.
    pub direction: Vector3<f64>,
}

impl Line {
    /// The line through `p` along `d` (normalised), stored by its point closest to the origin.
    pub fn through(p: Vector3<f64>, d: Vector3<f64>) -> Self {
        let d = d.normalize();
        Self {
            point: p - d * d.dot(&p),
            direction: d,
        }
    }

    /// Distance \[m\] from `x` to the line.
    pub fn distance_to(&self, x: &Vector3<f64>) -> f64 {
        let r = x - self.point;
        (r - self.direction * self.direction.dot(&r)).norm()
    }

    /// The same line with its direction reversed if it points away from `reference`.
    pub fn aligned_with(mut self, reference: &Vector3<f64>) -> Self {
        if self.direction.dot(reference) < 0.0 {
            self.direction = -self.direction;
        }
        self
    }
}

/// A plane `{x : normal · x = offset}`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Plane {
    /// Unit normal.
    pub normal: Vector3<f64>,
    /// Offset \[m\]: signed distance of the plane from the origin along `normal`.
    pub offset: f64,
}

/// Signed angle \[rad\] from `a` to `b` about `axis` (unit), both projected onto the plane
/// normal to it (right-hand rule).
pub fn angle_about(axis: &Vector3<f64>, a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    let pa = a - axis * axis.dot(a);
    let pb = b - axis * axis.dot(b);
    axis.dot(&pa.cross(&pb)).atan2(pa.dot(&pb))
}

/// A symmetric 3×3 matrix by its 6 distinct entries `[xx, xy, xz, yy, yz, zz]`: sums of outer
/// products accumulate in 6 additions instead of 9.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Sym3(pub [f64; 6]);

impl Sym3 {
    /// The outer product `x xᵀ s`, its entries rounded as `(x_i x_j) s`, exactly as those of
    /// `x * x.transpose() * s`.
    #[inline]
    pub fn outer(x: &Vector3<f64>, s: f64) -> Self {
        Self([
            x.x * x.x * s,
            x.x * x.y * s,
            x.x * x.z * s,
            x.y * x.y * s,
            x.y * x.z * s,
            x.z * x.z * s,
        ])
    }

    /// Add `x xᵀ s` (rounded as [`Sym3::outer`]).
    #[inline]
    pub fn add_outer(&mut self, x: &Vector3<f64>, s: f64) {
        let o = Self::outer(x, s);
        for (a, b) in self.0.iter_mut().zip(o.0) {
            *a += b;
        }
    }

    /// `x xᵀ` (6 multiplications).
    #[inline]
    pub fn square(x: &Vector3<f64>) -> Self {
        Self::upper(x, x)
    }

    /// The upper triangle of `y xᵀ` (entries `y_i x_j`, i ≤ j), as a symmetric matrix.
    #[inline(always)]
    fn upper(y: &Vector3<f64>, x: &Vector3<f64>) -> Self {
        Self([
            y.x * x.x,
            y.x * x.y,
            y.x * x.z,
            y.y * x.y,
            y.y * x.z,
            y.z * x.z,
        ])
    }

    /// Add `o`.
    #[inline]
    pub fn add(&mut self, o: &Self) {
        for (a, b) in self.0.iter_mut().zip(o.0) {
            *a += b;
        }
    }

    /// Add `s o`.
    #[inline]
    pub fn add_scaled(&mut self, o: &Self, s: f64) {
        for (a, b) in self.0.iter_mut().zip(o.0) {
            *a += s * b;
        }
    }

    /// Add the upper triangle of `y xᵀ` (entries `y_i x_j`, i ≤ j): for `y = s x` that is
    /// `s x xᵀ` in 6 multiplications once `y` is known (rounded otherwise than
    /// [`Sym3::add_outer`]).
    #[inline]
    pub fn add_product(&mut self, y: &Vector3<f64>, x: &Vector3<f64>) {
        self.add(&Self::upper(y, x));
    }

    /// The full matrix.
    #[inline]
    pub fn to_matrix(&self) -> Matrix3<f64> {
        let [xx, xy, xz, yy, yz, zz] = self.0;
        Matrix3::new(xx, xy, xz, xy, yy, yz, xz, yz, zz)
    }
}

/// Two unit vectors normal to the unit `v` and to each other (`[a, v × a]`, `a` from `v × x`,
/// or `v × y` where `v` is near x).
pub fn normal_axes(v: &Vector3<f64>) -> [Vector3<f64>; 2] {
    let a = v.cross(&Vector3::x());
    let a = if a.norm() < 0.5 {
        v.cross(&Vector3::y())
    } else {
        a
    };
    let a = a.normalize();
    [a, v.cross(&a)]
}

/// Eigen-decomposition of a symmetric 3×3 matrix, eigenvalues ascending.
pub fn sym_eigen(m: &Matrix3<f64>) -> ([f64; 3], [Vector3<f64>; 3]) {
    let e = SymmetricEigen::new(0.5 * (m + m.transpose()));
    let mut idx = [0usize, 1, 2];
    idx.sort_by(|&a, &b| e.eigenvalues[a].total_cmp(&e.eigenvalues[b]));
    let vals = idx.map(|i| e.eigenvalues[i]);
    let vecs = idx.map(|i| e.eigenvectors.column(i).into_owned());
    (vals, vecs)
}

/// A line with the parts of [`LineStats::chi2`] that depend on it alone: the projector
/// `P = I - u uᵀ` normal to it and `pᵀ P p`.
#[derive(Clone, Copy, Debug)]
pub struct LineChi2 {
    point: Vector3<f64>,
    direction: Vector3<f64>,
    p_mat: Matrix3<f64>,
    p_p_p: f64,
}

impl LineChi2 {
    /// Prepare `line`.
    pub fn new(line: &Line) -> Self {
        let (p, u) = (line.point, line.direction);
        let p_mat = Matrix3::identity() - u * u.transpose();
        Self {
            point: p,
            direction: u,
            p_mat,
            p_p_p: p.dot(&(p_mat * p)),
        }
    }
}

/// Weighted sufficient statistics of a set of lines `(r_k, u_k)` (points closest to the origin,
/// unit directions), for the directional mean of the axes and the euclidean mean of the points.
///
/// * point weights `w_k` = 1 / (variance of `r_k` per axis across the line) \[1/m²\],
/// * direction weights `a_k` = 1 / (variance of `u_k` per axis) \[1/rad²\].
///
/// The mean direction is the principal eigenvector of `Σ a_k u_k u_kᵀ` (axial data: u and -u
/// count the same), and the mean point is the weighted mean of the `r_k` projected onto the
/// plane normal to it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LineStats {
    /// Number of lines.
    pub n: f64,
    /// Σ w.
    pub sw: f64,
    /// Σ w².
    pub sww: f64,
    /// Σ w r.
    pub swr: Vector3<f64>,
    /// Σ w r rᵀ.
    pub swrr: Matrix3<f64>,
    /// Σ a.
    pub sa: f64,
    /// Σ a².
    pub saa: f64,
    /// Σ a u uᵀ.
    pub sauu: Matrix3<f64>,
    /// Σ of the χ² of the along-axis translation (pitch) residuals.
    pub pitch_chi2: f64,
    /// Σ w / c, with c the chord `2 sin(θ/2)` of each line's rotation: the weighted mean of
    /// 1/c tells how strongly a common reference-pose error shifts these lines.
    pub sw_inv_chord: f64,
}

impl LineStats {
    /// Add one line with point weight `w` and direction weight `a`, and its pitch χ².
    #[inline]
    pub fn add(&mut self, r: &Vector3<f64>, u: &Vector3<f64>, w: f64, a: f64, pitch_chi2: f64) {
        self.add_with_chord(r, u, w, a, pitch_chi2, 0.0);
    }

    /// [`LineStats::add`] for a line from a rotation with chord `2 sin(θ/2)` = 1/`inv_chord`.
    #[inline]
    pub fn add_with_chord(
        &mut self,
        r: &Vector3<f64>,
        u: &Vector3<f64>,
        w: f64,
        a: f64,
        pitch_chi2: f64,
        inv_chord: f64,
    ) {
        self.sw_inv_chord += w * inv_chord;
        self.n += 1.0;
        self.sw += w;
        self.sww += w * w;
        self.swr += r * w;
        self.swrr += Sym3::outer(r, w).to_matrix();
        self.sa += a;
        self.saa += a * a;
        self.sauu += Sym3::outer(u, a).to_matrix();
        self.pitch_chi2 += pitch_chi2;
    }

    /// Merge another set of statistics into this one.
    pub fn merge(&mut self, o: &Self) {
        self.n += o.n;
        self.sw += o.sw;
        self.sww += o.sww;
        self.swr += o.swr;
        self.swrr += o.swrr;
        self.sa += o.sa;
        self.saa += o.saa;
        self.sauu += o.sauu;
        self.pitch_chi2 += o.pitch_chi2;
        self.sw_inv_chord += o.sw_inv_chord;
    }

    /// The mean line, or `None` without data.
    pub fn mean(&self) -> Option<Line> {
        if self.n < 1.0 || self.sw <= 0.0 || self.sa <= 0.0 {
            return None;
        }
        let (_, vecs) = sym_eigen(&self.sauu);
        let u = vecs[2];
        let p = self.swr / self.sw;
        Some(Line::through(p, u))
    }

    /// χ² of these lines against `line`: Σ w |P(r - p)|² + Σ a |u × u_L|² + pitch χ², with
    /// P the projector normal to the line. Degrees of freedom: 5 per line.
    pub fn chi2(&self, line: &Line) -> f64 {
        self.chi2_to(&LineChi2::new(line))
    }

    /// [`LineStats::chi2`] against a line prepared once for many statistics.
    #[inline]
    pub fn chi2_to(&self, l: &LineChi2) -> f64 {
        let (u, p, p_mat) = (l.direction, l.point, l.p_mat);
        let point =
            (p_mat * self.swrr).trace() - 2.0 * p.dot(&(p_mat * self.swr)) + self.sw * l.p_p_p;
        let dir = self.sa - u.dot(&(self.sauu * u));
        point.max(0.0) + dir.max(0.0) + self.pitch_chi2
    }

    /// Covariances of the mean line from the weighted scatter of the lines about it:
    /// `(point covariance \[m²\], direction covariance \[rad²\])`, each divided by the effective
    /// number of independent lines `(Σw)²/Σw²` and projected normal to the line.
    pub fn covariances(&self, line: &Line) -> (Matrix3<f64>, Matrix3<f64>) {
        let u = line.direction;
        let p_mat = Matrix3::identity() - u * u.transpose();
        let mean_r = self.swr / self.sw;
        let scatter_r = self.swrr / self.sw - mean_r * mean_r.transpose();
        let n_eff_r = (self.sw * self.sw / self.sww).max(1.0);
        // Scatter of the unit directions about u: E[uuᵀ] projected normal to u.
        let scatter_u = self.sauu / self.sa;
        let n_eff_u = (self.sa * self.sa / self.saa).max(1.0);
        // Formal (model) covariance floors: 1/Σw per axis and 1/Σa per axis.
        // The formal covariance, and the scatter's excess over it where the lines scatter
        // more than their weights say (the scatter holds the noise the weights already hold:
        // summing the two counted it twice, and the σ came out √2 too large).
        let with_excess = |scatter: Matrix3<f64>, formal: Matrix3<f64>| {
            let (vals, vecs) = sym_eigen(&(scatter - formal));
            let excess = (0..3).fold(Matrix3::zeros(), |m, i| {
                m + vecs[i] * vecs[i].transpose() * vals[i].max(0.0)
            });
            formal + p_mat * excess * p_mat
        };
        let cov_p = with_excess(p_mat * (scatter_r / n_eff_r) * p_mat, p_mat / self.sw);
        let cov_u = with_excess(p_mat * (scatter_u / n_eff_u) * p_mat, p_mat / self.sa);
        (cov_p, cov_u)
    }
}

/// Sufficient statistics for the plane-of-motion (slide) hypothesis: frames whose rotation
/// vectors ω_k are parallel to a normal n and whose translations t_k are normal to it.
///
/// `χ²(n) = Σ |ω_k × n|²/σ_ω² + Σ (n·t_k)²/σ_t² = tr(S_ωω) - nᵀ S_ωω n + nᵀ S_tt n`
/// with `S_ωω = Σ ω ωᵀ/σ_ω²`, `S_tt = Σ t tᵀ/σ_t²`; the best n is the eigenvector of the
/// smallest eigenvalue of `S_tt - S_ωω`. Degrees of freedom: 3 per frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PlaneStats {
    /// Number of frames.
    pub n: f64,
    /// Σ ω ωᵀ / σ_ω².
    pub sww: Matrix3<f64>,
    /// Σ t tᵀ / σ_t².
    pub stt: Matrix3<f64>,
}

impl PlaneStats {
    /// Add one frame: rotation vector `omega` \[rad\] with variance `var_omega` \[rad²\] per
    /// axis, translation `t` \[m\] with variance `var_t` \[m²\] per axis.
    #[inline]
    pub fn add(&mut self, omega: &Vector3<f64>, t: &Vector3<f64>, var_omega: f64, var_t: f64) {
        self.add_weighted(omega, t, 1.0 / var_omega, 1.0 / var_t);
    }

    /// [`PlaneStats::add`] with the weights (inverse variances) given: `w_omega` = 1/σ_ω²
    /// \[1/rad²\], `w_t` = 1/σ_t² \[1/m²\] (no division per frame).
    #[inline]
    pub fn add_weighted(&mut self, omega: &Vector3<f64>, t: &Vector3<f64>, w_omega: f64, w_t: f64) {
        self.n += 1.0;
        self.sww += Sym3::outer(omega, w_omega).to_matrix();
        self.stt += Sym3::outer(t, w_t).to_matrix();
    }

    /// Merge another set of statistics into this one.
    pub fn merge(&mut self, o: &Self) {
        self.n += o.n;
        self.sww += o.sww;
        self.stt += o.stt;
    }

    /// These statistics with a prior on the normal: `down` (unit) within `sigma` \[rad\] per
    /// axis, i.e. `χ²(n)` gains `|n × down|²/σ²`. For a unit `n`, `|n × d|² = nᵀ(I - d dᵀ)n`, so
    /// the prior is `(I - d dᵀ)/σ²` added to `S_tt`, and [`PlaneStats::normal`] and
    /// [`PlaneStats::normal_covariance`] then give the posterior normal and its covariance
    /// (the frame count is unchanged). Data that leave the normal undetermined within a plane
    /// (a straight push: every normal perpendicular to the translation fits) take it from the
    /// prior there; data that determine it are moved by it only as far as the weights say.
    pub fn with_normal_prior(&self, down: &Vector3<f64>, sigma: f64) -> Self {
        let d = down.normalize();
        Self {
            stt: self.stt + (Matrix3::identity() - d * d.transpose()) / (sigma * sigma),
            ..*self
        }
    }

    /// The best-fitting normal (sign arbitrary), `None` without data.
    pub fn normal(&self) -> Option<Unit<Vector3<f64>>> {
        if self.n < 1.0 {
            return None;
        }
        let (_, vecs) = sym_eigen(&(self.stt - self.sww));
        Some(Unit::new_normalize(vecs[0]))
    }

    /// χ² of these frames against the normal `n`.
    pub fn chi2(&self, n: &Vector3<f64>) -> f64 {
        (self.sww.trace() - n.dot(&(self.sww * n)) + n.dot(&(self.stt * n))).max(0.0)
    }

    /// Covariance \[rad²\] of the fitted normal: the inverse of the χ² Hessian restricted to the
    /// plane normal to n, `(S_ωω' + S_tt)` projected, where the Hessian of the quadratic form
    /// about its minimum is `2(M - λ_min I)` on that plane.
    pub fn normal_covariance(&self, n: &Vector3<f64>) -> Matrix3<f64> {
        let m = self.stt - self.sww;
        let (vals, vecs) = sym_eigen(&m);
        let mut cov = Matrix3::zeros();
        for i in 1..3 {
            let gap = (vals[i] - vals[0]).max(1e-300);
            cov += vecs[i] * vecs[i].transpose() / gap;
        }
        let p = Matrix3::identity() - n * n.transpose();
        p * cov * p
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_mean_recovers_a_line_and_chi2_is_zero_on_it() {
        let truth = Line::through(Vector3::new(0.05, 0.3, -0.1), Vector3::new(0.0, 1.0, 0.2));
        let mut s = LineStats::default();
        for k in 0..10 {
            let w = 1.0 + k as f64;
            // Same line, stored by different points along it (all project to the same point).
            s.add(
                &truth.point,
                &(truth.direction * if k % 2 == 0 { 1.0 } else { -1.0 }),
                w,
                w,
                0.0,
            );
        }
        let m = s.mean().unwrap();
        assert!((m.point - truth.point).norm() < 1e-12);
        assert!((m.direction.dot(&truth.direction).abs() - 1.0).abs() < 1e-12);
        assert!(s.chi2(&m) < 1e-9);
        let shifted = Line::through(truth.point + Vector3::new(0.01, 0.0, 0.0), truth.direction);
        assert!(s.chi2(&shifted) > 1e-5 * s.sw);
    }

    #[test]
    fn sym3_outer_is_the_outer_product_bit_for_bit() {
        let x = Vector3::new(0.3, -1.7e-3, 2.9);
        let s = 0.37;
        assert_eq!(Sym3::outer(&x, s).to_matrix(), x * x.transpose() * s);
    }

    #[test]
    fn plane_normal_from_planar_motion() {
        let n = Vector3::new(0.0, 0.6, 0.8);
        let a = n.cross(&Vector3::x()).normalize();
        let b = n.cross(&a);
        let mut s = PlaneStats::default();
        for k in 1..20 {
            let k = k as f64;
            s.add(
                &(n * 0.05 * k),
                &(a * 0.01 * k + b * 0.003 * k * k),
                1e-4,
                1e-6,
            );
        }
        let fit = s.normal().unwrap();
        assert!((fit.dot(&n).abs() - 1.0).abs() < 1e-12);
        assert!(s.chi2(&n) < 1e-6);
        assert!(s.chi2(&Vector3::x()) > 1.0);
    }
}
