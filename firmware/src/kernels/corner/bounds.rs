//! The thesis' corner rules (3.2.3, 3.3): bounding points, Q1/Q2/Q3 with MidNum, and
//! the Golden Section Search.

use super::{CornerCase, CornerParams, NoCorner};

/// Golden ratio conjugate used by the Golden Section Search (thesis 3.3: the middle
/// point sits 0.38 from one end and 0.62 from the other).
const GOLDEN: f32 = 0.618_034;

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

/// An edge pixel position in window coordinates.
pub type Pixel = (i32, i32);

/// The eight bounding points of thesis 3.2.3, in window coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BoundingPoints {
    /// First minimum bounding X: `x00 = min x`, `y00 = min y` on column `x00`.
    pub p00: Pixel,
    /// Last minimum bounding X: `(x00, max y on column x00)`.
    pub p01: Pixel,
    /// First maximum bounding X: `x10 = max x`, `y10 = min y` on column `x10`.
    pub p10: Pixel,
    /// Last maximum bounding X: `(x10, max y on column x10)`.
    pub p11: Pixel,
    /// First minimum bounding Y: `ȳ00 = min y`, `x̄00 = min x` on row `ȳ00`.
    pub bar_p00: Pixel,
    /// Last minimum bounding Y: `(max x on row ȳ00, ȳ00)`.
    pub bar_p01: Pixel,
    /// First maximum bounding Y: `ȳ10 = max y`, `x̄10 = min x` on row `ȳ10`.
    pub bar_p10: Pixel,
    /// Last maximum bounding Y: `(max x on row ȳ10, ȳ10)`.
    pub bar_p11: Pixel,
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
fn mid_num(map: &[u8], w: usize, h: usize, a: Pixel, b: Pixel) -> u32 {
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
pub(super) fn corner_from_bounds(
    map: &[u8],
    w: usize,
    h: usize,
    b: &BoundingPoints,
    params: &CornerParams,
) -> Result<(f32, f32, CornerCase), NoCorner> {
    let tol = i32::from(params.distinct_tol);
    let distinct = |p: Pixel, q: Pixel| (p.0 - q.0).abs().max((p.1 - q.1).abs()) > tol;
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
    let fresh = |p: Pixel| distinct(p, q1) && distinct(p, q2);
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
fn perpendicular_reach(map: &[u8], w: usize, h: usize, v: (f32, f32), m: f32) -> (f32, Pixel) {
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
    q1: Pixel,
    q2: Pixel,
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

/// [`bounding_points`] of bit rows (`None` if no bit is set).
pub(super) fn bounding_points_bits(rows: &[u64]) -> Option<BoundingPoints> {
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
