//! Window-based corner detector (thesis chapter 3).
//!
//! Pipeline (thesis Figure 3.1), each step a public function so it can be checked
//! against OpenCV:
//!
//! 1. **Sobel edges** ([`sobel_at`]): `gx`, `gy` with the 3x3 kernels of OpenCV
//!    `Sobel(ksize=3)` (`gx = [-1 0 1; -2 0 2; -1 0 1]`, `gy` its transpose) and
//!    OpenCV's default border `BORDER_REFLECT_101`, so edges reach the window border.
//!    The magnitude is the Euclidean norm, compared without a square root: a pixel is
//!    an edge iff `gx² + gy² > TH²` (exact in integers; the same edge map as
//!    `sqrt(gx² + gy²) > TH` and as the OpenCV benchmark script).
//! 2. **Pixel labelling** (3.2.1, [`keep_largest_component`]): 8-neighbour connected
//!    components (`|xi-xj| <= 1 ∧ |yi-yj| <= 1`); only the most populous label is kept
//!    (ties: the label met first in raster order).
//! 3. **Morphological opening** (3.2.2, [`open_cross`]): erosion then dilation with the
//!    3x3 plus-shaped element, OpenCV border semantics (outside = foreground for the
//!    erosion, background for the dilation).
//! 4. **Corner location** (3.2.3, 3.3, [`corner_from_edges`]): bounding points, Q1, Q2,
//!    Q3, MidNum logic, or the Golden Section Search when Q3 is undefined.
//!
//! Windows up to [`MAX_DIM`] x [`MAX_DIM`] are handled with fixed buffers held by a
//! [`CornerDetector`] (about 27 KiB, so it can live in a `static` on a microcontroller).

use crate::view::WindowView;

/// Largest window side handled by [`CornerDetector`] (the Foveal windows are 20x20 and
/// 24x24).
pub const MAX_DIM: usize = 64;
const CAP: usize = MAX_DIM * MAX_DIM;

/// Golden ratio conjugate used by the Golden Section Search (thesis 3.3: the middle
/// point sits 0.38 from one end and 0.62 from the other).
const GOLDEN: f32 = 0.618_034;

/// Parameters of the corner detector.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CornerParams {
    /// Edge threshold TH on `sqrt(gx² + gy²)` (thesis 3.4: good for 30 < TH < 70).
    pub threshold: u16,
    /// Two bounding points count as "the same point" in the Q1/Q2/Q3 rules when their
    /// Chebyshev distance is at most this many pixels. 0 is the thesis' literal `≠`;
    /// the default 2 is the width of a Sobel edge band, which the thesis' thin-edge
    /// reasoning implicitly assumes to be 0 (see the crate README).
    pub distinct_tol: u8,
    /// Beyond the thesis: report the centroid of the clean edge pixels within 2 px
    /// (5x5) of the located edge pixel instead of the pixel itself. The thesis' rules
    /// pick an extreme pixel of the edge band, which lies half a band width (1-2 px)
    /// outside the true corner; the centroid pulls it back to the band's centre line.
    pub refine: bool,
}

impl CornerParams {
    /// Threshold `th` with the default tolerance of 2 pixels and refinement on.
    pub fn new(threshold: u16) -> Self {
        Self { threshold, distinct_tol: 2, refine: true }
    }

    /// The thesis' rules literally: exact `≠` and the edge pixel itself.
    pub fn literal(threshold: u16) -> Self {
        Self { threshold, distinct_tol: 0, refine: false }
    }
}

/// Centroid of the set pixels within Chebyshev distance 2 of `(x, y)` rounded, or
/// `(x, y)` itself if there is none.
fn band_centroid(map: &[u8], w: usize, h: usize, x: f32, y: f32) -> (f32, f32) {
    let (cx, cy) = (libm::roundf(x) as i32, libm::roundf(y) as i32);
    let (mut sx, mut sy, mut n) = (0i32, 0i32, 0i32);
    for yy in (cy - 2).max(0)..=(cy + 2).min(h as i32 - 1) {
        for xx in (cx - 2).max(0)..=(cx + 2).min(w as i32 - 1) {
            if map.get(yy as usize * w + xx as usize).is_some_and(|&v| v != 0) {
                sx += xx;
                sy += yy;
                n += 1;
            }
        }
    }
    if n == 0 {
        (x, y)
    } else {
        (sx as f32 / n as f32, sy as f32 / n as f32)
    }
}

/// Why no corner was located.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NoCorner {
    /// The window has no pixel.
    Empty,
    /// The window is larger than [`MAX_DIM`] x [`MAX_DIM`].
    TooLarge,
    /// No pixel exceeds the edge threshold.
    NoEdges,
    /// The opening removed every edge pixel (edges thinner than the plus element).
    FilteredOut,
    /// Q1 and Q2 coincide: the edges form a vertical line.
    VerticalLine,
    /// Q1 and Q2 are on one row (GSS case): a horizontal line.
    HorizontalLine,
    /// Q3 undefined and no edge pixel lies off the line Q1-Q2: a straight line.
    StraightLine,
}

/// Which bounding point became Q3 (thesis 3.2.3, in the order of its case list).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Q3Source {
    /// First minimum bounding Y, `P̄00`.
    BarP00,
    /// First maximum bounding Y, `P̄10`.
    BarP10,
    /// Last minimum bounding Y, `P̄01`.
    BarP01,
    /// Last maximum bounding Y, `P̄11`.
    BarP11,
    /// Last minimum bounding X, `P01`.
    P01,
    /// Last maximum bounding X, `P11`.
    P11,
}

/// How the corner was found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CornerCase {
    /// Corner = Q1 (`MidNum(M12) > 0 ∧ MidNum(M13) > 0`), with Q3's source.
    Q1(Q3Source),
    /// Corner = Q2 (`MidNum(M12) > 0 ∧ MidNum(M13) = 0`).
    Q2(Q3Source),
    /// Corner = Q3 (`MidNum(M12) = 0`).
    Q3(Q3Source),
    /// Q3 undefined: farthest edge pixel from the line Q1-Q2 by Golden Section Search.
    Gss,
}

/// A located corner.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Corner {
    /// Column in frame coordinates.
    pub x: f32,
    /// Row in frame coordinates.
    pub y: f32,
    /// The rule that produced it.
    pub case: CornerCase,
    /// Edge pixels above the threshold (before filtering), for the information measures.
    pub edge_pixels: u32,
    /// Edge pixels left after labelling and opening.
    pub clean_pixels: u32,
}

/// An edge pixel position in window coordinates.
pub type Point = (i32, i32);

