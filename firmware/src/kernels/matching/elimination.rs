//! Successive elimination for SSD (thesis 2.4's Peripheral measure): placements that cannot
//! beat the best SSD found are skipped without computing their dot product.
//!
//! Split the template into `B x B` blocks (the last `tw % B` columns and `th % B` rows are left
//! out). Over a block of `n = B²` pixels, Cauchy-Schwarz gives `(Σ R - Σ I)² <= n Σ (R - I)²`,
//! and the blocks are disjoint, so for every placement
//!
//! `n · SSD >= L = Σ_blocks (Σ_block R - Σ_block I)²`
//!
//! (Li and Salari's successive elimination algorithm, with block sums). `L` costs one
//! subtraction and one multiply-add per block from the window's `B x B` box sums, against
//! `tw·th` multiply-adds for the SSD. A placement with `L > n · best` has an SSD above the best
//! one found before it and cannot be the first minimum in raster order, so the search is exact
//! (the same placement, ties to the first in raster order, as `cv::minMaxLoc`). The
//! placement with the smallest `L` is scored first, so the bound is tight from the start.
//! How many placements are left depends on the images, not their size: a flat window keeps them
//! all (then the bounds are extra work).
use super::MAX_SEARCH_WIDTH;
#[cfg(target_arch = "x86_64")]
use crate::kernels::x86::Isa;
use crate::kernels::view::WindowView;
use heapless::Vec;

/// Capacity of the box-sum image, in box positions (`(ww - B + 1)·(wh - B + 1)`): a 40x40
/// Peripheral window at full resolution has 1,089 with `B = 8`. Larger windows are searched
/// exhaustively.
const BOX_CAP: usize = 2048;

/// Most template blocks (a bound must also stay under 2³², see [`Elimination::new`]).
const BLOCK_CAP: usize = 256;

/// The block sums of a template and the box sums of a window, for the bound `L`, in buffers
/// the caller holds (4 KiB, built in place rather than copied there).
pub(super) struct Elimination<'a> {
    /// `Σ I` over the `B x B` box at each window position `(x, y)`, row-major with `cols`
    /// columns (at most `8²·255`, so differences and their squares fit `i16` and `i32`).
    boxes: &'a [i16],
    cols: usize,
    /// `Σ R` over each template block, row-major with `bw` columns.
    blocks: &'a [i16],
    bw: usize,
    b: usize,
}

