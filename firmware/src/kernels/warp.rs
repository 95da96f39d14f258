//! Lucas-Kanade alignment of a template under a similarity warp (beyond the thesis, issue
//! 21): where the object turns or scales, the point found by translation alone is biased
//! (a turned patch's best shifted match is not where its centre is), and the template's
//! angle and scale are what a user wants reported.
//!
//! The warp maps a template pixel `(u, v)`, taken from the template's centre, to the window
//! position `W(u, v) = (x + a u - b v, y + b u + a v)`: a turn by `atan2(b, a)` and a scale
//! by `sqrt(a² + b²)` about the centre, which lands on `(x, y)`. The alignment is the
//! inverse compositional algorithm (Baker & Matthews, 2004), with the template's side
//! prepared once ([`LkTemplate`]: its interior pixels and their gradients `g`):
//!
//! - the steepest-descent images `s = (gx u + gy v, gy u - gx v, gx, gy)` (the gradient
//!   times the warp's Jacobian at the identity);
//! - each iteration samples the window bilinearly at `W(u, v)` for every interior pixel
//!   whose sample falls inside it, normalises the samples to the template's mean and
//!   deviation over those pixels (`Ŵ = (W - mean W) σ_T / σ_W + mean T`, as NCC is blind to
//!   gain and offset), solves `H Δ = Σ s (Ŵ - T)` with `H = Σ s sᵀ` over the same pixels,
//!   and composes the warp with the inverse of `Δ`'s: with `z = a + i b` and `t = x + i y`,
//!   `z ← z / (1 + Δ₀ + i Δ₁)` and `t ← t - z (Δ₂ + i Δ₃)`;
//! - it stops when the step moves no template pixel by more than [`CONVERGED`] px.
//!
//! Pixels that fall outside the window are left out of every sum (so the window need not
//! hold the turned or grown template whole), and at least [`MIN_INSIDE`] of them must be
//! in. An iteration that walks away from the template (its score [`MAX_LOSS`] under the best
//! seen) ends the alignment, refused. Arithmetic is `f32`; no allocation, no panic.
use crate::kernels::fmath::sqrtf;
use crate::kernels::refine::{LkTemplate, MAX_SIDE};
use crate::kernels::view::WindowView;

/// Iterations at most.
const ITERATIONS: usize = 10;
/// A step that moves no template pixel by more than this many pixels ends the iteration.
pub const CONVERGED: f32 = 0.03;
/// Fraction of the template's interior pixels that must sample inside the window.
pub const MIN_INSIDE: f32 = 0.7;
/// [`MIN_INSIDE`] for a template the frame's edge cuts (the window lies against that edge):
/// half, as the long-term sets' truth calls a target visible while half of it is in view
/// (issue 38). A centred template is then half in view when its target is.
pub const MIN_IN_VIEW: f32 = 0.5;
/// Farthest the template's centre may walk from the start before the alignment is refused
/// (the start is a match of the translated template: a longer walk is a divergence).
pub const MAX_WALK: f32 = 3.0;
/// Scales outside `1/MAX_SCALE ..= MAX_SCALE` are refused as divergence.
pub const MAX_SCALE: f32 = 2.0;
/// An iteration whose zero-mean NCC is more than this under the best of the earlier ones
/// ends the alignment, refused as divergence: Gauss-Newton's steps climb towards a match,
/// and a walk that has lost this much has left it (it may climb again, but elsewhere: in
/// the unit test below, to a pose turned 51 degrees and twice the size). Under an object
/// partly covered the walk slides off it and would otherwise run every iteration, the
/// template partly outside the window (issue 38: the Cortex-M4's frames in doubt). The
/// scores compared may be over different pixels (those inside the window), so a drop may
/// also be pixels leaving it. Of the 5,788 alignments of `experiment long-term`,
/// `appearance` and `real-footage` that reach [`crate::processors::adapt::ALIGN`] (a scratch
/// build logged each one's scores), 6 lose
/// more than 0.05 on the way, 2 more than 0.08 and 1 more than 0.1 (its score 0.53). At 0.1
/// no position, precision or recall of those experiments moves (9 more rows of the labelled
/// clips are measured unvouched, a track in doubt held a little longer); at 0.05 the earring
/// of `Megamind.avi` loses 12 vouched rows.
pub const MAX_LOSS: f32 = 0.1;

