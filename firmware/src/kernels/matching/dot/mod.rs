//! The dot products `Σ R·I` (and `Σ |R - I|`) of every placement, the inner loop of template
//! matching (thesis 2.4).
//!
//! All sums are exact integers. The window energies `Σ I²` (and `Σ I` for ZNCC) of every
//! placement come from running column sums, updated by one row in and one row out per
//! placement row, and a running sum along the row, so each placement costs only the
//! dot product `Σ R·I`. SSD uses `Σ R² + Σ I² - 2 Σ R·I`, so it costs the same dot
//! product. The dot products of all placements ([`dot_products`]) come, on x86-64, from
//! column strips widened to `i16` (see `strip_dot_products`), in which every patch is one
//! contiguous run; four placements share each template load and LLVM turns the 16-lane
//! `i16·i16 -> i32` reduction into `pmaddwd`. Where the CPU has AVX-512 or AVX2 (asked at run
//! time), templates up to 32x32 are multiplied from the pixel rows instead, a template row a
//! register or two (`avx512.rs`, `avx2.rs`). A 32-bit Arm core (the Cortex-M4) has no such
//! vectors, so widening the window buys nothing there; its DSP extension multiplies pairs
//! of 16-bit halves instead, fed straight from the pixel rows (`arm.rs`).
//! Windows too large for either use per-row `u8` dot products.
//!
use super::SCORE_CACHE;
use crate::kernels::view::WindowView;
#[cfg(not(target_arch = "arm"))]
use heapless::Vec;

#[cfg(any(test, target_arch = "arm"))]
mod arm;
#[cfg(target_arch = "x86_64")]
mod avx2;
#[cfg(target_arch = "x86_64")]
mod avx512;
#[cfg(any(test, target_arch = "arm"))]
pub(super) use arm::dot_row_pairs;
#[cfg(test)]
pub(super) use arm::row_dot_products;
#[cfg(target_arch = "x86_64")]
use crate::kernels::x86::Isa;

/// Row dot products accumulate in `u32` in chunks of this many pixels:
/// `16384 · 255² < 2³²`, so no chunk can overflow.
pub(super) const DOT_CHUNK: usize = 16384;

/// `Σ a·b` of two pixel rows (the shorter's length).
#[inline(always)]
pub(super) fn dot_row(a: &[u8], b: &[u8]) -> u64 {
    #[cfg(target_arch = "arm")]
    return dot_row_pairs(a, b);
    #[cfg(not(target_arch = "arm"))]
    dot_row_bytes(a, b)
}

/// [`dot_row`] a pixel at a time (vectorised by LLVM where there are vectors).
#[cfg(any(test, not(target_arch = "arm")))]
#[inline(always)]
pub(super) fn dot_row_bytes(a: &[u8], b: &[u8]) -> u64 {
    let n = a.len().min(b.len());
    let (Some(a), Some(b)) = (a.get(..n), b.get(..n)) else { return 0 };
    let mut s = 0u64;
    for (ca, cb) in a.chunks(DOT_CHUNK).zip(b.chunks(DOT_CHUNK)) {
        // Whole 16-pixel vectors, then one of 8, then the rest: a short row (a 16- or 8-pixel
        // template's) would otherwise fall entirely into the vectorised loop's scalar remainder.
        let (qa, qb) = (ca.chunks_exact(16), cb.chunks_exact(16));
        let (ea, eb) = (qa.remainder().chunks_exact(8), qb.remainder().chunks_exact(8));
        let tail = ea.remainder().iter().zip(eb.remainder()).fold(0u32, |acc, (&x, &y)| {
            acc.wrapping_add(u32::from(u16::from(x) * u16::from(y)))
        });
        let (sixteen, eight) = (lanes_dot::<16>(qa.zip(qb)), lanes_dot::<8>(ea.zip(eb)));
        s += u64::from(tail.wrapping_add(sixteen).wrapping_add(eight));
    }
    s
}

