//! Motion detection by image differencing (thesis 2.4, Watch window).
//!
//! The thesis estimates the temporal derivative by differencing,
//! `df/dt = (f(x,y,t) - f(x,y,t-δt)) / δt`, and thresholds it to separate motion from
//! noise. With `δt` one frame this is: pixel `(x, y)` moves iff
//! `|f(x,y,t) - f(x,y,t-1)| > T` (strict, like OpenCV `absdiff` + `THRESH_BINARY`).
//! The motion area is the bounding box and the count of moving pixels. It works on any
//! sub-window, including the MPDF strips (256x20 at the top and bottom of the frame).

use crate::kernels::view::WindowView;
#[cfg(target_arch = "x86_64")]
use crate::kernels::x86::Isa;
#[cfg(target_arch = "x86_64")]
mod avx2;
#[cfg(target_arch = "x86_64")]
mod avx512;

/// The motion area of a window pair, in frame coordinates (inclusive bounds).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MotionArea {
    /// Leftmost moving column.
    pub xmin: u32,
    /// Rightmost moving column.
    pub xmax: u32,
    /// Top moving row.
    pub ymin: u32,
    /// Bottom moving row.
    pub ymax: u32,
    /// Number of moving pixels.
    pub count: u32,
}

/// The two views do not describe the same window.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MotionError {
    /// Widths or heights differ.
    SizeMismatch,
}

error_messages!(MotionError {
    SizeMismatch => "the two images differ in size",
});

/// Pixels per block of a row scan: fixed-size blocks compile to whole SIMD vectors on the
/// host (a scalar remainder loop per block would cost more than the vectors).
const BLOCK: usize = 64;

/// Whether pixel pair `(p, q)` moves: `|p - q| > t`.
#[inline(always)]
fn moves(p: u8, q: u8, t: u8) -> bool {
    p.abs_diff(q) > t
}

/// The moving pixels of one block (at most 64: the `u8` lanes of the sum cannot wrap).
#[inline(always)]
fn block_count(a: &[u8; BLOCK], b: &[u8; BLOCK], t: u8) -> u32 {
    u32::from(a.iter().zip(b).fold(0u8, |acc, (&p, &q)| acc.wrapping_add(u8::from(moves(p, q, t)))))
}

/// The first and last moving columns of the first [`BLOCK`] pixels of two runs: the tests as
/// bytes of 0/1, read eight at a time, so the search branches per eight pixels, not per pixel.
fn block_span(a: &[u8], b: &[u8], t: u8) -> Option<(usize, usize)> {
    let mut m = [0u8; BLOCK];
    for ((d, &p), &q) in m.iter_mut().zip(a).zip(b) {
        *d = u8::from(moves(p, q, t));
    }
    let mut span = None;
    for (k, c) in m.chunks_exact(8).enumerate() {
        let word = <&[u8; 8]>::try_from(c).map_or(0, |c| u64::from_le_bytes(*c));
        if word != 0 {
            let (lo, hi) = (8 * k + word.trailing_zeros() as usize / 8, 8 * k + (63 - word.leading_zeros() as usize) / 8);
            span = Some(span.map_or((lo, hi), |(first, _)| (first, hi)));
        }
    }
    span
}

/// The moving pixels of two equally long rows with the first and last moving columns, or
/// `None` when none moves, in [`BLOCK`]s of pixels, in the baseline build's vectors (or
/// none): whole blocks are counted without a branch per pixel; only the first and last blocks
/// that move are searched for the columns ([`block_span`]).
fn scan_row_blocks(a: &[u8], b: &[u8], t: u8) -> Option<(u32, usize, usize)> {
    let (ca, cb) = (a.chunks_exact(BLOCK), b.chunks_exact(BLOCK));
    let (ra, rb) = (ca.remainder(), cb.remainder());
    // The first and last blocks that move (the tail after the blocks is block `blocks`).
    let (mut count, mut span) = (0u32, None);
    let blocks = a.len().min(b.len()) / BLOCK;
    for (k, (x, y)) in ca.zip(cb).enumerate() {
        if let (Ok(x), Ok(y)) = (<&[u8; BLOCK]>::try_from(x), <&[u8; BLOCK]>::try_from(y)) {
            let c = block_count(x, y, t);
            if c > 0 {
                count += c;
                span = Some((span.map_or(k, |(first, _)| first), k));
            }
        }
    }
    let tail = ra.iter().zip(rb).filter(|&(&p, &q)| moves(p, q, t)).count() as u32;
    if tail > 0 {
        count += tail;
        span = Some((span.map_or(blocks, |(first, _)| first), blocks));
    }
    let (first, last) = span?;
    let block = |k: usize| Some((k * BLOCK, block_span(a.get(k * BLOCK..)?, b.get(k * BLOCK..)?, t)?));
    let ((lo, (x0, _)), (hi, (_, x1))) = (block(first)?, block(last)?);
    Some((count, lo + x0, hi + x1))
}

