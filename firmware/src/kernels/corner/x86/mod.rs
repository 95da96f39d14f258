//! The Sobel pass in vectors, on an x86-64 host that runs AVX-512 BW (`avx512.rs`) or AVX2
//! (`avx2.rs`), for windows up to [`MAX_W`] wide.
//!
//! A window row is one register of 32 `i16` (AVX-512) or two of 16 (AVX2), read from the
//! view's bytes (no widened copy); the horizontal neighbours come from permutes and shifts
//! in registers, not from margins stored then reloaded (whose scalar stores stall the vector
//! loads over them). The pass also keeps what `lines::collect_points` needs, so that
//! [`Gradients::collect_points`] reads each edge pixel's values instead of computing three
//! Sobel sums per pixel: the gradients, the squared magnitudes, and which pixels are maxima
//! along their axis, tested for a whole row at a time without a branch per pixel. Its
//! sub-pixel points are the portable path's, bit for bit (`tests.rs`,
//! `vector_pass_matches_portable`).

use super::lines::{push_peak, EdgePoints};
use crate::kernels::view::WindowView;
use crate::kernels::x86::Isa;

mod avx2;
mod avx512;

/// Widest window of the vector pass: a row of `i16` fills one 512-bit register.
pub(super) const MAX_W: usize = 32;

/// The last window's Sobel gradients and squared magnitudes, and its pixels that are maxima
/// of the magnitude along their axis, for windows up to `MAX_W x N`.
pub(super) struct Gradients<const N: usize> {
    gx: [[i16; MAX_W]; N],
    gy: [[i16; MAX_W]; N],
    m2: [[i32; MAX_W]; N],
    /// Bit `x` of row `y`: pixel `(x, y)` is a peak, a pixel that `collect_points` takes:
    /// interior, a maximum of the magnitude along the axis closer to its gradient, its two
    /// neighbours there interior too.
    maxima: [u64; N],
}

impl<const N: usize> Gradients<N> {
    pub(super) const fn new() -> Self {
        Self { gx: [[0; MAX_W]; N], gy: [[0; MAX_W]; N], m2: [[0; MAX_W]; N], maxima: [0; N] }
    }

    /// `sobel_rows`' edge map of `view` into `bits` on the path `isa` (narrowed to what the
    /// host runs), keeping the gradients, the squared magnitudes and the peaks; the number of
    /// edge pixels, or `None` where the path is the portable one or does not take the window
    /// (wider than [`MAX_W`]; AVX2 from 2 pixels wide).
    pub(super) fn sobel(&mut self, isa: Isa, view: &WindowView<'_>, bits: &mut [u64], th2: i32) -> Option<u32> {
        let w = view.width();
        // SAFETY: the host runs the path (narrowed by `detected`), the functions' only
        // requirement.
        #[allow(unsafe_code)]
        match isa.min(crate::kernels::x86::detected()) {
            Isa::Avx512 if w <= MAX_W => Some(unsafe { self.sobel_avx512(view, bits, th2) }),
            Isa::Avx2 if (2..=MAX_W).contains(&w) => Some(unsafe { self.sobel_avx2(view, bits, th2) }),
            _ => None,
        }
    }
}

impl<const N: usize> Gradients<N> {
    /// `lines::collect_points` of the last window from what [`sobel`](Self::sobel) kept: the
    /// points of the clean edge pixels `rows` that are peaks.
    pub(super) fn collect_points(&self, rows: &[u64], pts: &mut EdgePoints<N>) {
        pts.clear();
        for (y, (&row, &peaks)) in rows.iter().zip(&self.maxima).enumerate() {
            let mut bits = row & peaks;
            while bits != 0 {
                let x = bits.trailing_zeros() as usize;
                bits &= bits - 1;
                let Some((g, q, horizontal)) = self.peak(x, y) else { continue };
                if !push_peak(pts, (x, y), g, q, horizontal) {
                    return;
                }
            }
        }
    }

    /// The gradient at peak `(x, y)`, the squared magnitudes before, at and after it along
    /// its axis, and whether that is `x`; `None` outside the window's rows.
    fn peak(&self, x: usize, y: usize) -> Option<((i32, i32), [i32; 3], bool)> {
        let at = |a: &[[i16; MAX_W]; N]| a.get(y).and_then(|r| r.get(x)).map(|&g| i32::from(g));
        let (gx, gy) = (at(&self.gx)?, at(&self.gy)?);
        let m2 = |x: usize, y: usize| self.m2.get(y).and_then(|r| r.get(x)).copied();
        let horizontal = gx.abs() >= gy.abs();
        let (q0, q2) = if horizontal {
            (m2(x.wrapping_sub(1), y)?, m2(x + 1, y)?)
        } else {
            (m2(x, y.wrapping_sub(1))?, m2(x, y + 1)?)
        };
        Some(((gx, gy), [q0, m2(x, y)?, q2], horizontal))
    }
}