/// `Σ x·y` over pairs of `N`-pixel chunks, in `N` `u32` lanes (SIMD multiply-adds, no scalar
/// remainder), wrapping like the caller's `DOT_CHUNK` sums (which cannot wrap).
#[cfg(any(test, not(target_arch = "arm")))]
#[inline(always)]
fn lanes_dot<'a, const N: usize>(chunks: impl Iterator<Item = (&'a [u8], &'a [u8])>) -> u32 {
    let mut lanes = [0u32; N];
    for (x, y) in chunks {
        if let (Ok(x), Ok(y)) = (<&[u8; N]>::try_from(x), <&[u8; N]>::try_from(y)) {
            for ((l, &p), &q) in lanes.iter_mut().zip(x).zip(y) {
                *l = l.wrapping_add(u32::from(u16::from(p) * u16::from(q)));
            }
        }
    }
    lanes.iter().fold(0u32, |acc, &l| acc.wrapping_add(l))
}

/// `(Σ R·I, Σ I²)` of the template `tpl` over `win`'s patch at `(px, py)`, for templates a
/// multiple of 8 pixels wide: SSE2 multiply-adds (`pmaddwd`) into four `i32` lanes kept
/// across the rows and summed once, not a reduction per row as [`dot_row`]'s (LLVM's own
/// vectorisation of such loops came and went with the code around them). `None` for other
/// widths, a patch outside the window or one larger than [`DOT_CHUNK`] pixels (so no lane,
/// nor their sum, can pass 2³¹).
#[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
pub(super) fn patch_dots(tpl: &WindowView<'_>, win: &WindowView<'_>, px: usize, py: usize) -> Option<(u64, u64)> {
    // SAFETY: the only requirement of a `target_feature` function is that the CPU has the
    // feature, and this is compiled only where SSE2 is part of the build's target.
    #[allow(unsafe_code)]
    unsafe {
        patch_dots_sse2(tpl, win, px, py)
    }
}

/// [`patch_dots`] itself (the intrinsics are safe to call inside).
#[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
#[target_feature(enable = "sse2")]
fn patch_dots_sse2(tpl: &WindowView<'_>, win: &WindowView<'_>, px: usize, py: usize) -> Option<(u64, u64)> {
    use core::arch::x86_64::{__m128i, _mm_add_epi32, _mm_madd_epi16, _mm_set_epi64x, _mm_setzero_si128, _mm_unpackhi_epi64, _mm_unpacklo_epi8};
    let (tw, th) = (tpl.width(), tpl.height());
    if tw % 8 != 0 || tw.checked_mul(th)? > DOT_CHUNK {
        return None;
    }
    let zero = _mm_setzero_si128();
    // Eight pixels as a 64-bit word.
    let word = |p: &[u8]| <[u8; 8]>::try_from(p).ok().map(i64::from_le_bytes);
    let (mut a, mut e) = (zero, zero);
    // Eight pixels of each, widened to `i16`.
    let mut add = |t: __m128i, w: __m128i| {
        let (t, w) = (_mm_unpacklo_epi8(t, zero), _mm_unpacklo_epi8(w, zero));
        a = _mm_add_epi32(a, _mm_madd_epi16(t, w));
        e = _mm_add_epi32(e, _mm_madd_epi16(w, w));
    };
    for v in 0..th {
        let (t, w) = (tpl.row(v)?.get(..tw)?, win.row(py + v)?.get(px..px + tw)?);
        let (ct, cw) = (t.chunks_exact(16), w.chunks_exact(16));
        let (rt, rw) = (ct.remainder(), cw.remainder());
        for (x, y) in ct.zip(cw) {
            let (x, y) = (_mm_set_epi64x(word(x.get(8..)?)?, word(x.get(..8)?)?), _mm_set_epi64x(word(y.get(8..)?)?, word(y.get(..8)?)?));
            add(x, y);
            add(_mm_unpackhi_epi64(x, x), _mm_unpackhi_epi64(y, y));
        }
        if let (Some(x), Some(y)) = (word(rt), word(rw)) {
            add(_mm_set_epi64x(0, x), _mm_set_epi64x(0, y));
        }
    }
    Some((lane_sum(a), lane_sum(e)))
}

/// The sum of four `i32` lanes of non-negative sums, as `u64`.
#[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
#[target_feature(enable = "sse2")]
fn lane_sum(l: core::arch::x86_64::__m128i) -> u64 {
    use core::arch::x86_64::{_mm_add_epi32, _mm_cvtsi128_si32, _mm_shuffle_epi32};
    let l = _mm_add_epi32(l, _mm_shuffle_epi32::<0b0100_1110>(l));
    let l = _mm_add_epi32(l, _mm_shuffle_epi32::<0b1011_0001>(l));
    u64::from(_mm_cvtsi128_si32(l) as u32)
}