/// A similarity pose of a template in a window: its centre at `(x, y)` (window pixels) and
/// `(a, b) = scale (cos angle, sin angle)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// Window column of the template's centre.
    pub x: f32,
    /// Window row of the template's centre.
    pub y: f32,
    /// `scale cos(angle)`.
    pub a: f32,
    /// `scale sin(angle)`.
    pub b: f32,
}

impl Pose {
    /// The template's centre at `(x, y)`, turned by `angle` radians and scaled by `scale`.
    pub fn new(x: f32, y: f32, scale: f32, angle: f32) -> Pose {
        Pose { x, y, a: scale * libm::cosf(angle), b: scale * libm::sinf(angle) }
    }

    /// The scale: a side of the template spans `scale` times its pixels in the window.
    pub fn scale(&self) -> f32 {
        sqrtf(self.a * self.a + self.b * self.b)
    }

    /// The angle, radians, counter-clockwise on the screen being clockwise (rows grow down).
    pub fn angle(&self) -> f32 {
        libm::atan2f(self.b, self.a)
    }

    /// Where template offset `(u, v)` from the centre lands.
    pub fn map(&self, u: f32, v: f32) -> (f32, f32) {
        (self.x + self.a * u - self.b * v, self.y + self.b * u + self.a * v)
    }
}

/// What an alignment found: the pose, and the zero-mean NCC of the template with the window
/// sampled at it (over the pixels inside the window).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aligned {
    /// The pose.
    pub pose: Pose,
    /// Zero-mean NCC at the pose before its last (sub-[`CONVERGED`]) step.
    pub score: f32,
}

/// The template's side of one iteration's sums over the interior pixels sampled inside the
/// window (template values less the template's mean: small sums). Summed once per template
/// for iterations whose samples all fall inside the window ([`SimilarityTemplate`]), and
/// for those partly outside over the pixels inside ([`LkTemplate::sums_over`]): each field is
/// summed on its own and in the pixels' order, so the sum is the same to the bit as one
/// summed beside the window's sums, pixel by pixel.
#[derive(Clone, Default)]
struct TemplateSums {
    m: f32,
    t: f32,
    tt: f32,
    /// `Σ s`, `Σ s T` for each steepest-descent image.
    s: [f32; 4],
    st: [f32; 4],
    /// `H`, upper triangle row by row.
    h: [f32; 10],
}

impl TemplateSums {
    const ZERO: TemplateSums = TemplateSums { m: 0.0, t: 0.0, tt: 0.0, s: [0.0; 4], st: [0.0; 4], h: [0.0; 10] };

    fn add(&mut self, t: f32, s: [f32; 4]) {
        self.m += 1.0;
        self.t += t;
        self.tt += t * t;
        let mut k = 0;
        for i in 0..4 {
            self.s[i] += s[i];
            self.st[i] += s[i] * t;
            for j in i..4 {
                self.h[k] += s[i] * s[j];
                k += 1;
            }
        }
    }
}

/// The window's side of one iteration's sums (samples less the template's mean): small
/// enough to stay in registers through the pixel loop.
#[derive(Clone, Copy, Default)]
struct WindowSums {
    w: f32,
    ww: f32,
    wt: f32,
    /// `Σ s W` for each steepest-descent image.
    sw: [f32; 4],
}

impl WindowSums {
    #[inline(always)]
    fn add(&mut self, w: f32, t: f32, s: [f32; 4]) {
        self.w += w;
        self.ww += w * w;
        self.wt += w * t;
        for (sw, s) in self.sw.iter_mut().zip(s) {
            *sw += s * w;
        }
    }
}

/// `v` sampled bilinearly at `(x, y)` of `win` (`data` from its top-left, row pitch
/// `stride`), or `None` outside `[0, w - 1] x [0, h - 1]`: [`Inside::sample`] once the point
/// is known to be inside (the 2x2 block as one slice), [`bilinear_edge`] where that block
/// reaches past `data`.
#[inline(always)]
fn bilinear(data: &[u8], stride: usize, w: usize, h: usize, x: f32, y: f32) -> Option<f32> {
    if !(x >= 0.0 && y >= 0.0 && x <= (w - 1) as f32 && y <= (h - 1) as f32) {
        return None;
    }
    Inside::new(data, stride).sample(x, y).or_else(|| bilinear_edge(data, stride, w, h, x, y))
}

