//! [`Gradients::sobel`] in AVX2: a row of 32 `i16` in two registers of 16, the neighbours by
//! byte shifts across the two (the border's reflect-101 by blends), the squared magnitudes in
//! four registers of 8 `i32`.
use super::super::sobel::{reflect, row_mask};
use super::{Gradients, MAX_W};
use crate::kernels::view::WindowView;
use core::arch::x86_64::{
    __m256i, _mm256_abs_epi16, _mm256_add_epi16, _mm256_alignr_epi8, _mm256_andnot_si256, _mm256_blend_epi32, _mm256_blendv_epi8,
    _mm256_castsi256_ps, _mm256_castsi256_si128, _mm256_cmpgt_epi16, _mm256_cmpgt_epi32, _mm256_cvtepu8_epi16,
    _mm256_extracti128_si256, _mm256_loadu_si256, _mm256_madd_epi16, _mm256_movemask_epi8, _mm256_movemask_ps,
    _mm256_packs_epi16, _mm256_permute2x128_si256, _mm256_permute4x64_epi64, _mm256_permutevar8x32_epi32,
    _mm256_set1_epi32, _mm256_setr_epi32, _mm256_setzero_si256, _mm256_slli_epi16, _mm256_storeu_si256,
    _mm256_sub_epi16, _mm256_unpackhi_epi16, _mm256_unpacklo_epi16,
};

/// A row of 32 `i16`: pixels 0-15, 16-31.
type Row16 = [__m256i; 2];
/// A row of 32 `i32`: pixels 0-7, 8-15, 16-23, 24-31.
type Row8 = [__m256i; 4];