/// `Σ |a - b|` of two pixel rows.
#[inline(always)]
pub(super) fn sad_row(a: &[u8], b: &[u8]) -> u64 {
    let mut s = 0u64;
    for (ca, cb) in a.chunks(DOT_CHUNK).zip(b.chunks(DOT_CHUNK)) {
        let d = ca.iter().zip(cb).fold(0u32, |acc, (&x, &y)| {
            acc.wrapping_add(u32::from(x.abs_diff(y)))
        });
        s += u64::from(d);
    }
    s
}

/// Capacity of the lane-padded template copy used by the fast dot product.
const TPL_PAD_CAP: usize = 4096;

/// The template rearranged for [`dot_placement`]: each row is its first
/// `body = tw - tw % lanes` pixels followed, if `tw` is not a multiple of `lanes`, by a
/// `lanes`-pixel "tail" chunk holding the last `tw % lanes` pixels right-aligned after
/// zeros. The tail chunk is multiplied with the window's last `lanes` pixels under the
/// template, so every row is whole SIMD chunks and no scalar remainder loop is needed
/// (the zeros cancel the overlap). `lanes` is 16 for templates at least 16 wide, else 8.
pub(super) struct PaddedTemplate {
    buf: [u8; TPL_PAD_CAP],
    row_len: usize,
    body: usize,
    pub(super) lanes: usize,
}

impl PaddedTemplate {
    /// `None` when the template is narrower than 8 pixels or does not fit the buffer
    /// (the generic row-by-row dot product is used then).
    pub(super) fn new(tpl: &WindowView<'_>) -> Option<Self> {
        let tw = tpl.width();
        let lanes = if tw >= 16 { 16 } else { 8 };
        if tw < lanes {
            return None;
        }
        let body = tw - tw % lanes;
        let rem = tw - body;
        let row_len = body + if rem > 0 { lanes } else { 0 };
        if row_len.checked_mul(tpl.height())? > TPL_PAD_CAP {
            return None;
        }
        let mut buf = [0u8; TPL_PAD_CAP];
        for (v, dst) in buf.chunks_exact_mut(row_len).take(tpl.height()).enumerate() {
            let src = tpl.row(v)?;
            dst.get_mut(..body)?.copy_from_slice(src.get(..body)?);
            if rem > 0 {
                dst.get_mut(row_len - rem..)?.copy_from_slice(src.get(body..)?);
            }
        }
        Some(Self { buf, row_len, body, lanes })
    }
}

/// `Σ R·I` of placement `(px, py)` with the padded template: `N`-pixel chunks accumulate
/// into `N` `u32` lanes (SIMD multiply-adds), reduced once per placement. Lanes cannot
/// overflow: each gains at most 255² per chunk and a template holds at most
/// `TPL_PAD_CAP / 8 = 512` chunks.
#[inline(always)]
pub(super) fn dot_placement<const N: usize>(
    t: &PaddedTemplate,
    win: &WindowView<'_>,
    tw: usize,
    th: usize,
    px: usize,
    py: usize,
) -> u64 {
    let mut lanes = [0u32; N];
    let mut mac = |tc: &[u8], wc: &[u8]| {
        if let (Ok(tc), Ok(wc)) = (<&[u8; N]>::try_from(tc), <&[u8; N]>::try_from(wc)) {
            for ((l, &a), &b) in lanes.iter_mut().zip(tc).zip(wc) {
                *l = l.wrapping_add(u32::from(u16::from(a) * u16::from(b)));
            }
        }
    };
    let tail = t.row_len > t.body;
    let Some((data, stride)) = win.raw() else { return 0 };
    let base = py * stride + px;
    for (v, trow) in t.buf.chunks_exact(t.row_len).take(th).enumerate() {
        // Row py+v of the window from offset px, `tw` pixels (inside the view because
        // the placement is valid).
        let start = base + v * stride;
        let Some(wrow) = data.get(start..start + tw) else { continue };
        let (tbody, ttail) = trow.split_at(t.body.min(trow.len()));
        if let Some(wbody) = wrow.get(..t.body) {
            for (tc, wc) in tbody.chunks_exact(N).zip(wbody.chunks_exact(N)) {
                mac(tc, wc);
            }
        }
        if tail {
            if let Some(wtail) = wrow.get(tw - N..) {
                mac(ttail, wtail);
            }
        }
    }
    lanes.iter().map(|&l| u64::from(l)).sum()
}