/// [`bilinear`] at a point inside the window whose 2x2 block reaches past `data` (the last
/// row of a window at the end of its buffer): on the last column or row the weight of the
/// next is zero, so the same pixel is read again.
#[cold]
#[inline(never)]
fn bilinear_edge(data: &[u8], stride: usize, w: usize, h: usize, x: f32, y: f32) -> Option<f32> {
    let (x0, y0, ax, ay) = floor_split(x, y);
    let (dx, dy) = (usize::from(x0 + 1 < w), if y0 + 1 < h { stride } else { 0 });
    let at = y0 * stride + x0;
    let p = |i: usize| data.get(i).map(|&v| f32::from(v));
    Some(lerp2x2([p(at)?, p(at + dx)?, p(at + dy)?, p(at + dy + dx)?], ax, ay))
}

/// The integer parts of `x, y >= 0` (truncation is the floor there, exactly as `floorf`, a
/// library call on the M4) and their fractions. Through `i32`: a float's saturating
/// conversion to `usize` is a dozen instructions on x86-64 (to `i32`, and back, one each),
/// the same integers for a window's coordinates.
#[inline(always)]
fn floor_split(x: f32, y: f32) -> (usize, usize, f32, f32) {
    let (x0, y0) = (x as i32, y as i32);
    (x0 as usize, y0 as usize, x - x0 as f32, y - y0 as f32)
}

/// The 2x2 block `[p00, p10, p01, p11]` interpolated at `(ax, ay)` from its top-left.
#[inline(always)]
fn lerp2x2([p00, p10, p01, p11]: [f32; 4], ax: f32, ay: f32) -> f32 {
    let top = p00 + ax * (p10 - p00);
    let bottom = p01 + ax * (p11 - p01);
    top + ay * (bottom - top)
}

/// A window's pixels (`data` from its top-left, row pitch `stride`) for [`bilinear`] samples
/// at points known to lie inside it (every sample of a pose whose interior corners do,
/// [`SimilarityTemplate::align`]), bit for bit: the checks against the window's sides are
/// left out, and on the last column or row the next pixel is read as it is in memory, its
/// weight being exactly zero (`p + 0 * d` is `p`).
struct Inside<'a> {
    data: &'a [u8],
    stride: usize,
    /// `stride + 2`, a 2x2 block's span in `data`: read as one slice, so one bounds check
    /// covers its four pixels (and the compiler knows it holds two).
    span: usize,
}

impl<'a> Inside<'a> {
    #[inline(always)]
    fn new(data: &'a [u8], stride: usize) -> Self {
        // A stride within 2 of `usize::MAX` saturates: no block is that long, so none is read.
        Inside { data, stride, span: stride.saturating_add(2) }
    }

    /// The sample at `(x, y)`; `None` where its 2x2 block reaches past `data` (the window's
    /// last row at the end of its buffer).
    #[inline(always)]
    fn sample(&self, x: f32, y: f32) -> Option<f32> {
        let (x0, y0, ax, ay) = floor_split(x, y);
        let block = self.data.get(y0 * self.stride + x0..)?.get(..self.span)?;
        let (&[p00, p10, ..], Some(&[p01, p11])) = (block, block.last_chunk::<2>()) else { return None };
        Some(lerp2x2([p00, p10, p01, p11].map(f32::from), ax, ay))
    }
}

/// The window's sums of one iteration at a `pose` whose samples all lie inside the window
/// (`(data, stride)` its pixels, `(w, h)` its size), `None` if one does not after all. Out of
/// line: inlined into the frame, the seven sums spill to the stack at every pixel.
#[inline(never)]
fn sums_inside<const P: usize>(lk: &LkTemplate<P>, (data, stride): (&[u8], usize), (w, h): (usize, usize), pose: &Pose, t_mean: f32) -> Option<WindowSums> {
    let inside = Inside::new(data, stride);
    let mut seen = WindowSums::default();
    let mut missed = false;
    lk.each_used(|_, u, v, t, s| {
        let (x, y) = pose.map(u, v);
        match inside.sample(x, y).or_else(|| bilinear(data, stride, w, h, x, y)) {
            Some(sample) => seen.add(sample - t_mean, t, s),
            None => missed = true,
        }
    })?;
    (!missed).then_some(seen)
}

