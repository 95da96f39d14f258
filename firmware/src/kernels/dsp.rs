//! The Cortex-M4's dual 16-bit multiply-accumulate, `SMLAD`, for the matching kernels' dot
//! products (`matching/dot.rs`).
//!
//! `SMLAD acc, a, b` adds both products of the signed 16-bit halves of `a` and `b` to `acc`
//! in one instruction. LLVM's parallel-DSP pass forms it from a single running sum, but not
//! from the four sums of four placements sharing each template pair, the shape that saves
//! the loads; so it is written out. The products are exact and the sums wrap like
//! `i32::wrapping_add` (the instruction only sets the sticky `Q` flag on overflow, which
//! nothing reads), so the results are the bits of the portable form, which other targets use.

/// Two `i16` as the halves of a word, `lo` in bits 0-15 (as a little-endian load of the pair
/// reads them).
#[inline(always)]
pub(crate) fn pair(lo: i16, hi: i16) -> u32 {
    u32::from(lo as u16) | u32::from(hi as u16) << 16
}

/// `acc + lo(a)·lo(b) + hi(a)·hi(b)` (halves as [`pair`] makes them), wrapping.
#[cfg(all(target_arch = "arm", target_feature = "dsp"))]
#[inline(always)]
#[allow(unsafe_code)]
pub(crate) fn smlad(acc: i32, a: u32, b: u32) -> i32 {
    let mut acc = acc;
    // SAFETY: one register-only instruction of the DSP extension, which the target has.
    unsafe {
        core::arch::asm!("smlad {0}, {1}, {2}, {0}", inout(reg) acc, in(reg) a, in(reg) b, options(pure, nomem, nostack));
    }
    acc
}

/// `acc + lo(a)·lo(b) + hi(a)·hi(b)` (halves as [`pair`] makes them), wrapping.
#[cfg(not(all(target_arch = "arm", target_feature = "dsp")))]
#[inline(always)]
pub(crate) fn smlad(acc: i32, a: u32, b: u32) -> i32 {
    let half = |v: u32, shift: u32| i32::from((v >> shift) as u16 as i16);
    acc.wrapping_add(half(a, 0) * half(b, 0)).wrapping_add(half(a, 16) * half(b, 16))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smlad_adds_both_products() {
        assert_eq!(smlad(10, pair(3, -4), pair(5, 6)), 10 + 15 - 24);
        assert_eq!(smlad(0, pair(255, 255), pair(255, 255)), 2 * 65025);
        assert_eq!(smlad(i32::MAX, pair(1, 0), pair(1, 0)), i32::MIN);
    }
}
