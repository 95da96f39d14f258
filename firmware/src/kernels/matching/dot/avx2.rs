//! The dot products of every placement in AVX2, on an x86-64 host that runs it and not
//! AVX-512 (`avx512.rs`, whose scheme this is with half-width registers).
use super::{LANES, SCORE_CACHE};
use crate::kernels::view::WindowView;
use core::arch::x86_64::{__m128i, __m256i, _mm256_add_epi32, _mm256_castsi256_si128, _mm256_cvtepu8_epi16, _mm256_extracti128_si256, _mm256_and_si256, _mm256_hadd_epi32, _mm256_loadu_si256, _mm256_madd_epi16, _mm256_setzero_si256, _mm_add_epi32, _mm_loadu_si128, _mm_storeu_si128};
use heapless::Vec;

/// [`super::dot_products`] in AVX2, for templates of at most [`LANES`] x [`LANES`] pixels:
/// each template row is widened once into `K` registers of 16 `i16` lanes (one for rows up to
/// 16 pixels, two up to 32; 0 past the row), and each window row under a placement column once
/// per four placement rows, and `pmaddwd` multiplies it with the template rows it meets in
/// those four placements, as in AVX-512 (`avx512.rs`). A window row is read `16·K` pixels
/// from its placement column, past the patch where the window's buffer goes on (those pixels
/// meet the template's zeros), else from a copy padded with zeros. Lanes cannot overflow: each
/// gains at most `2·255²` a row, at most [`LANES`] rows.
#[target_feature(enable = "avx2")]
pub(in super::super) fn dot_products(win: &WindowView<'_>, tpl: &WindowView<'_>, dots: &mut Vec<u32, SCORE_CACHE>) -> Option<()> {
    match tpl.width() {
        0 => None,
        1..=16 => products::<1>(win, tpl, dots),
        _ => products::<2>(win, tpl, dots),
    }
}

/// [`dot_products`] with template rows of `K` registers (`tw <= 16·K`).
#[target_feature(enable = "avx2")]
#[inline]
fn products<const K: usize>(win: &WindowView<'_>, tpl: &WindowView<'_>, dots: &mut Vec<u32, SCORE_CACHE>) -> Option<()> {
    let (tw, th) = (tpl.width(), tpl.height());
    let nx = win.width().checked_sub(tw)? + 1;
    let ny = win.height().checked_sub(th)? + 1;
    if tw == 0 || tw > 16 * K || th > LANES || nx * ny > SCORE_CACHE {
        return None;
    }
    let ((data, stride), (tdata, tstride)) = (win.raw()?, tpl.raw()?);
    // Template row `v` at `v + 3`, rows of zeros around (see `avx512.rs`), its lanes past `tw`
    // zeroed: read in place, not from a copy whose byte stores the vector load would wait for
    // (a third of the Foveal match's time).
    let keep: [i16; LANES] = core::array::from_fn(|x| if x < tw { -1 } else { 0 });
    let mut t = [[_mm256_setzero_si256(); K]; LANES + 7];
    for v in 0..th {
        let row = widen::<K>(tdata, v * tstride, tw);
        let tv = t.get_mut(v + 3)?;
        for (k, (tv, &r)) in tv.iter_mut().zip(&row).enumerate() {
            // SAFETY: 32 readable bytes at `16·k` of `keep` (k < 2).
            #[allow(unsafe_code)]
            let keep = unsafe { _mm256_loadu_si256(keep.as_ptr().add(16 * k).cast()) };
            *tv = _mm256_and_si256(r, keep);
        }
    }
    dots.clear();
    dots.resize(nx * ny, 0).ok()?;
    for px in 0..nx {
        let mut py = 0;
        while py < ny {
            // Four placement rows at a time, the last group as many as are left (no sums of
            // rows no placement covers).
            let (group, at) = ((ny - py).min(4), py * stride + px);
            let sums = match group {
                4 => column::<K, 4>(&t, data, stride, at, tw, th),
                3 => column::<K, 3>(&t, data, stride, at, tw, th),
                2 => column::<K, 2>(&t, data, stride, at, tw, th),
                _ => column::<K, 1>(&t, data, stride, at, tw, th),
            };
            for (j, &s) in sums.iter().enumerate().take(group) {
                *dots.get_mut((py + j) * nx + px)? = s;
            }
            py += group;
        }
    }
    Some(())
}

/// The dot products of the `G` placements of one column from the one whose patch starts at
/// `data[at]` down (the rest of the four 0): window row `r` of the `G + th - 1` rows adds
/// template row `r - j` (`t[r + 3 - j]`) to placement `j`'s sum.
#[target_feature(enable = "avx2")]
#[inline]
fn column<const K: usize, const G: usize>(t: &[[__m256i; K]; LANES + 7], data: &[u8], stride: usize, at: usize, tw: usize, th: usize) -> [u32; 4] {
    let zero = _mm256_setzero_si256();
    let mut acc = [zero; 4];
    for k in 3..G + th + 2 {
        let w = widen::<K>(data, at + (k - 3) * stride, tw);
        for (j, a) in acc.iter_mut().enumerate().take(G) {
            if let Some(tr) = t.get(k - j) {
                for (&tv, &wv) in tr.iter().zip(&w) {
                    *a = _mm256_add_epi32(*a, _mm256_madd_epi16(tv, wv));
                }
            }
        }
    }
    let mut sums = [0u32; 4];
    // SAFETY: 16 writable bytes.
    #[allow(unsafe_code)]
    unsafe {
        _mm_storeu_si128(sums.as_mut_ptr().cast(), reduce4(acc));
    }
    sums
}

/// `16·K` pixels of `data` from `at` widened to `i16`: read in place where `data` holds them,
/// else the first `n` (or as many as there are) from a copy, zeros after them.
#[target_feature(enable = "avx2")]
#[inline]
#[allow(unsafe_code)]
fn widen<const K: usize>(data: &[u8], at: usize, n: usize) -> [__m256i; K] {
    let mut pad = [0u8; 32];
    let src = match data.get(at..at + 16 * K) {
        Some(s) => s,
        None => {
            let have = data.get(at..).unwrap_or(&[]);
            let n = n.min(have.len()).min(16 * K);
            pad.get_mut(..n).unwrap_or(&mut []).copy_from_slice(have.get(..n).unwrap_or(&[]));
            &pad[..]
        }
    };
    let mut w = [_mm256_setzero_si256(); K];
    for (k, w) in w.iter_mut().enumerate() {
        // SAFETY: `src` holds at least `16·K` bytes; the load needs no alignment.
        *w = _mm256_cvtepu8_epi16(unsafe { _mm_loadu_si128(src.as_ptr().add(16 * k).cast()) });
    }
    w
}

/// The sums of the eight `i32` lanes of each of four registers, as four lanes.
#[target_feature(enable = "avx2")]
#[inline]
fn reduce4([a, b, c, d]: [__m256i; 4]) -> __m128i {
    let s = _mm256_hadd_epi32(_mm256_hadd_epi32(a, b), _mm256_hadd_epi32(c, d));
    _mm_add_epi32(_mm256_castsi256_si128(s), _mm256_extracti128_si256::<1>(s))
}