/// The window's sums of one iteration at a `pose` whose samples may fall outside the window,
/// over those inside, which it marks in `inside` (bit `i` of row `j`: used interior pixel
/// `(i, j)`, as [`LkTemplate`]'s `used`). Out of line, as [`sums_inside`].
#[inline(never)]
fn sums_clipped<const P: usize>(lk: &LkTemplate<P>, (data, stride): (&[u8], usize), (w, h): (usize, usize), pose: &Pose, t_mean: f32, inside: &mut [u32; MAX_SIDE]) -> Option<WindowSums> {
    *inside = [0; MAX_SIDE];
    let mut seen = WindowSums::default();
    lk.each_used(|(j, bit), u, v, t, s| {
        let (x, y) = pose.map(u, v);
        if let (Some(sample), Some(row)) = (bilinear(data, stride, w, h, x, y), inside.get_mut(j)) {
            seen.add(sample - t_mean, t, s);
            *row |= bit;
        }
    })?;
    Some(seen)
}

/// The solution of `H d = b` for the symmetric positive definite `H` (upper triangle row by
/// row), by Cholesky; `None` when `H` is not (the template lacks texture for some motion).
// Indices, as the formulas of the factorisation and the substitutions write them.
#[allow(clippy::needless_range_loop)]
fn solve4(h: &[f32; 10], b: [f32; 4]) -> Option<[f32; 4]> {
    let mut full = [[0.0f32; 4]; 4];
    let mut k = 0;
    for i in 0..4 {
        for j in i..4 {
            full[i][j] = h[k];
            full[j][i] = h[k];
            k += 1;
        }
    }
    let mut l = [[0.0f32; 4]; 4];
    for i in 0..4 {
        for j in 0..=i {
            let sum = full[i][j] - (0..j).map(|k| l[i][k] * l[j][k]).sum::<f32>();
            if i == j {
                // Relative to the diagonal, as the images' scales differ by the template's size.
                // Negated so that a NaN sum is refused too.
                #[allow(clippy::neg_cmp_op_on_partial_ord)]
                if !(sum > 1e-6 * full[i][i]) {
                    return None;
                }
                l[i][i] = sqrtf(sum);
            } else {
                l[i][j] = sum / l[j][j];
            }
        }
    }
    let mut y = [0.0f32; 4];
    for i in 0..4 {
        y[i] = (b[i] - (0..i).map(|k| l[i][k] * y[k]).sum::<f32>()) / l[i][i];
    }
    let mut d = [0.0f32; 4];
    for i in (0..4).rev() {
        d[i] = (y[i] - (i + 1..4).map(|k| l[k][i] * d[k]).sum::<f32>()) / l[i][i];
    }
    d.iter().all(|v| v.is_finite()).then_some(d)
}

/// A template prepared for [`SimilarityTemplate::align`]: its Lucas-Kanade side
/// ([`LkTemplate`], which also refines translations) and the template's side of every
/// iteration's sums over all its used pixels, both computed once per template.
#[derive(Clone, Default)]
pub struct SimilarityTemplate<const P: usize> {
    lk: LkTemplate<P>,
    fixed: TemplateSums,
}

impl<const P: usize> SimilarityTemplate<P> {
    /// Nothing prepared: aligns nothing.
    pub const fn sized() -> Self {
        SimilarityTemplate { lk: LkTemplate::sized(), fixed: TemplateSums::ZERO }
    }

    /// Prepares `tpl` (as [`LkTemplate::prepare`] over all its pixels); `false` when that fails.
    pub fn prepare(&mut self, tpl: &WindowView<'_>) -> bool {
        self.fixed = TemplateSums::ZERO;
        if !self.lk.prepare(tpl, None) {
            return false;
        }
        let mut sums = TemplateSums::ZERO;
        let ok = self.lk.each_used(|_, _, _, t, s| sums.add(t, s)).is_some();
        self.fixed = sums;
        ok
    }

