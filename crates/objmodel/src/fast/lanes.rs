//! Four `f64` lanes, for the per-frame kernels that take frames four at a time.
//!
//! [`F4`] is a plain `[f64; 4]` with element-wise arithmetic. Compiled inside a function built
//! for AVX2 (see [`super::avx2_or_baseline!`]), each operation is one 256-bit instruction; elsewhere it is two
//! 128-bit ones (SSE2, every x86-64) or four scalar ones. Every lane is rounded exactly as the
//! scalar expression it mirrors (IEEE-754 `+ - * / sqrt` are correctly rounded whatever the
//! vector width, and Rust never fuses a multiply and an add), so a four-lane kernel gives the
//! same bits as its scalar original, frame by frame; the tests of each kernel check that.
//!
//! The gain is in the divider and the square root: on current x86 cores a 256-bit division
//! issues about as often as a scalar one, so four frames share its cost.
//!
//! Branches become [`M4`] masks and [`M4::select`]; a kernel computes both sides only when its
//! lanes disagree.
//!
//! Everything here is written out lane by lane, without `array::map`, `from_fn` or iterators:
//! those are generic functions that the compiler may leave un-inlined, and a call out of an
//! AVX2 kernel costs more than the operation.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// Four `f64` lanes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct F4(pub [f64; 4]);

/// Four lane conditions (the result of a comparison of [`F4`]s).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct M4(pub [bool; 4]);

/// A 3-vector of lanes: lane `k` of each coordinate is the `k`-th vector.
pub type V4 = [F4; 3];

macro_rules! lanewise {
    ($trait:ident, $method:ident, $op:tt) => {
        impl $trait for F4 {
            type Output = F4;
            #[inline(always)]
            fn $method(self, o: F4) -> F4 {
                let (a, b) = (self.0, o.0);
                F4([a[0] $op b[0], a[1] $op b[1], a[2] $op b[2], a[3] $op b[3]])
            }
        }
        impl $trait<f64> for F4 {
            type Output = F4;
            #[inline(always)]
            fn $method(self, o: f64) -> F4 {
                self $op F4::splat(o)
            }
        }
        impl $trait<F4> for f64 {
            type Output = F4;
            #[inline(always)]
            fn $method(self, o: F4) -> F4 {
                F4::splat(self) $op o
            }
        }
    };
}
lanewise!(Add, add, +);
lanewise!(Sub, sub, -);
lanewise!(Mul, mul, *);
lanewise!(Div, div, /);

impl Neg for F4 {
    type Output = F4;
    #[inline(always)]
    fn neg(self) -> F4 {
        let a = self.0;
        F4([-a[0], -a[1], -a[2], -a[3]])
    }
}

impl F4 {
    /// All lanes `x`.
    #[inline(always)]
    pub fn splat(x: f64) -> Self {
        F4([x; 4])
    }

    /// Lane `k` is `f(k)`.
    #[inline(always)]
    pub fn from_fn(mut f: impl FnMut(usize) -> f64) -> Self {
        F4([f(0), f(1), f(2), f(3)])
    }

    /// Square root of each lane.
    #[inline(always)]
    pub fn sqrt(self) -> Self {
        let a = self.0;
        F4([a[0].sqrt(), a[1].sqrt(), a[2].sqrt(), a[3].sqrt()])
    }

    /// [`f64::min`] of each lane (a NaN lane takes the other operand).
    #[inline(always)]
    pub fn min(self, o: F4) -> Self {
        let (a, b) = (self.0, o.0);
        F4([
            a[0].min(b[0]),
            a[1].min(b[1]),
            a[2].min(b[2]),
            a[3].min(b[3]),
        ])
    }

    /// [`f64::max`] of each lane (a NaN lane takes the other operand).
    #[inline(always)]
    pub fn max(self, o: F4) -> Self {
        let (a, b) = (self.0, o.0);
        F4([
            a[0].max(b[0]),
            a[1].max(b[1]),
            a[2].max(b[2]),
            a[3].max(b[3]),
        ])
    }

    /// The sum of the four lanes, as `(a₀ + a₁) + (a₂ + a₃)`.
    #[inline(always)]
    pub fn sum(self) -> f64 {
        let a = self.0;
        (a[0] + a[1]) + (a[2] + a[3])
    }

    /// `self < o`, lane by lane (false where either is NaN).
    #[inline(always)]
    pub fn lt(self, o: F4) -> M4 {
        let (a, b) = (self.0, o.0);
        M4([a[0] < b[0], a[1] < b[1], a[2] < b[2], a[3] < b[3]])
    }

    /// `self > o`, lane by lane (false where either is NaN).
    #[inline(always)]
    pub fn gt(self, o: F4) -> M4 {
        let (a, b) = (self.0, o.0);
        M4([a[0] > b[0], a[1] > b[1], a[2] > b[2], a[3] > b[3]])
    }

    /// `self <= o`, lane by lane (false where either is NaN).
    #[inline(always)]
    pub fn le(self, o: F4) -> M4 {
        let (a, b) = (self.0, o.0);
        M4([a[0] <= b[0], a[1] <= b[1], a[2] <= b[2], a[3] <= b[3]])
    }
}

