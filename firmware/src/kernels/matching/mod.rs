//! Template matching (thesis 2.4): SSD, SAD, NCC and, beyond the thesis, zero-mean NCC.
//!
//! For a template `R` of `ulen x vlen` pixels and a search window `I`, each placement
//! `(x, y)` of the template's top-left pixel with the template fully inside the window
//! is scored (sums over `0 <= u < ulen`, `0 <= v < vlen`):
//!
//! * `SSD(x,y) = Σ (R(u,v) - I(x+u,y+v))²` (difference, best = minimum; Peripheral);
//! * `SAD(x,y) = Σ |R(u,v) - I(x+u,y+v)|` (difference, best = minimum);
//! * `NCC(x,y) = P/Q`, `P = Σ R(u,v)·I(x+u,y+v)`, `Q = sqrt(Σ R² · Σ I²(x+u,y+v))`
//!   (similarity, best = maximum; Foveal). This is OpenCV's `TM_CCORR_NORMED`.
//! * `ZNCC(x,y)` = NCC of the mean-free template and window patch,
//!   `(nΣRI - ΣRΣI) / sqrt((nΣR² - (ΣR)²)(nΣI² - (ΣI)²))`, `n = ulen·vlen`
//!   (option beyond the thesis: invariant to gain and offset of the illumination).
//!
//! ## How it is fast
//! All sums are exact integers. The window energies `Σ I²` (and `Σ I` for ZNCC) of every
//! placement come from running column sums, updated by one row in and one row out per
//! placement row, and a running sum along the row, so each placement costs only the
//! dot product `Σ R·I`. SSD uses `Σ R² + Σ I² - 2 Σ R·I`, so it costs the same dot
//! product. The dot products of all placements come from column strips widened to `i16`
//! (see `strip_dot_products`), in which every patch is one contiguous run; four
//! placements share each template load and LLVM turns the 16-lane `i16·i16 -> i32`
//! reduction into `pmaddwd` on baseline x86-64. Windows too large for the strips use
//! per-row `u8` dot products.
//!
//! ## Sub-pixel refinement
//! Around the best placement `s0` with neighbours `s-` and `s+` along x (then y), the
//! parabola through the three scores has its vertex at
//! `d = (s- - s+) / (2 (s- - 2 s0 + s+))`. The offset is used only when the parabola
//! opens the right way (downwards for NCC/ZNCC, upwards for SSD/SAD) and is clamped to
//! `[-0.5, 0.5]`; at the window border or for a flat neighbourhood it is 0.
//!
//! ## Zero energy
//! An NCC template with `Σ R² = 0` (or a ZNCC template with no variance) is rejected with
//! [`MatchError::ZeroEnergy`]. A placement whose window patch has zero energy (variance
//! for ZNCC) scores 0, as in OpenCV, and if no placement has energy the result is
//! [`MatchError::NoMatch`]. No score is ever NaN.

use crate::kernels::view::WindowView;
use heapless::Vec;

/// Maximum number of placements along x (window width - template width + 1) and of
/// window columns: the running-sum buffers have this fixed capacity.
pub const MAX_SEARCH_WIDTH: usize = 256;

/// Capacity, in pixels, of the buffers that pack a decimated (or otherwise strided)
/// view before matching: a 128x128 Peripheral window at 25 % is 64x64 = 4096 pixels.
pub const MAX_PACKED_PIXELS: usize = 4096;

/// Row dot products accumulate in `u32` in chunks of this many pixels:
/// `16384 · 255² < 2³²`, so no chunk can overflow.
const DOT_CHUNK: usize = 16384;

/// A matching measure of thesis 2.4 (or ZNCC beyond it).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Sum of squared differences (minimise).
    Ssd,
    /// Sum of absolute differences (minimise).
    Sad,
    /// Normalised cross-correlation (maximise), thesis form (not mean-free).
    Ncc,
    /// Zero-mean normalised cross-correlation (maximise).
    Zncc,
}

impl Method {
    /// True for similarity measures (best = maximum).
    pub fn maximises(self) -> bool {
        matches!(self, Method::Ncc | Method::Zncc)
    }
}

/// Why no match could be computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MatchError {
    /// Window or template has no pixel.
    Empty,
    /// The template is wider or taller than the window: there is no placement.
    TemplateLarger,
    /// The window is wider than [`MAX_SEARCH_WIDTH`], or a strided view does not fit
    /// [`MAX_PACKED_PIXELS`].
    TooLarge,
    /// NCC template with zero energy, or ZNCC template with zero variance.
    ZeroEnergy,
    /// Every placement has a zero-energy (NCC) or zero-variance (ZNCC) window patch.
    NoMatch,
    /// The output map slice is shorter than the number of placements.
    MapTooSmall,
}