    /// The prepared template's Lucas-Kanade side (translation refinement).
    pub fn lk(&self) -> &LkTemplate<P> {
        &self.lk
    }

    /// The similarity pose of the prepared template in `win` (a full-resolution view),
    /// starting from `start`; `None` when nothing is prepared, the window is not full
    /// resolution, fewer than `min_inside` of the pixels sample inside it ([`MIN_INSIDE`],
    /// [`MIN_IN_VIEW`]), the window is flat there, `H` is singular, or the iteration walks
    /// over [`MAX_WALK`] px, out of the scales [`MAX_SCALE`] allows or [`MAX_LOSS`] under its
    /// best score.
    pub fn align(&self, win: &WindowView<'_>, start: Pose, min_inside: f32) -> Option<Aligned> {
        let (data, stride) = win.raw()?;
        let (w, h) = (win.width(), win.height());
        let (iw, used, tg, t_mean) = self.lk.interior()?;
        if w == 0 || h == 0 || ![start.x, start.y, start.a, start.b].iter().all(|v| v.is_finite()) {
            return None;
        }
        // The template's centre, in interior pixels: the template is `iw + 2` a side.
        let c = (iw as f32 - 1.0) / 2.0;
        let reach = sqrtf(2.0) * (c + 1.0);
        let need = min_inside * tg.len() as f32;
        // The interior's corners, from its centre: every pixel's sample lies within theirs,
        // as each rounding in `Pose::map` is monotonic in `u` and in `v`.
        let corners = [(-c, -c), (c, -c), (-c, used.len() as f32 - 1.0 - c), (c, used.len() as f32 - 1.0 - c)];
        let mut pose = start;
        let (mut score, mut best) = (0.0, f32::NEG_INFINITY);
        // Where the template is partly outside the window: the pixels sampled inside, and the
        // template's sums over them, kept while an iteration samples the same pixels.
        let mut inside = [0u32; MAX_SIDE];
        let mut clipped: Option<([u32; MAX_SIDE], TemplateSums)> = None;
        for _ in 0..ITERATIONS {
            let all_inside = corners.iter().all(|&(u, v)| {
                let (x, y) = pose.map(u, v);
                x >= 0.0 && y >= 0.0 && x <= (w - 1) as f32 && y <= (h - 1) as f32
            });
            let (fixed, seen) = if all_inside {
                (&self.fixed, sums_inside(&self.lk, (data, stride), (w, h), &pose, t_mean)?)
            } else {
                let seen = sums_clipped(&self.lk, (data, stride), (w, h), &pose, t_mean, &mut inside)?;
                let fixed = match &clipped {
                    Some((was, sums)) if *was == inside => sums,
                    _ => &clipped.insert((inside, self.lk.sums_over(&inside)?)).1,
                };
                (fixed, seen)
            };
            if fixed.m < need {
                return None;
            }
            let (w_mean, t_mean_in) = (seen.w / fixed.m, fixed.t / fixed.m);
            let (var_w, var_t) = (seen.ww - seen.w * w_mean, fixed.tt - fixed.t * t_mean_in);
            if !(var_w > 1e-5 * seen.ww && var_t > 0.0) {
                return None;
            }
            score = (seen.wt - seen.w * t_mean_in) / sqrtf(var_w * var_t);
            // Negated so that a NaN score is refused too.
            #[allow(clippy::neg_cmp_op_on_partial_ord)]
            if !(score >= best - MAX_LOSS) {
                return None;
            }
            best = best.max(score);
            let gain = sqrtf(var_t / var_w);
            let b = core::array::from_fn(|i| gain * (seen.sw[i] - w_mean * fixed.s[i]) + t_mean_in * fixed.s[i] - fixed.st[i]);
            let d = solve4(&fixed.h, b)?;
            // Compose with the inverse of the step's warp (complex arithmetic).
            let (ra, rb) = (1.0 + d[0], d[1]);
            let norm = ra * ra + rb * rb;
            let (a, bb) = ((pose.a * ra + pose.b * rb) / norm, (pose.b * ra - pose.a * rb) / norm);
            let next = Pose { x: pose.x - (a * d[2] - bb * d[3]), y: pose.y - (bb * d[2] + a * d[3]), a, b: bb };
            // The step moves a template pixel by at most its centre's move plus the reach
            // times the change of (a, b).
            let moved = sqrtf((next.x - pose.x) * (next.x - pose.x) + (next.y - pose.y) * (next.y - pose.y))
                + reach * sqrtf((a - pose.a) * (a - pose.a) + (bb - pose.b) * (bb - pose.b));
            pose = next;
            let walk = sqrtf((pose.x - start.x) * (pose.x - start.x) + (pose.y - start.y) * (pose.y - start.y));
            let scale = pose.scale();
            // Negated so that a NaN walk or scale stops the walk too.
            #[allow(clippy::manual_range_contains)]
            if !(walk <= MAX_WALK && scale <= MAX_SCALE && scale >= 1.0 / MAX_SCALE) {
                return None;
            }
            if moved < CONVERGED {
                break;
            }
        }
        Some(Aligned { pose, score })
    }
}