impl<'a> Elimination<'a> {
    /// The bound's sums for `tpl` in `win` (both step 1), with blocks of half the template's
    /// shorter side rounded down to a power of two, at most 8 (four 8x8 blocks for 16x16, four
    /// 4x4 for 8x8: a bound costs four multiply-adds); `None` (search every placement) for
    /// templates under 4 pixels on a side (blocks of one pixel would cost the SSD itself),
    /// windows or maps too large for the buffers, or with so many blocks that a bound, at most
    /// `blocks · (B²·255)²`, could pass 2³².
    #[cfg_attr(target_arch = "x86_64", inline(always))]
    fn new(win: &WindowView<'_>, tpl: &WindowView<'_>, boxes: &'a mut Vec<i16, BOX_CAP>, blocks: &'a mut Vec<i16, BLOCK_CAP>) -> Option<Self> {
        let (tw, th, ww, wh) = (tpl.width(), tpl.height(), win.width(), win.height());
        // A power of two, so a box sum is `log2 B` doublings.
        let b = 1usize << (tw.min(th) / 2).clamp(1, 8).ilog2();
        let most = ((b * b * 255) as u64).pow(2);
        if b < 2 || tw > ww || th > wh || ww > MAX_SEARCH_WIDTH || ((tw / b) * (th / b)) as u64 * most >= u64::from(NOT_PLACED) {
            return None;
        }
        let (cols, rows) = (ww - b + 1, wh - b + 1);
        if cols.checked_mul(rows)? > BOX_CAP || (wh - th) * cols + (ww - tw + 1) > PLACEMENT_CAP {
            return None;
        }
        blocks.clear();
        for by in 0..th / b {
            for bx in 0..tw / b {
                let mut s = 0i16;
                for v in 0..b {
                    s += tpl.row(by * b + v)?.get(bx * b..bx * b + b)?.iter().map(|&p| i16::from(p)).sum::<i16>();
                }
                blocks.push(s).ok()?;
            }
        }
        // Box sums: the sums of `b` rows down each column (one row in, one out), then of `b`
        // of those along the row (both loops over whole rows: SIMD on the host), the last
        // doubling written straight into the box row.
        boxes.clear();
        boxes.resize(cols * rows, 0).ok()?;
        let (mut col, mut buf, mut spare) = ([0i16; MAX_SEARCH_WIDTH], [0i16; MAX_SEARCH_WIDTH], [0i16; MAX_SEARCH_WIDTH]);
        let (col, buf, spare) = (col.get_mut(..ww)?, buf.get_mut(..ww)?, spare.get_mut(..ww)?);
        for v in 0..b {
            col.iter_mut().zip(win.row(v)?).for_each(|(c, &p)| *c += i16::from(p));
        }
        // `dst[i] = src[i] + src[i + width]`: sums of twice `width` columns.
        let double = |dst: &mut [i16], src: &[i16], width: usize| {
            let sums = src.iter().zip(src.get(width..).unwrap_or(&[])).map(|(&x, &y)| x + y);
            dst.iter_mut().zip(sums).for_each(|(d, s)| *d = s);
        };
        for (y, out) in boxes.chunks_exact_mut(cols).enumerate() {
            if y > 0 {
                let (add, sub) = (win.row(y + b - 1)?, win.row(y - 1)?);
                col.iter_mut().zip(add.iter().zip(sub)).for_each(|(c, (&a, &s))| *c += i16::from(a) - i16::from(s));
            }
            // Sums of 2, 4, ..., b columns, each of two of the previous width.
            // `from`: where the sums of `width` columns are (0 `col`, 1 `buf`, 2 `spare`).
            let (mut from, mut width) = (0, 1);
            while 2 * width < b {
                match from {
                    0 => double(buf, col, width),
                    1 => double(spare, buf, width),
                    _ => double(buf, spare, width),
                }
                (from, width) = (if from == 1 { 2 } else { 1 }, 2 * width);
            }
            double(out, [&*col, &*buf, &*spare].get(from).copied().unwrap_or(&[]), width);
        }
        Some(Self { boxes, cols, blocks, bw: tw / b, b })
    }

    /// `n = B²`, the pixels of a block: `L <= n · SSD`.
    fn block_pixels(&self) -> u64 {
        (self.b * self.b) as u64
    }

    /// The bounds `L` into `out`, placement `(x, y)` at `y · cols + x` as its box sums are:
    /// a block at a time over the whole map as one run (SIMD on the host, no remainder per
    /// row). The columns from the last placement's on are no placements (the caller marks
    /// them [`NOT_PLACED`]).
    #[cfg_attr(target_arch = "x86_64", inline(always))]
    fn bounds(&self, out: &mut [u32]) {
        out.iter_mut().for_each(|l| *l = 0);
        let n = out.len();
        for (j, row) in self.blocks.chunks(self.bw.max(1)).enumerate() {
            for (i, &t) in row.iter().enumerate() {
                let at = j * self.b * self.cols + i * self.b;
                let Some(boxes) = self.boxes.get(at..at + n) else { continue };
                for (l, &w) in out.iter_mut().zip(boxes) {
                    let d = i32::from(t - w);
                    *l = l.wrapping_add((d * d) as u32);
                }
            }
        }
    }
}

/// Most bounds kept, each computed once: a 40x40 window's 625 placements of a 16x16 template,
/// in rows as long as the box rows (817 bounds, see [`Elimination::bounds`]). Larger maps
/// are searched exhaustively.
const PLACEMENT_CAP: usize = 1024;

/// The bound of a column that is no placement: above every bound (see [`Elimination::new`])
/// and every cut-off, so it is never searched.
const NOT_PLACED: u32 = u32::MAX;

/// A placement summed alone costs about this many times its share of the exhaustive search
/// (which sums rows of placements together): where the first bound keeps more than this
/// fraction of them, the exhaustive search is cheaper. Measured on the M4: a Peripheral
/// window without its object (nothing eliminated) took 1,353,080 instructions summed one by
/// one against 597,332 exhaustively.
const KEPT_MOST: usize = 4;

