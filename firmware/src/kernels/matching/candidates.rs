//! A wide search's bounded cost (beyond the thesis, issue 22): the template's few best
//! half-resolution placements, each searched at full resolution.
//!
//! An adapting Peripheral matches its 25 % windows of up to 64x64 samples (a sweep's 128x128
//! tile, 3,025 placements of a 10x10 template): scoring every placement took 2.08 million
//! instructions on the Cortex-M4 (commit 61921d5), 1.4 of the thesis's 8.8 ms frame periods
//! at 168 MHz. Here window and template are halved ([`halve`]: 2x2 means), every
//! half-resolution placement is ranked (784 of 25 pixels), and the [`CANDIDATES`] best of
//! them, apart from one another, are searched at full resolution within [`REACH`] of the two
//! placements each stands for.
//! Unlike [`super::best_match_pyramid`] (a tracker's window, whose centre is searched too)
//! there is no prior: the object may be anywhere in the window, beside look-alikes. A tile's
//! look now takes at most 260,803 instructions (`docs/firmware-target.md`).
use super::dot::dot_products;
use super::scores::{placements, zncc_rank, Ranked, Scorer, Sums};
use super::{best_match_near, halve, near_range, rank_all, search_packed, with_packed, Match, MatchError, Method, NearRange, HALF_TEMPLATE_PIXELS, MAX_PACKED_PIXELS, MAX_SEARCH_WIDTH, SCORE_CACHE, SUMS_CACHE};
use crate::kernels::view::WindowView;
use heapless::Vec;

/// Half-resolution placements searched at full resolution: the best one and three
/// look-alikes (the unit tests plant three beside the object; the board suite's sweep hands
/// over the brute-force best placement).
pub const CANDIDATES: usize = 4;

/// Full-resolution placements searched on each side of the two a candidate stands for: a
/// 4x4 range. On a smooth image the half-resolution peak lies at the half of the full one's
/// placement or beside it; a winner on its range's edge is refitted in its own 3x3 range.
const REACH: usize = 1;

/// Windows with more placements than this are searched by candidates: a 10x10 template's in
/// 32x32 windows (529) and more; the 40x40 window's 20x20 samples (121) in full.
pub const CANDIDATES_FROM: usize = 256;

/// [`super::best_match`] by zero-mean NCC (strided views are packed) with a bounded cost: a
/// window of more than [`CANDIDATES_FROM`] placements is searched by candidates (the module
/// docs), a smaller one, or one whose halves cannot be ranked (a template flat at half
/// resolution), in full. The result is in `win`'s frame, as `best_match`'s, and is the full
/// search's wherever its best placement lies within `REACH` (1) of a candidate's.
pub fn best_match_candidates(win: &WindowView<'_>, tpl: &WindowView<'_>) -> Result<Match, MatchError> {
    let method = Method::Zncc;
    with_packed(win, tpl, |pw, pt| {
        let (nx, ny) = placements(pw, pt)?;
        if nx * ny <= CANDIDATES_FROM {
            return search_packed(method, win, pw, pt);
        }
        match coarse(pw, pt) {
            Some(found) => fine(method, win, pw, pt, &found),
            None => search_packed(method, win, pw, pt),
        }
    })
}

/// The [`CANDIDATES`] best half-resolution placements by zero-mean NCC, no two adjacent (a
/// better neighbour replaces a candidate): `None` where the halves do not fit or the template
/// is flat at half resolution. Every placement is ranked, so this is where the cost is: the
/// window's sums come from running column sums in `u32` (at most 256 template pixels: `Σ I²`
/// <= 256·255²), each rank is [`zncc_rank`] of the exact numerator and variance, and the worst
/// candidate is beaten by few placements. In a frame of its own, apart from the fine searches'.
#[inline(never)]
fn coarse(win: &WindowView<'_>, tpl: &WindowView<'_>) -> Option<Top> {
    let (mut wbuf, mut tbuf) = (Vec::<u8, { MAX_PACKED_PIXELS / 4 }>::new(), Vec::<u8, HALF_TEMPLATE_PIXELS>::new());
    let (hw, ht) = (halve(win, &mut wbuf)?, halve(tpl, &mut tbuf)?);
    let (nx, ny) = placements(&hw, &ht).ok()?;
    let (tw, th) = (ht.width(), ht.height());
    let mut dots: Vec<u32, SCORE_CACHE> = Vec::new();
    dot_products(&hw, &ht, &mut dots)?;
    // The template's n, Σ R and variance n Σ R² - (Σ R)², which must be positive.
    let (mut sum, mut sq) = (0i64, 0i64);
    for v in 0..th {
        for &p in ht.row(v)? {
            sum += i64::from(p);
            sq += i64::from(p) * i64::from(p);
        }
    }
    let n = (tw * th) as i64;
    if n * sq - sum * sum <= 0 {
        return None;
    }
    // Column sums of I and I² over the template's rows at the current placement row.
    let mut cols: Vec<(u32, u32), { MAX_SEARCH_WIDTH / 2 }> = Vec::new();
    cols.resize(hw.width(), (0, 0)).ok()?;
    // Adds row `enter` and takes away row `leave` (zeros for none) in one pass.
    let slide = |cols: &mut [(u32, u32)], enter: &[u8], leave: &[u8]| {
        for ((c, &a), &b) in cols.iter_mut().zip(enter).zip(leave) {
            let (a, b) = (u32::from(a), u32::from(b));
            *c = (c.0.wrapping_add(a).wrapping_sub(b), c.1.wrapping_add(a * a).wrapping_sub(b * b));
        }
    };
    let none = [0u8; MAX_SEARCH_WIDTH / 2];
    let mut top = Top { kept: Vec::new(), worst: 0 };
    for py in 0..ny {
        if py == 0 {
            for v in 0..th {
                slide(&mut cols, hw.row(v)?, &none);
            }
        } else {
            slide(&mut cols, hw.row(py + th - 1)?, hw.row(py - 1)?);
        }
        // A placement of negative numerator ranks below zero: no better than a worst kept
        // candidate of positive rank, so it is passed over before its variance is computed.
        let floor = top.floor().is_some_and(|w| w >= 0.0);
        let (mut s, mut q) = cols.iter().take(tw).fold((0u32, 0u32), |a, c| (a.0 + c.0, a.1 + c.1));
        for (px, &a) in dots.get(py * nx..(py + 1) * nx)?.iter().enumerate() {
            if px > 0 {
                let (enter, leave) = (cols.get(px + tw - 1)?, cols.get(px - 1)?);
                (s, q) = (s.wrapping_add(enter.0).wrapping_sub(leave.0), q.wrapping_add(enter.1).wrapping_sub(leave.1));
            }
            let s = i64::from(s);
            let num = n * i64::from(a) - sum * s;
            if floor && num <= 0 {
                continue;
            }
            let var = n * i64::from(q) - s * s;
            if var > 0 {
                top.offer((px, py, zncc_rank(num, var)));
            }
        }
    }
    (!top.kept.is_empty()).then_some(top)
}

