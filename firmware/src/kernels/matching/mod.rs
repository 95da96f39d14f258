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
//! ## Zero energy
//! An NCC template with `Σ R² = 0` (or a ZNCC template with no variance) is rejected with
//! [`MatchError::ZeroEnergy`]. A placement whose window patch has zero energy (variance
//! for ZNCC) scores 0, as in OpenCV, and if no placement has energy the result is
//! [`MatchError::NoMatch`]. No score is ever NaN.
//!
//! [`best_match`] refines the best placement to sub-pixel accuracy with a parabola through its
//! neighbours' scores (`subpixel.rs`). The dot products that dominate the cost are in `dot.rs`
//! (how they are fast), the scores from running sums in `scores.rs`. Wide windows have two
//! searches of bounded cost: [`best_match_pyramid`] around a tracker's prediction, and
//! [`best_match_candidates`] (`candidates.rs`) where the object may be anywhere.

mod blocks;
mod candidates;
mod dot;
mod elimination;
mod scores;
mod subpixel;
#[cfg(test)]
mod tests;

use crate::kernels::view::WindowView;
use heapless::Vec;
pub use blocks::blocks_matching;
pub use candidates::{best_match_candidates, CANDIDATES, CANDIDATES_FROM};
use elimination::search;
use scores::{for_each_score, placements, sums_at, Ranked, Scorer, Sums};
pub(crate) use subpixel::parabola;

/// Maximum number of placements along x (window width - template width + 1) and of
/// window columns: the running-sum buffers have this fixed capacity.
pub const MAX_SEARCH_WIDTH: usize = 256;

/// Capacity, in pixels, of the buffers that pack a decimated (or otherwise strided)
/// view before matching: a 128x128 Peripheral window at 25 % is 64x64 = 4096 pixels.
pub const MAX_PACKED_PIXELS: usize = 4096;

/// Placements whose dot products are computed ahead in one pass (a 40x40 window with a 16x16
/// template has 625).
const SCORE_CACHE: usize = 1024;

/// Placements whose sums [`best_match`] keeps for the sub-pixel fit: the Foveal window's 25
/// (20x20 in 24x24), the pyramid's 9x9 coarse map and its joined fine ranges (11x6), any map
/// up to 81. A larger map (the Peripheral's 625) recomputes the best placement's four
/// neighbours instead, the same exact sums: 1.9 KiB of stack, not 24.
const SUMS_CACHE: usize = 81;

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
    /// A full-resolution match ([`best_match_full`]) was given a strided view.
    Strided,
}

error_messages!(MatchError {
    Empty => "the window or the template has no pixel",
    TemplateLarger => "the template is wider or taller than the window",
    TooLarge => "the window is too large for the matcher's buffers",
    ZeroEnergy => "the template is flat (no energy for NCC, no variance for ZNCC)",
    NoMatch => "every placement's window patch is flat",
    MapTooSmall => "the score map is shorter than the number of placements",
    Strided => "the window or the template is not at full resolution (decimated)",
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
        let scorer = Scorer::new(method, tpl)?;
        for_each_score(&scorer, win, tpl, |px, py, x| {
            if let Some(o) = out.get_mut(py * nx + px) {
                *o = scorer.score(&x).unwrap_or(0.0);
            }
        })?;
        Ok((nx, ny))
    })
}

/// The score of the one placement `(px, py)` of `tpl` in `win` (both full resolution), as
/// [`best_match`] scores it (the same exact sums), without a search's setup: a tracker
/// measuring a template where it expects it. [`MatchError::TemplateLarger`] where the
/// template does not fit there, [`MatchError::NoMatch`] on a flat patch (as `best_match`).
pub fn score_at(method: Method, win: &WindowView<'_>, tpl: &WindowView<'_>, (px, py): (usize, usize)) -> Result<f64, MatchError> {
    if win.step() != 1 || tpl.step() != 1 {
        return Err(MatchError::Strided);
    }
    let scorer = Scorer::new(method, tpl)?;
    let sums = sums_at(method, win, tpl, px, py).ok_or(MatchError::TemplateLarger)?;
    scorer.score(&sums).ok_or(MatchError::NoMatch)
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
    packed(win, tpl, f)
}