impl<const N: usize> Gradients<N> {
    /// `sobel_avx512`'s pass (the same edge map, gradients, magnitudes and peaks) for windows
    /// 2 to [`MAX_W`] wide. A row is read 32 bytes at once where the view's buffer holds them
    /// (the pixels past the window's width only reach lanes past it), else from a copy.
    #[target_feature(enable = "avx2")]
    #[allow(unsafe_code)]
    pub(super) fn sobel_avx2(&mut self, view: &WindowView<'_>, bits: &mut [u64], th2: i32) -> u32 {
        let (w, h) = (view.width().min(MAX_W), view.height().min(N).min(bits.len()));
        let raw = view.raw();
        let row = |y: usize| -> Row16 {
            let mut buf = [0u8; MAX_W];
            let src = match raw {
                Some((data, stride)) => match data.get(y * stride..y * stride + MAX_W) {
                    Some(r) => r,
                    None => {
                        buf.iter_mut().zip(data.get(y * stride..).unwrap_or(&[])).take(w).for_each(|(d, &s)| *d = s);
                        &buf[..]
                    }
                },
                None => {
                    buf.iter_mut().zip(view.row_iter(y)).for_each(|(d, s)| *d = s);
                    &buf[..]
                }
            };
            // SAFETY: `src` holds `MAX_W` (32) bytes; the load needs no alignment.
            let v = unsafe { _mm256_loadu_si256(src.as_ptr().cast()) };
            [_mm256_cvtepu8_epi16(_mm256_castsi256_si128(v)), _mm256_cvtepu8_epi16(_mm256_extracti128_si256::<1>(v))]
        };
        // Lane `x` alone, as `i16` lanes of -1.
        let lane = |x: usize| -> Row16 {
            let m: [i16; MAX_W] = core::array::from_fn(|i| if i == x { -1 } else { 0 });
            // SAFETY: 64 readable bytes.
            unsafe { [_mm256_loadu_si256(m.as_ptr().cast()), _mm256_loadu_si256(m.as_ptr().add(16).cast())] }
        };
        let (first, last) = (lane(0), lane(w - 1));
        // Columns x-1 and x+1 of a row, reflected (101) at the border: at 0 the right
        // neighbour, at w-1 the left one (w >= 2).
        let neighbours = |r: Row16| -> (Row16, Row16) {
            let (before, after) = (before16(r), after16(r));
            let left = [_mm256_blendv_epi8(before[0], after[0], first[0]), _mm256_blendv_epi8(before[1], after[1], first[1])];
            let right = [_mm256_blendv_epi8(after[0], left[0], last[0]), _mm256_blendv_epi8(after[1], left[1], last[1])];
            (left, right)
        };
        let (lanes, inner, inner2) = (row_mask(w) as u32, row_mask(w.saturating_sub(1)) as u32 & !1, row_mask(w.saturating_sub(2)) as u32 & !3);
        let thv = _mm256_set1_epi32(th2);
        let (mut up, mut mid) = (row(reflect(-1, h)), row(0));
        // Rows y-1 and y-2: squared magnitudes, and (y-1) the pixels whose gradient is closer
        // to x than to y.
        let (mut q1, mut q2, mut horizontal) = ([thv; 4], [thv; 4], 0u32);
        let mut count = 0;
        self.maxima.iter_mut().for_each(|m| *m = 0);
        for (y, out) in bits.iter_mut().enumerate().take(h) {
            let dn = row(reflect(y as isize + 1, h));
            let mut smooth = [_mm256_setzero_si256(); 2];
            let mut diff = [_mm256_setzero_si256(); 2];
            for k in 0..2 {
                smooth[k] = _mm256_add_epi16(_mm256_add_epi16(up[k], dn[k]), _mm256_slli_epi16::<1>(mid[k]));
                diff[k] = _mm256_sub_epi16(dn[k], up[k]);
            }
            let ((sl, sr), (dl, dr)) = (neighbours(smooth), neighbours(diff));
            let (mut gx, mut gy) = ([_mm256_setzero_si256(); 2], [_mm256_setzero_si256(); 2]);
            for k in 0..2 {
                gx[k] = _mm256_sub_epi16(sr[k], sl[k]);
                gy[k] = _mm256_add_epi16(_mm256_add_epi16(dl[k], dr[k]), _mm256_slli_epi16::<1>(diff[k]));
            }
            let q = mag2(gx, gy);
            let edge = greater(q, [thv; 4]) & lanes;
            *out = u64::from(edge);
            count += edge.count_ones();
            if let (Some(gxr), Some(gyr), Some(m2r)) = (self.gx.get_mut(y), self.gy.get_mut(y), self.m2.get_mut(y)) {
                // SAFETY: each row is 64 (`i16`) or 128 (`i32`) writable bytes.
                unsafe {
                    for k in 0..2 {
                        _mm256_storeu_si256(gxr.as_mut_ptr().add(16 * k).cast(), gx[k]);
                        _mm256_storeu_si256(gyr.as_mut_ptr().add(16 * k).cast(), gy[k]);
                    }
                    for (k, &v) in q.iter().enumerate() {
                        _mm256_storeu_si256(m2r.as_mut_ptr().add(8 * k).cast(), v);
                    }
                }
            }
            // Row y-1's peaks, now that the row below it is known (as `sobel_avx512`'s).
            if y >= 2 {
                let along_x = maximum(q1, before8(q1), after8(q1)) & inner2;
                let along_y = if y >= 3 && y + 1 < h { maximum(q1, q2, q) } else { 0 };
                if let Some(m) = self.maxima.get_mut(y - 1) {
                    *m = u64::from((horizontal & along_x | !horizontal & along_y) & inner);
                }
            }
            horizontal = !closer_to_y(gx, gy);
            (q2, q1) = (q1, q);
            (up, mid) = (mid, dn);
        }
        count
    }
}

/// Lane `x` of the result is lane `x - 1` of `r` (0 at lane 0).
#[target_feature(enable = "avx2")]
#[inline]
fn before16([lo, hi]: Row16) -> Row16 {
    let zero = _mm256_setzero_si256();
    [
        _mm256_alignr_epi8::<14>(lo, _mm256_permute2x128_si256::<0x21>(zero, lo)),
        _mm256_alignr_epi8::<14>(hi, _mm256_permute2x128_si256::<0x21>(lo, hi)),
    ]
}

/// Lane `x` of the result is lane `x + 1` of `r` (0 at lane 31).
#[target_feature(enable = "avx2")]
#[inline]
fn after16([lo, hi]: Row16) -> Row16 {
    let zero = _mm256_setzero_si256();
    [
        _mm256_alignr_epi8::<2>(_mm256_permute2x128_si256::<0x21>(lo, hi), lo),
        _mm256_alignr_epi8::<2>(_mm256_permute2x128_si256::<0x21>(hi, zero), hi),
    ]
}