/// The eight bounding points of thesis 3.2.3, in window coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BoundingPoints {
    /// First minimum bounding X: `x00 = min x`, `y00 = min y` on column `x00`.
    pub p00: Point,
    /// Last minimum bounding X: `(x00, max y on column x00)`.
    pub p01: Point,
    /// First maximum bounding X: `x10 = max x`, `y10 = min y` on column `x10`.
    pub p10: Point,
    /// Last maximum bounding X: `(x10, max y on column x10)`.
    pub p11: Point,
    /// First minimum bounding Y: `ȳ00 = min y`, `x̄00 = min x` on row `ȳ00`.
    pub bar_p00: Point,
    /// Last minimum bounding Y: `(max x on row ȳ00, ȳ00)`.
    pub bar_p01: Point,
    /// First maximum bounding Y: `ȳ10 = max y`, `x̄10 = min x` on row `ȳ10`.
    pub bar_p10: Point,
    /// Last maximum bounding Y: `(max x on row ȳ10, ȳ10)`.
    pub bar_p11: Point,
}

/// BORDER_REFLECT_101 index: `-1 -> 1`, `n -> n-2` (`0` for a single pixel).
#[inline]
fn reflect(i: isize, n: usize) -> usize {
    let n = n as isize;
    let r = if i < 0 {
        -i
    } else if i >= n {
        2 * n - 2 - i
    } else {
        i
    };
    r.clamp(0, (n - 1).max(0)) as usize
}

/// Sobel derivatives `(gx, gy)` at view pixel `(x, y)` with 3x3 kernels and
/// `BORDER_REFLECT_101`, identical to OpenCV `Sobel(src, CV_32S, 1, 0, 3)` /
/// `(0, 1, 3)`. `None` outside the view.
pub fn sobel_at(view: &WindowView<'_>, x: usize, y: usize) -> Option<(i32, i32)> {
    let (w, h) = (view.width(), view.height());
    if x >= w || y >= h {
        return None;
    }
    let p = |dx: isize, dy: isize| -> i32 {
        let xx = reflect(x as isize + dx, w);
        let yy = reflect(y as isize + dy, h);
        i32::from(view.get(xx, yy).unwrap_or(0))
    };
    let gx = (p(1, -1) - p(-1, -1)) + 2 * (p(1, 0) - p(-1, 0)) + (p(1, 1) - p(-1, 1));
    let gy = (p(-1, 1) + 2 * p(0, 1) + p(1, 1)) - (p(-1, -1) + 2 * p(0, -1) + p(1, -1));
    Some((gx, gy))
}

/// Result of [`keep_largest_component`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Components {
    /// Number of labels including the background, as `cv::connectedComponents`.
    pub num_labels: u32,
    /// Pixels in the largest foreground component (0 if none).
    pub largest_area: u32,
}

/// Pixel labelling (thesis 3.2.1): labels the non-zero pixels of the `w x h` binary
/// `map` by 8-connectivity and clears every pixel not in the most populous component
/// (ties: first in raster order). `labels` and `stack` are scratch of at least
/// `(w+2)·(h+2)` entries (a padded frame); `None` if they or `map` are too short, or
/// `(w+2)·(h+2) > 65535`.
pub fn keep_largest_component(
    map: &mut [u8],
    w: usize,
    h: usize,
    labels: &mut [u16],
    stack: &mut [u16],
) -> Option<Components> {
    // Labels live in a frame padded by one background pixel on every side, so the eight
    // neighbours of any pixel are at fixed offsets and need no border tests.
    let pw = w.checked_add(2)?;
    let pn = pw.checked_mul(h.checked_add(2)?)?;
    if pn > usize::from(u16::MAX) {
        return None;
    }
    let map = map.get_mut(..w * h)?;
    let labels = labels.get_mut(..pn)?;
    let stack = stack.get_mut(..pn)?;
    // Background 0, unvisited foreground UNSEEN, then component labels 1, 2, ...
    const UNSEEN: u16 = u16::MAX;
    labels.iter_mut().for_each(|l| *l = 0);
    if w > 0 {
        for (src, dst) in map.chunks_exact(w).zip(labels.chunks_exact_mut(pw).skip(1)) {
            for (d, &v) in dst.iter_mut().skip(1).zip(src) {
                *d = if v != 0 { UNSEEN } else { 0 };
            }
        }
    }
    let offsets = [pw + 1, pw, pw - 1, 1];
    let (mut next, mut best, mut best_area) = (0u16, 0u16, 0u32);
    for start in pw..pn - pw {
        if labels.get(start) != Some(&UNSEEN) {
            continue;
        }
        // At most (w·h + 1) / 2 components, so labels stay below UNSEEN.
        next += 1;
        labels[start] = next;
        stack[0] = start as u16;
        let (mut sp, mut area) = (1usize, 0u32);
        while sp > 0 {
            sp -= 1;
            let i = usize::from(stack[sp]);
            area += 1;
            // i is an interior pixel of the padded frame: i ± (pw + 1) is inside it.
            for j in offsets.iter().flat_map(|&o| [i - o, i + o]) {
                if let Some(l) = labels.get_mut(j) {
                    if *l == UNSEEN {
                        *l = next;
                        // Each pixel is pushed once, so sp < pn always.
                        if let Some(s) = stack.get_mut(sp) {
                            *s = j as u16;
                            sp += 1;
                        }
                    }
                }
            }
        }
        if area > best_area {
            best = next;
            best_area = area;
        }
    }
    if w > 0 {
        for (dst, src) in map.chunks_exact_mut(w).zip(labels.chunks_exact(pw).skip(1)) {
            for (m, &l) in dst.iter_mut().zip(src.iter().skip(1)) {
                *m = u8::from(l != 0 && l == best);
            }
        }
    }
    Some(Components { num_labels: u32::from(next) + 1, largest_area: best_area })
}

/// Morphological opening (thesis 3.2.2) of the `w x h` binary `map` with the 3x3
/// plus-shaped element: erosion (a pixel survives iff it and its 4 neighbours are set;
/// outside the map counts as set) then dilation (a pixel is set iff it or a 4-neighbour
/// is set; outside counts as clear). These are OpenCV's `morphologyEx(MORPH_OPEN,
/// MORPH_CROSS 3x3)` default borders. `tmp` is scratch of `w*h` bytes. Returns the
/// number of set pixels, or `None` if a slice is too short.
pub fn open_cross(map: &mut [u8], w: usize, h: usize, tmp: &mut [u8]) -> Option<u32> {
    let n = w.checked_mul(h)?;
    let map = map.get_mut(..n)?;
    let tmp = tmp.get_mut(..n)?;
    if n == 0 {
        return Some(0);
    }
    map.iter_mut().for_each(|v| *v = u8::from(*v != 0));
    // Whole-row passes (zipped slices, so they vectorise): the centre row combined with
    // the rows above and below and with itself shifted one pixel left and right. Rows
    // or columns outside the map are simply skipped: skipping an AND is "outside = 1",
    // skipping an OR is "outside = 0".
    cross_pass(map, tmp, w, |a, b| a & b);
    cross_pass(tmp, map, w, |a, b| a | b);
    Some(map.iter().map(|&v| u32::from(v)).sum())
}