/// [`with_packed`]'s strided case, in a frame of its own: its 8 KiB of buffers are on the
/// stack only while a strided view is matched.
#[inline(never)]
fn packed<R>(
    win: &WindowView<'_>,
    tpl: &WindowView<'_>,
    f: impl FnOnce(&WindowView<'_>, &WindowView<'_>) -> Result<R, MatchError>,
) -> Result<R, MatchError> {
    // Only the pixels used are zeroed before packing (zeroing both 4 KiB arrays cost as much
    // as the 25 % match itself).
    let (mut wbuf, mut tbuf) = (Vec::<u8, MAX_PACKED_PIXELS>::new(), Vec::<u8, MAX_PACKED_PIXELS>::new());
    let size = |v: &WindowView<'_>| v.width().checked_mul(v.height()).ok_or(MatchError::TooLarge);
    wbuf.resize(size(win)?, 0).map_err(|_| MatchError::TooLarge)?;
    tbuf.resize(size(tpl)?, 0).map_err(|_| MatchError::TooLarge)?;
    let pw = win.pack_into(&mut wbuf).ok_or(MatchError::TooLarge)?;
    let pt = tpl.pack_into(&mut tbuf).ok_or(MatchError::TooLarge)?;
    f(&pw, &pt)
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
    with_packed(win, tpl, |packed_win, packed_tpl| search_packed(method, win, packed_win, packed_tpl))
}

/// [`best_match`] for full-resolution views only ([`MatchError::Strided`] otherwise), without
/// the packing of strided views: a caller that never matches one (the Foveal, whose windows
/// are full resolution) carries no packing buffers on its stack (8 KiB, which the NCC
/// master's image in 64 KiB has no room for).
pub fn best_match_full(method: Method, win: &WindowView<'_>, tpl: &WindowView<'_>) -> Result<Match, MatchError> {
    if win.step() != 1 || tpl.step() != 1 {
        return Err(MatchError::Strided);
    }
    search_packed(method, win, win, tpl)
}