/// The first placement in raster order with the smallest SSD of `tpl` in `win` (both step
/// 1, `nx x ny` placements), with its sums: `sums` gives a placement's sums and `ssd` their
/// SSD. Only the placements whose bound does not exclude them are summed (see the module
/// docs). `None` when the elimination does not apply ([`Elimination::new`]) or would keep
/// more than a [`KEPT_MOST`]th of the placements: search every placement; `Some(None)` if
/// `sums` fails. In a frame of its own, so the other methods'
/// matching does not carry its buffers.
#[inline(never)]
pub(super) fn search<S>(
    win: &WindowView<'_>,
    tpl: &WindowView<'_>,
    (nx, ny): (usize, usize),
    sums: impl FnMut(usize, usize) -> Option<S>,
    ssd: impl Fn(&S) -> u64,
) -> Option<Option<(usize, usize, S)>> {
    #[cfg(target_arch = "x86_64")]
    return search_on(crate::kernels::x86::path(), win, tpl, (nx, ny), sums, ssd);
    #[cfg(not(target_arch = "x86_64"))]
    search_in(win, tpl, (nx, ny), sums, ssd)
}

/// [`search`] on the path `isa` (narrowed to what the host runs): its box sums, bounds and
/// scans of the bounds in 512-bit or 256-bit vectors, where the baseline build's 128-bit ones
/// took 3.3 us of the 40x40 Peripheral match (AVX-512 2.5, AVX2 3.0; OpenCV on one thread
/// takes about 30).
#[cfg(target_arch = "x86_64")]
fn search_on<S>(
    isa: Isa,
    win: &WindowView<'_>,
    tpl: &WindowView<'_>,
    placed: (usize, usize),
    sums: impl FnMut(usize, usize) -> Option<S>,
    ssd: impl Fn(&S) -> u64,
) -> Option<Option<(usize, usize, S)>> {
    // SAFETY: the host runs the path (narrowed by `detected`), the functions' only requirement.
    #[allow(unsafe_code)]
    match isa.min(crate::kernels::x86::detected()) {
        Isa::Avx512 => unsafe { search_avx512(win, tpl, placed, sums, ssd) },
        Isa::Avx2 => unsafe { search_avx2(win, tpl, placed, sums, ssd) },
        Isa::Portable => search_in(win, tpl, placed, sums, ssd),
    }
}

/// [`search_in`] compiled for an instruction set: `$name` requires the CPU to run `$features`.
#[cfg(target_arch = "x86_64")]
macro_rules! search_build {
    ($name:ident, $features:literal) => {
        #[target_feature(enable = $features)]
        fn $name<S>(
            win: &WindowView<'_>,
            tpl: &WindowView<'_>,
            placed: (usize, usize),
            sums: impl FnMut(usize, usize) -> Option<S>,
            ssd: impl Fn(&S) -> u64,
        ) -> Option<Option<(usize, usize, S)>> {
            search_in(win, tpl, placed, sums, ssd)
        }
    };
}
#[cfg(target_arch = "x86_64")]
search_build!(search_avx512, "avx512f,avx512bw");
#[cfg(target_arch = "x86_64")]
search_build!(search_avx2, "avx2");

/// [`search`]'s body, inlined into each build of it (the baseline's, AVX2's and AVX-512's).
#[inline(always)]
fn search_in<S>(
    win: &WindowView<'_>,
    tpl: &WindowView<'_>,
    (nx, ny): (usize, usize),
    sums: impl FnMut(usize, usize) -> Option<S>,
    ssd: impl Fn(&S) -> u64,
) -> Option<Option<(usize, usize, S)>> {
    let (mut boxes, mut blocks) = (Vec::new(), Vec::new());
    let el = Elimination::new(win, tpl, &mut boxes, &mut blocks)?;
    search_with(&el, nx, ny, sums, ssd)
}

