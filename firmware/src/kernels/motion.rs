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
use core::arch::x86_64::{__m512i, _mm512_cmpgt_epu8_mask, _mm512_loadu_si512, _mm512_maskz_loadu_epi8, _mm512_max_epu8, _mm512_or_si512, _mm512_set1_epi8, _mm512_setzero_si512, _mm512_subs_epu8};

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
/// `None` when none moves, 64 pixels a vector (AVX-512 BW): the test of each pixel is one bit
/// of a mask register, whose bits give the count and, from the first and last vectors that
/// move, the columns.
/// OpenCV's differencing runs its own AVX-512 kernels on such a host; the baseline build's
/// 16-byte vectors took 3.2 to 5.4 us a 256x256 frame against its 11.3
/// (`fixtures/bench/README.md`, stop 35).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512bw")]
#[inline]
fn scan_row_avx512(a: &[u8], b: &[u8], t: u8) -> Option<(u32, usize, usize)> {
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
#[cfg(target_arch = "x86_64")]
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
#[cfg(target_arch = "x86_64")]
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
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512bw")]
#[inline]
fn abs_diff(x: __m512i, y: __m512i) -> __m512i {
    _mm512_or_si512(_mm512_subs_epu8(x, y), _mm512_subs_epu8(y, x))
}

/// The last pixels of two rows, fewer than 64, in vectors through a byte mask, 0 past them (a
/// pair of zeros never moves), so that a row needs no scalar tail.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512bw")]
#[allow(unsafe_code)]
#[inline]
fn tail_pair(a: &[u8], b: &[u8]) -> (__m512i, __m512i) {
    let keep = (1u64 << a.len().min(b.len()).min(63)) - 1;
    // SAFETY: only the bytes of `keep`, inside both slices, are read; the masked-off ones are
    // neither read nor able to fault.
    unsafe { (_mm512_maskz_loadu_epi8(keep, a.as_ptr().cast()), _mm512_maskz_loadu_epi8(keep, b.as_ptr().cast())) }
}

/// [`scan_row_avx512`] in blocks of [`BLOCK`] pixels, in the baseline build's vectors (or
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
    if super::x86::path() == super::x86::Isa::Avx512 {
        // SAFETY: the CPU and the OS run AVX-512 F and BW, the function's only requirement.
        #[allow(unsafe_code)]
        return Ok(unsafe { motion_avx512(prev, next, threshold) });
    }
    Ok(motion_rows(prev, next, threshold, scan_row_blocks))
}

/// [`detect_motion`] with [`scan_row_avx512`], in one function so that the row scan is
/// inlined (a call a row was half of a frame's time). Full-resolution views are walked by
/// stride straight from their buffers, without two [`WindowView::row`] calls a row (256-pixel
/// rows are only 4 vectors: per-row work counts), [`GROUP`] rows at a time: most rows of a
/// Watch window do not move, so a group is first only tested for any motion
/// ([`largest_diff`], no branch per vector), and only a group that moves is scanned row by
/// row, from L1 by then.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512bw")]
fn motion_avx512(prev: &WindowView<'_>, next: &WindowView<'_>, threshold: u8) -> Option<MotionArea> {
    let ((Some((a, sa)), Some((b, sb))), w) = ((prev.raw(), next.raw()), next.width()) else {
        // Decimated views: motion_rows' scalar scan.
        return motion_rows(prev, next, threshold, |a, b, t| scan_row_avx512(a, b, t));
    };
    // Row `y < height` is `data[y * stride..][..width]`: the constructors checked that the
    // buffers are that long if `width > 0`, so the products do not overflow (empty rows move
    // nowhere, whatever the height). No closure goes through `Option`'s or iterators'
    // adapters here: those lack the target feature, so closures that have it would not inline.
    let row = |y: usize| match (a.get(y * sa..y * sa + w), b.get(y * sb..y * sb + w)) {
        (Some(ra), Some(rb)) => (ra, rb),
        _ => (&[][..], &[][..]),
    };
    let (h, tv) = (if w == 0 { 0 } else { next.height() }, _mm512_set1_epi8(threshold as i8));
    let (mut area, mut count) = (None, 0u32);
    for y0 in (0..h).step_by(GROUP) {
        let ys = y0..h.min(y0 + GROUP);
        let mut largest = _mm512_setzero_si512();
        for y in ys.clone() {
            let (ra, rb) = row(y);
            largest = _mm512_max_epu8(largest, largest_diff(ra, rb));
        }
        if _mm512_cmpgt_epu8_mask(largest, tv) == 0 {
            continue;
        }
        for y in ys {
            let (ra, rb) = row(y);
            if let Some((c, first, last)) = scan_row_avx512(ra, rb, threshold) {
                count = count.saturating_add(c);
                area = Some(grow(area, y, first, last));
            }
        }
    }
    in_frame(next, area, count)
}

