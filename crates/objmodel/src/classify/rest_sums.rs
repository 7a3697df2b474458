//! The least-squares sums of the rest test's window ([`super::rest`]): per coordinate, the
//! sums a straight-line fit in time needs, about a local origin, and the χ²₆ test of the
//! fitted slopes.

/// Number of running sums (padded to an even count for two-lane SIMD).
pub(super) const TERMS: usize = 16;

/// Least-squares sums of (t, x) over a run of items, about a local origin: with `dt = t - t₀`
/// and `x = x - x₀`, the terms of a frame are `[1, dt, dt², 0, x₀..x₅, dt·x₀..dt·x₅]`, so adding
/// an item is one vector addition. (The padding lane 3 keeps each group on whole SIMD lanes.)
#[derive(Clone, Copy, Debug)]
pub(super) struct Sums(pub(super) [f64; TERMS]);

/// Lane of the first `x` sum in [`Sums`].
const SX: usize = 4;
/// Lane of the first `dt·x` sum in [`Sums`].
const STX: usize = 10;

impl Default for Sums {
    fn default() -> Self {
        Sums([0.0; TERMS])
    }
}

/// The terms of a frame at `t, x` about `origin` (see [`Sums`]).
#[inline(always)]
pub(super) fn terms(t: f64, x: &[f64; 6], origin: &(f64, [f64; 6])) -> [f64; TERMS] {
    let dt = t - origin.0;
    let mut v = [0.0; TERMS];
    v[0] = 1.0;
    v[1] = dt;
    v[2] = dt * dt;
    for j in 0..6 {
        let d = x[j] - origin.1[j];
        v[SX + j] = d;
        v[STX + j] = dt * d;
    }
    v
}

impl Sums {
    // `add` and `minus` work on copies, written back whole: in place, the compiler cannot rule
    // out that the operand overlaps the sums, and adds lane by lane through memory.

    /// Add the terms of an item.
    #[inline(always)]
    pub(super) fn add(&mut self, terms: &[f64; TERMS]) {
        let (mut s, v) = (self.0, *terms);
        for j in 0..TERMS {
            s[j] += v[j];
        }
        self.0 = s;
    }

    /// `self - other`: the sums over the items in one run and not in the other.
    #[inline(always)]
    pub(super) fn minus(&self, other: &Sums) -> Sums {
        let (mut s, v) = (self.0, other.0);
        for j in 0..TERMS {
            s[j] -= v[j];
        }
        Sums(s)
    }

    /// Whether the χ²₆ statistic of the slope exceeds `threshold` (never with fewer than 3
    /// frames). With `D = n S_tt - S_t²` the slope is `β_j = (n S_tx_j - S_t S_x_j) / D` and
    /// its variance `σ_j² n / D`, so the statistic is `Σ_j (n S_tx_j - S_t S_x_j)² / (σ_j² n D)`,
    /// compared here without a division.
    #[inline(always)]
    pub(super) fn exceeds(&self, inv_var: &[f64; 6], threshold: f64) -> bool {
        let [n, st, stt, ..] = self.0;
        if n < 2.5 {
            return false;
        }
        let den = n * stt - st * st;
        if den <= 0.0 {
            return false;
        }
        let mut sum = 0.0;
        for (j, iv) in inv_var.iter().enumerate() {
            let b = n * self.0[STX + j] - st * self.0[SX + j];
            sum += b * b * iv;
        }
        sum > threshold * n * den
    }
}
