//! Beyond the thesis: the corner as the intersection of the two edge lines.
//!
//! The thesis' rules (3.2.3) return one pixel of the edge band, chosen by the band's
//! bounding box, so they depend on the orientation and are off by half a band width at
//! best. Fitting lines is the approach the thesis sets aside (3.1, \[Jain95b\]) because
//! edge pixels near the corner get assigned to the wrong side; here the sides are told
//! apart by gradient orientation, and the pixels near the apex, where the two bands
//! merge, are left out of the fits:
//!
//! 1. **Sub-pixel edge points**: every clean edge pixel that is a maximum of the
//!    Sobel magnitude `m = sqrt(gx² + gy²)` along the pixel axis closer to its gradient
//!    gives the vertex of the parabola through the three magnitudes on that axis,
//!    `p + ½ (m₋ - m₊) / (m₋ - 2m + m₊)` (Devernay's sub-pixel edge point). Only
//!    pixels whose Sobel sums stay inside the window count: the reflected border
//!    distorts the gradient.
//! 2. **Two sides**: 2-means on the doubled gradient angle `(cos 2θ, sin 2θ)` (weights
//!    `m`), so both polarities and either direction of a gradient give the same line
//!    orientation.
//! 3. **Lines**: per side, a line through the `m`-weighted centroid of its points
//!    whose orientation is within 20° of the side's ([`COS_2_SIDE_TOL`]), along the mean of
//!    their total least squares direction and gradient orientation ([`fit_side`]);
//!    then three more fits without the points closer than [`MERGE_DIST`] to the other
//!    side's ray (the merged bands at the apex) or, after the first, farther than
//!    [`OUTLIER_DIST`] from their own line.
//! 4. **Apex**: the intersection of the two lines.
//!
//! Cost (the Cortex-M4F runs it, `docs/firmware-target.md`): each point's orientation and
//! magnitude are computed once, when it is collected, and the passes (2-means rounds,
//! fits, rays) only read them; which points a pass takes is kept as per-point flags, so a
//! fit whose points did not change is not redone and the iterations stop once nothing
//! moves (the results are those of running every round: each round is a pure function of
//! what changed). No trigonometric function is evaluated (the M4F's FPU has none, and
//! `libm`'s `sinf`/`cosf` work in soft-float `f64`): orientations stay unit vectors of the
//! doubled angle, halved by [`half_angle`] and binned by comparisons ([`bin`]); angles that
//! do not depend on the points are constants ([`SIN_MIN_ANGLE`], [`CENTRES`], [`EDGES`]),
//! checked by the tests.

use super::NoCorner;
use crate::kernels::fmath::sqrtf;

/// Most sub-pixel edge points kept. A point is an interior pixel, so windows up to 47x47
/// never reach it (nor the `N x N` room of a detector of side `N`); larger windows keep the
/// first ones in raster order.
const MAX_POINTS: usize = 2048;

/// A point belongs to a side when its edge orientation is within 20° of the side's (the
/// two sides of a 45-135° wedge are at least 45° apart): when the dot product of their
/// doubled-angle orientations is at least this, `cos 40°` as `libm::cosf` computes it.
const COS_2_SIDE_TOL: f32 = f32::from_bits(0x3f44_1b7d);

/// Bins of the orientation histogram seeding the 2-means (10° of doubled angle each).
const BINS: usize = 36;

/// Sides closer than this many degrees to parallel are one straight edge.
const MIN_ANGLE_DEG: f32 = 30.0;

/// `sin(MIN_ANGLE_DEG)` as `libm::sinf` computes it (0.5 exactly).
const SIN_MIN_ANGLE: f32 = f32::from_bits(0x3f00_0000);

/// `cos(2 MIN_ANGLE_DEG)` as `libm::cosf` computes it (one ulp under 0.5).
const COS_2_MIN_ANGLE: f32 = f32::from_bits(0x3eff_ffff);

