//! `f32` square root on the FPU where there is one.
//!
//! `libm::sqrtf` is software: on the Cortex-M4F it costs a loop of integer steps, while the
//! single-precision FPU has `VSQRT.F32`. Both are IEEE 754 square roots, correctly rounded
//! (round to nearest even, the FPU's default mode, which nothing here changes), so they give
//! the same bits for every input; `scripts/board.sh` compares the board's results with the
//! host's, which take `libm`'s. NaNs aside: a negative input gives the FPU's default NaN on
//! both paths of the board.
//!
//! The instruction needs an `s` register, and Rust's `sreg` operand class asks for the
//! `vfp2` target feature, which `thumbv7em-none-eabihf` (single precision only) does not
//! set; so the value goes through a core register and `s0`, saved and restored around it.

/// `sqrt(x)`, correctly rounded: `VSQRT.F32` on a hard-float Arm target, `libm` elsewhere.
#[cfg(all(target_arch = "arm", target_abi = "eabihf"))]
#[inline]
#[allow(unsafe_code)]
pub(crate) fn sqrtf(x: f32) -> f32 {
    let bits: u32;
    // SAFETY: register-only instructions on the FPU that every hard-float Arm target has;
    // `s0` is pushed and popped around its use, so no register the compiler allocated
    // changes. The push and pop touch only the stack below `sp`.
    unsafe {
        core::arch::asm!(
            "vpush {{s0}}",
            "vmov s0, {x}",
            "vsqrt.f32 s0, s0",
            "vmov {r}, s0",
            "vpop {{s0}}",
            x = in(reg) x.to_bits(),
            r = lateout(reg) bits,
            options(pure, nomem, preserves_flags)
        );
    }
    f32::from_bits(bits)
}

/// `sqrt(x)`, correctly rounded: `VSQRT.F32` on a hard-float Arm target, `libm` elsewhere.
#[cfg(not(all(target_arch = "arm", target_abi = "eabihf")))]
#[inline]
pub(crate) fn sqrtf(x: f32) -> f32 {
    libm::sqrtf(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn is_libm_sqrtf() {
        for v in [0.0f32, -0.0, 1.0, 2.0, 0.5, 1e-40, 3.4e38, f32::INFINITY, 2_080_800.0, 0.01] {
            assert_eq!(sqrtf(v).to_bits(), libm::sqrtf(v).to_bits(), "{v}");
        }
        assert!(sqrtf(-1.0).is_nan());
    }
}