/// Capacity, in pixels, of the column strip of [`strip_dot_products`] (window height x
/// template width) and of its widened template copy.
pub(super) const STRIP_CAP: usize = 4096;

/// Widens `src` (`u8`) into `dst` (`i16`, same length). For runs of at least 8 pixels
/// this copies fixed 8-pixel chunks (the last one overlapping the previous, if the
/// length is not a multiple of 8), so each chunk is one load, one unpack and one store
/// instead of a call to a generic loop.
#[cfg(not(target_arch = "arm"))]
#[inline(always)]
fn widen_into(dst: &mut [i16], src: &[u8]) {
    let n = dst.len().min(src.len());
    if n < 8 {
        for (d, &s) in dst.iter_mut().zip(src) {
            *d = i16::from(s);
        }
        return;
    }
    let mut widen8 = |at: usize| {
        if let (Some(d), Some(s)) = (dst.get_mut(at..at + 8), src.get(at..at + 8)) {
            if let (Ok(d), Ok(s)) = (<&mut [i16; 8]>::try_from(d), <&[u8; 8]>::try_from(s)) {
                for (d, &s) in d.iter_mut().zip(s) {
                    *d = i16::from(s);
                }
            }
        }
    };
    let mut at = 0;
    while at + 8 <= n {
        widen8(at);
        at += 8;
    }
    if at < n {
        widen8(n - 8);
    }
}

/// Widens columns `px..px+tw` of every row of `view` into consecutive `tw`-pixel rows of
/// `dst`; `None` if `dst` is too short or the columns are outside the view.
#[cfg(not(target_arch = "arm"))]
#[inline(never)]
fn fill_strip(dst: &mut [i16], view: &WindowView<'_>, px: usize, tw: usize) -> Option<()> {
    let rows = dst.get_mut(..tw.checked_mul(view.height())?)?;
    for (y, d) in rows.chunks_exact_mut(tw).enumerate() {
        widen_into(d, view.row(y)?.get(px..px + tw)?);
    }
    Some(())
}

/// `Σ R·I` of every placement, row-major, computed strip by strip: for each placement
/// column `px` the window columns `px..px+tw` are widened to `i16` into a contiguous
/// strip, in which the patch of every placement `(px, py)` is one contiguous run of
/// `tw·th` pixels laid out exactly like the (also widened) template. Each dot product is
/// then a single long `i16·i16 -> i32` reduction, which LLVM turns into `pmaddwd`
/// (16 lanes, two SSE registers) with no unpacking in the inner loop, and four
/// placements of a column share every template load. The strip costs `tw` pixels per
/// window row and placement column, far less than the `tw·th` multiply-adds per
/// placement.
///
/// The products go into `dots` (row-major placements; a 4 KiB vector is not returned by
/// value, which would copy it). `None` (use the other paths) when the strip or the placement
/// count exceed their capacities.
#[cfg(not(target_arch = "arm"))]
pub(super) fn strip_dot_products(win: &WindowView<'_>, tpl: &WindowView<'_>, dots: &mut Vec<u32, SCORE_CACHE>) -> Option<()> {
    // Small windows use small buffers: zeroing two 8 KiB arrays would cost as much as
    // the whole Foveal match.
    if tpl.width().checked_mul(win.height())? <= SMALL_STRIP_CAP {
        strip_dot_products_in::<SMALL_STRIP_CAP>(win, tpl, dots)
    } else {
        strip_dot_products_in::<STRIP_CAP>(win, tpl, dots)
    }
}

/// Capacity of the strip buffers for small windows (Foveal 20 x 24 = 480 pixels,
/// Peripheral 16 x 40 = 640).
#[cfg(not(target_arch = "arm"))]
const SMALL_STRIP_CAP: usize = 1024;

