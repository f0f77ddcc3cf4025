//! The kernel sets: which instruction set the hot loops (BVH traversal,
//! triangle and box tests) are compiled for, detected once at start-up and
//! chosen at run time in one portable binary.
//!
//! # Sets
//! | name | needs | on |
//! |---|---|---|
//! | `avx512` | AVX-512 F, VL, BW, DQ, CD with AVX2, FMA, BMI1/2, LZCNT, POPCNT | x86-64 |
//! | `avx2` | AVX2, FMA, BMI1/2, LZCNT, POPCNT | x86-64 |
//! | `neon` | NEON (the baseline of the architecture) | AArch64 |
//! | `portable` | nothing beyond the architecture's baseline (SSE2 on x86-64) | everywhere |
//!
//! The best set the processor supports is the default; `--simd NAME` (or
//! [`SIMD_VAR`]) forces one, and a set the processor lacks is refused.
//!
//! # Same bits
//! Every set runs the same source: a kernel is the portable code compiled
//! again with the set's instructions enabled ([`KernelSet::run`]).
//! Rust never contracts a multiply and an add into a fused multiply-add on
//! its own, and every explicit `mul_add` rounds once whatever the set, so
//! each set gives the portable kernel's results bit for bit; the lanes of
//! the box and triangle tests are IEEE operations in a fixed order. The
//! tests of `accel` check every set the machine supports against the
//! portable one, and images across sets for every integrator.
//!
//! # Safety
//! This module is the only place that runs code compiled for instructions
//! the baseline lacks. [`KernelSet::run`] is safe: a set other than
//! `portable` is only ever run after [`KernelSet::is_supported`] has
//! confirmed it on this processor, which [`set_active`] and
//! [`KernelSet::supported`] enforce.

use std::fmt;
use std::sync::atomic::{AtomicU8, Ordering};

/// The environment variable naming the kernel set to use (`portable`,
/// `avx2`, `avx512`, `neon`), as `--simd` does.
pub const SIMD_VAR: &str = "PENUMBRA_SIMD";

/// An instruction set the hot loops are compiled for; see the module docs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum KernelSet {
    Portable,
    Avx2,
    Avx512,
    Neon,
}

/// A kernel set was named that does not exist or that this processor
/// lacks.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SimdError {
    pub name: String,
    /// The set exists but this processor lacks it.
    pub unsupported: bool,
}

impl fmt::Display for SimdError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names: Vec<&str> = KernelSet::supported().iter().map(|k| k.name()).collect();
        if self.unsupported {
            write!(
                f,
                "kernel set '{}' is not supported by this processor; it supports: {}",
                self.name,
                names.join(", ")
            )
        } else {
            write!(
                f,
                "unknown kernel set '{}'; this processor supports: {}",
                self.name,
                names.join(", ")
            )
        }
    }
}

impl std::error::Error for SimdError {}

impl KernelSet {
    /// Every set, widest first.
    pub const ALL: [KernelSet; 4] = [
        KernelSet::Avx512,
        KernelSet::Avx2,
        KernelSet::Neon,
        KernelSet::Portable,
    ];

    /// The set's name, as `--simd` takes it.
    pub fn name(self) -> &'static str {
        match self {
            KernelSet::Portable => "portable",
            KernelSet::Avx2 => "avx2",
            KernelSet::Avx512 => "avx512",
            KernelSet::Neon => "neon",
        }
    }

    /// The set called `name`, whether or not this processor has it.
    pub fn parse(name: &str) -> Result<KernelSet, SimdError> {
        KernelSet::ALL
            .into_iter()
            .find(|k| k.name() == name.trim())
            .ok_or_else(|| SimdError {
                name: name.to_string(),
                unsupported: false,
            })
    }

    /// Whether this processor can run the set.
    pub fn is_supported(self) -> bool {
        match self {
            KernelSet::Portable => true,
            #[cfg(target_arch = "x86_64")]
            KernelSet::Avx2 => {
                is_x86_feature_detected!("avx2")
                    && is_x86_feature_detected!("fma")
                    && is_x86_feature_detected!("bmi1")
                    && is_x86_feature_detected!("bmi2")
                    && is_x86_feature_detected!("lzcnt")
                    && is_x86_feature_detected!("popcnt")
            }
            #[cfg(target_arch = "x86_64")]
            KernelSet::Avx512 => {
                KernelSet::Avx2.is_supported()
                    && is_x86_feature_detected!("avx512f")
                    && is_x86_feature_detected!("avx512vl")
                    && is_x86_feature_detected!("avx512bw")
                    && is_x86_feature_detected!("avx512dq")
                    && is_x86_feature_detected!("avx512cd")
            }
            #[cfg(target_arch = "aarch64")]
            KernelSet::Neon => std::arch::is_aarch64_feature_detected!("neon"),
            #[allow(unreachable_patterns)]
            _ => false,
        }
    }

    /// The set itself if this processor can run it, else the error that
    /// says it cannot.
    pub fn require(self) -> Result<KernelSet, SimdError> {
        if self.is_supported() {
            Ok(self)
        } else {
            Err(SimdError {
                name: self.name().to_string(),
                unsupported: true,
            })
        }
    }

    /// The sets this processor supports, widest first (`portable` last).
    pub fn supported() -> Vec<KernelSet> {
        KernelSet::ALL
            .into_iter()
            .filter(|k| k.is_supported())
            .collect()
    }

    /// The widest set this processor supports.
    pub fn best() -> KernelSet {
        KernelSet::ALL
            .into_iter()
            .find(|k| k.is_supported())
            .unwrap_or(KernelSet::Portable)
    }

    /// Runs `f` compiled for this set: the kernels `f` inlines (traversal,
    /// box and triangle tests) use its instructions. `f` must be small
    /// enough to be inlined into the set's entry point, which the kernels'
    /// `#[inline(always)]` ensures.
    #[inline(always)]
    pub fn run<R>(self, f: impl FnOnce() -> R) -> R {
        match self {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: a set other than `Portable` is only held after
            // `is_supported` confirmed it (`set_active`, `supported`,
            // `best`, `active`), so the processor has these instructions.
            KernelSet::Avx512 => unsafe { x86::avx512(f) },
            #[cfg(target_arch = "x86_64")]
            // SAFETY: as above.
            KernelSet::Avx2 => unsafe { x86::avx2(f) },
            _ => f(),
        }
    }
}