/// Lane `x` of the result is lane `(x - 1) % 32` of `r`.
#[target_feature(enable = "avx2")]
#[inline]
fn before8(r: Row8) -> Row8 {
    let rot = _mm256_setr_epi32(7, 0, 1, 2, 3, 4, 5, 6);
    let p = [_mm256_permutevar8x32_epi32(r[0], rot), _mm256_permutevar8x32_epi32(r[1], rot), _mm256_permutevar8x32_epi32(r[2], rot), _mm256_permutevar8x32_epi32(r[3], rot)];
    [_mm256_blend_epi32::<0x01>(p[0], p[3]), _mm256_blend_epi32::<0x01>(p[1], p[0]), _mm256_blend_epi32::<0x01>(p[2], p[1]), _mm256_blend_epi32::<0x01>(p[3], p[2])]
}

/// Lane `x` of the result is lane `(x + 1) % 32` of `r`.
#[target_feature(enable = "avx2")]
#[inline]
fn after8(r: Row8) -> Row8 {
    let rot = _mm256_setr_epi32(1, 2, 3, 4, 5, 6, 7, 0);
    let p = [_mm256_permutevar8x32_epi32(r[0], rot), _mm256_permutevar8x32_epi32(r[1], rot), _mm256_permutevar8x32_epi32(r[2], rot), _mm256_permutevar8x32_epi32(r[3], rot)];
    [_mm256_blend_epi32::<0x80>(p[0], p[1]), _mm256_blend_epi32::<0x80>(p[1], p[2]), _mm256_blend_epi32::<0x80>(p[2], p[3]), _mm256_blend_epi32::<0x80>(p[3], p[0])]
}

/// `gx² + gy²` of 32 pixels as `i32`, in pixel order: each pair `(gx, gy)` interleaved into one
/// `i32` lane, which `madd` squares and sums exactly (`|g| <= 1020`); the interleave works
/// within 128-bit halves, so the halves are put back in order.
#[target_feature(enable = "avx2")]
#[inline]
fn mag2(gx: Row16, gy: Row16) -> Row8 {
    let mut q = [_mm256_setzero_si256(); 4];
    for k in 0..2 {
        let (lo, hi) = (_mm256_unpacklo_epi16(gx[k], gy[k]), _mm256_unpackhi_epi16(gx[k], gy[k]));
        // Pixels 0-3 and 8-11 of the 16, then 4-7 and 12-15.
        let (a, b) = (_mm256_madd_epi16(lo, lo), _mm256_madd_epi16(hi, hi));
        q[2 * k] = _mm256_permute2x128_si256::<0x20>(a, b);
        q[2 * k + 1] = _mm256_permute2x128_si256::<0x31>(a, b);
    }
    q
}

/// Bit `x`: lane `x` of `a` is greater than that of `b`.
#[target_feature(enable = "avx2")]
#[inline]
fn greater(a: Row8, b: Row8) -> u32 {
    bits([_mm256_cmpgt_epi32(a[0], b[0]), _mm256_cmpgt_epi32(a[1], b[1]), _mm256_cmpgt_epi32(a[2], b[2]), _mm256_cmpgt_epi32(a[3], b[3])])
}

/// Bit `x`: `q ≥ a` and `q > b` at pixel `x` (the tests combined before their bits are taken).
#[target_feature(enable = "avx2")]
#[inline]
fn maximum(q: Row8, a: Row8, b: Row8) -> u32 {
    let at = |k: usize| _mm256_andnot_si256(_mm256_cmpgt_epi32(a[k], q[k]), _mm256_cmpgt_epi32(q[k], b[k]));
    bits([at(0), at(1), at(2), at(3)])
}

/// Bit `x`: lane `x` of the compare results `m` is set.
#[target_feature(enable = "avx2")]
#[inline]
fn bits(m: Row8) -> u32 {
    let mut bits = 0u32;
    for (k, &m) in m.iter().enumerate() {
        bits |= (_mm256_movemask_ps(_mm256_castsi256_ps(m)) as u32) << (8 * k);
    }
    bits
}

/// Bit `x`: `|gy| > |gx|` at pixel `x` (the `i16` tests packed to bytes, back in pixel order).
#[target_feature(enable = "avx2")]
#[inline]
fn closer_to_y(gx: Row16, gy: Row16) -> u32 {
    let test = |k: usize| _mm256_cmpgt_epi16(_mm256_abs_epi16(gy[k]), _mm256_abs_epi16(gx[k]));
    // Bytes of pixels 0-7, 16-23, 8-15, 24-31.
    let packed = _mm256_packs_epi16(test(0), test(1));
    _mm256_movemask_epi8(_mm256_permute4x64_epi64::<0b11_01_10_00>(packed)) as u32
}