/// [`best_match`] over the step-1 views `win` and `tpl` (`view`'s pixels, packed if it is
/// strided): the position is scaled back by `view`'s step and put in its frame.
fn search_packed(method: Method, view: &WindowView<'_>, win: &WindowView<'_>, tpl: &WindowView<'_>) -> Result<Match, MatchError> {
    let step = view.step();
    let (origin_x, origin_y) = view.origin();
    let maximise = method.maximises();
    let (nx, ny) = placements(win, tpl)?;
    let scorer = Scorer::new(method, tpl)?;
    // Placements are ranked by their sums (exactly, see `Scorer::better`); only the best
    // and its neighbours get a score. The sums are kept for the sub-pixel fit; maps
    // larger than the cache recompute the four neighbours instead. SSD skips the
    // placements its bound excludes (`elimination.rs`) and recomputes the neighbours.
    let mut cache: Vec<Sums, SUMS_CACHE> = Vec::new();
    let eliminated = match method {
        Method::Ssd => search(win, tpl, (nx, ny), |x, y| sums_at(method, win, tpl, x, y), |x| scorer.ssd(x)),
        _ => None,
    };
    let (best, cached) = match eliminated {
        Some(found) => (found, false),
        None => rank_all(&scorer, win, tpl, &mut cache)?,
    };
    let (bx, by, bsums) = best.ok_or(MatchError::NoMatch)?;
    let bs = scorer.score(&bsums).ok_or(MatchError::NoMatch)?;
    let at = |x: Option<usize>, y: Option<usize>| {
        let (x, y) = (x?, y?);
        if !cached {
            return scorer.score(&sums_at(method, win, tpl, x, y)?);
        }
        if x >= nx {
            return None;
        }
        scorer.score(cache.get(y * nx + x)?)
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
}

/// Windows with more placements than this are searched coarse to fine by
/// [`best_match_pyramid`]: a 20x20 template's in windows of 28x28 (81) and more, where the
/// full search's cost passes what the coarse and fine searches cost together.
pub const PYRAMID_FROM: usize = 64;

/// Full-resolution placements searched on each side of the coarse match's two.
const FINE_REACH: usize = 2;

/// The coarse match and the window's centre at most this many placements apart (a side) are
/// searched as one range: 8x8 placements at most instead of two of 6x6.
const FINE_JOIN: usize = 3;

/// Capacity of [`best_match_pyramid`]'s half-resolution window: a 64x64 window (the adapting
/// Foveal's widest is 52x52); a larger window is searched in full.
const HALF_PIXELS: usize = 1024;

/// Capacity of [`best_match_pyramid`]'s half-resolution template: a 32x32 template's (the
/// largest a processor cuts); a larger one is searched in full.
const HALF_TEMPLATE_PIXELS: usize = 256;

/// [`best_match`] with a bounded cost (beyond the thesis, issue 21): a window with more than
/// [`PYRAMID_FROM`] placements is searched at half resolution first (window and template
/// halved), then at full resolution within `FINE_REACH` (2) px of the two placements the
/// coarse one stands for, and as far around the window's centre, where a tracker's
/// prediction puts the target (a repeating texture's near-copy can win the coarse search);
/// the better of the two fine matches (the centre's on a tie), or one search over both where
/// that costs no more placements (the two close together, or side by side). A 20x20
/// template in a 52x52 window costs 289 placements of 100 pixels and at most 72 of 400
/// instead of 1,089 of 400; in a 28x28 window 25 of 100 and about 40 of 400 instead of 81
/// of 400. The result is in `win`'s pixels, as [`best_match`]'s; a smaller
/// window (or one too large to halve) is [`best_match_full`] itself (full-resolution views
/// only, as the Foveal's).
pub fn best_match_pyramid(method: Method, win: &WindowView<'_>, tpl: &WindowView<'_>) -> Result<Match, MatchError> {
    let (nx, ny) = placements(win, tpl)?;
    // Only the halves' pixels are zeroed before they are written (not the whole buffers).
    let (mut wbuf, mut tbuf) = (Vec::<u8, HALF_PIXELS>::new(), Vec::<u8, HALF_TEMPLATE_PIXELS>::new());
    let halves = (nx * ny > PYRAMID_FROM).then(|| Some((halve(win, &mut wbuf)?, halve(tpl, &mut tbuf)?))).flatten();
    let Some((half_win, half_tpl)) = halves else { return best_match_full(method, win, tpl) };
    let coarse = best_match_full(method, &half_win, &half_tpl)?;
    // A coarse placement stands for full-resolution `2c` and `2c + 1`. The two ranges are
    // searched as one where that costs no more placements (close together, or side by side):
    // one search's setup instead of two.
    let (centre, found) = (((nx - 1) / 2, (ny - 1) / 2), (2 * coarse.x, 2 * coarse.y));
    let (from, to) = ((centre.0.min(found.0), centre.1.min(found.1)), (centre.0.max(found.0) + 1, centre.1.max(found.1) + 1));
    let count = |from, to| near_range(from, to, FINE_REACH, (nx, ny)).count();
    let one = |p: (usize, usize)| count(p, (p.0 + 1, p.1 + 1));
    if (to.0 - from.0 <= FINE_JOIN && to.1 - from.1 <= FINE_JOIN) || count(from, to) <= one(centre) + one(found) {
        return best_match_near(method, win, tpl, from, to, FINE_REACH);
    }
    let fine = |(x, y): (usize, usize)| best_match_near(method, win, tpl, (x, y), (x + 1, y + 1), FINE_REACH);
    match (fine(centre), fine(found)) {
        (Ok(c), Ok(f)) => Ok(if (method.maximises() && f.score > c.score) || (!method.maximises() && f.score < c.score) { f } else { c }),
        (Ok(m), Err(_)) | (Err(_), Ok(m)) => Ok(m),
        (Err(e), Err(_)) => Err(e),
    }
}

/// The placements from `from - reach` to `to + reach` (top-left pixels, inclusive) clipped
/// to the `(nx, ny)` placements of a window.
#[derive(Clone, Copy)]
struct NearRange {
    x: (usize, usize),
    y: (usize, usize),
}

impl NearRange {
    /// How many placements the range holds.
    fn count(self) -> usize {
        (self.x.1 - self.x.0 + 1) * (self.y.1 - self.y.0 + 1)
    }
}

/// [`NearRange`] of `from`, `to` and `reach` in a window of `(nx, ny)` placements (both at least 1).
fn near_range(from: (usize, usize), to: (usize, usize), reach: usize, (nx, ny): (usize, usize)) -> NearRange {
    let range = |lo: usize, hi: usize, n: usize| {
        let (lo, hi) = (lo.saturating_sub(reach).min(n - 1), hi.saturating_add(reach).min(n - 1));
        (lo.min(hi), hi)
    };
    NearRange { x: range(from.0, to.0, nx), y: range(from.1, to.1, ny) }
}

/// [`best_match`] over the placements from `from - reach` to `to + reach` (top-left pixels,
/// inclusive, clipped to the window's placements), in `win`'s pixels: a search around where
/// the template is expected. A best placement on the range's edge is fitted with the
/// neighbours inside it only.
pub fn best_match_near(
    method: Method,
    win: &WindowView<'_>,
    tpl: &WindowView<'_>,
    from: (usize, usize),
    to: (usize, usize),
    reach: usize,
) -> Result<Match, MatchError> {
    let NearRange { x: (x0, x1), y: (y0, y1) } = near_range(from, to, reach, placements(win, tpl)?);
    let sub = win.sub(x0, y0, x1 - x0 + tpl.width(), y1 - y0 + tpl.height()).ok_or(MatchError::TooLarge)?;
    let m = best_match_full(method, &sub, tpl)?;
    Ok(Match { x: m.x + x0, y: m.y + y0, sub_x: m.sub_x + x0 as f32, sub_y: m.sub_y + y0 as f32, ..m })
}

/// `view` (full resolution) at half resolution in `buf`, each pixel the rounded mean of a
/// 2x2 block: a pyramid level, which unlike every other pixel does not alias texture finer
/// than 2 px into false matches. `None` when it has no pixel or does not fit `buf`.
fn halve<'b, const N: usize>(view: &WindowView<'_>, buf: &'b mut Vec<u8, N>) -> Option<WindowView<'b>> {
    let (w, h) = (view.width() / 2, view.height() / 2);
    if w == 0 || h == 0 {
        return None;
    }
    buf.clear();
    buf.resize(w.checked_mul(h)?, 0).ok()?;
    let out = &mut buf[..];
    // Two output pixels from a word of each row: its pixel pairs' sums as 16-bit halves
    // (`UXTB16` on the M4), at most 4·255 + 2, so no half carries into the other.
    let word = |c: &[u8]| <[u8; 4]>::try_from(c).map_or(0, u32::from_le_bytes);
    let pairs = |x: u32| (x & 0x00ff_00ff) + ((x >> 8) & 0x00ff_00ff);
    for (j, dst) in out.chunks_exact_mut(w).enumerate() {
        let (a, b) = (view.row(2 * j)?, view.row(2 * j + 1)?);
        let (ca, cb, cd) = (a.chunks_exact(4), b.chunks_exact(4), dst.chunks_exact_mut(2));
        let last = (ca.remainder(), cb.remainder());
        for ((a, b), d) in ca.zip(cb).zip(cd) {
            let s = pairs(word(a)) + pairs(word(b)) + 0x0002_0002;
            if let [d0, d1] = d {
                (*d0, *d1) = ((s >> 2) as u8, (s >> 18) as u8);
            }
        }
        // An odd width's last pixel.
        if let (&[a0, a1, ..], &[b0, b1, ..], Some(d)) = (last.0, last.1, (w % 2 == 1).then(|| dst.last_mut()).flatten()) {
            *d = ((u16::from(a0) + u16::from(a1) + u16::from(b0) + u16::from(b1) + 2) / 4) as u8;
        }
    }
    WindowView::packed(out, w, h).ok()
}

/// [`rank_all`]'s result: the first best placement with its sums, and whether the cache
/// holds every placement's sums.
type Ranking = (Option<(usize, usize, Sums)>, bool);

/// The first best placement in raster order with its sums, every placement ranked (see
/// [`best_match`]), and whether `cache` holds the sums of every placement (else only the
/// first [`SUMS_CACHE`]). In a frame of its own, apart from the SSD's elimination.
#[inline(never)]
fn rank_all(
    scorer: &Scorer,
    win: &WindowView<'_>,
    tpl: &WindowView<'_>,
    cache: &mut Vec<Sums, SUMS_CACHE>,
) -> Result<Ranking, MatchError> {
    let mut best: Option<(usize, usize, Ranked)> = None;
    let mut cached = true;
    for_each_score(scorer, win, tpl, |px, py, x| {
        if cached {
            cached = cache.push(x).is_ok();
        }
        if let Some(x) = scorer.ranked(x) {
            if best.as_ref().is_none_or(|b| scorer.better(&x, &b.2)) {
                best = Some((px, py, x));
            }
        }
    })?;
    Ok((best.map(|(x, y, r)| (x, y, r.sums)), cached))
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

