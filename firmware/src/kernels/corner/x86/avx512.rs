//! [`Gradients::sobel`] in AVX-512 BW: a row of 32 `i16` in one register, the neighbours by
//! reflect-101 permutes.
use super::super::sobel::{reflect, row_mask};
use super::{Gradients, MAX_W};
use crate::kernels::view::WindowView;
use core::arch::x86_64::{
    __m256i, __m512i, _mm512_abs_epi16, _mm512_add_epi16, _mm512_castsi512_si256, _mm512_cmpge_epi16_mask,
    _mm512_cmpge_epi32_mask, _mm512_cmpgt_epi32_mask, _mm512_cvtepu16_epi32, _mm512_cvtepu8_epi16,
    _mm512_extracti64x4_epi64, _mm512_loadu_si512, _mm512_madd_epi16, _mm512_maskz_loadu_epi8, _mm512_or_si512,
    _mm512_permutex2var_epi32, _mm512_permutexvar_epi16, _mm512_set1_epi32, _mm512_slli_epi16, _mm512_slli_epi32,
    _mm512_storeu_si512, _mm512_sub_epi16,
};

/// Two halves of a row of 32 `i32` (pixels 0-15, 16-31).
type Row32 = (__m512i, __m512i);

impl<const N: usize> Gradients<N> {
    /// `sobel_rows`' edge map of `view` (`w <= MAX_W`, `h <= N`) into `bits`: pixel
    /// `(x, y)` is an edge iff `gx² + gy² > th2`, with
    /// `gx = s(x+1) - s(x-1)`, `s = up + 2 mid + down` and `gy = d(x-1) + 2 d(x) + d(x+1)`,
    /// `d = down - up`, columns and rows reflected (101) at the border. Keeps the gradients,
    /// the squared magnitudes and the peaks; returns the number of edge pixels.
    #[target_feature(enable = "avx512f,avx512bw")]
    #[allow(unsafe_code)]
    pub(super) fn sobel_avx512(&mut self, view: &WindowView<'_>, bits: &mut [u64], th2: i32) -> u32 {
        let (w, h) = (view.width().min(MAX_W), view.height().min(N).min(bits.len()));
        let row = |y: usize| -> __m512i {
            let mut buf = [0u8; MAX_W];
            let src = match view.row(y) {
                Some(r) => r,
                None => {
                    buf.iter_mut().zip(view.row_iter(y)).for_each(|(d, s)| *d = s);
                    &buf[..]
                }
            };
            // SAFETY: only the first `min(w, len)` bytes of `src` are read (masked-off bytes
            // are neither read nor able to fault).
            let bytes = unsafe { _mm512_maskz_loadu_epi8(row_mask(w.min(src.len())), src.as_ptr().cast()) };
            _mm512_cvtepu8_epi16(_mm512_castsi512_si256(bytes))
        };
        let index = |d: isize| {
            let i: [i16; MAX_W] = core::array::from_fn(|x| reflect(x as isize + d, w) as i16);
            // SAFETY: 64 readable bytes.
            unsafe { _mm512_loadu_si512(i.as_ptr().cast()) }
        };
        let (left, right) = (index(-1), index(1));
        // Lanes x-1 and x+1 of a row of 32 `i32` held as two halves.
        let halves = |d: i32| -> Row32 {
            let i: [i32; 32] = core::array::from_fn(|x| (x as i32 + d) & 31);
            // SAFETY: 128 readable bytes.
            unsafe { (_mm512_loadu_si512(i.as_ptr().cast()), _mm512_loadu_si512(i.as_ptr().add(16).cast())) }
        };
        let (before, after) = (halves(-1), halves(1));
        let shifted = |q: Row32, (lo, hi): Row32| (_mm512_permutex2var_epi32(q.0, lo, q.1), _mm512_permutex2var_epi32(q.0, hi, q.1));
        // q ≥ a and q > b per pixel, as 32 bits.
        let maximum = |q: Row32, a: Row32, b: Row32| {
            let half = |q, a, b| u32::from(_mm512_cmpge_epi32_mask(q, a) & _mm512_cmpgt_epi32_mask(q, b));
            half(q.0, a.0, b.0) | half(q.1, a.1, b.1) << 16
        };
        let (lanes, inner, inner2) = (row_mask(w) as u32, row_mask(w.saturating_sub(1)) as u32 & !1, row_mask(w.saturating_sub(2)) as u32 & !3);
        let thv = _mm512_set1_epi32(th2);
        let (mut up, mut mid) = (row(reflect(-1, h)), row(0));
        // Rows y-1 and y-2: squared magnitudes, and (y-1) the pixels whose gradient is closer
        // to x than to y.
        let (mut q1, mut q2, mut horizontal) = ((thv, thv), (thv, thv), 0u32);
        let mut count = 0;
        self.maxima.iter_mut().for_each(|m| *m = 0);
        for (y, out) in bits.iter_mut().enumerate().take(h) {
            let dn = row(reflect(y as isize + 1, h));
            let smooth = _mm512_add_epi16(_mm512_add_epi16(up, dn), _mm512_slli_epi16(mid, 1));
            let diff = _mm512_sub_epi16(dn, up);
            let gx = _mm512_sub_epi16(_mm512_permutexvar_epi16(right, smooth), _mm512_permutexvar_epi16(left, smooth));
            let gy = _mm512_add_epi16(
                _mm512_add_epi16(_mm512_permutexvar_epi16(left, diff), _mm512_permutexvar_epi16(right, diff)),
                _mm512_slli_epi16(diff, 1),
            );
            let q = (mag2(_mm512_castsi512_si256(gx), _mm512_castsi512_si256(gy)), mag2(_mm512_extracti64x4_epi64(gx, 1), _mm512_extracti64x4_epi64(gy, 1)));
            let edge = (u32::from(_mm512_cmpgt_epi32_mask(q.0, thv)) | u32::from(_mm512_cmpgt_epi32_mask(q.1, thv)) << 16) & lanes;
            *out = u64::from(edge);
            count += edge.count_ones();
            if let (Some(gxr), Some(gyr), Some(m2r)) = (self.gx.get_mut(y), self.gy.get_mut(y), self.m2.get_mut(y)) {
                // SAFETY: each row is 64 (`i16`) or 128 (`i32`) writable bytes.
                unsafe {
                    _mm512_storeu_si512(gxr.as_mut_ptr().cast(), gx);
                    _mm512_storeu_si512(gyr.as_mut_ptr().cast(), gy);
                    _mm512_storeu_si512(m2r.as_mut_ptr().cast(), q.0);
                    _mm512_storeu_si512(m2r.as_mut_ptr().add(16).cast(), q.1);
                }
            }
            // Row y-1's peaks, now that the row below it is known: an interior pixel that is a
            // maximum along its axis, whose neighbours there are interior too.
            if y >= 2 {
                let along_x = maximum(q1, shifted(q1, before), shifted(q1, after)) & inner2;
                let along_y = if y >= 3 && y + 1 < h { maximum(q1, q2, q) } else { 0 };
                if let Some(m) = self.maxima.get_mut(y - 1) {
                    *m = u64::from((horizontal & along_x | !horizontal & along_y) & inner);
                }
            }
            horizontal = _mm512_cmpge_epi16_mask(_mm512_abs_epi16(gx), _mm512_abs_epi16(gy));
            (q2, q1) = (q1, q);
            (up, mid) = (mid, dn);
        }
        count
    }
}

/// `gx² + gy²` of 16 pixels as `i32`: each pair `(gx, gy)` is one `i32` lane, which
/// `madd` squares and sums exactly (`|g| <= 1020`).
#[target_feature(enable = "avx512f,avx512bw")]
#[inline]
fn mag2(gx: __m256i, gy: __m256i) -> __m512i {
    let pairs = _mm512_or_si512(_mm512_cvtepu16_epi32(gx), _mm512_slli_epi32(_mm512_cvtepu16_epi32(gy), 16));
    _mm512_madd_epi16(pairs, pairs)
}