impl fmt::Display for KernelSet {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(target_arch = "x86_64")]
mod x86 {
    //! The entry points of the x86-64 sets: each compiles the closure it is
    //! given, once inlined, for the set's instructions.

    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    #[inline]
    pub(super) fn avx2<R>(f: impl FnOnce() -> R) -> R {
        f()
    }

    #[target_feature(
        enable = "avx512f,avx512vl,avx512bw,avx512dq,avx512cd,avx2,fma,bmi1,bmi2,lzcnt,popcnt"
    )]
    #[inline]
    pub(super) fn avx512<R>(f: impl FnOnce() -> R) -> R {
        f()
    }
}

/// Not chosen yet.
const UNSET: u8 = u8::MAX;

/// The set chosen for the process, as an index into [`KernelSet::ALL`].
static ACTIVE: AtomicU8 = AtomicU8::new(UNSET);

/// Chooses the set used by worlds built from now on.
///
/// # Errors
/// If this processor lacks the set (nothing changes then).
pub fn set_active(set: KernelSet) -> Result<(), SimdError> {
    set.require()?;
    let i = KernelSet::ALL.iter().position(|&k| k == set).unwrap_or(3);
    ACTIVE.store(i as u8, Ordering::Relaxed);
    Ok(())
}

/// Chooses the set named `name` ([`set_active`] of [`KernelSet::parse`]).
///
/// # Errors
/// If no set has that name or this processor lacks it.
pub fn set_active_name(name: &str) -> Result<KernelSet, SimdError> {
    let set = KernelSet::parse(name)?;
    set_active(set).map_err(|e| SimdError {
        name: name.to_string(),
        ..e
    })?;
    Ok(set)
}

/// The set named by [`SIMD_VAR`], if it is set.
///
/// # Errors
/// If it names no set or one this processor lacks.
pub fn from_env() -> Result<Option<KernelSet>, SimdError> {
    match std::env::var(SIMD_VAR) {
        Ok(name) if !name.trim().is_empty() => set_active_name(&name).map(Some),
        _ => Ok(None),
    }
}

/// The set in use: the one chosen with [`set_active`], else the one
/// [`SIMD_VAR`] names (when valid and supported), else the best this
/// processor supports. Read when a world is built, not in hot loops.
pub fn active() -> KernelSet {
    match ACTIVE.load(Ordering::Relaxed) {
        UNSET => {
            let set = from_env().ok().flatten().unwrap_or_else(KernelSet::best);
            // Not stored by `from_env` when invalid: store the fallback.
            let _ = set_active(set);
            set
        }
        i => KernelSet::ALL[i as usize],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_unknown_is_refused() {
        for k in KernelSet::ALL {
            assert_eq!(KernelSet::parse(k.name()), Ok(k));
        }
        let e = KernelSet::parse("sse9").unwrap_err();
        assert!(!e.unsupported);
        assert!(e.to_string().contains("portable"), "{e}");
    }

    #[test]
    fn portable_is_always_supported_and_last() {
        let s = KernelSet::supported();
        assert_eq!(s.last(), Some(&KernelSet::Portable));
        assert_eq!(s[0], KernelSet::best());
    }

    #[test]
    fn a_set_of_another_architecture_is_refused() {
        #[cfg(target_arch = "x86_64")]
        let other = KernelSet::Neon;
        #[cfg(not(target_arch = "x86_64"))]
        let other = KernelSet::Avx2;
        let e = set_active(other).unwrap_err();
        assert!(e.unsupported);
        assert!(e.to_string().contains("not supported"), "{e}");
    }

    #[test]
    fn every_supported_set_runs_code() {
        for k in KernelSet::supported() {
            let v: Vec<f32> = (0..100).map(|i| i as f32 * 0.1).collect();
            let sum = k.run(|| v.iter().map(|x| x * x).sum::<f32>());
            let expect: f32 = v.iter().map(|x| x * x).sum();
            assert_eq!(sum.to_bits(), expect.to_bits(), "{k}");
        }
    }
}