/// Image differencing `|next - prev| > threshold` over two equally sized views
/// (thesis 2.4). Returns the motion area in `next`'s frame coordinates, or `None` when
/// no pixel moved (also for empty views).
pub fn detect_motion(
    prev: &WindowView<'_>,
    next: &WindowView<'_>,
    threshold: u8,
) -> Result<Option<MotionArea>, MotionError> {
    if prev.width() != next.width() || prev.height() != next.height() {
        return Err(MotionError::SizeMismatch);
    }
    #[cfg(target_arch = "x86_64")]
    return Ok(motion_on(super::x86::path(), prev, next, threshold));
    #[cfg(not(target_arch = "x86_64"))]
    Ok(motion_rows(prev, next, threshold, scan_row_blocks))
}

/// [`detect_motion`] of two views of one size on the path `isa` (narrowed to what the host
/// runs). OpenCV's differencing runs its own AVX2 or AVX-512 kernels on such hosts; the
/// baseline build's 16-byte vectors took 3.2 to 5.4 us a 256x256 frame against its 11.3
/// (`fixtures/bench/README.md`, stop 35).
#[cfg(target_arch = "x86_64")]
fn motion_on(isa: Isa, prev: &WindowView<'_>, next: &WindowView<'_>, threshold: u8) -> Option<MotionArea> {
    // SAFETY: the host runs the path (narrowed by `detected`), the functions' only requirement.
    #[allow(unsafe_code)]
    match isa.min(super::x86::detected()) {
        Isa::Avx512 => unsafe { avx512::motion(prev, next, threshold) },
        Isa::Avx2 => unsafe { avx2::motion(prev, next, threshold) },
        Isa::Portable => motion_rows(prev, next, threshold, scan_row_blocks),
    }
}

/// The rows of two full-resolution views of one size, walked by stride straight from their
/// buffers, without two [`WindowView::row`] calls a row (256-pixel rows are only a few
/// vectors: per-row work counts).
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy)]
struct FullRows<'a> {
    a: &'a [u8],
    sa: usize,
    b: &'a [u8],
    sb: usize,
    width: usize,
    height: usize,
}

#[cfg(target_arch = "x86_64")]
impl<'a> FullRows<'a> {
    /// `None` for decimated views (their rows are not slices).
    #[inline(always)]
    fn new(prev: &WindowView<'a>, next: &WindowView<'a>) -> Option<Self> {
        let ((a, sa), (b, sb), width) = (prev.raw()?, next.raw()?, next.width());
        // Empty rows move nowhere, whatever the height.
        Some(Self { a, sa, b, sb, width, height: if width == 0 { 0 } else { next.height() } })
    }

    /// Row `y < height` of both: `data[y * stride..][..width]`. The constructors checked that
    /// the buffers are that long if `width > 0`, so the products do not overflow. No closure
    /// goes through `Option`'s or iterators' adapters here: those lack the vector paths' target
    /// features, so closures that have them would not inline.
    #[inline(always)]
    fn at(&self, y: usize) -> (&'a [u8], &'a [u8]) {
        match (self.a.get(y * self.sa..y * self.sa + self.width), self.b.get(y * self.sb..y * self.sb + self.width)) {
            (Some(ra), Some(rb)) => (ra, rb),
            _ => (&[][..], &[][..]),
        }
    }
}