impl<const P: usize> LkTemplate<P> {
    /// The template's side of an iteration's sums over the used pixels marked in `inside`
    /// ([`sums_clipped`]), in the pixels' order. Out of line: its 21 sums fill the registers.
    #[inline(never)]
    fn sums_over(&self, inside: &[u32; MAX_SIDE]) -> Option<TemplateSums> {
        let mut sums = TemplateSums::ZERO;
        self.each_used(|(j, bit), _, _, t, s| {
            if inside.get(j).is_some_and(|row| row & bit != 0) {
                sums.add(t, s);
            }
        })?;
        Some(sums)
    }

    /// Visits the used interior pixels in order with their place (row `j`, and the pixel's
    /// bit in that row of `used`), their offset `(u, v)` from the interior's centre,
    /// `T - mean T` and the steepest-descent images `(gx u + gy v, gy u - gx v, gx, gy)`;
    /// `None` when nothing is prepared.
    #[inline(always)]
    fn each_used(&self, mut f: impl FnMut((usize, u32), f32, f32, f32, [f32; 4])) -> Option<()> {
        let (iw, used, tg, t_mean) = self.interior()?;
        let c = (iw as f32 - 1.0) / 2.0;
        // The bits of a row's `iw` pixels: a clear bit costs nothing below.
        let row = u32::MAX.checked_shr(32 - iw.min(32) as u32).unwrap_or(0);
        let mut tg = tg.iter();
        for (j, &bits) in used.iter().enumerate() {
            let v = j as f32 - c;
            let mut rest = bits & row;
            while rest != 0 {
                let i = rest.trailing_zeros();
                rest &= rest - 1;
                let &[t, gx, gy] = tg.next()?;
                let u = i as f32 - c;
                f((j, 1 << i), u, v, t - t_mean, [gx * u + gy * v, gy * u - gx * v, gx, gy]);
            }
        }
        Some(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernels::refine::INTERIOR;
    use std::vec::Vec;

    /// A smooth texture with detail in both directions, sampled at any real point.
    fn texture(x: f32, y: f32) -> f32 {
        let (x, y) = (f64::from(x), f64::from(y));
        (120.0 + 40.0 * (0.45 * x).sin() * (0.3 * y).cos() + 30.0 * (0.21 * x + 0.37 * y).sin()) as f32
    }

    /// A `w x h` window showing the texture turned by `angle` and scaled by `scale` about
    /// texture point (0, 0), which lands at `(cx, cy)`: window pixel `p` shows the texture at
    /// `R(-angle) (p - c) / scale`.
    fn render(w: usize, h: usize, cx: f32, cy: f32, scale: f32, angle: f32) -> Vec<u8> {
        let (cs, sn) = (libm::cosf(angle), libm::sinf(angle));
        (0..w * h)
            .map(|k| {
                let (dx, dy) = ((k % w) as f32 - cx, (k / w) as f32 - cy);
                let (u, v) = ((cs * dx + sn * dy) / scale, (-sn * dx + cs * dy) / scale);
                libm::roundf(texture(u, v)) as u8
            })
            .collect()
    }

    fn prepared(tpl: &[u8], n: usize) -> SimilarityTemplate<INTERIOR> {
        let mut lk = SimilarityTemplate::sized();
        assert!(lk.prepare(&WindowView::packed(tpl, n, n).unwrap()));
        lk
    }

    #[test]
    fn recovers_a_known_turn_scale_and_shift() {
        // Independent reference: the pose the window was rendered with. The 20x20 template
        // is the texture with its centre (9.5, 9.5) on texture point (0, 0); the window shows
        // it turned by 25 degrees, scaled by 1.2, centred at (17.3, 16.6).
        let tpl = render(20, 20, 9.5, 9.5, 1.0, 0.0);
        let lk = prepared(&tpl, 20);
        let (angle, scale) = (25f32.to_radians(), 1.2);
        let px = render(36, 36, 17.3, 16.6, scale, angle);
        let win = WindowView::packed(&px, 36, 36).unwrap();
        // Started as a translation-only tracker leaves it: 1 px off, no turn, no scale.
        let found = lk.align(&win, Pose::new(16.5, 17.2, 1.0, 0.0), MIN_INSIDE).expect("converges");
        let p = found.pose;
        assert!((p.x - 17.3).abs() < 0.03 && (p.y - 16.6).abs() < 0.03, "{p:?}");
        assert!((p.angle() - angle).abs() < 0.3f32.to_radians(), "{}", p.angle().to_degrees());
        assert!((p.scale() - scale).abs() < 0.005, "{}", p.scale());
        assert!(found.score > 0.99, "{}", found.score);
    }

    #[test]
    fn a_template_partly_outside_the_window_still_aligns_on_what_is_inside() {
        // The turned 20x20 template spans 27 px; the window is 24: its corners fall outside.
        let tpl = render(20, 20, 9.5, 9.5, 1.0, 0.0);
        let lk = prepared(&tpl, 20);
        let angle = -20f32.to_radians();
        let px = render(24, 24, 11.8, 11.2, 1.0, angle);
        let win = WindowView::packed(&px, 24, 24).unwrap();
        let p = lk.align(&win, Pose::new(11.5, 11.5, 1.0, 0.0), MIN_INSIDE).expect("converges").pose;
        assert!((p.x - 11.8).abs() < 0.03 && (p.y - 11.2).abs() < 0.03, "{p:?}");
        assert!((p.angle() - angle).abs() < 0.3f32.to_radians(), "{}", p.angle().to_degrees());
    }

    #[test]
    fn refuses_a_flat_window_a_template_mostly_outside_and_a_bad_start() {
        let tpl = render(20, 20, 9.5, 9.5, 1.0, 0.0);
        let lk = prepared(&tpl, 20);
        let flat = [90u8; 36 * 36];
        let win = WindowView::packed(&flat, 36, 36).unwrap();
        assert_eq!(lk.align(&win, Pose::new(17.0, 17.0, 1.0, 0.0), MIN_INSIDE), None);
        let px = render(36, 36, 17.0, 17.0, 1.0, 0.0);
        let win = WindowView::packed(&px, 36, 36).unwrap();
        // Centred on the window's corner: a quarter of the pixels inside.
        assert_eq!(lk.align(&win, Pose::new(0.0, 0.0, 1.0, 0.0), MIN_INSIDE), None);
        assert_eq!(lk.align(&win, Pose::new(f32::NAN, 17.0, 1.0, 0.0), MIN_INSIDE), None);
        assert_eq!(SimilarityTemplate::<INTERIOR>::sized().align(&win, Pose::new(17.0, 17.0, 1.0, 0.0), MIN_INSIDE), None);
    }

    #[test]
    fn a_walk_that_loses_its_match_is_refused_before_it_ends_on_a_wrong_pose() {
        // The texture as the template shows it, centred at (17, 17), but flat (90) over the
        // window's columns 7-22, 16 of the template's 20; the alignment starts 2.5 px right.
        let tpl = render(20, 20, 9.5, 9.5, 1.0, 0.0);
        let lk = prepared(&tpl, 20);
        let mut px = render(36, 36, 17.0, 17.0, 1.0, 0.0);
        for row in px.chunks_mut(36) {
            row[7..23].fill(90);
        }
        let win = WindowView::packed(&px, 36, 36).unwrap();
        // Its score climbs to 0.336 and falls to 0.228 by the sixth iteration, more than
        // MAX_LOSS under it. Measured with the rule lifted: the walk goes on to end at scale
        // 1.96, turned -51 degrees, with a score of 0.649, over adapt::ALIGN, where the
        // window shows the object unturned at scale 1 (the independent reference: the pose it
        // was rendered with).
        assert_eq!(lk.align(&win, Pose::new(19.5, 17.0, 1.0, 0.0), MIN_INSIDE), None);
        // Less covered (columns 7-12), from the same start, the walk keeps its match and aligns.
        let mut px = render(36, 36, 17.0, 17.0, 1.0, 0.0);
        for row in px.chunks_mut(36) {
            row[7..13].fill(90);
        }
        let win = WindowView::packed(&px, 36, 36).unwrap();
        assert!(lk.align(&win, Pose::new(19.5, 17.0, 1.0, 0.0), MIN_INSIDE).is_some_and(|a| a.score > 0.8));
    }

    #[test]
    fn an_iteration_partly_outside_sums_exactly_the_template_pixels_inside() {
        // The template of the partly-outside test, centred at the window's (3.2, 11.6): its
        // left columns fall outside (220 of the 324 pixels inside: fewer than MIN_INSIDE asks
        // of an alignment, which this one iteration's sums do not check). Reference: each used
        // pixel inside or not by its mapped point against the window's sides, and both sides'
        // sums over those pixels added one by one in the pixels' order, beside each other as
        // the iteration summed them before it had a loop of its own.
        let tpl = render(20, 20, 9.5, 9.5, 1.0, 0.0);
        let lk = prepared(&tpl, 20);
        let px = render(24, 24, 11.8, 11.2, 1.0, 0.0);
        let pose = Pose::new(3.2, 11.6, 1.0, -0.1);
        let t_mean = lk.lk.interior().unwrap().3;
        let (mut inside, mut want, mut want_sums, mut want_seen) = ([0u32; MAX_SIDE], [0u32; MAX_SIDE], TemplateSums::ZERO, WindowSums::default());
        lk.lk.each_used(|(j, bit), u, v, t, s| {
            let (x, y) = pose.map(u, v);
            if (0.0..=23.0).contains(&x) && (0.0..=23.0).contains(&y) {
                want[j] |= bit;
                want_sums.add(t, s);
                let (x0, y0) = (x.floor() as usize, y.floor() as usize);
                let p = |dx: usize, dy: usize| f32::from(px[(y0 + dy).min(23) * 24 + (x0 + dx).min(23)]);
                want_seen.add(lerp2x2([p(0, 0), p(1, 0), p(0, 1), p(1, 1)], x - x0 as f32, y - y0 as f32) - t_mean, t, s);
            }
        });
        let seen = sums_clipped(&lk.lk, (&px, 24), (24, 24), &pose, t_mean, &mut inside).unwrap();
        assert_eq!(inside, want);
        let n: u32 = want.iter().map(|r| r.count_ones()).sum();
        assert!(n > 200 && n < 324, "{n} of the 18x18 interior inside");
        let sums = lk.lk.sums_over(&inside).unwrap();
        assert_eq!((sums.m, sums.t, sums.tt, sums.s, sums.st, sums.h), (want_sums.m, want_sums.t, want_sums.tt, want_sums.s, want_sums.st, want_sums.h));
        assert_eq!(sums.m, n as f32);
        assert_eq!((seen.w, seen.ww, seen.wt, seen.sw), (want_seen.w, want_seen.ww, want_seen.wt, want_seen.sw));
    }

    #[test]
    fn solves_a_hand_made_system() {
        // H = diag(4, 9, 1, 16) + 1 in (0, 1): by hand, d = (1, 2, 3, 0.25) gives
        // b = (4 + 2, 1 + 18, 3, 4).
        let h = [4.0, 1.0, 0.0, 0.0, 9.0, 0.0, 0.0, 1.0, 0.0, 16.0];
        let d = solve4(&h, [6.0, 19.0, 3.0, 4.0]).unwrap();
        for (got, want) in d.iter().zip([1.0, 2.0, 3.0, 0.25]) {
            assert!((got - want).abs() < 1e-5, "{d:?}");
        }
        assert_eq!(solve4(&[1.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 1.0], [1.0; 4]), None);
    }
}