/// `(cos a, sin a)` of the centre `a = (i + ½)·2π/BINS - π` of histogram bin `i`, as
/// `libm::cosf` and `libm::sinf` compute them (their last bits are not symmetric).
const CENTRES: [(u32, u32); BINS] = [
    (0xbf7f_069e, 0xbdb2_7ea8),
    (0xbf77_46eb, 0xbe84_83ea),
    (0xbf68_03c9, 0xbed8_616e),
    (0xbf51_b3f3, 0xbf12_d5e8),
    (0xbf35_04f3, 0xbf35_04f3),
    (0xbf12_d5e8, 0xbf51_b3f2),
    (0xbed8_616e, 0xbf68_03c9),
    (0xbe84_83ee, 0xbf77_46ea),
    (0xbdb2_7eb9, 0xbf7f_069e),
    (0x3db2_7ebe, 0xbf7f_069e),
    (0x3e84_83ef, 0xbf77_46ea),
    (0x3ed8_616b, 0xbf68_03ca),
    (0x3f12_d5e7, 0xbf51_b3f3),
    (0x3f35_04f5, 0xbf35_04f1),
    (0x3f51_b3f4, 0xbf12_d5e6),
    (0x3f68_03ca, 0xbed8_6169),
    (0x3f77_46ea, 0xbe84_83ec),
    (0x3f7f_069e, 0xbdb2_7eb3),
    (0x3f7f_069e, 0x3db2_7eb3),
    (0x3f77_46e9, 0x3e84_83f4),
    (0x3f68_03c8, 0x3ed8_6170),
    (0x3f51_b3f2, 0x3f12_d5e9),
    (0x3f35_04f2, 0x3f35_04f4),
    (0x3f12_d5e7, 0x3f51_b3f3),
    (0x3ed8_616b, 0x3f68_03ca),
    (0x3e84_83ef, 0x3f77_46ea),
    (0x3db2_7ebe, 0x3f7f_069e),
    (0xbdb2_7ee9, 0x3f7f_069d),
    (0xbe84_83f9, 0x3f77_46e9),
    (0xbed8_6175, 0x3f68_03c7),
    (0xbf12_d5ec, 0x3f51_b3f0),
    (0xbf35_04f6, 0x3f35_04f0),
    (0xbf51_b3f5, 0x3f12_d5e5),
    (0xbf68_03cb, 0x3ed8_6166),
    (0xbf77_46eb, 0x3e84_83ea),
    (0xbf7f_069e, 0x3db2_7ea8),
];

/// `(cos e, sin e)` of the bin edges `e = k·2π/BINS` inside `(0, π)` (`k = 1..BINS/2`),
/// rounded to `f32`.
const EDGES: [(f32, f32); BINS / 2 - 1] = [
    (0.984_807_7, 0.173_648_18),
    (0.9396926, 0.34202014),
    (0.8660254, 0.5),
    (0.76604444, 0.64278761),
    (0.64278761, 0.76604444),
    (0.5, 0.8660254),
    (0.34202014, 0.9396926),
    (0.173_648_18, 0.984_807_7),
    (0.0, 1.0),
    (-0.173_648_18, 0.984_807_7),
    (-0.34202014, 0.9396926),
    (-0.5, 0.8660254),
    (-0.64278761, 0.76604444),
    (-0.76604444, 0.64278761),
    (-0.8660254, 0.5),
    (-0.9396926, 0.34202014),
    (-0.984_807_7, 0.173_648_18),
];

/// The histogram bin of the doubled-angle orientation `(c, s)`: bin `i` holds the angles
/// `atan2(s, c)` in `[i·2π/BINS - π, (i+1)·2π/BINS - π)`. The lower half turn is turned by
/// π onto the upper one, where an angle is past edge `e` iff `(cos e, sin e) × (c, s) >= 0`,
/// so the bin is found by comparisons (a binary search of [`EDGES`]), without `atan2`.
fn bin(c: f32, s: f32) -> usize {
    let (half, c, s) = if s < 0.0 { (0, -c, -s) } else { (BINS / 2, c, s) };
    let past = EDGES.partition_point(|&(ec, es)| s * ec - c * es >= 0.0);
    half + past
}

/// Points closer than this to the other side's ray are left out (px): the Sobel band
/// of a blurred edge is about 4 px wide, so within 3 px the two bands overlap.
const MERGE_DIST: f32 = 3.0;

/// Points farther than this from their own fitted line are outliers (px).
const OUTLIER_DIST: f32 = 1.0;