error_messages!(MatchError {
    Empty => "the window or the template has no pixel",
    TemplateLarger => "the template is wider or taller than the window",
    TooLarge => "the window is too large for the matcher's buffers",
    ZeroEnergy => "the template is flat (no energy for NCC, no variance for ZNCC)",
    NoMatch => "every placement's window patch is flat",
    MapTooSmall => "the score map is shorter than the number of placements",
});

/// The best placement of a template in a window.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Match {
    /// Column of the template's top-left pixel, in full-resolution window pixels
    /// (decimated matches are scaled by the view's step).
    pub x: usize,
    /// Row of the template's top-left pixel, in full-resolution window pixels.
    pub y: usize,
    /// Score at the best placement (never NaN).
    pub score: f64,
    /// Sub-pixel refined column of the top-left pixel (parabola fit), window pixels.
    pub sub_x: f32,
    /// Sub-pixel refined row of the top-left pixel, window pixels.
    pub sub_y: f32,
    /// `sub_x` in frame coordinates (window origin added).
    pub frame_x: f32,
    /// `sub_y` in frame coordinates.
    pub frame_y: f32,
}

#[inline(always)]
fn dot_row(a: &[u8], b: &[u8]) -> u64 {
    let mut s = 0u64;
    for (ca, cb) in a.chunks(DOT_CHUNK).zip(b.chunks(DOT_CHUNK)) {
        let d = ca.iter().zip(cb).fold(0u32, |acc, (&x, &y)| {
            acc.wrapping_add(u32::from(u16::from(x) * u16::from(y)))
        });
        s += u64::from(d);
    }
    s
}

#[inline(always)]
fn sad_row(a: &[u8], b: &[u8]) -> u64 {
    let mut s = 0u64;
    for (ca, cb) in a.chunks(DOT_CHUNK).zip(b.chunks(DOT_CHUNK)) {
        let d = ca.iter().zip(cb).fold(0u32, |acc, (&x, &y)| {
            acc.wrapping_add(u32::from(x.abs_diff(y)))
        });
        s += u64::from(d);
    }
    s
}

/// Placements whose scores [`best_match`] keeps for the sub-pixel fit (a 40x40 window
/// with a 16x16 template has 625).
const SCORE_CACHE: usize = 1024;

/// Capacity of the lane-padded template copy used by the fast dot product.
const TPL_PAD_CAP: usize = 4096;

/// The template rearranged for [`dot_placement`]: each row is its first
/// `body = tw - tw % lanes` pixels followed, if `tw` is not a multiple of `lanes`, by a
/// `lanes`-pixel "tail" chunk holding the last `tw % lanes` pixels right-aligned after
/// zeros. The tail chunk is multiplied with the window's last `lanes` pixels under the
/// template, so every row is whole SIMD chunks and no scalar remainder loop is needed
/// (the zeros cancel the overlap). `lanes` is 16 for templates at least 16 wide, else 8.
struct PaddedTemplate {
    buf: [u8; TPL_PAD_CAP],
    row_len: usize,
    body: usize,
    lanes: usize,
}

