//! Motion's row scan in AVX2, on an x86-64 host that runs it and not AVX-512 (`avx512.rs`):
//! 32 pixels a vector, each pixel's test a bit of `vpmovmskb`'s mask.
use super::{motion_grouped, motion_rows, FullRows, MotionArea};
use crate::kernels::view::WindowView;
use core::arch::x86_64::{__m256i, _mm256_cmpeq_epi8, _mm256_loadu_si256, _mm256_max_epu8, _mm256_movemask_epi8, _mm256_or_si256, _mm256_set1_epi8, _mm256_setzero_si256, _mm256_subs_epu8, _mm256_testz_si256};

/// [`super::detect_motion`] with [`scan_row`], in one function so that the row scan is inlined;
/// full-resolution views by [`motion_grouped`], each group tested by the largest difference
/// of each lane over its rows.
#[target_feature(enable = "avx2")]
pub(super) fn motion(prev: &WindowView<'_>, next: &WindowView<'_>, threshold: u8) -> Option<MotionArea> {
    let Some(rows) = FullRows::new(prev, next) else {
        // Decimated views: motion_rows' scalar scan.
        return motion_rows(prev, next, threshold, |a, b, t| scan_row(a, b, t));
    };
    let tv = _mm256_set1_epi8(threshold as i8);
    let group_moves = |rows: FullRows<'_>, ys: core::ops::Range<usize>| {
        let mut largest = _mm256_setzero_si256();
        for y in ys {
            let (ra, rb) = rows.at(y);
            for_each_vector(ra, rb, |_, x, y| largest = _mm256_max_epu8(largest, abs_diff(x, y)));
        }
        // Some lane's largest difference passes the threshold.
        let over = _mm256_subs_epu8(largest, tv);
        _mm256_testz_si256(over, over) == 0
    };
    motion_grouped(next, rows, group_moves, |a, b| scan_row(a, b, threshold))
}

/// The moving pixels of two equally long rows with the first and last moving columns, or
/// `None` when none moves, 32 pixels a vector: the tests of a vector are the bits of a `u32`,
/// which give the count and, from the first and last vectors that move, the columns.
#[target_feature(enable = "avx2")]
#[inline]
pub(super) fn scan_row(a: &[u8], b: &[u8], t: u8) -> Option<(u32, usize, usize)> {
    let (tv, zero) = (_mm256_set1_epi8(t as i8), _mm256_setzero_si256());
    let (mut count, mut span) = (0u32, None);
    for_each_vector(a, b, |k, x, y| {
        // `|x - y| - t`, saturated, is 0 exactly where a pixel does not move (for any `t`).
        let still = _mm256_cmpeq_epi8(_mm256_subs_epu8(abs_diff(x, y), tv), zero);
        let m = !(_mm256_movemask_epi8(still) as u32);
        if m != 0 {
            count += m.count_ones();
            let (lo, hi) = (32 * k + m.trailing_zeros() as usize, 32 * k + 31 - m.leading_zeros() as usize);
            span = Some(span.map_or((lo, hi), |(first, _)| (first, hi)));
        }
    });
    span.map(|(first, last)| (count, first, last))
}

/// Calls `f(k, x, y)` for the `k`-th 32 pixels of two rows (up to the shorter's length) as
/// vectors, the last one from copies padded with zeros (a pair of zeros never moves) when the
/// length is not a multiple of 32. A loop, not an iterator of vectors (see `avx512.rs`).
#[target_feature(enable = "avx2")]
#[allow(unsafe_code)]
#[inline]
fn for_each_vector(a: &[u8], b: &[u8], mut f: impl FnMut(usize, __m256i, __m256i)) {
    let n = a.len().min(b.len());
    let (ca, cb) = (a.get(..n).unwrap_or(&[]).chunks_exact(32), b.get(..n).unwrap_or(&[]).chunks_exact(32));
    let (ra, rb) = (ca.remainder(), cb.remainder());
    let vectors = n / 32;
    for (k, (x, y)) in ca.zip(cb).enumerate() {
        // SAFETY: each chunk is 32 readable bytes; the load needs no alignment.
        let (x, y) = unsafe { (_mm256_loadu_si256(x.as_ptr().cast()), _mm256_loadu_si256(y.as_ptr().cast())) };
        f(k, x, y);
    }
    if !ra.is_empty() {
        let (mut pa, mut pb) = ([0u8; 32], [0u8; 32]);
        pa.iter_mut().zip(ra).for_each(|(d, &s)| *d = s);
        pb.iter_mut().zip(rb).for_each(|(d, &s)| *d = s);
        // SAFETY: 32 readable bytes each.
        let (x, y) = unsafe { (_mm256_loadu_si256(pa.as_ptr().cast()), _mm256_loadu_si256(pb.as_ptr().cast())) };
        f(vectors, x, y);
    }
}

/// `|x - y|` per byte, as the larger of the two saturating differences (the other is 0).
#[target_feature(enable = "avx2")]
#[inline]
fn abs_diff(x: __m256i, y: __m256i) -> __m256i {
    _mm256_or_si256(_mm256_subs_epu8(x, y), _mm256_subs_epu8(y, x))
}