/// Unit directions of the two edges away from the apex.
pub(super) type Rays = [(f32, f32); 2];

/// Fewest points per side for a line.
const MIN_SIDE_POINTS: usize = 2;

/// Fewest points per side for a total least squares direction.
const MIN_TLS_POINTS: usize = 5;

/// Per-point flag: the 2-means puts the point with the second centre.
const SECOND: u8 = 1;
/// Per-point flags: the point is on side 0, 1 (its orientation is within the tolerance).
const ON_SIDE: [u8; 2] = [2, 4];
/// Per-point flags: the point is among those side 0, 1's current line was fitted to.
const IN_FIT: [u8; 2] = [8, 16];

/// The sub-pixel edge points of one window (fixed capacity), each with its flags.
pub(super) struct EdgePoints<const N: usize> {
    /// Room for a point per pixel of an `N x N` window, of which at most [`MAX_POINTS`] are
    /// taken.
    points: [[EdgePoint; N]; N],
    /// What the passes of [`apex_from_points`] found about each point ([`SECOND`],
    /// [`ON_SIDE`], [`IN_FIT`]).
    flags: [[u8; N]; N],
    n: usize,
}

impl<const N: usize> EdgePoints<N> {
    pub(super) const fn new() -> Self {
        const NONE: EdgePoint = EdgePoint { x: 0.0, y: 0.0, c2: 0.0, s2: 0.0, m: 0.0 };
        Self { points: [[NONE; N]; N], flags: [[0; N]; N], n: 0 }
    }

    /// Appends a point at `(x, y)` with Sobel gradient `(gx, gy)` of magnitude
    /// `m = sqrt(gx² + gy²)`; `false` when full. A zero gradient has no orientation: such a
    /// point takes no part and is not kept. `|g| <= 4·255`, so `gx²`, `gy²` and their sum
    /// are below 2²⁴ and exact in `f32`.
    fn push(&mut self, x: f32, y: f32, gx: i32, gy: i32, m: f32) -> bool {
        let (gx, gy) = (gx as f32, gy as f32);
        let m2 = gx * gx + gy * gy;
        if m2 <= 0.0 {
            return true;
        }
        let Some(slot) = self.points.as_flattened_mut().get_mut(self.n).filter(|_| self.n < MAX_POINTS) else { return false };
        *slot = EdgePoint { x, y, c2: (gx * gx - gy * gy) / m2, s2: 2.0 * gx * gy / m2, m };
        self.n += 1;
        true
    }

    /// Empties the list.
    pub(super) fn clear(&mut self) {
        self.n = 0;
    }

    /// The points' fields `(x, y, cos 2θ, sin 2θ, m)` as bits, in the order collected (for the
    /// x86 vector passes' test).
    #[cfg(all(test, target_arch = "x86_64"))]
    pub(super) fn bits(&self) -> impl Iterator<Item = [u32; 5]> + '_ {
        self.iter().map(|(p, _)| [p.x, p.y, p.c2, p.s2, p.m].map(f32::to_bits))
    }

    /// The points, each with its flags, in the order collected.
    fn iter(&self) -> impl Iterator<Item = (&EdgePoint, u8)> + '_ {
        self.points.as_flattened().iter().zip(self.flags.as_flattened().iter().copied()).take(self.n)
    }

    /// The points whose flags include `flag`.
    fn with(&self, flag: u8) -> impl Iterator<Item = &EdgePoint> + '_ {
        self.iter().filter(move |(_, f)| f & flag != 0).map(|(p, _)| p)
    }

    /// Sets or clears the flags `flag` (one or more bits) of every point by `set` (given the
    /// point and its flags); whether any point's flags changed.
    fn mark(&mut self, flag: u8, set: impl Fn(&EdgePoint, u8) -> bool) -> bool {
        let mut changed = false;
        for (p, f) in self.points.as_flattened().iter().zip(self.flags.as_flattened_mut().iter_mut()).take(self.n) {
            let new = if set(p, *f) { *f | flag } else { *f & !flag };
            changed |= new != *f;
            *f = new;
        }
        changed
    }
}