/// The candidates kept so far (placement, [`zncc_rank`]), and which of them is the worst
/// (where [`CANDIDATES`] are kept).
struct Top {
    kept: Vec<(usize, usize, f32), CANDIDATES>,
    worst: usize,
}

impl Top {
    /// The worst candidate's rank once [`CANDIDATES`] are kept (a placement must beat it).
    fn floor(&self) -> Option<f32> {
        self.kept.is_full().then(|| self.kept.get(self.worst).map(|w| w.2)).flatten()
    }

    /// Keeps `c` if it is better than a neighbour kept (which it replaces) or, with no
    /// neighbour kept, than the worst (when full). Most placements are no better than the
    /// worst: one comparison each.
    fn offer(&mut self, c: (usize, usize, f32)) {
        let full = self.kept.is_full();
        if full && self.kept.get(self.worst).is_some_and(|w| c.2 <= w.2) {
            return;
        }
        match self.kept.iter().position(|t| t.0.abs_diff(c.0) <= 1 && t.1.abs_diff(c.1) <= 1) {
            Some(i) => match self.kept.get_mut(i) {
                Some(t) if c.2 > t.2 => *t = c,
                _ => return,
            },
            None if !full => {
                let _ = self.kept.push(c);
            }
            None => {
                if let Some(w) = self.kept.get_mut(self.worst) {
                    *w = c;
                }
            }
        }
        if self.kept.is_full() {
            let worst = self.kept.iter().enumerate().reduce(|w, t| if t.1 .2 < w.1 .2 { t } else { w });
            self.worst = worst.map_or(0, |w| w.0);
        }
    }
}

/// The best full-resolution match near the candidates (ties to the first in raster order, as
/// the full search's), in `view`'s frame (`win` and `tpl` its packed pixels and template):
/// each candidate's range ranked exactly ([`Scorer::better`]), only the winner scored.
#[inline(never)]
fn fine(method: Method, view: &WindowView<'_>, win: &WindowView<'_>, tpl: &WindowView<'_>, found: &Top) -> Result<Match, MatchError> {
    let scorer = Scorer::new(method, tpl)?;
    let all = placements(win, tpl)?;
    let mut cache: Vec<Sums, SUMS_CACHE> = Vec::new();
    let mut best: Option<(usize, usize, Ranked)> = None;
    for &(cx, cy, _) in &found.kept {
        // A half-resolution placement stands for full-resolution `2c` and `2c + 1`.
        let NearRange { x: (x0, x1), y: (y0, y1) } = near_range((2 * cx, 2 * cy), (2 * cx + 1, 2 * cy + 1), REACH, all);
        let Some(range) = win.sub(x0, y0, x1 - x0 + tpl.width(), y1 - y0 + tpl.height()) else { continue };
        cache.clear();
        let Ok((Some((x, y, sums)), _)) = rank_all(&scorer, &range, tpl, &mut cache) else { continue };
        let Some(c) = scorer.ranked(sums) else { continue };
        let (x, y) = (x + x0, y + y0);
        let first = |b: &(usize, usize, Ranked)| scorer.better(&c, &b.2) || (!scorer.better(&b.2, &c) && (y, x) < (b.1, b.0));
        if best.as_ref().is_none_or(first) {
            best = Some((x, y, c));
        }
    }
    let (bx, by, _) = best.ok_or(MatchError::NoMatch)?;
    // Scored with its neighbours on every side, as the full search's (the best may lie on its
    // range's edge): its own 3x3 range, which keeps it unless a neighbour outside beats it.
    let m = best_match_near(method, win, tpl, (bx, by), (bx, by), 1)?;
    let step = view.step();
    let (origin_x, origin_y) = view.origin();
    let (sub_x, sub_y) = (m.sub_x * step as f32, m.sub_y * step as f32);
    Ok(Match { x: m.x * step, y: m.y * step, sub_x, sub_y, frame_x: origin_x as f32 + sub_x, frame_y: origin_y as f32 + sub_y, ..m })
}