/// Rows tested together for motion by [`motion_avx512`] before any is scanned.
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
mod tests {
    use super::*;

    #[test]
    fn hand_computed_area() {
        // 4x3 frame at (10, 100); differences: (1,0)=40, (3,1)=31, (2,2)=30 (not > 30).
        let prev = [0u8; 12];
        let mut next = [0u8; 12];
        next[1] = 40;
        next[4 + 3] = 31;
        next[8 + 2] = 30;
        let p = WindowView::new(&prev, 4, 3, 4, 10, 100).unwrap();
        let n = WindowView::new(&next, 4, 3, 4, 10, 100).unwrap();
        let a = detect_motion(&p, &n, 30).unwrap().unwrap();
        assert_eq!(
            a,
            MotionArea {
                xmin: 11,
                xmax: 13,
                ymin: 100,
                ymax: 101,
                count: 2
            }
        );
        // Differencing is symmetric.
        assert_eq!(detect_motion(&n, &p, 30).unwrap(), Some(a));
        assert_eq!(detect_motion(&p, &n, 40).unwrap(), None);
        let mut m = [9u8; 12];
        assert_eq!(motion_mask(&p, &n, 30, &mut m), Some(2));
        assert_eq!(m, [0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0]);
    }

    #[test]
    fn long_rows_and_strips() {
        // 600-wide rows exercise the 255-byte chunking; every pixel moves.
        let prev = [0u8; 600 * 2];
        let next = [255u8; 600 * 2];
        let p = WindowView::packed(&prev, 600, 2).unwrap();
        let n = WindowView::packed(&next, 600, 2).unwrap();
        let a = detect_motion(&p, &n, 0).unwrap().unwrap();
        assert_eq!(
            (a.xmin, a.xmax, a.ymin, a.ymax, a.count),
            (0, 599, 0, 1, 1200)
        );
    }

    /// Moving pixels in whole blocks, across a block boundary and in the tail after the
    /// blocks, on 200-wide rows (3 blocks of 64 and 8 more); reference: a direct per-pixel
    /// scan written here.
    #[test]
    fn blocks_and_tail_match_a_pixel_scan() {
        const W: usize = 200;
        const H: usize = 6;
        let prev = [100u8; W * H];
        let mut next = [100u8; W * H];
        let moves: [(usize, usize, u8); 7] = [(70, 0, 131), (63, 1, 0), (64, 1, 255), (195, 2, 140), (199, 3, 60), (0, 5, 69), (128, 5, 131)];
        for &(x, y, v) in &moves {
            next[y * W + x] = v;
        }
        let p = WindowView::new(&prev, W, H, W, 7, 3).unwrap();
        let n = WindowView::new(&next, W, H, W, 7, 3).unwrap();
        // Reference: every pixel tested once.
        let mut want: Option<MotionArea> = None;
        for y in 0..H {
            for x in 0..W {
                if prev[y * W + x].abs_diff(next[y * W + x]) > 30 {
                    let (fx, fy) = (7 + x as u32, 3 + y as u32);
                    want = Some(match want {
                        None => MotionArea { xmin: fx, xmax: fx, ymin: fy, ymax: fy, count: 1 },
                        Some(a) => MotionArea { xmin: a.xmin.min(fx), xmax: a.xmax.max(fx), ymin: a.ymin, ymax: fy, count: a.count + 1 },
                    });
                }
            }
        }
        // All seven differ by more than 30 (the closest by 31).
        assert_eq!(want.map(|a| (a.xmin, a.xmax, a.ymin, a.ymax, a.count)), Some((7, 206, 3, 8, 7)));
        assert_eq!(detect_motion(&p, &n, 30).unwrap(), want);
        // Rows whose only motion is in the tail, or in one block: first and last columns.
        assert_eq!(scan_row_blocks(&prev[3 * W..4 * W], &next[3 * W..4 * W], 30), Some((1, 199, 199)));
        assert_eq!(scan_row_blocks(&prev[W..2 * W], &next[W..2 * W], 30), Some((2, 63, 64)));
        assert_eq!(scan_row_blocks(&prev[4 * W..5 * W], &next[4 * W..5 * W], 30), None);
    }