/// A sub-pixel edge point: its position (px), the unit doubled-angle orientation
/// `(cos 2θ, sin 2θ)` of the gradient at its edge pixel, and the gradient's magnitude `m`.
#[derive(Clone, Copy)]
struct EdgePoint {
    x: f32,
    y: f32,
    c2: f32,
    s2: f32,
    m: f32,
}

/// Sobel `(gx, gy)` at the centre of the 3x3 block of rows `up`, `mid`, `down`.
#[inline(always)]
fn sobel3([a, b, c]: [i32; 3], [d, _, f]: [i32; 3], [g, k, l]: [i32; 3]) -> (i32, i32) {
    ((c - a) + 2 * (f - d) + (l - g), (g + 2 * k + l) - (a + 2 * b + c))
}

/// `gx² + gy²` at the centre of a 3x3 block ([`sobel3`]).
#[inline(always)]
fn mag2(up: [i32; 3], mid: [i32; 3], down: [i32; 3]) -> i32 {
    let (gx, gy) = sobel3(up, mid, down);
    gx * gx + gy * gy
}

/// `L` pixels of row `y` of `wide` from column `x`, widened; `None` past the rows or columns.
#[inline(always)]
fn run<const N: usize, const L: usize>(wide: &[[i16; N]], x: usize, y: usize) -> Option<[i32; L]> {
    Some(<&[i16; L]>::try_from(wide.get(y)?.get(x..x + L)?).ok()?.map(i32::from))
}

/// Sobel `(gx, gy)` at an interior pixel of the `w x h` window held in `wide` (no
/// border handling: `1 <= x <= w-2`, `1 <= y <= h-2`); `None` otherwise.
fn grad<const N: usize>(wide: &[[i16; N]], w: usize, h: usize, x: usize, y: usize) -> Option<(i32, i32)> {
    if x == 0 || y == 0 || x + 1 >= w || y + 1 >= h {
        return None;
    }
    Some(sobel3(run(wide, x - 1, y - 1)?, run(wide, x - 1, y)?, run(wide, x - 1, y + 1)?))
}

/// `gx² + gy²` at the pixels before and after `(x, y)` along `x` (`along_x`) or along `y`,
/// `None` where either is not an interior pixel of the `w x h` window. Their two 3x3 blocks
/// are read as one 3x5 (or 5x3) block: a bounds check a row, not one a row of each block.
fn neighbour_mags<const N: usize>(wide: &[[i16; N]], w: usize, h: usize, (x, y): (usize, usize), along_x: bool) -> Option<(i32, i32)> {
    if along_x {
        if x < 2 || x + 2 >= w || y == 0 || y + 1 >= h {
            return None;
        }
        let ([u0, u1, u2, u3, u4], [m0, m1, m2, m3, m4], [d0, d1, d2, d3, d4]) = (run(wide, x - 2, y - 1)?, run(wide, x - 2, y)?, run(wide, x - 2, y + 1)?);
        Some((mag2([u0, u1, u2], [m0, m1, m2], [d0, d1, d2]), mag2([u2, u3, u4], [m2, m3, m4], [d2, d3, d4])))
    } else {
        if y < 2 || y + 2 >= h || x == 0 || x + 1 >= w {
            return None;
        }
        let r = |j: usize| run::<N, 3>(wide, x - 1, j);
        let (r0, r1, r2, r3, r4) = (r(y - 2)?, r(y - 1)?, r(y)?, r(y + 1)?, r(y + 2)?);
        Some((mag2(r0, r1, r2), mag2(r2, r3, r4)))
    }
}

/// Collects the sub-pixel edge points (step 1) of the clean edge pixels `rows` (bit `x`
/// of row `y` = pixel `(x, y)`) of the `w x h` window in `wide`.
pub(super) fn collect_points<const N: usize>(
    wide: &[[i16; N]],
    rows: &[u64],
    w: usize,
    h: usize,
    pts: &mut EdgePoints<N>,
) {
    pts.clear();
    for (y, &row) in rows.iter().enumerate().take(h) {
        let mut bits = row;
        while bits != 0 {
            let x = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            let Some((gx, gy)) = grad(wide, w, h, x, y) else { continue };
            // Compare along the axis closer to the gradient; both neighbours must be
            // interior pixels too.
            let horizontal = gx.abs() >= gy.abs();
            let Some((q0, q2)) = neighbour_mags(wide, w, h, (x, y), horizontal) else { continue };
            let q1 = gx * gx + gy * gy;
            // A maximum (compared squared: the magnitudes are not negative); ties broken
            // towards the lower index, so a plateau of two gives one point.
            if q1 < q0 || q1 <= q2 {
                continue;
            }
            if !push_peak(pts, (x, y), (gx, gy), [q0, q1, q2], horizontal) {
                return;
            }
        }
    }
}