/// `dst[p] = op` over `src[p]` and its 4-neighbours that lie inside the map.
fn cross_pass(src: &[u8], dst: &mut [u8], w: usize, op: impl Fn(u8, u8) -> u8 + Copy) {
    dst.copy_from_slice(src);
    for (y, out) in dst.chunks_exact_mut(w).enumerate() {
        let row = |r: usize| src.get(r * w..(r + 1) * w);
        for nb in [y.checked_sub(1).and_then(row), row(y + 1)].into_iter().flatten() {
            out.iter_mut().zip(nb).for_each(|(o, &v)| *o = op(*o, v));
        }
        if let Some(cur) = row(y) {
            out.iter_mut().skip(1).zip(cur).for_each(|(o, &v)| *o = op(*o, v));
            out.iter_mut().zip(cur.iter().skip(1)).for_each(|(o, &v)| *o = op(*o, v));
        }
    }
}

/// The eight bounding points of the set pixels of a `w x h` binary map (thesis 3.2.3),
/// or `None` if no pixel is set or `map` is too short.
pub fn bounding_points(map: &[u8], w: usize, h: usize) -> Option<BoundingPoints> {
    let map = map.get(..w.checked_mul(h)?)?;
    let set = |x: usize, y: usize| map.get(y * w + x).is_some_and(|&v| v != 0);
    let rows_with = |y: usize| (0..w).filter(move |&x| set(x, y));
    let cols_with = |x: usize| (0..h).filter(move |&y| set(x, y));
    let ymin = (0..h).find(|&y| rows_with(y).next().is_some())?;
    let ymax = (0..h).rev().find(|&y| rows_with(y).next().is_some())?;
    let xmin = (0..w).find(|&x| cols_with(x).next().is_some())?;
    let xmax = (0..w).rev().find(|&x| cols_with(x).next().is_some())?;
    let p = |x: usize, y: usize| (x as i32, y as i32);
    Some(BoundingPoints {
        p00: p(xmin, cols_with(xmin).next()?),
        p01: p(xmin, cols_with(xmin).next_back()?),
        p10: p(xmax, cols_with(xmax).next()?),
        p11: p(xmax, cols_with(xmax).next_back()?),
        bar_p00: p(rows_with(ymin).next()?, ymin),
        bar_p01: p(rows_with(ymin).next_back()?, ymin),
        bar_p10: p(rows_with(ymax).next()?, ymax),
        bar_p11: p(rows_with(ymax).next_back()?, ymax),
    })
}

/// MidNum: number of set pixels in the 3x3 neighbourhood of the midpoint of `a` and `b`
/// (midpoint rounded down to a pixel).
fn mid_num(map: &[u8], w: usize, h: usize, a: Point, b: Point) -> u32 {
    let (mx, my) = ((a.0 + b.0).div_euclid(2), (a.1 + b.1).div_euclid(2));
    let mut n = 0;
    for y in my - 1..=my + 1 {
        for x in mx - 1..=mx + 1 {
            if x >= 0 && y >= 0 && (x as usize) < w && (y as usize) < h {
                n += u32::from(
                    map.get(y as usize * w + x as usize)
                        .is_some_and(|&v| v != 0),
                );
            }
        }
    }
    n
}

/// Corner location on a clean `w x h` edge map (thesis 3.2.3 and 3.3).
///
/// `Q1 = P00`, `Q2 = P10`; `Q3` is the first of `P̄00`, `P̄10`, `P̄01 (≠ P̄00)`,
/// `P̄11 (≠ P̄10)`, `P01 (≠ P00)`, `P11 (≠ P10)` that is also distinct from Q1 and Q2,
/// where "distinct" means Chebyshev distance `> distinct_tol`. With Q3 defined the
/// corner is Q3 if `MidNum(M12) = 0`, else Q2 if `MidNum(M13) = 0`, else Q1. With Q3
/// undefined, the Golden Section Search maximises over points `v` of the line `L`
/// through Q1 and Q2 the distance `D_p` from `v` to the last edge pixel on the
/// perpendicular through `v` (stepping `Δp = min(|m|, 1)` per eq. 3.1); the corner is
/// that edge pixel. Returns `(x, y, case)` in window coordinates.
pub fn corner_from_edges(
    map: &[u8],
    w: usize,
    h: usize,
    params: &CornerParams,
) -> Result<(f32, f32, CornerCase), NoCorner> {
    let b = bounding_points(map, w, h).ok_or(NoCorner::NoEdges)?;
    corner_from_bounds(map, w, h, &b, params)
}

/// [`corner_from_edges`] with the bounding points of `map` already known.
fn corner_from_bounds(
    map: &[u8],
    w: usize,
    h: usize,
    b: &BoundingPoints,
    params: &CornerParams,
) -> Result<(f32, f32, CornerCase), NoCorner> {
    let tol = i32::from(params.distinct_tol);
    let distinct = |p: Point, q: Point| (p.0 - q.0).abs().max((p.1 - q.1).abs()) > tol;
    let (q1, q2) = (b.p00, b.p10);
    // A Sobel edge band is 3-4 px wide, so with a tolerance a bounding box up to
    // 2·tol + 1 px across is one straight edge (the literal rule: exactly 0 px).
    let line_tol = if tol == 0 { 0 } else { 2 * tol + 1 };
    if !distinct(q1, q2) || q2.0 - q1.0 <= line_tol {
        return Err(NoCorner::VerticalLine);
    }
    if tol > 0 && b.bar_p10.1 - b.bar_p00.1 <= line_tol {
        return Err(NoCorner::HorizontalLine);
    }
    // The thesis: "the selection of Q3 is such that it remains distinct from Q1 and
    // Q2"; its last four cases state only the partner test, so the Q1/Q2 test is added
    // to them (otherwise a horizontal line would make Q3 = Q2).
    let fresh = |p: Point| distinct(p, q1) && distinct(p, q2);
    let q3 = if fresh(b.bar_p00) {
        Some((b.bar_p00, Q3Source::BarP00))
    } else if fresh(b.bar_p10) {
        Some((b.bar_p10, Q3Source::BarP10))
    } else if distinct(b.bar_p01, b.bar_p00) && fresh(b.bar_p01) {
        Some((b.bar_p01, Q3Source::BarP01))
    } else if distinct(b.bar_p11, b.bar_p10) && fresh(b.bar_p11) {
        Some((b.bar_p11, Q3Source::BarP11))
    } else if distinct(b.p01, b.p00) && fresh(b.p01) {
        Some((b.p01, Q3Source::P01))
    } else if distinct(b.p11, b.p10) && fresh(b.p11) {
        Some((b.p11, Q3Source::P11))
    } else {
        None
    };
    if let Some((q3, src)) = q3 {
        let (c, case) = if mid_num(map, w, h, q1, q2) == 0 {
            (q3, CornerCase::Q3(src))
        } else if mid_num(map, w, h, q1, q3) == 0 {
            (q2, CornerCase::Q2(src))
        } else {
            (q1, CornerCase::Q1(src))
        };
        return Ok((c.0 as f32, c.1 as f32, case));
    }
    if q1.1 == q2.1 {
        return Err(NoCorner::HorizontalLine);
    }
    gss_corner(map, w, h, q1, q2, tol)
}