    /// Both row scans (the AVX-512 one where this CPU has it) against a per-pixel scan written
    /// here: rows of every length around the 64-pixel vectors, motion sparse and dense, at the
    /// threshold's edge.
    #[test]
    fn row_scans_match_a_pixel_scan() {
        let mut x = 7u32;
        let mut next = || {
            x = x.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (x >> 24) as u8
        };
        for len in [0, 1, 63, 64, 65, 127, 128, 200, 256, 600] {
            for density in [0u8, 4, 128, 255] {
                let a: std::vec::Vec<u8> = (0..len).map(|_| next()).collect();
                let b: std::vec::Vec<u8> = a.iter().map(|&p| if next() < density { next() } else { p.saturating_add(30) }).collect();
                let want = {
                    let hits: std::vec::Vec<usize> = (0..len).filter(|&i| a[i].abs_diff(b[i]) > 30).collect();
                    hits.first().map(|&f| (hits.len() as u32, f, *hits.last().unwrap_or(&f)))
                };
                assert_eq!(scan_row_blocks(&a, &b, 30), want, "blocks, {len} px, density {density}");
                #[cfg(target_arch = "x86_64")]
                if super::super::x86::detected() == super::super::x86::Isa::Avx512 {
                    #[allow(unsafe_code)]
                    let wide = unsafe { scan_row_avx512(&a, &b, 30) };
                    assert_eq!(wide, want, "AVX-512, {len} px, density {density}");
                }
            }
        }
    }

    /// The motion area of two views a pixel at a time through `get`, the reference below.
    fn area_by_pixels(prev: &WindowView<'_>, next: &WindowView<'_>, t: u8) -> Option<MotionArea> {
        let mut area: Option<MotionArea> = None;
        for y in 0..next.height() {
            for x in 0..next.width() {
                if prev.get(x, y).unwrap().abs_diff(next.get(x, y).unwrap()) > t {
                    let (fx, fy) = next.to_frame(x, y);
                    area = Some(match area {
                        None => MotionArea { xmin: fx, xmax: fx, ymin: fy, ymax: fy, count: 1 },
                        Some(a) => MotionArea { xmin: a.xmin.min(fx), xmax: a.xmax.max(fx), ymin: a.ymin.min(fy), ymax: a.ymax.max(fy), count: a.count + 1 },
                    });
                }
            }
        }
        area
    }