/// Appends the sub-pixel edge point of the maximum at pixel `(x, y)` with gradient
/// `(gx, gy)`, whose squared magnitudes before, at and after it along `x` (`horizontal`) or
/// `y` are `q` (step 1, [`collect_points`]); `false` when full.
#[inline(always)]
pub(super) fn push_peak<const N: usize>(pts: &mut EdgePoints<N>, (x, y): (usize, usize), (gx, gy): (i32, i32), q: [i32; 3], horizontal: bool) -> bool {
    // Below 2²⁴: exact in `f32`, and so are their roots correctly rounded.
    let [m0, m1, m2] = q.map(|q| sqrtf(q as f32));
    let curv = m0 - 2.0 * m1 + m2;
    let off = if curv < 0.0 { (0.5 * (m0 - m2) / curv).clamp(-0.5, 0.5) } else { 0.0 };
    let (px, py) = if horizontal { (x as f32 + off, y as f32) } else { (x as f32, y as f32 + off) };
    pts.push(px, py, gx, gy, m1)
}

/// A fitted line `n·p = d` (`n` unit).
#[derive(Clone, Copy)]
struct Line {
    nx: f32,
    ny: f32,
    d: f32,
}

impl Line {
    fn dist(&self, x: f32, y: f32) -> f32 {
        (self.nx * x + self.ny * y - self.d).abs()
    }
}

/// `(x, y) / |(x, y)|`, `None` for the zero vector.
fn unit(x: f32, y: f32) -> Option<(f32, f32)> {
    let r = sqrtf(x * x + y * y);
    (r > 0.0).then(|| (x / r, y / r))
}

/// `(cos b, sin b)` for `b = ½ atan2(y, x)` in `(-π/2, π/2]`, without trigonometry: the
/// direction at half the angle of `v = (x, y)` bisects `v` and `(|v|, 0)`, i.e. it is along
/// `(|v| + x, y)`, or along `(|y|, ±(|v| - x))` (the same direction, without the
/// cancellation) when `x < 0`. `(1, 0)` for the zero vector, as `atan2(0, 0) = 0` gives.
fn half_angle(x: f32, y: f32) -> (f32, f32) {
    let r = sqrtf(x * x + y * y);
    let (bx, by) = if x >= 0.0 { (r + x, y) } else { (y.abs(), (r - x).copysign(y)) };
    unit(bx, by).unwrap_or((1.0, 0.0))
}

