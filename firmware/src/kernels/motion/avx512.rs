//! Motion's row scan in AVX-512 BW, on an x86-64 host that runs it: 64 pixels a vector, each
//! pixel's test a bit of a mask register.
use super::{motion_grouped, motion_rows, FullRows, MotionArea};
use crate::kernels::view::WindowView;
use core::arch::x86_64::{__m512i, _mm512_cmpgt_epu8_mask, _mm512_loadu_si512, _mm512_maskz_loadu_epi8, _mm512_max_epu8, _mm512_or_si512, _mm512_set1_epi8, _mm512_setzero_si512, _mm512_subs_epu8};

/// [`super::detect_motion`] with [`scan_row`], in one function so that the row scan is inlined
/// (a call a row was half of a frame's time); full-resolution views by
/// [`motion_grouped`], each group tested by [`largest_diff`].
#[target_feature(enable = "avx512f,avx512bw")]
pub(super) fn motion(prev: &WindowView<'_>, next: &WindowView<'_>, threshold: u8) -> Option<MotionArea> {
    let Some(rows) = FullRows::new(prev, next) else {
        // Decimated views: motion_rows' scalar scan.
        return motion_rows(prev, next, threshold, |a, b, t| scan_row(a, b, t));
    };
    let tv = _mm512_set1_epi8(threshold as i8);
    let group_moves = |rows: FullRows<'_>, ys: core::ops::Range<usize>| {
        let mut largest = _mm512_setzero_si512();
        for y in ys {
            let (ra, rb) = rows.at(y);
            largest = _mm512_max_epu8(largest, largest_diff(ra, rb));
        }
        _mm512_cmpgt_epu8_mask(largest, tv) != 0
    };
    motion_grouped(next, rows, group_moves, |a, b| scan_row(a, b, threshold))
}

/// The moving pixels of two equally long rows with the first and last moving columns, or
/// `None` when none moves, 64 pixels a vector (AVX-512 BW): the test of each pixel is one bit
/// of a mask register, whose bits give the count and, from the first and last vectors that
/// move, the columns.
#[target_feature(enable = "avx512f,avx512bw")]
#[inline]
pub(super) fn scan_row(a: &[u8], b: &[u8], t: u8) -> Option<(u32, usize, usize)> {
    let tv = _mm512_set1_epi8(t as i8);
    let (mut count, mut span) = (0u32, None);
    for_each_vector(a, b, |k, x, y| {
        let m = _mm512_cmpgt_epu8_mask(abs_diff(x, y), tv);
        if m != 0 {
            count += m.count_ones();
            let (lo, hi) = (64 * k + m.trailing_zeros() as usize, 64 * k + 63 - m.leading_zeros() as usize);
            span = Some(span.map_or((lo, hi), |(first, _)| (first, hi)));
        }
    });
    span.map(|(first, last)| (count, first, last))
}

/// The largest `|a - b|` of each lane over the vectors of two rows (0 for empty rows): whether
/// any pixel of them moves, without a branch per vector.
#[target_feature(enable = "avx512f,avx512bw")]
#[inline]
fn largest_diff(a: &[u8], b: &[u8]) -> __m512i {
    let mut m = _mm512_setzero_si512();
    for_each_vector(a, b, |_, x, y| m = _mm512_max_epu8(m, abs_diff(x, y)));
    m
}

/// Calls `f(k, x, y)` for the `k`-th 64 pixels of two rows (up to the shorter's length) as
/// vectors, the last one fewer ([`tail_pair`]) when the length is not a multiple of 64. A
/// loop, not an iterator of vectors: adapters such as `Chain::fold` lack the target feature,
/// so nothing passed through them inlines, and every vector would go through memory (10x).
#[target_feature(enable = "avx512f,avx512bw")]
#[allow(unsafe_code)]
#[inline]
fn for_each_vector(a: &[u8], b: &[u8], mut f: impl FnMut(usize, __m512i, __m512i)) {
    let n = a.len().min(b.len());
    let (ca, cb) = (a.get(..n).unwrap_or(&[]).chunks_exact(64), b.get(..n).unwrap_or(&[]).chunks_exact(64));
    let (ra, rb) = (ca.remainder(), cb.remainder());
    let vectors = n / 64;
    for (k, (x, y)) in ca.zip(cb).enumerate() {
        // SAFETY: each chunk is 64 readable bytes; the load needs no alignment.
        let (x, y) = unsafe { (_mm512_loadu_si512(x.as_ptr().cast()), _mm512_loadu_si512(y.as_ptr().cast())) };
        f(k, x, y);
    }
    if !ra.is_empty() {
        let (x, y) = tail_pair(ra, rb);
        f(vectors, x, y);
    }
}

/// `|x - y|` per byte, as the larger of the two saturating differences (the other is 0).
#[target_feature(enable = "avx512f,avx512bw")]
#[inline]
fn abs_diff(x: __m512i, y: __m512i) -> __m512i {
    _mm512_or_si512(_mm512_subs_epu8(x, y), _mm512_subs_epu8(y, x))
}

/// The last pixels of two rows, fewer than 64, in vectors through a byte mask, 0 past them (a
/// pair of zeros never moves), so that a row needs no scalar tail.
#[target_feature(enable = "avx512f,avx512bw")]
#[allow(unsafe_code)]
#[inline]
fn tail_pair(a: &[u8], b: &[u8]) -> (__m512i, __m512i) {
    let keep = (1u64 << a.len().min(b.len()).min(63)) - 1;
    // SAFETY: only the bytes of `keep`, inside both slices, are read; the masked-off ones are
    // neither read nor able to fault.
    unsafe { (_mm512_maskz_loadu_epi8(keep, a.as_ptr().cast()), _mm512_maskz_loadu_epi8(keep, b.as_ptr().cast())) }
}
