//! Speed, and nothing else: an implementation detail of the classifiers, behind one
//! crate-private boundary.
//!
//! Everything here computes what a plainer expression elsewhere in the crate defines, with the
//! same bits, only faster; each kernel's tests (beside it) check the bits against that
//! reference. What is here:
//!
//! * one choice of code, [`avx2_or_baseline!`]: an expression compiled twice, for AVX2 and for
//!   the baseline, and run in the AVX2 copy where the processor has it (see [`avx2`]). Every
//!   run-time choice of code in the crate goes through it; the portable copy is the reference.
//!   (The pose parser in `crate::format` chooses its own code; it is not part of this.)
//! * [`lanes`]: four `f64` lanes ([`lanes::F4`]) for the kernels that take frames four at a
//!   time, rounded lane by lane as the scalar expression they mirror;
//! * [`atan`]: a first-quadrant `atan2` (the rotation angle of every logarithm), scalar and in
//!   lanes;
//! * [`twist4`]: the SE(3) logarithm of four rigid motions and their screws, lane by lane
//!   (the scalar originals are [`crate::se3::Twist::log_quat`] and
//!   [`crate::screw::Screw::from_twist`]);
//! * [`line_costs`]: the MSAC line cost of many blocks, four per step (AVX2 intrinsics);
//! * [`moving_sums`]: a segment's per-frame sums taken sixteen frames at a time;
//! * [`drift_sums`]: a rest's sums kept in whole lanes (store forwarding);
//! * [`handover`]: the parsing thread and the buffers that hand its output over;
//! * [`prefetch`]: a hint to the processor to fetch memory that a stream will read soon;
//! * [`bench`]: a doorway for the benchmark examples, hidden from the documentation.
//!
//! A test hook (`set_baseline_only`, tests only) makes every choice take the baseline copy,
//! so that the tests can compare both.

pub mod atan;
#[doc(hidden)]
pub mod bench;
pub mod drift_sums;
pub mod handover;
pub mod lanes;
pub mod line_costs;
pub mod moving_sums;
pub mod twist4;

pub use lanes::{cross, dot, Real};

