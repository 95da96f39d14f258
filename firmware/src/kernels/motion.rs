//! Motion detection by image differencing (thesis 2.4, Watch window).
//!
//! The thesis estimates the temporal derivative by differencing,
//! `df/dt = (f(x,y,t) - f(x,y,t-δt)) / δt`, and thresholds it to separate motion from
//! noise. With `δt` one frame this is: pixel `(x, y)` moves iff
//! `|f(x,y,t) - f(x,y,t-1)| > T` (strict, like OpenCV `absdiff` + `THRESH_BINARY`).
//! The motion area is the bounding box and the count of moving pixels. It works on any
//! sub-window, including the MPDF strips (256x20 at the top and bottom of the frame).

use crate::kernels::view::WindowView;

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

/// Rows are counted in chunks of 255 bytes so that the per-lane `u8` counters cannot
/// overflow; this keeps the inner loop at 16 moving-pixel tests per SSE2 instruction.
const CHUNK: usize = 255;

#[inline]
fn count_row(a: &[u8], b: &[u8], t: u8) -> u32 {
    let mut total = 0u32;
    for (ca, cb) in a.chunks(CHUNK).zip(b.chunks(CHUNK)) {
        let c: u8 = ca.iter().zip(cb).fold(0u8, |acc, (&p, &q)| {
            acc.wrapping_add(u8::from(p.abs_diff(q) > t))
        });
        total += u32::from(c);
    }
    total
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
    let (w, h) = (next.width(), next.height());
    let mut area: Option<(usize, usize, usize, usize)> = None;
    let mut count = 0u32;
    for y in 0..h {
        let (rc, first, last) = match (prev.row(y), next.row(y)) {
            (Some(a), Some(b)) => {
                let c = count_row(a, b, threshold);
                if c == 0 {
                    continue;
                }
                let moving = |(p, q): (&u8, &u8)| p.abs_diff(*q) > threshold;
                let first = a.iter().zip(b).position(moving).unwrap_or(0);
                let last = a.iter().zip(b).rposition(moving).unwrap_or(w - 1);
                (c, first, last)
            }
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
        area = Some(match area {
            None => (first, last, y, y),
            Some((x0, x1, y0, _)) => (x0.min(first), x1.max(last), y0, y),
        });
    }
    Ok(area.map(|(x0, x1, y0, y1)| {
        let (fx0, fy0) = next.to_frame(x0, y0);
        let (fx1, fy1) = next.to_frame(x1, y1);
        MotionArea {
            xmin: fx0,
            xmax: fx1,
            ymin: fy0,
            ymax: fy1,
            count,
        }
    }))
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