/// The line of one side through the `m`-weighted centroid of the points flagged `side`.
/// With at least [`MIN_TLS_POINTS`] points its normal is the mean, in
/// doubled angles, of two estimates: the normal of the principal axis of the weighted
/// scatter, `a = ½ atan2(2 Sxy, Sxx - Syy)` (total least squares), and the mean
/// gradient orientation `θ = ½ atan2(Σ m sin 2θᵢ, Σ m cos 2θᵢ)`, both kept as unit vectors
/// of the doubled angle and halved without trigonometry ([`half_angle`]); with fewer (a side cut
/// short by the window border) the gradient orientation alone. The scatter's slope is
/// noisy over a short side and the gradients are independent evidence: the mean
/// lowers the worst errors (1.85 to 1.14 px over 6000 random wedges). `None` with
/// fewer than [`MIN_SIDE_POINTS`] points.
fn fit_side<const N: usize>(pts: &EdgePoints<N>, side: u8) -> Option<Line> {
    let (mut sw, mut sx, mut sy, mut sc, mut ss, mut n) = (0.0f32, 0.0f32, 0.0f32, 0.0f32, 0.0f32, 0usize);
    for p in pts.with(side) {
        sw += p.m;
        sx += p.m * p.x;
        sy += p.m * p.y;
        sc += p.m * p.c2;
        ss += p.m * p.s2;
        n += 1;
    }
    if n < MIN_SIDE_POINTS || sw <= 0.0 {
        return None;
    }
    let (mx, my) = (sx / sw, sy / sw);
    let (nx, ny) = if n >= MIN_TLS_POINTS {
        let (mut sxx, mut sxy, mut syy) = (0.0f32, 0.0f32, 0.0f32);
        for p in pts.with(side) {
            let (dx, dy) = (p.x - mx, p.y - my);
            sxx += p.m * dx * dx;
            sxy += p.m * dx * dy;
            syy += p.m * dy * dy;
        }
        // The scatter's principal axis in doubled angles is (Sxx - Syy, 2 Sxy); its normal
        // is the opposite direction, averaged with the gradients' mean unit orientation.
        let (ac, as_) = unit(sxx - syy, 2.0 * sxy).unwrap_or((1.0, 0.0));
        let g = sqrtf(sc * sc + ss * ss).max(f32::MIN_POSITIVE);
        half_angle(sc / g - ac, ss / g - as_)
    } else {
        half_angle(sc, ss)
    };
    Some(Line { nx, ny, d: nx * mx + ny * my })
}

/// Intersection of two lines, `None` when they are within [`MIN_ANGLE_DEG`] of
/// parallel.
fn intersect(a: &Line, b: &Line) -> Option<(f32, f32)> {
    let det = a.nx * b.ny - a.ny * b.nx;
    if det.abs() < SIN_MIN_ANGLE {
        return None;
    }
    Some(((a.d * b.ny - b.d * a.ny) / det, (a.nx * b.d - b.nx * a.d) / det))
}

/// Unit direction of `line` pointing from `apex` towards the weighted mass of the
/// points flagged `side` (where the side's edge lies).
fn ray<const N: usize>(line: &Line, apex: (f32, f32), pts: &EdgePoints<N>, side: u8) -> (f32, f32) {
    let (tx, ty) = (line.ny, -line.nx);
    let s: f32 = pts.with(side).map(|p| p.m * ((p.x - apex.0) * tx + (p.y - apex.1) * ty)).sum();
    if s >= 0.0 {
        (tx, ty)
    } else {
        (-tx, -ty)
    }
}

/// Distance from `(x, y)` to the ray from `apex` along the unit `t`.
fn ray_dist(x: f32, y: f32, apex: (f32, f32), t: (f32, f32)) -> f32 {
    let (dx, dy) = (x - apex.0, y - apex.1);
    let along = dx * t.0 + dy * t.1;
    if along <= 0.0 {
        sqrtf(dx * dx + dy * dy)
    } else {
        (dx * t.1 - dy * t.0).abs()
    }
}

/// The highest bin of `hist` among those `ok` takes (the last of equal ones).
fn peak(hist: &[f32; BINS], ok: impl Fn(usize) -> bool) -> Option<usize> {
    hist.iter().enumerate().filter(|&(i, _)| ok(i)).max_by(|a, b| a.1.total_cmp(b.1)).map(|(i, _)| i)
}