/// [`search`] with the bound's sums built.
#[cfg_attr(target_arch = "x86_64", inline(always))]
fn search_with<S>(
    el: &Elimination,
    nx: usize,
    ny: usize,
    mut sums: impl FnMut(usize, usize) -> Option<S>,
    ssd: impl Fn(&S) -> u64,
) -> Option<Option<(usize, usize, S)>> {
    let (n, cols) = (el.block_pixels(), el.cols);
    if nx == 0 || ny == 0 || nx > cols {
        return None;
    }
    // Placement `(x, y)`'s bound at `y · cols + x`; the last row ends at its last placement.
    let mut bounds: Vec<u32, PLACEMENT_CAP> = Vec::new();
    bounds.resize((ny - 1) * cols + nx, 0).ok()?;
    el.bounds(&mut bounds);
    for row in bounds.chunks_mut(cols) {
        row.get_mut(nx..).unwrap_or(&mut []).fill(NOT_PLACED);
    }
    // The smallest bound first (the first in raster order): its SSD bounds the search from the
    // start. The least value, then where it is first: two passes over whole vectors, not one
    // carried through every compare.
    let least = bounds.iter().copied().min()?;
    let first = first_at_most(&bounds, 0, least)?;
    let Some(x) = sums(first % cols, first / cols) else { return Some(None) };
    let mut limit = ssd(&x);
    // A placement can beat `limit` only if its bound is at most `n · limit` (compared in
    // `u32`, as the bounds are: vector compares on the host).
    let cut = |limit: u64| u32::try_from(n.saturating_mul(limit)).map_or(NOT_PLACED - 1, |c| c.min(NOT_PLACED - 1));
    let mut most = cut(limit);
    if bounds.iter().filter(|&&l| l <= most).count() * KEPT_MOST > nx * ny {
        return None;
    }
    let mut start = Some(x);
    let mut best: Option<(usize, S, u64)> = None;
    let mut from = 0;
    while let Some(k) = first_at_most(&bounds, from, most) {
        from = k + 1;
        // The first placement scored is not summed twice.
        let x = match start.take_if(|_| k == first) {
            Some(x) => x,
            None => match sums(k % cols, k / cols) {
                Some(x) => x,
                None => return Some(None),
            },
        };
        let s = ssd(&x);
        if s < limit {
            (limit, most) = (s, cut(s));
        }
        if best.as_ref().is_none_or(|b| s < b.2) {
            best = Some((k, x, s));
        }
    }
    Some(best.map(|(k, x, _)| (k % cols, k / cols, x)))
}

/// Bounds a run of which [`first_at_most`] passes over with one vector compare.
const RUN: usize = 16;

