//! Which of x86-64's wider vector extensions the host has, for the kernels with paths of their
//! own there (`motion`'s row scan, the SSD's elimination, the dot products, the corner
//! detector's Sobel pass): AVX-512 BW where it runs, else AVX2, else the portable path (the
//! baseline build's SSE2, the code the Cortex-M4 runs). `no_std` has no
//! `is_x86_feature_detected!`, so the CPU and the operating system are asked directly: `CPUID`
//! for the instructions, `XGETBV` for whether the OS saves the registers they use. Asked once,
//! then cached.
use core::arch::x86_64::{__cpuid, __cpuid_count, _xgetbv};
use core::sync::atomic::{AtomicU8, Ordering};

/// A kernel path, narrowest first: a host that runs one runs every path before it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Isa {
    /// The baseline build (SSE2): the portable code.
    Portable = 1,
    /// AVX2, 256-bit vectors (every x86-64 since about 2013-2015).
    Avx2 = 2,
    /// AVX-512 F and BW, 512-bit vectors and mask registers.
    Avx512 = 3,
}

impl Isa {
    /// Every path, narrowest first.
    pub const ALL: [Isa; 3] = [Isa::Portable, Isa::Avx2, Isa::Avx512];

    fn from_u8(v: u8) -> Self {
        match v {
            3 => Isa::Avx512,
            2 => Isa::Avx2,
            _ => Isa::Portable,
        }
    }
}

/// The widest path the host runs; 0 until asked.
static DETECTED: AtomicU8 = AtomicU8::new(0);
/// The widest path the kernels take ([`use_at_most`]).
static CEILING: AtomicU8 = AtomicU8::new(Isa::Avx512 as u8);

/// The widest path this CPU and OS run.
pub fn detected() -> Isa {
    match DETECTED.load(Ordering::Relaxed) {
        0 => {
            let isa = detect();
            DETECTED.store(isa as u8, Ordering::Relaxed);
            isa
        }
        v => Isa::from_u8(v),
    }
}

/// Makes the kernels take no path wider than `isa` from now on (process-wide), so that a
/// narrower path can be measured on a wider host (`benches/kernels.rs`, `COOPWIN_ISA`). A path
/// the host does not run is never taken: [`path`] is the narrower of this and [`detected`].
pub fn use_at_most(isa: Isa) {
    CEILING.store(isa as u8, Ordering::Relaxed);
}

/// The path the kernels take: the widest the host runs, at most [`use_at_most`]'s.
pub fn path() -> Isa {
    detected().min(Isa::from_u8(CEILING.load(Ordering::Relaxed)))
}

/// The paths the host runs, narrowest first (the tests run each).
#[cfg(test)]
pub(crate) fn runnable() -> impl Iterator<Item = Isa> {
    Isa::ALL.into_iter().filter(|&i| i <= detected())
}

fn detect() -> Isa {
    const OSXSAVE_AVX: u32 = 1 << 27 | 1 << 28;
    const AVX2: u32 = 1 << 5;
    const F_BW: u32 = 1 << 16 | 1 << 30;
    // XCR0: SSE and AVX state (bits 1, 2); with opmask and the upper ZMM registers (5, 6, 7).
    const YMM: u64 = 0b0000_0110;
    const ZMM: u64 = 0b1110_0110;
    if __cpuid(0).eax < 7 || __cpuid(1).ecx & OSXSAVE_AVX != OSXSAVE_AVX {
        return Isa::Portable;
    }
    let ebx = __cpuid_count(7, 0).ebx;
    // SAFETY: `XGETBV` (the `xsave` feature) exists where `CPUID` reports OSXSAVE, as here.
    #[allow(unsafe_code)]
    let xcr0 = unsafe { xcr0() };
    if ebx & (F_BW | AVX2) == F_BW | AVX2 && xcr0 & ZMM == ZMM {
        Isa::Avx512
    } else if ebx & AVX2 != 0 && xcr0 & YMM == YMM {
        Isa::Avx2
    } else {
        Isa::Portable
    }
}

/// `XCR0`, the register state the OS saves.
#[target_feature(enable = "xsave")]
#[allow(unsafe_code)]
fn xcr0() -> u64 {
    // SAFETY: register-only; the feature is this function's.
    unsafe { _xgetbv(0) }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The `CPUID`/`XGETBV` answer against the standard library's own detection (which asks
    /// the same registers, independently written): AVX-512 where F and BW run, else AVX2 where
    /// it runs.
    #[test]
    fn detection_agrees_with_std() {
        let want = if std::is_x86_feature_detected!("avx512f") && std::is_x86_feature_detected!("avx512bw") {
            Isa::Avx512
        } else if std::is_x86_feature_detected!("avx2") {
            Isa::Avx2
        } else {
            Isa::Portable
        };
        assert_eq!(detected(), want);
        assert_eq!(runnable().last(), Some(want));
    }

    /// A ceiling narrows the path and never widens it past the host's. (Other tests running
    /// meanwhile may take a narrower path: every path gives the same results.)
    #[test]
    fn a_ceiling_narrows_the_path() {
        for isa in Isa::ALL {
            use_at_most(isa);
            assert_eq!(path(), isa.min(detected()), "at most {isa:?}");
        }
        use_at_most(Isa::Avx512);
        assert_eq!(path(), detected());
    }
}