impl M4 {
    /// Lane by lane, `a` where the condition holds, else `b`.
    #[inline(always)]
    pub fn select(self, a: F4, b: F4) -> F4 {
        let (m, a, b) = (self.0, a.0, b.0);
        let pick = |k: usize| if m[k] { a[k] } else { b[k] };
        F4([pick(0), pick(1), pick(2), pick(3)])
    }

    /// Whether the condition holds in every lane.
    #[inline(always)]
    pub fn all(self) -> bool {
        let a = self.0;
        a[0] & a[1] & a[2] & a[3]
    }

    /// Whether the condition holds in some lane.
    #[inline(always)]
    pub fn any(self) -> bool {
        let a = self.0;
        a[0] | a[1] | a[2] | a[3]
    }
}

impl std::ops::BitAnd for M4 {
    type Output = M4;
    /// Lane by lane, both conditions.
    #[inline(always)]
    fn bitand(self, o: M4) -> M4 {
        let (a, b) = (self.0, o.0);
        M4([a[0] & b[0], a[1] & b[1], a[2] & b[2], a[3] & b[3]])
    }
}

impl std::ops::Not for M4 {
    type Output = M4;
    /// Lane by lane, the negated condition.
    #[inline(always)]
    fn not(self) -> M4 {
        let a = self.0;
        M4([!a[0], !a[1], !a[2], !a[3]])
    }
}

/// The arithmetic a kernel written once for `f64` and [`F4`] uses (each operation with an
/// `f64` constant on the right: IEEE-754 addition and multiplication are commutative, so
/// `z * c` has the bits of `c * z`).
pub trait Real:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Add<f64, Output = Self>
    + Sub<f64, Output = Self>
    + Mul<f64, Output = Self>
    + Div<f64, Output = Self>
{
}

impl Real for f64 {}
impl Real for F4 {}

/// `a · b`, rounded as nalgebra's `Vector3::dot`: `(a_x b_x + a_y b_y) + a_z b_z`.
#[inline(always)]
pub fn dot<T: Real>(a: &[T; 3], b: &[T; 3]) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `a × b`, rounded as nalgebra's `Vector3::cross`.
#[inline(always)]
pub fn cross<T: Real>(a: &[T; 3], b: &[T; 3]) -> [T; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Lane `k` of `a` as a vector.
#[inline(always)]
pub fn lane(a: &V4, k: usize) -> nalgebra::Vector3<f64> {
    nalgebra::Vector3::new(a[0].0[k], a[1].0[k], a[2].0[k])
}

/// `s a` for a scalar `s` (of lanes, for lanes).
#[inline(always)]
pub fn scale<T: Real>(a: &[T; 3], s: T) -> [T; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lanes_round_as_scalars() {
        let mut s = <rand::rngs::StdRng as rand::SeedableRng>::seed_from_u64(0x2545_f491_4f6c_dd1d);
        for _ in 0..1000 {
            let mut r = || (rand::Rng::random::<f64>(&mut s) - 0.5) * 1e3;
            let a = F4([r(), r(), r(), r()]);
            let b = F4([r(), r(), r(), r()]);
            for k in 0..4 {
                let (x, y) = (a.0[k], b.0[k]);
                assert_eq!((a + b).0[k].to_bits(), (x + y).to_bits());
                assert_eq!((a - b).0[k].to_bits(), (x - y).to_bits());
                assert_eq!((a * b).0[k].to_bits(), (x * y).to_bits());
                assert_eq!((a / b).0[k].to_bits(), (x / y).to_bits());
                assert_eq!(
                    F4(a.0.map(f64::abs)).sqrt().0[k].to_bits(),
                    x.abs().sqrt().to_bits()
                );
                assert_eq!(a.lt(b).0[k], x < y);
                assert_eq!(a.le(b).0[k], x <= y);
                assert_eq!(a.gt(b).0[k], x > y);
                assert_eq!(a.lt(b).select(a, b).0[k], if x < y { x } else { y });
            }
        }
    }

    #[test]
    fn vector_ops_round_as_nalgebra() {
        use nalgebra::Vector3;
        let mut s = <rand::rngs::StdRng as rand::SeedableRng>::seed_from_u64(0x9e37_79b9_7f4a_7c15);
        let mut r = || rand::Rng::random::<f64>(&mut s) - 0.5;
        let a: [Vector3<f64>; 4] = std::array::from_fn(|_| Vector3::new(r(), r(), r()));
        let b: [Vector3<f64>; 4] = std::array::from_fn(|_| Vector3::new(r(), r(), r()));
        let la: V4 = std::array::from_fn(|i| F4::from_fn(|k| a[k][i]));
        let lb: V4 = std::array::from_fn(|i| F4::from_fn(|k| b[k][i]));
        let (d, c) = (dot(&la, &lb), cross(&la, &lb));
        for k in 0..4 {
            assert_eq!(d.0[k].to_bits(), a[k].dot(&b[k]).to_bits());
            let ck = a[k].cross(&b[k]);
            for i in 0..3 {
                assert_eq!(c[i].0[k].to_bits(), ck[i].to_bits());
            }
        }
        // And the NaN rule of `min`.
        let m = F4([f64::NAN, 1.0, 2.0, f64::NAN]).min(F4([0.5, f64::NAN, 1.0, f64::NAN]));
        assert_eq!(&m.0[..3], &[0.5, 1.0, 1.0]);
        assert!(m.0[3].is_nan());
    }
}