/// [`strip_dot_products`] with strip buffers of `CAP <= STRIP_CAP` pixels.
#[cfg(not(target_arch = "arm"))]
fn strip_dot_products_in<const CAP: usize>(win: &WindowView<'_>, tpl: &WindowView<'_>, dots: &mut Vec<u32, SCORE_CACHE>) -> Option<()> {
    let (tw, th, ww, wh) = (tpl.width(), tpl.height(), win.width(), win.height());
    let nx = ww.checked_sub(tw)? + 1;
    let ny = wh.checked_sub(th)? + 1;
    let n = tw.checked_mul(th)?;
    // n = tw·th <= tw·wh <= STRIP_CAP, so the i32 sums of dot_long cannot overflow
    // (4096 · 255² < 2³¹).
    if nx * ny > SCORE_CACHE || tw.checked_mul(wh)? > CAP.min(STRIP_CAP) || tw == 0 {
        return None;
    }
    // Buffers of the sizes used (the rest of a zeroed array would cost its zeroing).
    let mut tbuf: Vec<i16, CAP> = Vec::new();
    tbuf.resize(n, 0).ok()?;
    fill_strip(&mut tbuf, tpl, 0, tw)?;
    let t = tbuf.get(..n)?;
    let body = n - n % 16;
    dots.clear();
    dots.resize(nx * ny, 0).ok()?;
    let mut strip: Vec<i16, CAP> = Vec::new();
    strip.resize(tw * wh, 0).ok()?;
    for px in 0..nx {
        fill_strip(&mut strip, win, px, tw)?;
        let mut py = 0;
        while py + 4 <= ny {
            let s = strip.get(py * tw..)?;
            let d = dot_long4(t.get(..body)?, s, tw);
            for (k, &v) in d.iter().enumerate() {
                let at = (py + k) * tw;
                let tail = dot_tail(t.get(body..)?, strip.get(at + body..at + n)?);
                *dots.get_mut((py + k) * nx + px)? = v.wrapping_add(tail) as u32;
            }
            py += 4;
        }
        while py < ny {
            let patch = strip.get(py * tw..py * tw + n)?;
            *dots.get_mut(py * nx + px)? = dot_long(t, patch) as u32;
            py += 1;
        }
    }
    Some(())
}

/// Scalar `Σ a·b` of two short runs (the last `n % 16` pixels of [`dot_long4`]).
#[cfg(not(target_arch = "arm"))]
#[inline(never)]
fn dot_tail(a: &[i16], b: &[i16]) -> i32 {
    a.iter().zip(b).fold(0i32, |s, (&p, &q)| s.wrapping_add(i32::from(p) * i32::from(q)))
}

/// `Σ a·b` of two equally long `i16` runs of non-negative pixels (`len <= STRIP_CAP`,
/// so `i32` cannot overflow). 16 lanes: LLVM folds the pairs into `pmaddwd`.
#[cfg(not(target_arch = "arm"))]
#[inline(never)]
fn dot_long(a: &[i16], b: &[i16]) -> i32 {
    let mut lanes = [0i32; 16];
    let (ca, cb) = (a.chunks_exact(16), b.chunks_exact(16));
    let (ra, rb) = (ca.remainder(), cb.remainder());
    for (x, y) in ca.zip(cb) {
        if let (Ok(x), Ok(y)) = (<&[i16; 16]>::try_from(x), <&[i16; 16]>::try_from(y)) {
            for ((l, &p), &q) in lanes.iter_mut().zip(x).zip(y) {
                *l = l.wrapping_add(i32::from(p) * i32::from(q));
            }
        }
    }
    let tail = ra.iter().zip(rb).fold(0i32, |s, (&p, &q)| s.wrapping_add(i32::from(p) * i32::from(q)));
    lanes.iter().fold(tail, |s, &l| s.wrapping_add(l))
}

/// `l[k] += t[k]·a[k]` over 16 lanes.
#[cfg(not(target_arch = "arm"))]
#[inline(always)]
fn mac16(l: &mut [i32; 16], t: &[i16; 16], a: &[i16; 16]) {
    for ((l, &p), &q) in l.iter_mut().zip(t).zip(a) {
        *l = l.wrapping_add(i32::from(p) * i32::from(q));
    }
}

/// The four runs of `n` values of `s` starting at `0`, `step`, `2·step` and `3·step`.
#[cfg(not(target_arch = "arm"))]
#[inline(always)]
fn four_runs(s: &[i16], step: usize, n: usize) -> Option<[&[i16]; 4]> {
    Some([s.get(..n)?, s.get(step..step + n)?, s.get(2 * step..2 * step + n)?, s.get(3 * step..3 * step + n)?])
}