/// Distance² from `v` to the last edge pixel on the perpendicular to L through `v`,
/// walking both ways (the thesis picks one side from the edge pixels of row `y_v`;
/// walking both sides and taking the farther is equivalent when the edges lie on one
/// side of L and robust when the row is ambiguous), with that pixel.
fn perpendicular_reach(map: &[u8], w: usize, h: usize, v: (f32, f32), m: f32) -> (f32, Point) {
    // Eq. 3.1: Δp = min(|m|, 1), m·m_p = -1; so each step moves at most 1 px per axis.
    let dp = m.abs().min(1.0);
    let mp = -1.0 / m;
    // Half steps: the thesis' unit steps can jump over a pixel of a thin diagonal edge
    // between two rounding positions.
    let (sx, sy) = (0.5 * dp, 0.5 * mp * dp);
    let mut best = (0.0f32, (libm::roundf(v.0) as i32, libm::roundf(v.1) as i32));
    for sign in [1.0f32, -1.0] {
        // A walk longer than the window diagonal leaves the window.
        for i in 0..(4 * (w + h)) as u32 {
            let t = sign * i as f32;
            let (x, y) = (v.0 + sx * t, v.1 + sy * t);
            let (xi, yi) = (libm::roundf(x) as i32, libm::roundf(y) as i32);
            if xi < 0 || yi < 0 || xi as usize >= w || yi as usize >= h {
                break;
            }
            if map
                .get(yi as usize * w + xi as usize)
                .is_some_and(|&p| p != 0)
            {
                let d2 = (x - v.0) * (x - v.0) + (y - v.1) * (y - v.1);
                if d2 > best.0 {
                    best = (d2, (xi, yi));
                }
            }
        }
    }
    best
}

/// Golden Section Search (thesis 3.3) for the edge pixel farthest from the line Q1-Q2.
fn gss_corner(
    map: &[u8],
    w: usize,
    h: usize,
    q1: Point,
    q2: Point,
    tol: i32,
) -> Result<(f32, f32, CornerCase), NoCorner> {
    let span = (q2.0 - q1.0) as f32;
    let m = (q2.1 - q1.1) as f32 / span;
    let f = |delta: f32| {
        let v = (q1.0 as f32 + delta, q1.1 as f32 + m * delta);
        perpendicular_reach(map, w, h, v, m)
    };
    // Bracket [a, c] in Δv = x_v - x00; interior points at 0.38 and 0.62 of it.
    let (mut a, mut c) = (0.0f32, span);
    let mut x1 = c - GOLDEN * (c - a);
    let mut x2 = a + GOLDEN * (c - a);
    let (mut f1, mut f2) = (f(x1), f(x2));
    let mut best = if f1.0 >= f2.0 { f1 } else { f2 };
    // Stop when the bracket is below half a pixel (bounded: span <= MAX window side).
    while c - a > 0.5 {
        if f1.0 >= f2.0 {
            c = x2;
            x2 = x1;
            f2 = f1;
            x1 = c - GOLDEN * (c - a);
            f1 = f(x1);
            if f1.0 > best.0 {
                best = f1;
            }
        } else {
            a = x1;
            x1 = x2;
            f1 = f2;
            x2 = a + GOLDEN * (c - a);
            f2 = f(x2);
            if f2.0 > best.0 {
                best = f2;
            }
        }
    }
    // F is a staircase on a pixel grid, so finish with the whole pixels around the
    // final bracket.
    let centre = libm::roundf(0.5 * (a + c));
    for d in [-1.0f32, 0.0, 1.0] {
        let x = (centre + d).clamp(0.0, span);
        let r = f(x);
        if r.0 > best.0 {
            best = r;
        }
    }
    let reach = (tol + 1) as f32;
    if best.0 <= reach * reach {
        return Err(NoCorner::StraightLine);
    }
    Ok((best.1 .0 as f32, best.1 .1 as f32, CornerCase::Gss))
}

/// Sobel + threshold of the `w x h` window in `wide` into bit rows `bits`, with `N`-pixel
/// fixed-length rows (`w <= N`; `M = N + 2`) so every loop is whole SIMD vectors.
/// Pixels beyond `w` are computed from whatever the rows hold there and masked off.
/// Returns the number of edge pixels.
fn sobel_rows<const N: usize, const M: usize>(
    wide: &[[i16; MAX_DIM]; MAX_DIM],
    bits: &mut [u64; MAX_DIM],
    w: usize,
    h: usize,
    th2: i32,
) -> u32 {
    let fixed = |y: usize| -> &[i16; N] {
        let r = wide.get(y).map_or(&[][..], |r| r.get(..N).unwrap_or(&[]));
        <&[i16; N]>::try_from(r).unwrap_or(&[0; N])
    };
    let mask = row_mask(w);
    let (l, r) = (reflect(-1, w), reflect(w as isize, w));
    let mut count = 0;
    for (y, out) in bits.iter_mut().enumerate().take(h) {
        let (up, mid, dn) = (
            fixed(reflect(y as isize - 1, h)),
            fixed(y),
            fixed(reflect(y as isize + 1, h)),
        );
        // Vertical pass: smooth = up + 2 mid + down, diff = down - up, at index x + 1,
        // then the reflect-101 margins at 0 and w + 1.
        let mut smooth = [0i16; M];
        let mut diff = [0i16; M];
        for x in 0..N {
            smooth[x + 1] = up[x] + 2 * mid[x] + dn[x];
            diff[x + 1] = dn[x] - up[x];
        }
        smooth[0] = smooth[l + 1];
        diff[0] = diff[l + 1];
        smooth[w + 1] = smooth[r + 1];
        diff[w + 1] = diff[r + 1];
        let mut edge = [0u8; N];
        for x in 0..N {
            let gx = i32::from(smooth[x + 2] - smooth[x]);
            let gy = i32::from(diff[x] + 2 * diff[x + 1] + diff[x + 2]);
            edge[x] = u8::from(gx * gx + gy * gy > th2);
        }
        let mut b = 0u64;
        for (k, c) in edge.chunks_exact(8).enumerate() {
            if let Ok(c) = <&[u8; 8]>::try_from(c) {
                b |= pack8(c) << (8 * k);
            }
        }
        *out = b & mask;
        count += out.count_ones();
    }
    count
}

