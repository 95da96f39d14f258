//! Which of x86-64's wider vector extensions the host has, for the kernels with a path of
//! their own there (`motion`'s row scan, the SSD's elimination). `no_std` has no
//! `is_x86_feature_detected!`, so the CPU and the operating system are asked directly: `CPUID`
//! for the instructions, `XGETBV` for whether the OS saves the registers they use. Asked once,
//! then cached.
use core::arch::x86_64::{__cpuid, __cpuid_count, _xgetbv};
use core::sync::atomic::{AtomicU8, Ordering};

/// 0: not asked yet; 1: no; 2: yes.
static AVX512BW: AtomicU8 = AtomicU8::new(0);

/// Whether AVX-512 F and BW run here: the CPU has them (`CPUID` leaf 7, EBX bits 16 and 30)
/// and the OS saves the mask and 512-bit registers (`XCR0` bits 1, 2, 5, 6 and 7).
pub(crate) fn has_avx512bw() -> bool {
    match AVX512BW.load(Ordering::Relaxed) {
        0 => {
            let yes = detect();
            AVX512BW.store(if yes { 2 } else { 1 }, Ordering::Relaxed);
            yes
        }
        v => v == 2,
    }
}

fn detect() -> bool {
    const OSXSAVE: u32 = 1 << 27;
    const F_BW: u32 = 1 << 16 | 1 << 30;
    const STATE: u64 = 0b1110_0110;
    if __cpuid(0).eax < 7 || __cpuid(1).ecx & OSXSAVE == 0 || __cpuid_count(7, 0).ebx & F_BW != F_BW {
        return false;
    }
    // SAFETY: `XGETBV` (the `xsave` feature) exists where `CPUID` reports OSXSAVE, as here.
    #[allow(unsafe_code)]
    let xcr0 = unsafe { xcr0() };
    xcr0 & STATE == STATE
}

/// `XCR0`, the register state the OS saves.
#[target_feature(enable = "xsave")]
#[allow(unsafe_code)]
fn xcr0() -> u64 {
    // SAFETY: register-only; the feature is this function's.
    unsafe { _xgetbv(0) }
}