/// Whether this processor runs AVX2 code (x86-64 only; checked once, then cached by `std`),
/// unless the test hook `set_baseline_only` said otherwise.
#[inline]
pub fn avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2") && !baseline_only()
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// `avx2_or_baseline!(expr)`: evaluate `expr` in a copy compiled for AVX2 where the processor
/// runs AVX2 code ([`avx2`]), else in the baseline copy. Both copies are the same operations,
/// so the same bits (IEEE-754 `+ - * / sqrt` are correctly rounded at any vector width, and
/// Rust never fuses a multiply and an add); only their instructions differ.
///
/// `avx2_or_baseline!(avx2: unsafe_expr, baseline: expr)` runs a hand-written AVX2 version
/// (intrinsics, in a function compiled for AVX2) instead of a second copy of the baseline
/// expression; its tests check that it gives the baseline's bits.
///
/// The expression is the body of a closure called once in the AVX2 copy, inlined there: it may
/// borrow the caller's variables, but not `return` from the caller. The baseline copy is the
/// expression itself, in the caller's code.
///
/// `avx2_or_baseline!(#[inline(never)] fn(name: Type = value, ..) -> Ret { body })` keeps both
/// copies out of the caller's line (a per-frame call whose work would crowd the caller's loop:
/// measured faster so), with the body's inputs passed as arguments (in registers) rather than
/// through a closure's captures (through memory, 2 ns a frame more on the 10^6-pose
/// benchmark; 6% of `learn`'s wall time for the hand-over loops). The body sees only its
/// arguments and its own generic parameters, `fn<T: Bound>(..)` (no `Self`, no generic
/// parameters of the caller; `impl Trait` argument types are fine).
macro_rules! avx2_or_baseline {
    (#[inline(never)] fn $(<$($g:ident : $b:path),* $(,)?>)? ($($arg:ident : $ty:ty = $val:expr),* $(,)?) $(-> $ret:ty)? $body:block) => {{
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx2")]
        #[inline(never)]
        unsafe fn avx2_copy $(<$($g: $b),*>)? ($($arg: $ty),*) $(-> $ret)? $body
        #[inline(never)]
        fn baseline_copy $(<$($g: $b),*>)? ($($arg: $ty),*) $(-> $ret)? $body
        #[cfg(target_arch = "x86_64")]
        let r = if $crate::fast::avx2() {
            // SAFETY: the processor runs AVX2 code (checked just above).
            unsafe { avx2_copy($($val),*) }
        } else {
            baseline_copy($($val),*)
        };
        #[cfg(not(target_arch = "x86_64"))]
        let r = baseline_copy($($val),*);
        r
    }};
    (avx2: $avx2:expr, baseline: $baseline:expr) => {{
        #[cfg(target_arch = "x86_64")]
        let r = if $crate::fast::avx2() {
            // SAFETY: the processor runs AVX2 code (checked just above).
            unsafe { $avx2 }
        } else {
            $baseline
        };
        #[cfg(not(target_arch = "x86_64"))]
        let r = $baseline;
        r
    }};
    ($body:expr) => {{
        #[cfg(target_arch = "x86_64")]
        let r = if $crate::fast::avx2() {
            // SAFETY: the processor runs AVX2 code (checked just above).
            unsafe { $crate::fast::avx2_copy(#[inline(always)] || $body) }
        } else {
            $body
        };
        #[cfg(not(target_arch = "x86_64"))]
        let r = $body;
        r
    }};
}
pub(crate) use avx2_or_baseline;

/// The AVX2 copy of an [`avx2_or_baseline!`] expression.
///
/// # Safety
/// The processor must run AVX2 code.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
pub unsafe fn avx2_copy<R>(f: impl FnOnce() -> R) -> R {
    f()
}

/// Ask the processor to fetch the `bytes` bytes from `at` on into its first-level cache
/// (one request per 64-byte line). A hint with no effect on what any code computes: it never
/// faults, whatever the address (an unmapped one, or one past the end of a buffer, is simply
/// not fetched), so `at` may point anywhere.
///
/// For the streams whose memory the processor's own prefetchers bring in late: they follow a
/// sequential stream only within a 4 KiB page, so each new page of a long buffer starts with
/// a miss, and lines another core wrote are fetched one miss at a time. Measured on the
/// 10^6-pose benchmark file (`bench/ab.sh`, 25-41 interleaved runs): the parser 2048 bytes
/// ahead, its thread's CPU 40 -> 28 ms; the hand-over chunks 32 frames ahead, `learn`'s
/// median wall time 68.9 -> 66.9 ms.
#[inline(always)]
pub fn prefetch(at: *const u8, bytes: usize) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        let mut d = 0;
        while d < bytes {
            // SAFETY: a prefetch only hints; it reads nothing the program sees and never
            // faults, whatever the address (wrapping arithmetic keeps the pointer a value).
            unsafe { _mm_prefetch::<_MM_HINT_T0>(at.wrapping_add(d).cast::<i8>()) };
            d += 64;
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (at, bytes);
}

/// Set by [`set_baseline_only`].
#[cfg(test)]
static BASELINE_ONLY: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Test hook: make [`avx2`] answer false from now on (`on`), or again what the processor runs,
/// so that every [`avx2_or_baseline!`] takes its baseline copy. Process-wide.
#[cfg(test)]
pub fn set_baseline_only(on: bool) {
    BASELINE_ONLY.store(on, std::sync::atomic::Ordering::Relaxed);
}

#[cfg(test)]
fn baseline_only() -> bool {
    BASELINE_ONLY.load(std::sync::atomic::Ordering::Relaxed)
}

#[cfg(not(test))]
#[inline(always)]
fn baseline_only() -> bool {
    false
}

#[cfg(test)]
mod tests {
    use crate::classify::{classify_files, Config};
    use crate::format;
    use crate::synth::{self, SynthBox, SynthDemo, SynthNoise, ToppleParams};
    use rand::{rngs::StdRng, SeedableRng};

    /// Takes the baseline code while it lives.
    struct BaselineOnly;

    impl BaselineOnly {
        fn new() -> Self {
            super::set_baseline_only(true);
            Self
        }
    }

    impl Drop for BaselineOnly {
        fn drop(&mut self) {
            super::set_baseline_only(false);
        }
    }

    /// Every kernel that chooses AVX2 code at run time gives the same classification, bit for
    /// bit, in its baseline code (the claim of [`super::avx2_or_baseline!`]): files of a topple, an
    /// instrumented topple, a quasi-static topple (the slow-motion path), a slide and a general
    /// motion, at real tracking noise, each classified from its files both ways. (On a
    /// processor without AVX2 both ways are the baseline code.)
    #[test]
    fn baseline_and_avx2_code_classify_alike() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path();
        let noise = SynthNoise::REAL;
        let mut rng = StdRng::seed_from_u64(77);
        let b = SynthBox::random(&mut rng);
        let topple = |push_s: f64, seed: u64| {
            let p = ToppleParams {
                side: (seed % 4) as usize,
                push_s,
                ..Default::default()
            };
            synth::topple(&b, &p, &noise, 30.0, seed)
        };
        let demos: Vec<(&str, SynthDemo)> = vec![
            ("topple", topple(1.5, 1)),
            (
                "instrumented",
                synth::instrumented_topple(&b, 2, 0.2, &noise, 30.0, 2),
            ),
            ("quasi_static", topple(60.0, 3)),
            ("slide", synth::slide(&b, &noise, 30.0, 4)),
            ("general", synth::general(&b, &noise, 30.0, 5)),
        ];
        let config = Config::default();
        for (name, d) in &demos {
            let object = dir.join(format!("{name}.tum"));
            format::write_tum(&object, &d.demo.object, name).unwrap();
            let palm = d.demo.palm.as_ref().map(|p| {
                let path = dir.join(format!("{name}.palm.tum"));
                format::write_tum(&path, p, name).unwrap();
                path
            });
            let fast = classify_files(&object, palm.as_deref(), &config).unwrap();
            let base = {
                let _baseline = BaselineOnly::new();
                classify_files(&object, palm.as_deref(), &config).unwrap()
            };
            assert_eq!(fast.kind, d.truth.kind, "{name}");
            assert_eq!(format!("{fast:?}"), format!("{base:?}"), "{name}");
        }
    }
}