    /// Whole frames, the AVX-512 path (where this CPU has it) and the portable one, against
    /// [`area_by_pixels`]: widths around the 64-pixel vectors, heights around the row groups,
    /// strides past the width, sub-views with origins, their decimated views and empty ones;
    /// no motion, one moving pixel anywhere, sparse, random and all-moving pixels; thresholds
    /// 0, 30, 254 and 255.
    #[test]
    fn frames_match_a_pixel_scan() {
        let mut x = 11u32;
        let mut rand = || {
            x = x.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            x >> 8
        };
        /// The view of `d` at `(x0, 0)`, its decimated view and two sub-views.
        fn views(d: &[u8], x0: usize, w: usize, h: usize, stride: usize, fx: u32) -> std::vec::Vec<WindowView<'_>> {
            let Ok(v) = WindowView::new(&d[x0..], w, h, stride, fx, 3) else { return std::vec::Vec::new() };
            let mut views = std::vec![v, v.decimated()];
            views.extend(v.sub(w.min(3), h.min(1), w - w.min(3), h - h.min(1)));
            views.extend(v.sub(0, 0, w / 2, h));
            views
        }
        let mut checked = 0;
        for w in [0usize, 1, 5, 63, 64, 65, 127, 128, 129, 200, 256, 300] {
            for h in [0usize, 1, 2, 3, 4, 5, 7, 9] {
                for pad in [0usize, 1, 37, 64] {
                    let (x0, stride) = (pad % 13, w + pad);
                    let len = (stride * h + x0).max(1);
                    for kind in 0..5 {
                        let prev: std::vec::Vec<u8> = (0..len).map(|_| if kind == 4 { 255 * (rand() % 2) as u8 } else { rand() as u8 }).collect();
                        let mut next = prev.clone();
                        match kind {
                            // One pixel (maybe outside the view: then none) by 255 or more than 30.
                            1 => {
                                let i = rand() as usize % len;
                                next[i] = if rand() % 2 == 0 { 255 - prev[i] } else { prev[i].wrapping_add(31 + rand() as u8 % 200) };
                            }
                            2 => {
                                for q in next.iter_mut() {
                                    if rand() % 64 == 0 {
                                        *q = rand() as u8;
                                    }
                                }
                            }
                            3 => next.iter_mut().for_each(|q| *q = rand() as u8),
                            4 => next.iter_mut().for_each(|q| *q = 255 - *q),
                            _ => {}
                        }
                        let fx = 5 + pad as u32;
                        for (p, n) in views(&prev, x0, w, h, stride, fx).iter().zip(&views(&next, x0, w, h, stride, fx)) {
                            for t in [0, 30, 254, 255] {
                                let want = area_by_pixels(p, n, t);
                                let at = (w, h, stride, kind, p.width(), p.height(), p.step(), t);
                                assert_eq!(motion_rows(p, n, t, scan_row_blocks), want, "portable, {at:?}");
                                assert_eq!(detect_motion(p, n, t).unwrap(), want, "{at:?}");
                                #[cfg(target_arch = "x86_64")]
                                if super::super::x86::detected() == super::super::x86::Isa::Avx512 {
                                    // SAFETY: the CPU and the OS run AVX-512 F and BW (checked).
                                    #[allow(unsafe_code)]
                                    let wide = unsafe { motion_avx512(p, n, t) };
                                    assert_eq!(wide, want, "AVX-512, {at:?}");
                                }
                                checked += usize::from(want.is_some());
                            }
                        }
                    }
                }
            }
        }
        // Most cases move somewhere.
        assert!(checked > 5000, "{checked}");
    }

    #[test]
    fn decimated_and_mismatch() {
        let prev = [0u8; 16];
        let mut next = [0u8; 16];
        next[2 * 4 + 2] = 200; // frame (2,2) = decimated (1,1)
        next[3] = 200; // odd column: invisible at 25 %
        let p = WindowView::packed(&prev, 4, 4).unwrap();
        let n = WindowView::packed(&next, 4, 4).unwrap();
        let a = detect_motion(&p.decimated(), &n.decimated(), 10)
            .unwrap()
            .unwrap();
        assert_eq!(
            a,
            MotionArea {
                xmin: 2,
                xmax: 2,
                ymin: 2,
                ymax: 2,
                count: 1
            }
        );
        let small = WindowView::packed(&prev, 2, 2).unwrap();
        assert_eq!(detect_motion(&small, &n, 1), Err(MotionError::SizeMismatch));
    }
}