/// The motion area of `rows` (of `next`), [`GROUP`] rows at a time, for the vector paths (each
/// inlines it with its `group_moves` and `scan`): most rows of a Watch window do not move, so a
/// group is first only tested for any motion (`group_moves(rows, ys)`, no branch a vector),
/// and only a group that moves is scanned row by row (`scan`), from L1 by then.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn motion_grouped(
    next: &WindowView<'_>,
    rows: FullRows<'_>,
    group_moves: impl Fn(FullRows<'_>, core::ops::Range<usize>) -> bool,
    scan: impl Fn(&[u8], &[u8]) -> Option<(u32, usize, usize)>,
) -> Option<MotionArea> {
    let (mut area, mut count) = (None, 0u32);
    for y0 in (0..rows.height).step_by(GROUP) {
        let ys = y0..rows.height.min(y0 + GROUP);
        if !group_moves(rows, ys.clone()) {
            continue;
        }
        for y in ys {
            let (ra, rb) = rows.at(y);
            if let Some((c, first, last)) = scan(ra, rb) {
                count = count.saturating_add(c);
                area = Some(grow(area, y, first, last));
            }
        }
    }
    in_frame(next, area, count)
}

/// Rows tested together for motion by [`motion_grouped`] before any is scanned.
#[cfg(target_arch = "x86_64")]
const GROUP: usize = 4;

/// The moving rows' bounding box in view coordinates (`None` until a row moves), grown by
/// row `y` (below the rows before) moving from column `first` to `last`.
#[inline(always)]
fn grow(area: Option<(usize, usize, usize, usize)>, y: usize, first: usize, last: usize) -> (usize, usize, usize, usize) {
    match area {
        None => (first, last, y, y),
        Some((x0, x1, y0, _)) => (x0.min(first), x1.max(last), y0, y),
    }
}

/// The motion area in `view`'s frame coordinates of the moving rows' bounding box `area` (view
/// coordinates) and their `count` of moving pixels, `None` if no row moved.
#[inline(always)]
fn in_frame(view: &WindowView<'_>, area: Option<(usize, usize, usize, usize)>, count: u32) -> Option<MotionArea> {
    area.map(|(x0, x1, y0, y1)| {
        let (fx0, fy0) = view.to_frame(x0, y0);
        let (fx1, fy1) = view.to_frame(x1, y1);
        MotionArea {
            xmin: fx0,
            xmax: fx1,
            ymin: fy0,
            ymax: fy1,
            count,
        }
    })
}

/// The motion area of two views of one size, each row's moving pixels from `scan`.
#[inline(always)]
fn motion_rows(prev: &WindowView<'_>, next: &WindowView<'_>, threshold: u8, scan: impl Fn(&[u8], &[u8], u8) -> Option<(u32, usize, usize)>) -> Option<MotionArea> {
    let h = next.height();
    let mut area = None;
    let mut count = 0u32;
    for y in 0..h {
        let (rc, first, last) = match (prev.row(y), next.row(y)) {
            (Some(a), Some(b)) => match scan(a, b, threshold) {
                Some(r) => r,
                None => continue,
            },
            // Decimated views have no contiguous rows: fall back to a scalar scan.
            _ => {
                let mut c = 0u32;
                let (mut first, mut last) = (usize::MAX, 0);
                for (x, (p, q)) in prev.row_iter(y).zip(next.row_iter(y)).enumerate() {
                    if p.abs_diff(q) > threshold {
                        c += 1;
                        first = first.min(x);
                        last = x;
                    }
                }
                if c == 0 {
                    continue;
                }
                (c, first, last)
            }
        };
        count = count.saturating_add(rc);
        area = Some(grow(area, y, first, last));
    }
    in_frame(next, area, count)
}

/// Writes the motion mask `|next - prev| > threshold` (1 = moving) row-major into `out`
/// and returns the number of moving pixels; `None` if sizes differ or `out` is shorter
/// than `width * height`.
pub fn motion_mask(
    prev: &WindowView<'_>,
    next: &WindowView<'_>,
    threshold: u8,
    out: &mut [u8],
) -> Option<u32> {
    if prev.width() != next.width() || prev.height() != next.height() {
        return None;
    }
    let w = next.width();
    let out = out.get_mut(..w.checked_mul(next.height())?)?;
    let mut count = 0u32;
    if w == 0 {
        return Some(0);
    }
    for (y, dst) in out.chunks_exact_mut(w).enumerate() {
        for (d, (p, q)) in dst.iter_mut().zip(prev.row_iter(y).zip(next.row_iter(y))) {
            *d = u8::from(p.abs_diff(q) > threshold);
            count = count.saturating_add(u32::from(*d));
        }
    }
    Some(count)
}

#[cfg(test)]
mod tests;