/// 2-means of the points' doubled-angle orientations (step 2): the two unit centres;
/// leaves each point's [`SECOND`] flag telling its centre.
/// Seeds: the two highest peaks, at least `2·MIN_ANGLE_DEG` apart, of the `m`-weighted
/// histogram of doubled angles in [`BINS`] bins smoothed by `[1 2 1]`. (Seeding from
/// single points fails when a strong pixel where the bands merge has an orientation
/// between the sides.)
fn two_sides<const N: usize>(pts: &mut EdgePoints<N>) -> Option<[(f32, f32); 2]> {
    let mut hist = [0.0f32; BINS];
    let width = 2.0 * core::f32::consts::PI / BINS as f32;
    for (p, _) in pts.iter() {
        if let Some(hb) = hist.get_mut(bin(p.c2, p.s2)) {
            *hb += p.m;
        }
    }
    let at = |i: usize| hist.get(i % BINS).copied().unwrap_or(0.0);
    let smooth: [f32; BINS] = core::array::from_fn(|i| at(i + BINS - 1) + 2.0 * at(i) + at(i + 1));
    let first = peak(&smooth, |_| true)?;
    let apart = (2.0 * MIN_ANGLE_DEG.to_radians() / width) as usize;
    let second = peak(&smooth, |i| {
        let d = i.abs_diff(first);
        d.min(BINS - d) >= apart
    })?;
    let centre = |i: usize| CENTRES.get(i).map(|&(c, s)| (f32::from_bits(c), f32::from_bits(s)));
    let mut c = [centre(first)?, centre(second)?];
    // Converges in a few rounds; a fixed count keeps the time bounded. A round that
    // assigns every point as the one before would compute the same centres again, and so
    // would every later round: the iteration stops there.
    for round in 0..8 {
        let moved = pts.mark(SECOND, |p, _| p.c2 * c[1].0 + p.s2 * c[1].1 > p.c2 * c[0].0 + p.s2 * c[0].1);
        if round > 0 && !moved {
            break;
        }
        let mut acc = [(0.0f32, 0.0f32); 2];
        for (p, f) in pts.iter() {
            if let Some(a) = acc.get_mut(usize::from(f & SECOND != 0)) {
                a.0 += p.m * p.c2;
                a.1 += p.m * p.s2;
            }
        }
        for (ck, a) in c.iter_mut().zip(acc) {
            let norm = sqrtf(a.0 * a.0 + a.1 * a.1);
            if norm > 0.0 {
                *ck = (a.0 / norm, a.1 / norm);
            }
        }
    }
    Some(c)
}