/// The corner detector with its fixed working buffers (edge map, labels, stack).
pub struct CornerDetector {
    edges: [u8; CAP],
    /// Bit-packed edge rows (bit `x` of row `y` = pixel `(x, y)`).
    bits: [u64; MAX_DIM],
    /// The window widened to `i16`, one `MAX_DIM` row per window row (Sobel input).
    wide: [[i16; MAX_DIM]; MAX_DIM],
    runs: Runs,
    w: usize,
    h: usize,
    edge_pixels: u32,
}

/// Most horizontal runs of set pixels a `MAX_DIM x MAX_DIM` map can hold.
const MAX_RUNS: usize = MAX_DIM * MAX_DIM / 2;

/// Scratch of the run-based labelling ([`largest_component_bits`]).
struct Runs {
    x0: [u8; MAX_RUNS],
    x1: [u8; MAX_RUNS],
    y: [u8; MAX_RUNS],
    parent: [u16; MAX_RUNS],
    area: [u16; MAX_RUNS],
}

impl Runs {
    const fn new() -> Self {
        Self {
            x0: [0; MAX_RUNS],
            x1: [0; MAX_RUNS],
            y: [0; MAX_RUNS],
            parent: [0; MAX_RUNS],
            area: [0; MAX_RUNS],
        }
    }
}

/// Root of run `i` (path halving). Parents always point to smaller indices, so the root
/// is the component's first run in raster order.
#[inline]
fn find(parent: &mut [u16], mut i: usize) -> usize {
    loop {
        let p = usize::from(parent.get(i).copied().unwrap_or(0));
        if p == i {
            return i;
        }
        let gp = parent.get(p).copied().unwrap_or(0);
        if let Some(slot) = parent.get_mut(i) {
            *slot = gp;
        }
        i = p;
    }
}

/// Row mask of a `w`-pixel row (`1 <= w <= 64`).
#[inline]
fn row_mask(w: usize) -> u64 {
    if w >= 64 {
        u64::MAX
    } else {
        (1u64 << w) - 1
    }
}

/// [`keep_largest_component`] on bit rows: union-find over horizontal runs. Two runs of
/// consecutive rows are 8-connected iff their column ranges, each widened by one pixel,
/// overlap. The root of a component is its first run in raster order, so the largest
/// component with ties to the smallest root is the one `keep_largest_component` keeps.
/// Returns the number of pixels kept.
fn largest_component_bits(rows: &mut [u64], runs: &mut Runs) -> u32 {
    let Runs { x0, x1, y: ry, parent, area } = runs;
    let mut n = 0usize;
    let mut prev = (0usize, 0usize);
    for (y, row) in rows.iter().enumerate() {
        let start = n;
        let mut b = *row;
        while b != 0 && n < MAX_RUNS {
            let a = b.trailing_zeros();
            let len = (b >> a).trailing_ones();
            let end = a + len; // exclusive, <= 64
            b = if end >= 64 { 0 } else { b & (u64::MAX << end) };
            x0[n] = a as u8;
            x1[n] = (end - 1) as u8;
            ry[n] = y as u8;
            parent[n] = n as u16;
            area[n] = 0;
            n += 1;
        }
        // Merge with the runs of the previous row (two pointers, both sorted by x).
        let (mut i, mut j) = prev;
        while i < prev.1 && j < n {
            let (pa, pb, ca, cb) = (x0[i], x1[i], x0[j], x1[j]);
            if u16::from(pb) + 1 < u16::from(ca) {
                i += 1;
            } else if u16::from(cb) + 1 < u16::from(pa) {
                j += 1;
            } else {
                let (ri, rj) = (find(parent, i), find(parent, j));
                if ri < rj {
                    parent[rj] = ri as u16;
                } else if rj < ri {
                    parent[ri] = rj as u16;
                }
                if pb < cb {
                    i += 1;
                } else {
                    j += 1;
                }
            }
        }
        prev = (start, n);
    }
    let (mut best, mut best_area) = (usize::MAX, 0u32);
    for r in 0..n {
        let root = find(parent, r);
        parent[r] = root as u16;
        let len = u16::from(x1[r]) - u16::from(x0[r]) + 1;
        area[root] += len;
    }
    for r in 0..n {
        if usize::from(parent[r]) == r && u32::from(area[r]) > best_area {
            best = r;
            best_area = u32::from(area[r]);
        }
    }
    rows.iter_mut().for_each(|r| *r = 0);
    for r in 0..n {
        if usize::from(parent[r]) == best {
            let (a, e) = (u32::from(x0[r]), u32::from(x1[r]));
            let m = (u64::MAX >> (63 - e)) & (u64::MAX << a);
            if let Some(row) = rows.get_mut(usize::from(ry[r])) {
                *row |= m;
            }
        }
    }
    best_area
}

/// [`open_cross`] on bit rows of width `w`; returns the number of set pixels.
fn open_cross_bits(rows: &mut [u64], w: usize, tmp: &mut [u64]) -> u32 {
    let mask = row_mask(w);
    let left_out = 1u64; // pixel 0's left neighbour is outside
    let right_out = 1u64 << (w - 1).min(63);
    let h = rows.len().min(tmp.len());
    for y in 0..h {
        let c = rows[y];
        let up = if y > 0 { rows[y - 1] } else { u64::MAX };
        let dn = if y + 1 < h { rows[y + 1] } else { u64::MAX };
        tmp[y] = c & up & dn & ((c << 1) | left_out) & ((c >> 1) | right_out) & mask;
    }
    let mut count = 0;
    for y in 0..h {
        let e = tmp[y];
        let up = if y > 0 { tmp[y - 1] } else { 0 };
        let dn = if y + 1 < h { tmp[y + 1] } else { 0 };
        let d = (e | up | dn | (e << 1) | (e >> 1)) & mask;
        rows[y] = d;
        count += d.count_ones();
    }
    count
}