impl PaddedTemplate {
    /// `None` when the template is narrower than 8 pixels or does not fit the buffer
    /// (the generic row-by-row dot product is used then).
    fn new(tpl: &WindowView<'_>) -> Option<Self> {
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
fn dot_placement<const N: usize>(
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
const STRIP_CAP: usize = 4096;

/// Widens `src` (`u8`) into `dst` (`i16`, same length). For runs of at least 8 pixels
/// this copies fixed 8-pixel chunks (the last one overlapping the previous, if the
/// length is not a multiple of 8), so each chunk is one load, one unpack and one store
/// instead of a call to a generic loop.
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
/// `None` (use the other paths) when the strip or the placement count exceed their
/// capacities.
fn strip_dot_products(win: &WindowView<'_>, tpl: &WindowView<'_>) -> Option<Vec<u32, SCORE_CACHE>> {
    // Small windows use small buffers: zeroing two 8 KiB arrays would cost as much as
    // the whole Foveal match.
    if tpl.width().checked_mul(win.height())? <= SMALL_STRIP_CAP {
        strip_dot_products_in::<SMALL_STRIP_CAP>(win, tpl)
    } else {
        strip_dot_products_in::<STRIP_CAP>(win, tpl)
    }
}

/// Capacity of the strip buffers for small windows (Foveal 20 x 24 = 480 pixels,
/// Peripheral 16 x 40 = 640).
const SMALL_STRIP_CAP: usize = 1024;

/// [`strip_dot_products`] with strip buffers of `CAP <= STRIP_CAP` pixels.
fn strip_dot_products_in<const CAP: usize>(
    win: &WindowView<'_>,
    tpl: &WindowView<'_>,
) -> Option<Vec<u32, SCORE_CACHE>> {
    let (tw, th, ww, wh) = (tpl.width(), tpl.height(), win.width(), win.height());
    let nx = ww.checked_sub(tw)? + 1;
    let ny = wh.checked_sub(th)? + 1;
    let n = tw.checked_mul(th)?;
    // n = tw·th <= tw·wh <= STRIP_CAP, so the i32 sums of dot_long cannot overflow
    // (4096 · 255² < 2³¹).
    if nx * ny > SCORE_CACHE || tw.checked_mul(wh)? > CAP.min(STRIP_CAP) || tw == 0 {
        return None;
    }
    let mut tbuf = [0i16; CAP];
    fill_strip(&mut tbuf, tpl, 0, tw)?;
    let t = tbuf.get(..n)?;
    let body = n - n % 16;
    let mut dots: Vec<u32, SCORE_CACHE> = Vec::new();
    dots.resize(nx * ny, 0).ok()?;
    let mut strip = [0i16; CAP];
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
    Some(dots)
}

/// Scalar `Σ a·b` of two short runs (the last `n % 16` pixels of [`dot_long4`]).
#[inline(never)]
fn dot_tail(a: &[i16], b: &[i16]) -> i32 {
    a.iter().zip(b).fold(0i32, |s, (&p, &q)| s.wrapping_add(i32::from(p) * i32::from(q)))
}

/// `Σ a·b` of two equally long `i16` runs of non-negative pixels (`len <= STRIP_CAP`,
/// so `i32` cannot overflow). 16 lanes: LLVM folds the pairs into `pmaddwd`.
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

/// [`dot_long4`] for 32-bit Arm (Cortex-M4, thesis 2.6's processors on a microcontroller):
/// 64 lanes of accumulators spill on its 13 registers, so here four scalar sums, one per
/// placement, take the template two pixels at a time, the shape LLVM's parallel-DSP pass
/// turns into `SMLAD` (two 16-bit products a cycle). Exact integers either way, so the
/// results are the same bits (checked against x86 by `scripts/board.sh`, and against
/// [`dot_long4`] by a unit test).
#[cfg(any(test, target_arch = "arm"))]
#[inline(never)]
fn dot_long4_pairs(t: &[i16], s: &[i16], step: usize) -> [i32; 4] {
    let Some([s0, s1, s2, s3]) = four_runs(s, step, t.len()) else { return [0; 4] };
    let (mut a0, mut a1, mut a2, mut a3) = (0i32, 0i32, 0i32, 0i32);
    let it = t
        .chunks_exact(2)
        .zip(s0.chunks_exact(2))
        .zip(s1.chunks_exact(2))
        .zip(s2.chunks_exact(2))
        .zip(s3.chunks_exact(2));
    let dot2 = |t: &[i16], x: &[i16]| match (t, x) {
        (&[t0, t1], &[x0, x1]) => (i32::from(t0) * i32::from(x0)).wrapping_add(i32::from(t1) * i32::from(x1)),
        _ => 0,
    };
    for ((((tc, a), b), c), d) in it {
        a0 = a0.wrapping_add(dot2(tc, a));
        a1 = a1.wrapping_add(dot2(tc, b));
        a2 = a2.wrapping_add(dot2(tc, c));
        a3 = a3.wrapping_add(dot2(tc, d));
    }
    [a0, a1, a2, a3]
}

#[cfg(target_arch = "arm")]
use dot_long4_pairs as dot_long4;

/// Template statistics that do not depend on the placement.
struct TemplateStats {
    energy: u64,
    sum: u64,
    n: u64,
}

fn template_stats(tpl: &WindowView<'_>) -> TemplateStats {
    let mut energy = 0u64;
    let mut sum = 0u64;
    for v in 0..tpl.height() {
        let r = tpl.row(v).unwrap_or(&[]);
        energy += dot_row(r, r);
        sum += r.iter().map(|&p| u64::from(p)).sum::<u64>();
    }
    TemplateStats {
        energy,
        sum,
        n: (tpl.width() * tpl.height()) as u64,
    }
}

/// Score of one placement from its integer sums (see the module formulas).
#[inline(always)]
fn score(method: Method, t: &TemplateStats, dot_or_sad: u64, e: u64, s: u64) -> Option<f64> {
    match method {
        Method::Sad => Some(dot_or_sad as f64),
        // Σ(R-I)² = ΣR² + ΣI² - 2ΣRI >= 0 exactly in integers.
        Method::Ssd => Some((t.energy + e).saturating_sub(2 * dot_or_sad) as f64),
        Method::Ncc => {
            if e == 0 {
                return None;
            }
            let q = libm::sqrt(t.energy as f64 * e as f64);
            Some((dot_or_sad as f64 / q).min(1.0))
        }
        Method::Zncc => {
            let n = i128::from(t.n);
            let num = n * i128::from(dot_or_sad) - i128::from(t.sum) * i128::from(s);
            let vt = n * i128::from(t.energy) - i128::from(t.sum) * i128::from(t.sum);
            let vw = n * i128::from(e) - i128::from(s) * i128::from(s);
            if vw <= 0 || vt <= 0 {
                return None;
            }
            let q = libm::sqrt(vt as f64 * vw as f64);
            Some((num as f64 / q).clamp(-1.0, 1.0))
        }
    }
}

/// Validates sizes and returns `(placements_x, placements_y)`.
fn placements(win: &WindowView<'_>, tpl: &WindowView<'_>) -> Result<(usize, usize), MatchError> {
    if win.is_empty() || tpl.is_empty() {
        return Err(MatchError::Empty);
    }
    if tpl.width() > win.width() || tpl.height() > win.height() {
        return Err(MatchError::TemplateLarger);
    }
    if win.width() > MAX_SEARCH_WIDTH {
        return Err(MatchError::TooLarge);
    }
    Ok((
        win.width() - tpl.width() + 1,
        win.height() - tpl.height() + 1,
    ))
}

/// Visits every placement in raster order with its score (`None` = no energy) over two
/// full-resolution (step 1) views. The visitor sees placement `(px, py)`.
fn for_each_score(
    method: Method,
    win: &WindowView<'_>,
    tpl: &WindowView<'_>,
    visit: impl FnMut(usize, usize, Option<f64>),
) -> Result<(), MatchError> {
    // A column of `th` squared pixels fits `u32` while th·255² < 2³² (th <= 66051); the
    // narrow columns halve the running-sum work.
    if tpl.height() <= 66_051 {
        for_each_score_in::<u32>(method, win, tpl, visit)
    } else {
        for_each_score_in::<u64>(method, win, tpl, visit)
    }
}

/// An exact column-sum accumulator (`u32` for columns short enough, else `u64`).
trait ColSum: Copy + Default {
    /// `self + add - sub`, exact when the true result is representable.
    fn update(self, add: u32, sub: u32) -> Self;
    fn wide(self) -> u64;
}

impl ColSum for u32 {
    #[inline(always)]
    fn update(self, add: u32, sub: u32) -> Self {
        self.wrapping_add(add).wrapping_sub(sub)
    }
    #[inline(always)]
    fn wide(self) -> u64 {
        u64::from(self)
    }
}

impl ColSum for u64 {
    #[inline(always)]
    fn update(self, add: u32, sub: u32) -> Self {
        self.wrapping_add(u64::from(add)).wrapping_sub(u64::from(sub))
    }
    #[inline(always)]
    fn wide(self) -> u64 {
        self
    }
}

/// Adds row `add` and removes row `sub` (if any) from the column sums of `I²` (and of
/// `I` when `sums` is set): one fused pass per placement row.
#[inline(never)]
fn update_cols<C: ColSum>(sq: &mut [C], sum: &mut [C], add: &[u8], sub: Option<&[u8]>, sums: bool) {
    let sq2 = |p: u8| u32::from(p) * u32::from(p);
    match sub {
        Some(sub) => {
            for ((q, &a), &b) in sq.iter_mut().zip(add).zip(sub) {
                *q = q.update(sq2(a), sq2(b));
            }
            if sums {
                for ((s, &a), &b) in sum.iter_mut().zip(add).zip(sub) {
                    *s = s.update(u32::from(a), u32::from(b));
                }
            }
        }
        None => {
            for (q, &a) in sq.iter_mut().zip(add) {
                *q = q.update(sq2(a), 0);
            }
            if sums {
                for (s, &a) in sum.iter_mut().zip(add) {
                    *s = s.update(u32::from(a), 0);
                }
            }
        }
    }
}

fn for_each_score_in<C: ColSum>(
    method: Method,
    win: &WindowView<'_>,
    tpl: &WindowView<'_>,
    mut visit: impl FnMut(usize, usize, Option<f64>),
) -> Result<(), MatchError> {
    let (nx, ny) = placements(win, tpl)?;
    let (tw, th, ww) = (tpl.width(), tpl.height(), win.width());
    let t = template_stats(tpl);
    match method {
        Method::Ncc if t.energy == 0 => return Err(MatchError::ZeroEnergy),
        Method::Zncc if (t.n as u128) * (t.energy as u128) == (t.sum as u128).pow(2) => {
            return Err(MatchError::ZeroEnergy)
        }
        _ => {}
    }
    let needs_energy = method != Method::Sad;
    let strip_dots = if needs_energy { strip_dot_products(win, tpl) } else { None };
    let padded = if needs_energy && strip_dots.is_none() { PaddedTemplate::new(tpl) } else { None };
    // Column sums of I² and I over the `th` rows of the current placement row.
    let mut col_sq: Vec<C, MAX_SEARCH_WIDTH> = Vec::new();
    let mut col_sum: Vec<C, MAX_SEARCH_WIDTH> = Vec::new();
    let sums = method == Method::Zncc;
    let mut acc: Vec<u64, MAX_SEARCH_WIDTH> = Vec::new();
    // Capacity checked in `placements` (ww <= MAX_SEARCH_WIDTH, nx <= ww).
    let _ = col_sq.resize(ww, C::default());
    let _ = col_sum.resize(ww, C::default());
    let _ = acc.resize(nx, 0);
    if needs_energy {
        for v in 0..th {
            update_cols(&mut col_sq, &mut col_sum, win.row(v).unwrap_or(&[]), None, sums);
        }
    }
    for py in 0..ny {
        if needs_energy && py > 0 {
            let (add, sub) = (win.row(py + th - 1).unwrap_or(&[]), win.row(py - 1));
            update_cols(&mut col_sq, &mut col_sum, add, sub, sums);
        }
        if let Some(d) = strip_dots.as_ref() {
            for (a, &v) in acc.iter_mut().zip(d.iter().skip(py * nx)) {
                *a = u64::from(v);
            }
        } else if let Some(pt) = padded.as_ref() {
            for (px, a) in acc.iter_mut().enumerate() {
                *a = if pt.lanes == 16 {
                    dot_placement::<16>(pt, win, tw, th, px, py)
                } else {
                    dot_placement::<8>(pt, win, tw, th, px, py)
                };
            }
        } else {
            acc.iter_mut().for_each(|a| *a = 0);
        }
        for v in (0..th).filter(|_| padded.is_none() && strip_dots.is_none()) {
            let trow = tpl.row(v).unwrap_or(&[]);
            let wrow = win.row(py + v).unwrap_or(&[]);
            if method == Method::Sad {
                for (a, w) in acc.iter_mut().zip(wrow.windows(tw)) {
                    *a += sad_row(trow, w);
                }
            } else {
                for (a, w) in acc.iter_mut().zip(wrow.windows(tw)) {
                    *a += dot_row(trow, w);
                }
            }
        }
        // Running sums along the row of the column sums give each placement's energy.
        let col = |c: &[C], i: usize| c.get(i).map_or(0, |v| v.wide());
        let mut e: u64 = col_sq.iter().take(tw).map(|v| v.wide()).sum();
        let mut s: u64 = col_sum.iter().take(tw).map(|v| v.wide()).sum();
        for (px, &a) in acc.iter().enumerate() {
            if px > 0 && needs_energy {
                e = e + col(&col_sq, px + tw - 1) - col(&col_sq, px - 1);
                if sums {
                    s = s + col(&col_sum, px + tw - 1) - col(&col_sum, px - 1);
                }
            }
            visit(px, py, score(method, &t, a, e, s));
        }
    }
    Ok(())
}

/// Score of the single placement `(px, py)` computed directly (used for the sub-pixel
/// neighbours of the peak); `None` outside or without energy.
fn score_at(
    method: Method,
    win: &WindowView<'_>,
    tpl: &WindowView<'_>,
    px: usize,
    py: usize,
) -> Option<f64> {
    let (tw, th) = (tpl.width(), tpl.height());
    if px + tw > win.width() || py + th > win.height() {
        return None;
    }
    let t = template_stats(tpl);
    let (mut a, mut e, mut s) = (0u64, 0u64, 0u64);
    for v in 0..th {
        let trow = tpl.row(v)?;
        let w = win.row(py + v)?.get(px..px + tw)?;
        a += if method == Method::Sad {
            sad_row(trow, w)
        } else {
            dot_row(trow, w)
        };
        e += dot_row(w, w);
        s += w.iter().map(|&p| u64::from(p)).sum::<u64>();
    }
    score(method, &t, a, e, s)
}

/// Writes the score of every placement, row-major with `placements_x` columns, into
/// `out` (placements without energy score 0, like OpenCV) and returns
/// `(placements_x, placements_y)`.
///
/// Both views must be full resolution; a strided view is packed first (see
/// [`MAX_PACKED_PIXELS`]) and the map is then in decimated pixels.
pub fn score_map(
    method: Method,
    win: &WindowView<'_>,
    tpl: &WindowView<'_>,
    out: &mut [f64],
) -> Result<(usize, usize), MatchError> {
    with_packed(win, tpl, |win, tpl| {
        let (nx, ny) = placements(win, tpl)?;
        let out = out.get_mut(..nx * ny).ok_or(MatchError::MapTooSmall)?;
        for_each_score(method, win, tpl, |px, py, s| {
            if let Some(o) = out.get_mut(py * nx + px) {
                *o = s.unwrap_or(0.0);
            }
        })?;
        Ok((nx, ny))
    })
}

/// Runs `f` on step-1 versions of both views, packing strided views into fixed buffers.
fn with_packed<R>(
    win: &WindowView<'_>,
    tpl: &WindowView<'_>,
    f: impl FnOnce(&WindowView<'_>, &WindowView<'_>) -> Result<R, MatchError>,
) -> Result<R, MatchError> {
    if win.step() == 1 && tpl.step() == 1 {
        return f(win, tpl);
    }
    let mut wbuf = [0u8; MAX_PACKED_PIXELS];
    let mut tbuf = [0u8; MAX_PACKED_PIXELS];
    let pw = win.pack_into(&mut wbuf).ok_or(MatchError::TooLarge)?;
    let pt = tpl.pack_into(&mut tbuf).ok_or(MatchError::TooLarge)?;
    f(&pw, &pt)
}

/// Parabola vertex offset through `(−1, l), (0, c), (1, r)`, or 0 when the parabola
/// does not open towards the optimum or a neighbour is missing.
fn parabola(l: Option<f64>, c: f64, r: Option<f64>, maximise: bool) -> f64 {
    let (Some(l), Some(r)) = (l, r) else {
        return 0.0;
    };
    let curv = l - 2.0 * c + r;
    let opens_right = if maximise { curv < 0.0 } else { curv > 0.0 };
    if !opens_right {
        return 0.0;
    }
    let d = (l - r) / (2.0 * curv);
    if d.is_finite() {
        d.clamp(-0.5, 0.5)
    } else {
        0.0
    }
}

/// The best placement of `tpl` in `win` under `method` (minimum SSD/SAD, maximum
/// NCC/ZNCC; ties go to the first placement in raster order, as `cv::minMaxLoc`), with
/// its score and a parabola-fit sub-pixel position (see the module docs).
///
/// Decimated views are matched at their resolution and the position is scaled back by
/// the window's step, so `best_match(m, &w.decimated(), &t.decimated())` is the 25 %
/// variant of the Peripheral window (also available as [`best_match_decimated`]).
pub fn best_match(
    method: Method,
    win: &WindowView<'_>,
    tpl: &WindowView<'_>,
) -> Result<Match, MatchError> {
    let step = win.step();
    let (origin_x, origin_y) = win.origin();
    with_packed(win, tpl, |win, tpl| {
        let maximise = method.maximises();
        let mut best: Option<(usize, usize, f64)> = None;
        // Scores kept for the sub-pixel fit (no-energy placements as -inf); maps larger
        // than the cache recompute the four neighbours instead.
        let nx = win.width().saturating_sub(tpl.width()) + 1;
        let mut cache: Vec<f64, SCORE_CACHE> = Vec::new();
        let mut cached = true;
        for_each_score(method, win, tpl, |px, py, s| {
            if cached {
                cached = cache.push(s.unwrap_or(f64::NEG_INFINITY)).is_ok();
            }
            if let Some(s) = s {
                let better = match best {
                    None => true,
                    Some((_, _, b)) => {
                        if maximise {
                            s > b
                        } else {
                            s < b
                        }
                    }
                };
                if better {
                    best = Some((px, py, s));
                }
            }
        })?;
        let (bx, by, bs) = best.ok_or(MatchError::NoMatch)?;
        let at = |x: Option<usize>, y: Option<usize>| {
            let (x, y) = (x?, y?);
            if !cached {
                return score_at(method, win, tpl, x, y);
            }
            if x >= nx {
                return None;
            }
            cache.get(y * nx + x).copied().filter(|v| v.is_finite())
        };
        let dx = parabola(
            at(bx.checked_sub(1), Some(by)),
            bs,
            at(Some(bx + 1), Some(by)),
            maximise,
        );
        let dy = parabola(
            at(Some(bx), by.checked_sub(1)),
            bs,
            at(Some(bx), Some(by + 1)),
            maximise,
        );
        let sub_x = ((bx as f64 + dx) * step as f64) as f32;
        let sub_y = ((by as f64 + dy) * step as f64) as f32;
        Ok(Match {
            x: bx * step,
            y: by * step,
            score: bs,
            sub_x,
            sub_y,
            frame_x: origin_x as f32 + sub_x,
            frame_y: origin_y as f32 + sub_y,
        })
    })
}

/// The 25 %-resolution match of the Peripheral window (thesis 2.3): both views are
/// decimated (every other pixel of every other row) and the result is in full-resolution
/// window pixels.
pub fn best_match_decimated(
    method: Method,
    win: &WindowView<'_>,
    tpl: &WindowView<'_>,
) -> Result<Match, MatchError> {
    best_match(method, &win.decimated(), &tpl.decimated())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_arm_pairwise_dot_products_equal_the_lane_ones() {
        // Pixels from a fixed LCG; template lengths multiples of 16 as the caller passes.
        let mut x = 12345u32;
        let mut px = || {
            x = x.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (x >> 24) as i16
        };
        for (n, step) in [(16, 16), (400, 20), (256, 16), (4096, 64)] {
            let t: std::vec::Vec<i16> = (0..n).map(|_| px()).collect();
            let s: std::vec::Vec<i16> = (0..n + 3 * step).map(|_| px()).collect();
            let want: std::vec::Vec<i32> = (0..4)
                .map(|k| t.iter().zip(&s[k * step..]).map(|(&a, &b)| i32::from(a) * i32::from(b)).sum())
                .collect();
            assert_eq!(dot_long4_pairs(&t, &s, step).to_vec(), want, "n {n}");
            #[cfg(not(target_arch = "arm"))]
            assert_eq!(dot_long4(&t, &s, step).to_vec(), want, "n {n}");
        }
    }

    fn v<'a>(d: &'a [u8], w: usize, h: usize) -> WindowView<'a> {
        WindowView::packed(d, w, h).unwrap()
    }

    // Window 3x2 = [1 2 3; 4 5 6], template 2x1 = [1 2]. Placements 2x2.
    const W: [u8; 6] = [1, 2, 3, 4, 5, 6];
    const T: [u8; 2] = [1, 2];

    #[test]
    fn hand_computed_maps() {
        let (w, t) = (v(&W, 3, 2), v(&T, 2, 1));
        let mut m = [0f64; 4];
        // SSD: (0,0): 0; (1,0): (1-2)²+(2-3)²=2; (0,1): 9+9=18; (1,1): 16+16=32.
        assert_eq!(score_map(Method::Ssd, &w, &t, &mut m), Ok((2, 2)));
        assert_eq!(m, [0.0, 2.0, 18.0, 32.0]);
        // SAD: 0, 2, 6, 8.
        score_map(Method::Sad, &w, &t, &mut m).unwrap();
        assert_eq!(m, [0.0, 2.0, 6.0, 8.0]);
        // NCC (0,1): P = 4+10 = 14, Q = sqrt(5 * 41).
        score_map(Method::Ncc, &w, &t, &mut m).unwrap();
        assert!((m[0] - 1.0).abs() < 1e-12);
        assert!((m[1] - 8.0 / (5.0f64 * 13.0).sqrt()).abs() < 1e-12);
        assert!((m[2] - 14.0 / (5.0f64 * 41.0).sqrt()).abs() < 1e-12);
        // ZNCC of two increasing pairs is exactly 1 everywhere.
        score_map(Method::Zncc, &w, &t, &mut m).unwrap();
        assert!(m.iter().all(|s| (s - 1.0).abs() < 1e-12));
        let b = best_match(Method::Ssd, &w, &t).unwrap();
        assert_eq!((b.x, b.y, b.score), (0, 0, 0.0));
    }

    #[test]
    fn zero_energy_is_typed() {
        let z = [0u8; 6];
        let (w, t) = (v(&W, 3, 2), v(&T, 2, 1));
        assert_eq!(
            best_match(Method::Ncc, &w, &v(&z, 2, 1)),
            Err(MatchError::ZeroEnergy)
        );
        assert_eq!(
            best_match(Method::Ncc, &v(&z, 3, 2), &t),
            Err(MatchError::NoMatch)
        );
        let flat = [7u8; 2];
        assert_eq!(
            best_match(Method::Zncc, &w, &v(&flat, 2, 1)),
            Err(MatchError::ZeroEnergy)
        );
        // A zero window is still fine for difference measures.
        assert_eq!(
            best_match(Method::Ssd, &v(&z, 3, 2), &t).unwrap().score,
            5.0
        );
        assert_eq!(
            best_match(Method::Ssd, &t, &w),
            Err(MatchError::TemplateLarger)
        );
        assert_eq!(
            best_match(Method::Ssd, &v(&[], 0, 0), &t),
            Err(MatchError::Empty)
        );
    }

    #[test]
    fn errors_read_as_sentences() {
        use std::string::ToString;
        // Every variant has its own message (a copied line would repeat one).
        let all = [
            MatchError::Empty,
            MatchError::TemplateLarger,
            MatchError::TooLarge,
            MatchError::ZeroEnergy,
            MatchError::NoMatch,
            MatchError::MapTooSmall,
        ];
        let texts: std::vec::Vec<_> = all.iter().map(ToString::to_string).collect();
        assert!(texts.iter().all(|t| !t.is_empty() && !t.contains("Error")));
        let distinct: std::collections::BTreeSet<_> = texts.iter().collect();
        assert_eq!(distinct.len(), all.len());
        assert_eq!(MatchError::ZeroEnergy.to_string(), "the template is flat (no energy for NCC, no variance for ZNCC)");
    }

    #[test]
    fn parabola_vertex() {
        // Scores 1, 3, 2 along x: vertex at (1-2)/(2(1-6+2)) = 1/6.
        assert!((parabola(Some(1.0), 3.0, Some(2.0), true) - 1.0 / 6.0).abs() < 1e-12);
        assert_eq!(parabola(Some(1.0), 3.0, Some(2.0), false), 0.0);
        assert_eq!(parabola(None, 3.0, Some(2.0), true), 0.0);
        assert_eq!(parabola(Some(3.0), 3.0, Some(3.0), true), 0.0);
    }

    #[test]
    fn subpixel_of_symmetric_peak_is_between_placements() {
        // A bright bar at columns 2 and 3 and a template that is one column of the bar:
        // placements 1 and 2 tie (first wins), SSD at 0, 1, 2 is 2c, c, c, so the
        // parabola vertex is at (2c - c) / (2 (2c - 2c + c)) = +0.5: exactly between.
        let mut d = [10u8; 6 * 3];
        for y in 0..3 {
            d[y * 6 + 2] = 200;
            d[y * 6 + 3] = 200;
        }
        let t = [10u8, 200, 10, 10, 200, 10, 10, 200, 10];
        let m = best_match(Method::Ssd, &v(&d, 6, 3), &v(&t, 3, 3)).unwrap();
        assert_eq!((m.x, m.y), (1, 0));
        assert_eq!(m.sub_x, 1.5);
    }

    #[test]
    fn decimated_scales_back() {
        // 8x8 window with a single bright 2x2 block at (4,4); template 4x4 with the block
        // at (2,2): at 25 % the match is at decimated (1,1) = full (2,2).
        let mut w = [0u8; 64];
        let mut t = [0u8; 16];
        for (y, x) in [(4, 4), (4, 5), (5, 4), (5, 5)] {
            w[y * 8 + x] = 255;
        }
        for (y, x) in [(2, 2), (2, 3), (3, 2), (3, 3)] {
            t[y * 4 + x] = 255;
        }
        let m = best_match_decimated(Method::Ssd, &v(&w, 8, 8), &v(&t, 4, 4)).unwrap();
        assert_eq!((m.x, m.y, m.score), (2, 2, 0.0));
        let full = best_match(Method::Ncc, &v(&w, 8, 8), &v(&t, 4, 4)).unwrap();
        assert_eq!((full.x, full.y), (2, 2));
        assert!((full.score - 1.0).abs() < 1e-12);
    }
}