/// The dot products of `t` (length `n`, a multiple of 16; see [`dot_tail`]) with the
/// four runs of `s` starting at `0`, `step`, `2·step` and `3·step`: four placements of
/// one strip column, sharing each template chunk. (A remainder loop in the same
/// function stops the SLP vectoriser, so the tail is summed by the caller.)
#[cfg(not(target_arch = "arm"))]
#[inline(never)]
fn dot_long4(t: &[i16], s: &[i16], step: usize) -> [i32; 4] {
    let Some([s0, s1, s2, s3]) = four_runs(s, step, t.len()) else { return [0; 4] };
    let (mut l0, mut l1, mut l2, mut l3) = ([0i32; 16], [0i32; 16], [0i32; 16], [0i32; 16]);
    let ct = t.chunks_exact(16);
    let it = ct
        .zip(s0.chunks_exact(16))
        .zip(s1.chunks_exact(16))
        .zip(s2.chunks_exact(16))
        .zip(s3.chunks_exact(16));
    for ((((tc, a), b), c), d) in it {
        let (Ok(tc), Ok(a), Ok(b), Ok(c), Ok(d)) = (
            <&[i16; 16]>::try_from(tc),
            <&[i16; 16]>::try_from(a),
            <&[i16; 16]>::try_from(b),
            <&[i16; 16]>::try_from(c),
            <&[i16; 16]>::try_from(d),
        ) else {
            continue;
        };
        // Four separate 16-lane accumulators (one array each): this is the shape the
        // SLP vectoriser turns into eight `pmaddwd` per chunk.
        mac16(&mut l0, tc, a);
        mac16(&mut l1, tc, b);
        mac16(&mut l2, tc, c);
        mac16(&mut l3, tc, d);
    }
    let f = |l: &[i32; 16]| l.iter().fold(0i32, |s, &v| s.wrapping_add(v));
    [f(&l0), f(&l1), f(&l2), f(&l3)]
}

/// `Σ R·I` of every placement into `dots` (row-major), or `None` (then the other paths are
/// taken) when the placements or the template exceed the strips' capacities: column strips
/// on x86-64, pixel rows on 32-bit Arm (see the module docs). Exact integers either way, so
/// the same products (compared by a unit test, and x86 against the Cortex-M4 by
/// `scripts/board.sh`).
#[cfg(not(target_arch = "arm"))]
pub(super) use host_dot_products as dot_products;
#[cfg(target_arch = "arm")]
pub(super) use arm::row_dot_products as dot_products;

/// [`dot_products`] on a host: on x86-64 in the widest vectors the host runs
/// ([`dot_products_on`]), else from column strips.
#[cfg(not(target_arch = "arm"))]
pub(super) fn host_dot_products(win: &WindowView<'_>, tpl: &WindowView<'_>, dots: &mut Vec<u32, SCORE_CACHE>) -> Option<()> {
    #[cfg(target_arch = "x86_64")]
    return dot_products_on(crate::kernels::x86::path(), win, tpl, dots);
    #[cfg(not(target_arch = "x86_64"))]
    strip_dot_products(win, tpl, dots)
}

/// [`dot_products`] on the path `isa` (narrowed to what the host runs): in AVX-512 or AVX2 for
/// templates of at most [`LANES`] pixels a side, else from column strips.
#[cfg(target_arch = "x86_64")]
pub(super) fn dot_products_on(isa: Isa, win: &WindowView<'_>, tpl: &WindowView<'_>, dots: &mut Vec<u32, SCORE_CACHE>) -> Option<()> {
    if tpl.width() <= LANES && tpl.height() <= LANES {
        // SAFETY: the host runs the path (narrowed by `detected`), the functions' only
        // requirement.
        #[allow(unsafe_code)]
        match isa.min(crate::kernels::x86::detected()) {
            Isa::Avx512 => return unsafe { avx512::dot_products(win, tpl, dots) },
            Isa::Avx2 => return unsafe { avx2::dot_products(win, tpl, dots) },
            Isa::Portable => {}
        }
    }
    strip_dot_products(win, tpl, dots)
}

/// Template rows of at most this many pixels fill one AVX-512 register (or two AVX2 ones) as
/// `i16`, and at most this many rows are held widened.
#[cfg(target_arch = "x86_64")]
const LANES: usize = 32;