/// [`bounding_points`] of bit rows (`None` if no bit is set).
fn bounding_points_bits(rows: &[u64]) -> Option<BoundingPoints> {
    let ymin = rows.iter().position(|&r| r != 0)?;
    let ymax = rows.iter().rposition(|&r| r != 0)?;
    let lo = |r: u64| r.trailing_zeros() as i32;
    let hi = |r: u64| 63 - r.leading_zeros() as i32;
    let (mut xmin, mut xmax) = (64i32, -1i32);
    for &r in rows.iter().filter(|&&r| r != 0) {
        xmin = xmin.min(lo(r));
        xmax = xmax.max(hi(r));
    }
    let col = |x: i32| {
        let bit = 1u64 << x;
        let first = rows.iter().position(|&r| r & bit != 0).unwrap_or(0) as i32;
        let last = rows.iter().rposition(|&r| r & bit != 0).unwrap_or(0) as i32;
        (first, last)
    };
    let (a, b) = col(xmin);
    let (c, d) = col(xmax);
    let (rt, rb) = (rows[ymin], rows[ymax]);
    let (ymin, ymax) = (ymin as i32, ymax as i32);
    Some(BoundingPoints {
        p00: (xmin, a),
        p01: (xmin, b),
        p10: (xmax, c),
        p11: (xmax, d),
        bar_p00: (lo(rt), ymin),
        bar_p01: (hi(rt), ymin),
        bar_p10: (lo(rb), ymax),
        bar_p11: (hi(rb), ymax),
    })
}

/// `BYTES[b]`: the 8 bits of `b` as 8 bytes of 0/1, little-endian (bit 0 = byte 0).
const BYTES: [u64; 256] = {
    let mut t = [0u64; 256];
    let mut b = 0;
    while b < 256 {
        let mut k = 0;
        while k < 8 {
            if b & (1 << k) != 0 {
                t[b] |= 1u64 << (8 * k);
            }
            k += 1;
        }
        b += 1;
    }
    t
};

/// Packs 8 bytes of 0/1 (byte `k` = bit `k`) into a byte: `b_k` moves from bit `8k`
/// to bit `56 + k` of the product, and no two partial products collide.
#[inline(always)]
fn pack8(bytes: &[u8; 8]) -> u64 {
    u64::from_le_bytes(*bytes).wrapping_mul(0x0102_0408_1020_4080) >> 56
}

impl Default for CornerDetector {
    fn default() -> Self {
        Self::new()
    }
}

impl CornerDetector {
    /// A detector with zeroed buffers (`const`, so it can be a `static`).
    pub const fn new() -> Self {
        Self {
            edges: [0; CAP],
            bits: [0; MAX_DIM],
            wide: [[0; MAX_DIM]; MAX_DIM],
            runs: Runs::new(),
            w: 0,
            h: 0,
            edge_pixels: 0,
        }
    }

    /// Edge pixels above the threshold in the last [`detect`](Self::detect) call (before
    /// labelling and opening), for the information content measure (3.4.1).
    pub fn edge_pixels(&self) -> u32 {
        self.edge_pixels
    }

    /// The clean edge map of the last call (row-major, `width x height`, 1 = edge).
    pub fn edge_map(&self) -> (&[u8], usize, usize) {
        (
            self.edges.get(..self.w * self.h).unwrap_or(&[]),
            self.w,
            self.h,
        )
    }

    /// Thresholded Sobel edge map `gx² + gy² > TH²` of `view` into the bit rows;
    /// returns the number of edge pixels.
    fn threshold_edges(&mut self, view: &WindowView<'_>, th: u16) -> u32 {
        let (w, h) = (view.width(), view.height());
        if w == 0 || h == 0 || w > MAX_DIM || h > MAX_DIM {
            return 0;
        }
        for (y, r) in self.wide.iter_mut().take(h).enumerate() {
            match view.row(y) {
                Some(src) => {
                    for (d, &s) in r.iter_mut().zip(src) {
                        *d = i16::from(s);
                    }
                }
                None => {
                    for (d, s) in r.iter_mut().zip(view.row_iter(y)) {
                        *d = i16::from(s);
                    }
                }
            }
        }
        // |g| <= 4·255 per axis, so gx² + gy² <= 2.1e6 < i32::MAX: clamping TH² to
        // i32::MAX does not change any comparison.
        let th2 = i32::try_from(u32::from(th) * u32::from(th)).unwrap_or(i32::MAX);
        if w <= 32 {
            sobel_rows::<32, 34>(&self.wide, &mut self.bits, w, h, th2)
        } else {
            sobel_rows::<64, 66>(&self.wide, &mut self.bits, w, h, th2)
        }
    }

