//! `f32` square root on the FPU where there is one, and `hypotf` compared with a limit
//! without computing it where the comparison is certain.
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
pub fn sqrtf(x: f32) -> f32 {
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
pub fn sqrtf(x: f32) -> f32 {
    libm::sqrtf(x)
}

/// `libm::hypotf(x, y).partial_cmp(&limit)` for a `limit` between 1e-15 and 1e15.
///
/// `libm::hypotf` sums the squares in `f64` (soft float on the M4F): its result is within a
/// relative 2⁻²³ of the true `h = sqrt(x² + y²)`, and so is the `f32` sum `d = x² + y²` of
/// `h²` (one rounding per product and one for the sum). So `d > limit² (1 + 10⁻⁴)` means
/// `h` and `hypotf` are above `limit`, and `d < limit² (1 - 10⁻⁴)` that both are under it;
/// only in between (or for a NaN) is `hypotf` computed. A square that underflows errs by
/// under 10⁻⁴⁴, far inside the margin for such a `limit`; one that overflows means
/// `h > 10¹⁹ > limit`.
pub(crate) fn cmp_hypotf(x: f32, y: f32, limit: f32) -> Option<core::cmp::Ordering> {
    let (d, l) = (x * x + y * y, limit * limit);
    if d > l * (1.0 + 1e-4) {
        Some(core::cmp::Ordering::Greater)
    } else if d < l * (1.0 - 1e-4) {
        Some(core::cmp::Ordering::Less)
    } else {
        libm::hypotf(x, y).partial_cmp(&limit)
    }
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

    #[test]
    fn cmp_hypotf_is_hypotf_s_comparison() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 40) as f32 / (1u64 << 24) as f32
        };
        let specials = [0.0f32, -0.0, 1e-30, -1e-30, 1e30, f32::INFINITY, f32::NAN, f32::MIN_POSITIVE];
        for limit in [0.01f32, 1.0, 3.0, 1e-15, 1e15] {
            for k in 0..200_000 {
                // Around the limit (both sides of it, within a few ulps too), and anywhere.
                let r = limit * if k % 2 == 0 { 1.0 + (next() - 0.5) * 1e-5 } else { next() * 4.0 };
                let a = next() * core::f32::consts::TAU;
                let (x, y) = (r * libm::cosf(a), r * libm::sinf(a));
                let (x, y) = if k % 97 == 0 { (specials[k % specials.len()], y) } else { (x, y) };
                assert_eq!(cmp_hypotf(x, y, limit), libm::hypotf(x, y).partial_cmp(&limit), "{x} {y} {limit}");
            }
        }
    }
}