/// The first index from `from` on whose bound is at most `most`: runs of [`RUN`] bounds
/// are passed over by their least (most runs of a search hold no placement left to sum).
#[cfg_attr(target_arch = "x86_64", inline(always))]
fn first_at_most(bounds: &[u32], from: usize, most: u32) -> Option<usize> {
    let mut at = from;
    while let Some(run) = bounds.get(at..at + RUN) {
        if let Ok(run) = <&[u32; RUN]>::try_from(run) {
            if run.iter().fold(u32::MAX, |m, &l| m.min(l)) <= most {
                break;
            }
        }
        at += RUN;
    }
    bounds.get(at..)?.iter().position(|&l| l <= most).map(|i| at + i)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Pixels from a fixed LCG.
    fn lcg(seed: u32) -> impl FnMut() -> u8 {
        let mut x = seed;
        move || {
            x = x.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (x >> 24) as u8
        }
    }

    /// The window's box sums and the template's block sums against sums taken pixel by pixel
    /// here: blocks of 2, 4 and 8 (templates 4 to 17 a side), windows from the block's size up
    /// to 40x40, sub-views of a frame (rows `stride` apart), random and all-255 pixels (the
    /// largest sums).
    #[test]
    fn box_sums_are_the_pixel_sums() {
        let mut px = lcg(99);
        let (fw, fh) = (50, 46);
        for full in [false, true] {
            let frame: std::vec::Vec<u8> = (0..fw * fh).map(|_| if full { 255 } else { px() }).collect();
            let view = WindowView::packed(&frame, fw, fh).unwrap_or_else(|_| unreachable!());
            for (x, y, ww, wh, tw, th) in [(0, 0, 40, 40, 16, 16), (3, 5, 20, 20, 8, 8), (1, 2, 31, 23, 9, 7), (2, 2, 13, 11, 5, 4), (4, 1, 17, 17, 17, 17), (0, 3, 8, 9, 4, 4)] {
                let win = view.sub(x, y, ww, wh).unwrap_or_else(|| unreachable!());
                let tpl = view.sub(x + 1, y + 1, tw, th).unwrap_or_else(|| unreachable!());
                let (mut boxes, mut blocks) = (Vec::new(), Vec::new());
                let el = Elimination::new(&win, &tpl, &mut boxes, &mut blocks).unwrap_or_else(|| unreachable!());
                let b = el.b;
                let sum = |x0: usize, y0: usize| -> i16 { (0..b * b).map(|i| i16::from(frame[(y0 + i / b) * fw + x0 + i % b])).sum() };
                let want: std::vec::Vec<i16> = (0..(wh - b + 1) * el.cols).map(|k| sum(x + k % el.cols, y + k / el.cols)).collect();
                assert_eq!(el.boxes, &want[..], "{tw}x{th} in {ww}x{wh}, blocks of {b}");
                let want: std::vec::Vec<i16> = (0..(th / b) * el.bw).map(|k| sum(x + 1 + b * (k % el.bw), y + 1 + b * (k / el.bw))).collect();
                assert_eq!(el.blocks, &want[..], "{tw}x{th} blocks of {b}");
            }
        }
    }

    /// The scan of the bounds against `position` over every start and cut, on runs of bounds
    /// with and without a kept one, lengths not a multiple of [`RUN`] and starts past the end.
    #[test]
    fn the_run_scan_finds_the_first_kept_bound() {
        let mut px = lcg(31);
        for len in [0, 1, 15, 16, 17, 33, 64, 100] {
            let bounds: std::vec::Vec<u32> = (0..len).map(|_| u32::from(px()) * 1000 + u32::from(px())).collect();
            for most in [0, 1000, 50_000, 200_000, u32::MAX] {
                for from in 0..len + 2 {
                    let want = bounds.iter().enumerate().skip(from).find(|&(_, &l)| l <= most).map(|(k, _)| k);
                    assert_eq!(first_at_most(&bounds, from, most), want, "{len} bounds from {from}, at most {most}");
                }
            }
        }
    }

    /// Every build of the search the host runs (AVX-512, AVX2, the baseline's) against the SSD
    /// of each placement summed pixel by pixel: the same placement and sums for templates of the
    /// Peripheral's sizes and others (odd sides, blocks of 2, 4 and 8), in sub-views of a frame,
    /// on noise, on a window holding the template, flat and all-255.
    #[test]
    fn every_build_of_the_search_is_the_baseline_one() {
        let mut px = lcg(7);
        let (fw, fh) = (72, 60);
        for case in 0..4 {
            let frame: std::vec::Vec<u8> = (0..fw * fh)
                .map(|i| match case {
                    2 => 90,
                    3 => 255,
                    _ => px() / (1 + (i % 3) as u8),
                })
                .collect();
            let full = WindowView::packed(&frame, fw, fh).unwrap_or_else(|_| unreachable!());
            for (x, y, ww, wh, tw, th) in [(0, 0, 40, 40, 16, 16), (3, 5, 20, 20, 8, 8), (1, 2, 31, 23, 9, 7), (7, 1, 48, 48, 16, 16), (0, 0, 72, 60, 17, 12), (2, 2, 13, 11, 5, 4)] {
                let win = full.sub(x, y, ww, wh).unwrap_or_else(|| unreachable!());
                // Case 0: the template is the window's patch at (3, 2), one pixel changed.
                let t: std::vec::Vec<u8> = (0..tw * th)
                    .map(|i| if case == 0 { frame[(y + 2 + i / tw) * fw + x + 3 + i % tw].wrapping_add(u8::from(i == 5)) } else { px() })
                    .collect();
                let tpl = WindowView::packed(&t, tw, th).unwrap_or_else(|_| unreachable!());
                let ssd = |ox: usize, oy: usize| -> Option<u64> {
                    Some((0..tw * th).map(|i| (i64::from(t[i]) - i64::from(frame[(y + oy + i / tw) * fw + x + ox + i % tw])).pow(2) as u64).sum())
                };
                let placed = (ww - tw + 1, wh - th + 1);
                let base = search_in(&win, &tpl, placed, ssd, |&s| s);
                #[cfg(target_arch = "x86_64")]
                for isa in crate::kernels::x86::runnable() {
                    assert_eq!(search_on(isa, &win, &tpl, placed, ssd, |&s| s), base, "{isa:?}, case {case}: {tw}x{th} in {ww}x{wh} at ({x}, {y})");
                }
                // The windows up to 40x40 fit the buffers (larger ones are searched in full).
                if case == 0 && ww * wh <= 40 * 40 {
                    assert_eq!(base, Some(Some((3, 2, 1))), "{tw}x{th} in {ww}x{wh} at ({x}, {y})");
                }
            }
        }
    }
}