    /// Runs the whole chapter-3 pipeline on `view` and returns the corner in frame
    /// coordinates, or why there is none.
    pub fn detect(
        &mut self,
        view: &WindowView<'_>,
        params: &CornerParams,
    ) -> Result<Corner, NoCorner> {
        self.w = 0;
        self.h = 0;
        self.edge_pixels = 0;
        if view.is_empty() {
            return Err(NoCorner::Empty);
        }
        let (w, h) = (view.width(), view.height());
        if w > MAX_DIM || h > MAX_DIM {
            return Err(NoCorner::TooLarge);
        }
        self.w = w;
        self.h = h;
        self.edge_pixels = self.threshold_edges(view, params.threshold);
        if self.edge_pixels == 0 {
            return Err(NoCorner::NoEdges);
        }
        let rows = self.bits.get_mut(..h).ok_or(NoCorner::TooLarge)?;
        largest_component_bits(rows, &mut self.runs);
        let mut tmp = [0u64; MAX_DIM];
        let clean = open_cross_bits(rows, w, &mut tmp);
        // The byte map (for `edge_map` and the corner rules).
        for (dst, &r) in self.edges.chunks_exact_mut(w).zip(rows.iter()) {
            for (k, d) in dst.chunks_mut(8).enumerate() {
                let bytes = BYTES[((r >> (8 * k)) & 0xff) as usize].to_le_bytes();
                d.copy_from_slice(bytes.get(..d.len()).unwrap_or(&[]));
            }
        }
        if clean == 0 {
            return Err(NoCorner::FilteredOut);
        }
        let b = bounding_points_bits(rows).ok_or(NoCorner::FilteredOut)?;
        let (mut x, mut y, case) = corner_from_bounds(&self.edges, w, h, &b, params)?;
        if params.refine {
            (x, y) = band_centroid(&self.edges, w, h, x, y);
        }
        let (ox, oy) = view.origin();
        let step = view.step() as f32;
        Ok(Corner {
            x: ox as f32 + x * step,
            y: oy as f32 + y * step,
            case,
            edge_pixels: self.edge_pixels,
            clean_pixels: clean,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Parses a picture of `#` (edge) and `.` into a binary map.
    fn map(rows: &[&str]) -> ([u8; 64], usize, usize) {
        let mut m = [0u8; 64];
        let w = rows[0].len();
        for (y, r) in rows.iter().enumerate() {
            for (x, c) in r.bytes().enumerate() {
                m[y * w + x] = u8::from(c == b'#');
            }
        }
        (m, w, rows.len())
    }

    const LIT: CornerParams = CornerParams { threshold: 0, distinct_tol: 0, refine: false };

    #[test]
    fn reflect_101() {
        assert_eq!([reflect(-1, 5), reflect(5, 5), reflect(2, 5)], [1, 3, 2]);
        assert_eq!([reflect(-1, 1), reflect(1, 1)], [0, 0]);
    }

    #[test]
    fn sobel_hand_values() {
        // Step edge 0 | 100 between columns 1 and 2 of a 4x3 window.
        let d = [0, 0, 100, 100, 0, 0, 100, 100, 0, 0, 100, 100];
        let v = WindowView::packed(&d, 4, 3).unwrap();
        // gx at (1,1) = (100-0)*(1+2+1) = 400; gy = 0.
        assert_eq!(sobel_at(&v, 1, 1), Some((400, 0)));
        // Column 0 reflects column 1 onto -1: gx = 4*(0-0) = 0.
        assert_eq!(sobel_at(&v, 0, 0), Some((0, 0)));
        // Column 3: neighbour 4 reflects to 2: gx = 4*(100-100) = 0.
        assert_eq!(sobel_at(&v, 3, 2), Some((0, 0)));
        assert_eq!(sobel_at(&v, 4, 0), None);
        // The fast edge map agrees with sobel_at + threshold (400² > 399², not > 400²).
        let mut det = CornerDetector::new();
        det.w = 4;
        det.h = 3;
        assert_eq!(det.threshold_edges(&v, 400), 0);
        assert_eq!(det.threshold_edges(&v, 399), 6);
        assert_eq!(&det.bits[..3], &[0b0110, 0b0110, 0b0110]);
    }

    /// A xorshift64 generator for the random-map tests.
    fn xorshift(mut seed: u64) -> impl FnMut() -> u64 {
        move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        }
    }

    /// The bit-row pipeline of `detect` (run labelling, opening, bounding points) gives
    /// exactly the byte-map functions' results on random maps of every density.
    #[test]
    fn bit_pipeline_matches_byte_functions() {
        let mut rnd = xorshift(0x1234_5678_9abc_def0);
        let mut runs = Runs::new();
        for case in 0..3000 {
            let w = 1 + (rnd() % 64) as usize;
            let h = 1 + (rnd() % 64) as usize;
            let density = rnd() % 100;
            let mut m = std::vec![0u8; w * h];
            for v in m.iter_mut() {
                *v = u8::from(rnd() % 100 < density);
            }
            let mut bits = [0u64; MAX_DIM];
            for (y, b) in bits.iter_mut().take(h).enumerate() {
                for x in 0..w {
                    *b |= u64::from(m[y * w + x]) << x;
                }
            }
            let pn = (w + 2) * (h + 2);
            let (mut l, mut st) = (std::vec![0u16; pn], std::vec![0u16; pn]);
            let c = keep_largest_component(&mut m, w, h, &mut l, &mut st).unwrap();
            let area = largest_component_bits(&mut bits[..h], &mut runs);
            assert_eq!(area, c.largest_area, "case {case}");
            let mut tmp = std::vec![0u8; w * h];
            let n = open_cross(&mut m, w, h, &mut tmp).unwrap();
            let mut t = [0u64; MAX_DIM];
            assert_eq!(open_cross_bits(&mut bits[..h], w, &mut t), n, "case {case}");
            for y in 0..h {
                for x in 0..w {
                    assert_eq!(u8::from(bits[y] >> x & 1 != 0), m[y * w + x], "case {case} ({x},{y})");
                }
            }
            assert_eq!(bounding_points_bits(&bits[..h]), bounding_points(&m, w, h), "case {case}");
        }
    }

    /// The fixed-width Sobel rows agree with `sobel_at` + threshold on random windows,
    /// including strided (decimated) views and a detector reused across sizes.
    #[test]
    fn sobel_rows_match_sobel_at() {
        let mut rnd = xorshift(0x0ddb_a11c_afe5_eed5);
        let mut det = CornerDetector::new();
        for case in 0..600 {
            let (w, h) = (1 + (rnd() % 64) as usize, 1 + (rnd() % 64) as usize);
            let step = if case % 3 == 0 { 2 } else { 1 };
            let (fw, fh) = (w * step, h * step);
            let d: std::vec::Vec<u8> = (0..fw * fh).map(|_| rnd() as u8).collect();
            let mut v = WindowView::packed(&d, fw, fh).unwrap();
            if step == 2 {
                v = v.decimated();
            }
            let th = (rnd() % 1200) as u16;
            let n = det.threshold_edges(&v, th);
            let mut expect = 0;
            for y in 0..h {
                for x in 0..w {
                    let (gx, gy) = sobel_at(&v, x, y).unwrap();
                    let e = i64::from(gx * gx + gy * gy) > i64::from(th) * i64::from(th);
                    expect += u32::from(e);
                    assert_eq!(det.bits[y] >> x & 1 != 0, e, "case {case} ({x},{y})");
                }
                assert_eq!(det.bits[y] >> w.min(63) >> u32::from(w == 64), 0);
            }
            assert_eq!(n, expect);
        }
    }

    #[test]
    fn largest_component_8_connected() {
        let (mut m, w, h) = map(&["#..##", ".#..#", "....#", "##..."]);
        let (mut l, mut s) = ([0u16; 64], [0u16; 64]); // (5+2)·(4+2) = 42 entries
        let c = keep_largest_component(&mut m, w, h, &mut l, &mut s).unwrap();
        // Components: {(0,0),(1,1)} (diagonal), {(3,0),(4,0),(4,1),(4,2)}, {(0,3),(1,3)}.
        assert_eq!(
            c,
            Components {
                num_labels: 4,
                largest_area: 4
            }
        );
        assert_eq!(map(&["...##", "....#", "....#", "....."]).0, m);
    }

    #[test]
    fn opening_keeps_border_touching_plus() {
        // A 3-wide bar along the left border survives (outside counts as set for the
        // erosion); an isolated 2x2 block vanishes.
        let (mut m, w, h) = map(&["###...", "###.##", "###.##", "###..."]);
        let mut t = [0u8; 64];
        let n = open_cross(&mut m, w, h, &mut t).unwrap();
        assert_eq!(map(&["###...", "###...", "###...", "###..."]).0, m);
        assert_eq!(n, 12);
    }

    #[test]
    fn q3_is_bar_p00_diamond_tip() {
        // Tip at (3,0); edges down-left and down-right to the border.
        let (m, w, h) = map(&["...#...", "..#.#..", ".#...#.", "#.....#"]);
        let b = bounding_points(&m, w, h).unwrap();
        assert_eq!((b.p00, b.p10, b.bar_p00), ((0, 3), (6, 3), (3, 0)));
        // M12 = (3,3): no edge around (3,2..4) -> corner Q3.
        assert_eq!(
            corner_from_edges(&m, w, h, &LIT),
            Ok((3.0, 0.0, CornerCase::Q3(Q3Source::BarP00)))
        );
    }

    #[test]
    fn q1_corner_of_an_l() {
        // Corner at (0,0) of an L: Q1 = (0,0), Q2 = (4,0), Q3 = P̄10 = (0,3).
        let (m, w, h) = map(&["#####", "#....", "#....", "#...."]);
        assert_eq!(
            corner_from_edges(&m, w, h, &LIT),
            Ok((0.0, 0.0, CornerCase::Q1(Q3Source::BarP10)))
        );
    }

    #[test]
    fn q2_tip_pointing_right() {
        // ">" with the tip at (4,4): Q1 = (0,0), Q2 = (4,4), Q3 = P̄10 = (0,8);
        // M12 = (2,2) is on the upper edge, M13 = (0,4) has no edge within 3x3.
        let (m, w, h) = map(&[
            "#......", ".#.....", "..#....", "...#...", "....#..", "...#...", "..#....", ".#.....",
            "#......",
        ]);
        let mut big = [0u8; 64];
        big[..w * h].copy_from_slice(&m[..w * h]);
        let r = corner_from_edges(&big, w, h, &LIT);
        assert_eq!(r, Ok((4.0, 4.0, CornerCase::Q2(Q3Source::BarP10))));
    }

    #[test]
    fn gss_on_thin_v() {
        // Q3 undefined: edges from (0,0) to the corner (6,2) and on to (9,9); every
        // bounding point is Q1 = (0,0) or Q2 = (9,9).
        let mut m = [0u8; 100];
        let pts = [
            (0, 0),
            (1, 1),
            (2, 1),
            (3, 1),
            (4, 2),
            (5, 2),
            (6, 2),
            (7, 3),
            (7, 4),
            (7, 5),
            (8, 6),
            (8, 7),
            (8, 8),
            (9, 9),
        ];
        for (x, y) in pts {
            m[y * 10 + x] = 1;
        }
        let r = corner_from_edges(&m, 10, 10, &LIT).unwrap();
        assert_eq!(r.2, CornerCase::Gss);
        // Farthest pixels from y = x: (6,2) and (7,3), both at 4/√2 ≈ 2.83 px.
        assert!(
            (r.0 - 6.0).abs() <= 1.0 && (r.1 - 2.0).abs() <= 1.0,
            "{r:?}"
        );
    }

    /// Like `map` for larger pictures.
    fn big(rows: &[&str]) -> (std::vec::Vec<u8>, usize, usize) {
        let w = rows[0].len();
        let m = rows.iter().flat_map(|r| r.bytes().map(|c| u8::from(c == b'#'))).collect();
        (m, w, rows.len())
    }

    #[test]
    fn remaining_q3_cases() {
        // P̄01: a run along the top row, then a diagonal to the bottom-right.
        let top_run = [
            "#######......", ".......#.....", "........#....", ".........#...", "..........#..", "...........#.", "............#",
        ];
        let (m, w, h) = big(&top_run);
        assert_eq!(corner_from_edges(&m, w, h, &LIT), Ok((6.0, 0.0, CornerCase::Q3(Q3Source::BarP01))));
        // P̄11: the same upside down.
        let rev: std::vec::Vec<&str> = top_run.iter().rev().copied().collect();
        let (m, w, h) = big(&rev);
        assert_eq!(corner_from_edges(&m, w, h, &LIT), Ok((6.0, 6.0, CornerCase::Q3(Q3Source::BarP11))));
        // P01: a run down the left column, then a diagonal to the bottom-right.
        let rows: std::vec::Vec<std::string::String> = (0..13)
            .map(|y| (0..7).map(|x| if (x == 0 && y <= 6) || (y > 6 && x == y - 6) { '#' } else { '.' }).collect())
            .collect();
        let refs: std::vec::Vec<&str> = rows.iter().map(|r| r.as_str()).collect();
        let (m, w, h) = big(&refs);
        assert_eq!(corner_from_edges(&m, w, h, &LIT), Ok((0.0, 6.0, CornerCase::Q3(Q3Source::P01))));
        // P11: a diagonal from the bottom-left up to (6,6), then up the right column.
        let rows: std::vec::Vec<std::string::String> = (0..13)
            .map(|y| (0..7).map(|x| if (x == 6 && y <= 6) || (y > 6 && x == 12 - y) { '#' } else { '.' }).collect())
            .collect();
        let refs: std::vec::Vec<&str> = rows.iter().map(|r| r.as_str()).collect();
        let (m, w, h) = big(&refs);
        assert_eq!(corner_from_edges(&m, w, h, &LIT), Ok((6.0, 6.0, CornerCase::Q3(Q3Source::P11))));
    }

    #[test]
    fn lines_are_typed() {
        let (m, w, h) = map(&["..#..", "..#..", "..#.."]);
        assert_eq!(
            corner_from_edges(&m, w, h, &LIT),
            Err(NoCorner::VerticalLine)
        );
        let (m, w, h) = map(&[".....", "#####", "....."]);
        assert_eq!(
            corner_from_edges(&m, w, h, &LIT),
            Err(NoCorner::HorizontalLine)
        );
        let (m, w, h) = map(&["#....", ".#...", "..#..", "...#."]);
        assert_eq!(
            corner_from_edges(&m, w, h, &LIT),
            Err(NoCorner::StraightLine)
        );
        assert_eq!(
            corner_from_edges(&[0; 4], 2, 2, &LIT),
            Err(NoCorner::NoEdges)
        );
    }

    #[test]
    fn detector_rejects_large_and_flat() {
        let big = [0u8; 65 * 2];
        let mut d = CornerDetector::new();
        let v = WindowView::packed(&big, 65, 2).unwrap();
        assert_eq!(
            d.detect(&v, &CornerParams::new(50)),
            Err(NoCorner::TooLarge)
        );
        let flat = [9u8; 20 * 20];
        let v = WindowView::packed(&flat, 20, 20).unwrap();
        assert_eq!(d.detect(&v, &CornerParams::new(50)), Err(NoCorner::NoEdges));
        assert_eq!(d.edge_pixels(), 0);
    }
}
