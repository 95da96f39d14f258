//! The dot products of every placement in AVX-512 BW, on an x86-64 host that runs it.
use super::{LANES, SCORE_CACHE};
use crate::kernels::view::WindowView;
use heapless::Vec;

/// [`super::dot_products`] in AVX-512 BW, for templates of at most [`LANES`] x [`LANES`] pixels: each
/// template row is widened once into a register of 32 `i16` lanes (0 past the row), and each
/// window row under a placement column once per four placement rows; `pmaddwd` multiplies it
/// with the template rows it meets in those four placements (`Σ R·I` of placement `(px, py)`
/// gains row `r` times template row `r - py`). No strip is copied: the Foveal 20x20-in-24 match
/// widens 230 window rows instead of writing 2,400 strip pixels (five columns of 20x24) and
/// reading them back. Lanes cannot overflow: each gains at most `2·255²` a row, at most
/// [`LANES`] rows.
#[target_feature(enable = "avx512f,avx512bw")]
#[allow(unsafe_code)]
pub(in super::super) fn dot_products(win: &WindowView<'_>, tpl: &WindowView<'_>, dots: &mut Vec<u32, SCORE_CACHE>) -> Option<()> {
    use core::arch::x86_64::{__m512i, _mm512_add_epi32, _mm512_castsi512_si256, _mm512_cvtepu8_epi16, _mm512_madd_epi16, _mm512_maskz_loadu_epi8, _mm512_reduce_add_epi32, _mm512_setzero_si512};
    let (tw, th) = (tpl.width(), tpl.height());
    let nx = win.width().checked_sub(tw)? + 1;
    let ny = win.height().checked_sub(th)? + 1;
    if tw == 0 || tw > LANES || th > LANES || nx * ny > SCORE_CACHE {
        return None;
    }
    let keep = (1u64 << tw) - 1;
    // `tw` pixels from `row`'s start, widened.
    let widen = |row: &[u8]| -> Option<__m512i> {
        let row = row.get(..tw)?;
        // SAFETY: only the `tw` bytes of `keep`, inside `row`, are read; masked-off bytes are
        // neither read nor able to fault.
        Some(_mm512_cvtepu8_epi16(_mm512_castsi512_si256(unsafe { _mm512_maskz_loadu_epi8(keep, row.as_ptr().cast()) })))
    };
    // Template row `v` at `v + 3`, rows of zeros around: window row `r` adds template row
    // `r - py - j` to placement row `py + j`'s sum, `t[r - py + 3 - j]`, zeros where that
    // placement does not cover the row, so the four sums need no test.
    let mut t = [_mm512_setzero_si512(); LANES + 7];
    for (v, t) in t.iter_mut().skip(3).enumerate().take(th) {
        *t = widen(tpl.row(v)?)?;
    }
    dots.clear();
    dots.resize(nx * ny, 0).ok()?;
    for px in 0..nx {
        for py in (0..ny).step_by(4) {
            let group = (ny - py).min(4);
            let mut acc = [_mm512_setzero_si512(); 4];
            for k in 3..group + th + 2 {
                let w = widen(win.row(py + k - 3)?.get(px..)?)?;
                for (j, a) in acc.iter_mut().enumerate() {
                    *a = _mm512_add_epi32(*a, _mm512_madd_epi16(*t.get(k - j)?, w));
                }
            }
            for (j, a) in acc.iter().enumerate().take(group) {
                *dots.get_mut((py + j) * nx + px)? = _mm512_reduce_add_epi32(*a) as u32;
            }
        }
    }
    Some(())
}