/// The apex (window coordinates) from the sub-pixel edge points (steps 2-4), with the unit
/// directions of the two edges away from it.
///
/// Refuses with [`NoCorner::StraightLine`] when the two sides are within
/// [`MIN_ANGLE_DEG`] of parallel or one has fewer than [`MIN_SIDE_POINTS`] points,
/// [`NoCorner::TooFewPoints`] when a side keeps fewer once the points near the apex
/// are left out, and [`NoCorner::OutsideWindow`] when the apex is not within
/// `[0, w-1] x [0, h-1]`.
pub(super) fn apex_from_points<const N: usize>(pts: &mut EdgePoints<N>, w: usize, h: usize) -> Result<((f32, f32), Rays), NoCorner> {
    let c = two_sides(pts).ok_or(NoCorner::TooFewPoints)?;
    // Doubled angles: sides θ apart have centres 2θ apart.
    if c[0].0 * c[1].0 + c[0].1 * c[1].1 > COS_2_MIN_ANGLE {
        return Err(NoCorner::StraightLine);
    }
    // Each side's points, and the first lines, through all of them. A side without points:
    // one edge orientation only.
    for ((&ck, &side), &fit) in c.iter().zip(&ON_SIDE).zip(&IN_FIT) {
        pts.mark(side | fit, |p, _| p.c2 * ck.0 + p.s2 * ck.1 >= COS_2_SIDE_TOL);
    }
    let mut lines = [
        fit_side(pts, IN_FIT[0]).ok_or(NoCorner::StraightLine)?,
        fit_side(pts, IN_FIT[1]).ok_or(NoCorner::StraightLine)?,
    ];
    let mut apex = intersect(&lines[0], &lines[1]).ok_or(NoCorner::StraightLine)?;
    let rays_of = |pts: &EdgePoints<N>, lines: &[Line; 2], apex| {
        [ray(&lines[0], apex, pts, ON_SIDE[0]), ray(&lines[1], apex, pts, ON_SIDE[1])]
    };
    let mut rays = rays_of(pts, &lines, apex);
    for round in 0..3 {
        // Each side's points away from the other side's ray and, after the first round
        // (whose lines still lean towards the merged bands), near its own line. A side whose
        // points are those of its line keeps the line; when both do after the first round,
        // every later round would find the same.
        let prev = lines;
        let mut moved = false;
        for (k, (line, (&side, &fit))) in lines.iter_mut().zip(ON_SIDE.iter().zip(&IN_FIT)).enumerate() {
            let (own, other) = (prev.get(k), rays.get(k ^ 1));
            let keep = |p: &EdgePoint, f: u8| {
                f & side != 0
                    && (round == 0 || own.is_some_and(|l| l.dist(p.x, p.y) <= OUTLIER_DIST))
                    && other.is_some_and(|&t| ray_dist(p.x, p.y, apex, t) >= MERGE_DIST)
            };
            if pts.mark(fit, keep) {
                *line = fit_side(pts, fit).ok_or(NoCorner::TooFewPoints)?;
                moved = true;
            }
        }
        if moved {
            apex = intersect(&lines[0], &lines[1]).ok_or(NoCorner::StraightLine)?;
            rays = rays_of(pts, &lines, apex);
        } else if round > 0 {
            break;
        }
    }
    let inside = |v: f32, n: usize| v.is_finite() && v >= 0.0 && v <= n.saturating_sub(1) as f32;
    if inside(apex.0, w) && inside(apex.1, h) {
        Ok((apex, rays))
    } else {
        Err(NoCorner::OutsideWindow)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The angle constants are the bits `libm` computes for them.
    #[test]
    fn constants_are_libm_s() {
        let bits = |v: f32| v.to_bits();
        assert_eq!(bits(SIN_MIN_ANGLE), bits(libm::sinf(MIN_ANGLE_DEG.to_radians())));
        assert_eq!(bits(COS_2_MIN_ANGLE), bits(libm::cosf(2.0 * MIN_ANGLE_DEG.to_radians())));
        assert_eq!(bits(COS_2_SIDE_TOL), bits(libm::cosf(2.0 * 20f32.to_radians())));
        let width = 2.0 * core::f32::consts::PI / BINS as f32;
        for (i, &(c, s)) in CENTRES.iter().enumerate() {
            let a = (i as f32 + 0.5) * width - core::f32::consts::PI;
            assert_eq!((c, s), (bits(libm::cosf(a)), bits(libm::sinf(a))), "bin {i}");
        }
        for (k, &(c, s)) in (1..).zip(&EDGES) {
            let e = f64::from(k) * 2.0 * core::f64::consts::PI / BINS as f64;
            assert!((f64::from(c) - e.cos()).abs() < 1e-7 && (f64::from(s) - e.sin()).abs() < 1e-7, "edge {k}");
        }
    }

    /// Independent reference: `atan2`, `cos` and `sin` in `f64`.
    #[test]
    fn half_angle_is_half_of_atan2() {
        for k in 0..720 {
            let t = f64::from(k) * core::f64::consts::PI / 360.0 - core::f64::consts::PI + 1e-3;
            for r in [1e-3, 1.0, 250.0] {
                let (x, y) = ((r * t.cos()) as f32, (r * t.sin()) as f32);
                let b = 0.5 * f64::from(y).atan2(f64::from(x));
                let (c, s) = half_angle(x, y);
                assert!((f64::from(c) - b.cos()).abs() < 1e-6 && (f64::from(s) - b.sin()).abs() < 1e-6, "{t} {r}: {c} {s}");
            }
        }
        assert_eq!(half_angle(0.0, 0.0), (1.0, 0.0));
        assert_eq!(half_angle(-2.0, 0.0), (0.0, 1.0));
    }

    /// Independent reference: the bin by `atan2` in `f64`, away from the edges (where `f32`
    /// rounding may fall either way).
    #[test]
    fn bins_by_comparison_are_bins_by_angle() {
        let width = 2.0 * core::f64::consts::PI / BINS as f64;
        for k in 0..3600 {
            let t = f64::from(k) * core::f64::consts::PI / 1800.0 - core::f64::consts::PI;
            let (c, s) = (t.cos() as f32, t.sin() as f32);
            let a = f64::from(s).atan2(f64::from(c)) + core::f64::consts::PI;
            let frac = a / width - (a / width).floor();
            if frac > 1e-4 && frac < 1.0 - 1e-4 {
                assert_eq!(bin(c, s), ((a / width) as usize).min(BINS - 1), "{t}");
            }
        }
        assert_eq!(bin(1.0, 0.0), BINS / 2);
        assert_eq!(bin(-1.0, 0.0), BINS - 1);
        assert_eq!(bin(-1.0, -1e-30), 0);
    }
}
