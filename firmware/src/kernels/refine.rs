//! Sub-pixel refinement of a template match (beyond the thesis, which stops at the best
//! integer placement; [`crate::kernels::matching`] adds a parabola through three scores).
//!
//! A parabola through correlation scores is biased toward whole pixels ("pixel locking"): on
//! textured real images its error stays near 0.3 px whatever the noise. Here the match is
//! refined by Lucas-Kanade in its inverse compositional form (Baker & Matthews, 2004) for a
//! translation, with the window's gain and offset normalised to the template's as NCC does:
//!
//! - template gradients by central differences on its interior pixels,
//!   `g = ((T(i+1,j) - T(i-1,j)) / 2, (T(i,j+1) - T(i,j-1)) / 2)`, and `H = Σ g gᵀ`;
//! - each iteration samples the window bilinearly at the current placement `(x, y)`,
//!   `W(i,j) = I(x+i, y+j)`, normalises it, `Ŵ = (W - mean W) σ_T / σ_W + mean T`, and steps
//!   `(x, y) -= H⁻¹ Σ g (Ŵ - T)` until the step is under 0.03 px (at most 8 iterations).
//!
//! Arithmetic is `f32` (the Cortex-M4F's single-precision FPU); no allocation, no panic. The
//! template's side (its pixels, gradients, `H`, mean and deviation) does not depend on the
//! window, so a tracker prepares it once per template ([`LkTemplate`]); an iteration then
//! makes one pass over the used pixels, sampling and summing at once (the normalisation
//! and `Σ g (Ŵ - T)` follow from four sums, [`LkTemplate::refine`]), each window column
//! blended once.

use crate::kernels::support::Support;
use crate::kernels::fmath::{cmp_hypotf, sqrtf};
use core::cmp::Ordering::{Greater, Less};
use crate::kernels::view::WindowView;
use heapless::Vec;

/// Iterations at most.
const ITERATIONS: usize = 8;
/// A step under this many pixels ends the iteration. The steps shrink fast, so the step an
/// earlier stop would still take is a small fraction of this, well under the tracker's error.
const CONVERGED: f32 = 0.03;
/// Farthest the refined placement may be from the start before it is refused (the parabola
/// is within half a pixel of the truth, so a longer walk means the iteration diverged).
const MAX_WALK: f32 = 1.0;
/// A window whose spread `Q - S²/n` is at most this fraction of `Q` is flat: what is left
/// is the `f32` sums' rounding.
const FLAT: f32 = 1e-5;

/// Largest template side refined (the processors' templates are at most 32 x 32).
pub const MAX_SIDE: usize = 32;
/// Interior pixels of a [`MAX_SIDE`] template: what an [`LkTemplate`] holds by default.
pub const INTERIOR: usize = (MAX_SIDE - 2) * (MAX_SIDE - 2);

/// The refined top-left placement of `tpl` in `win`, starting from `(x, y)` (window pixels,
/// real-valued, e.g. the parabola fit), or `None` when the template is over [`MAX_SIDE`] or
/// has no texture in some direction (singular `H`), the window is flat, a sample would fall
/// outside the window, or the iteration walks more than a pixel.
pub fn refine_translation(win: &WindowView<'_>, tpl: &WindowView<'_>, x: f32, y: f32) -> Option<(f32, f32)> {
    let mut lk = LkTemplate::new();
    lk.prepare(tpl, None).then(|| lk.refine(win, x, y)).flatten()
}

/// [`refine_translation`] with the sums over the template pixels in `support` only (the
/// object's part of a corner template, see [`super::support`]); `None` also when the
/// support is not the template's size.
pub fn refine_translation_on(win: &WindowView<'_>, tpl: &WindowView<'_>, support: &Support, x: f32, y: f32) -> Option<(f32, f32)> {
    let mut lk = LkTemplate::new();
    lk.prepare(tpl, Some(support)).then(|| lk.refine(win, x, y)).flatten()
}

/// A prepared template's interior ([`LkTemplate::interior`]): its width, the used bits of each
/// row, the used pixels' `[T, gx, gy]` row by row and the mean `T`.
pub(crate) type Interior<'a> = (usize, &'a [u32], &'a [[f32; 3]], f32);

/// The template's side of the refinement (its used interior pixels, their gradients, `H` and
/// the template's mean and deviation), which does not depend on the window: a tracker that
/// refines every frame with one template prepares it once ([`LkTemplate::prepare`]) and
/// refines with it ([`LkTemplate::refine`]), with the results of [`refine_translation`] (or
/// [`refine_translation_on`] with a support). Prepared in place: it is 11 KiB for up to
/// [`INTERIOR`] used pixels (a 32x32 template); `P` sizes it for fewer (`(N - 2)²` for an
/// `N x N` template: 4 KiB at the thesis's 20), and a template with more prepares nothing.
#[derive(Clone, Debug)]
pub struct LkTemplate<const P: usize = INTERIOR> {
    /// A template was prepared and can refine.
    ready: bool,
    /// Bit `i` of `used[j]`: interior pixel `(i, j)` is summed over.
    used: [u32; MAX_SIDE],
    iw: usize,
    ih: usize,
    /// The used pixels' values and gradients `[T, gx, gy]`, row by row: the order of every
    /// sum (together, as the iterations read them).
    tg: Vec<[f32; 3], P>,
    h: (f32, f32, f32),
    det: f32,
    t_mean: f32,
    t_dev: f32,
    /// `(Σ gx, Σ gy)` and `(Σ gx (mean T - T), Σ gy (mean T - T))` over the used pixels.
    g_sum: (f32, f32),
    g_err: (f32, f32),
}

impl<const P: usize> Default for LkTemplate<P> {
    fn default() -> Self {
        Self::sized()
    }
}

impl LkTemplate {
    /// Nothing prepared: refines nothing.
    pub const fn new() -> Self {
        Self::sized()
    }
}

impl<const P: usize> LkTemplate<P> {
    /// [`LkTemplate::new`], for up to `P` used pixels.
    pub const fn sized() -> Self {
        LkTemplate {
            ready: false,
            used: [0; MAX_SIDE],
            iw: 0,
            ih: 0,
            tg: Vec::new(),
            h: (0.0, 0.0, 0.0),
            det: 0.0,
            t_mean: 0.0,
            t_dev: 0.0,
            g_sum: (0.0, 0.0),
            g_err: (0.0, 0.0),
        }
    }

    /// Prepares `tpl` for refinement, over the pixels in `support` if there is one; `false`
    /// (and it refines nothing) when the template is under 3 or over [`MAX_SIDE`] pixels a
    /// side, the support is not its size or holds no interior pixel, or `H` is singular.
    pub fn prepare(&mut self, tpl: &WindowView<'_>, support: Option<&Support>) -> bool {
        self.ready = false;
        self.ready = self.fill(tpl, support).is_some();
        self.ready
    }

    fn fill(&mut self, tpl: &WindowView<'_>, support: Option<&Support>) -> Option<()> {
        let (tw, th) = (tpl.width(), tpl.height());
        if !(3..=MAX_SIDE).contains(&tw) || !(3..=MAX_SIDE).contains(&th) || support.is_some_and(|s| s.size() != (tw, th)) {
            return None;
        }
        let (iw, ih) = (tw - 2, th - 2);
        let used = &mut self.used;
        for (j, u) in used.iter_mut().enumerate() {
            *u = (0..iw).filter(|&i| j < ih && support.is_none_or(|s| s.contains(i + 1, j + 1))).fold(0, |b, i| b | 1 << i);
        }
        let mut packed = [0u8; MAX_SIDE * MAX_SIDE];
        let tpl = if tpl.step() == 1 { *tpl } else { tpl.pack_into(&mut packed)? };
        let tg = &mut self.tg;
        tg.clear();
        for (j, &bits) in used.iter().enumerate().take(ih) {
            let (up, mid, down) = (tpl.row(j)?, tpl.row(j + 1)?, tpl.row(j + 2)?);
            // Interior pixel i: pixels i, i+1 and i+2 of its row, i+1 of the rows above and below.
            let [left, centre, right, above, below] =
                [mid.get(..iw), mid.get(1..=iw), mid.get(2..iw + 2), up.get(1..=iw), down.get(1..=iw)];
            let columns = left?.iter().zip(centre?).zip(right?).zip(above?.iter().zip(below?));
            let mut bit = bits;
            for (((&l, &c), &r), (&u, &d)) in columns {
                if bit & 1 == 1 {
                    tg.push([f32::from(c), (f32::from(r) - f32::from(l)) / 2.0, (f32::from(d) - f32::from(u)) / 2.0]).ok()?;
                }
                bit >>= 1;
            }
        }
        let n = tg.len();
        if n == 0 {
            return None;
        }
        let dot = |a: usize, b: usize| tg.iter().map(|v| v[a] * v[b]).sum::<f32>();
        let (h11, h12, h22) = (dot(1, 1), dot(1, 2), dot(2, 2));
        let det = h11 * h22 - h12 * h12;
        if det.is_nan() || det <= 1e-3 * (h11 + h22) * (h11 + h22) {
            return None;
        }
        let t_mean = tg.iter().map(|v| v[0]).sum::<f32>() / n as f32;
        let t_dev = sqrtf(tg.iter().map(|v| (v[0] - t_mean) * (v[0] - t_mean)).sum());
        let g_sum = (tg.iter().map(|v| v[1]).sum(), tg.iter().map(|v| v[2]).sum());
        let err = |a: usize| tg.iter().map(|v| v[a] * (t_mean - v[0])).sum::<f32>();
        (self.iw, self.ih, self.h, self.det, self.t_mean, self.t_dev) = (iw, ih, (h11, h12, h22), det, t_mean, t_dev);
        (self.g_sum, self.g_err) = (g_sum, (err(1), err(2)));
        Some(())
    }

    /// The prepared template's interior: its width, the used bits of each row, the used
    /// pixels' `[T, gx, gy]` row by row and the mean `T`; `None` when nothing is prepared.
    pub(crate) fn interior(&self) -> Option<Interior<'_>> {
        self.ready.then(|| (self.iw, self.used.get(..self.ih).unwrap_or(&[]), &self.tg[..], self.t_mean))
    }

    /// The refined top-left placement of the prepared template in `win` from `(x, y)`, as
    /// [`refine_translation`] finds it; `None` also when nothing is prepared.
    ///
    /// With `u = W - mean T` (the samples offset by a constant, which keeps the sums small
    /// and cancels from every term below), one pass over the used pixels gives
    /// `S = Σ u`, `Q = Σ u²`, `Gx = Σ gx u` and `Gy = Σ gy u`, and then
    /// `σ_W² = Q - S²/n` and `Σ g (Ŵ - T) = (σ_T / σ_W) (G - (S/n) Σ g) + Σ g (mean T - T)`,
    /// whose last term the template fixes ([`LkTemplate::prepare`]). The window's pixels
    /// are converted once per integer placement (a `Block`); the iterations that stay on it
    /// (most: the walk is under a pixel) only blend them. Never inlined: the block's 8 KiB are
    /// on the stack only during the refinement, not under the matching its caller also runs.
    #[inline(never)]
    pub fn refine(&self, win: &WindowView<'_>, x: f32, y: f32) -> Option<(f32, f32)> {
        if !self.ready || !x.is_finite() || !y.is_finite() {
            return None;
        }
        let LkTemplate { used, iw, ih, tg, h: (h11, h12, h22), det, t_mean, t_dev, g_sum, g_err, .. } = self;
        let used = used.get(..*ih)?;
        let n = tg.len() as f32;
        let mut block = Block { at: None, cols: Vec::new() };
        let (mut px, mut py) = (x, y);
        for _ in 0..ITERATIONS {
            // The template's interior starts one pixel in.
            let (sx, sy) = (px + 1.0, py + 1.0);
            if !(sx >= 0.0 && sy >= 0.0) {
                return None;
            }
            let (fx, fy) = (libm::floorf(sx), libm::floorf(sy));
            let (ax, ay) = (sx - fx, sy - fy);
            // A zero weight never reads the next column or row, so a block ending on the
            // window's last one is inside.
            let at = Placement { x0: fx as usize, y0: fy as usize, right: ax > 0.0, below: ay > 0.0 };
            if block.at != Some(at) {
                block.fill(win, at, *iw, used, *t_mean)?;
            }
            let s = block.sums(ax, ay, *iw, used, tg)?;
            let u_mean = s.s / n;
            let var = s.q - s.s * u_mean;
            // A flat window: its spread is within the sums' rounding.
            if var.is_nan() || var <= FLAT * s.q {
                return None;
            }
            let gain = t_dev / sqrtf(var);
            let b1 = gain * (s.gx - u_mean * g_sum.0) + g_err.0;
            let b2 = gain * (s.gy - u_mean * g_sum.1) + g_err.1;
            let (dx, dy) = ((h22 * b1 - h12 * b2) / det, (h11 * b2 - h12 * b1) / det);
            px -= dx;
            py -= dy;
            if cmp_hypotf(px - x, py - y, MAX_WALK) == Some(Greater) || !px.is_finite() || !py.is_finite() {
                return None;
            }
            if cmp_hypotf(dx, dy, CONVERGED) == Some(Less) {
                break;
            }
        }
        Some((px, py))
    }
}

/// An integer placement of the template's interior in the window: its top-left pixel, and
/// whether the next column and row carry weight.
#[derive(Clone, Copy, PartialEq, Eq)]
struct Placement {
    x0: usize,
    y0: usize,
    right: bool,
    below: bool,
}

/// One iteration's sums over the sampled window ([`LkTemplate::refine`]).
struct WindowSums {
    /// `Σ u`, `Σ u²`, `Σ gx u`, `Σ gy u` with `u = W - mean T`.
    s: f32,
    q: f32,
    gx: f32,
    gy: f32,
}

/// The window's pixels under the template's interior at one integer [`Placement`], ready
/// for bilinear samples at any fraction of it: per column, its top pixel `t` (offset
/// subtracted) and `d = bottom - top`, so the column at fraction `ay` is `t + ay d`.
struct Block {
    at: Option<Placement>,
    /// `[t, d]` of each used row's `iw` (`iw + 1` with a `right` column) columns, row by row.
    cols: Vec<[f32; 2], { MAX_SIDE * (MAX_SIDE + 1) }>,
}

impl Block {
    /// Converts the pixels at `at` (`offset` subtracted) for the `used` rows; `None` when
    /// the block (with its weighted column and row) reaches outside the window.
    #[inline(always)]
    fn fill(&mut self, win: &WindowView<'_>, at: Placement, iw: usize, used: &[u32], offset: f32) -> Option<()> {
        let (right, below) = (usize::from(at.right), usize::from(at.below));
        self.at = None;
        self.cols.clear();
        if at.x0.saturating_add(iw + right) > win.width() || at.y0.saturating_add(used.len() + below) > win.height() {
            return None;
        }
        let stride = iw + right;
        // Pushed, not resized and overwritten: zeroing first would cost more than the pushes.
        for j in 0..used.len() {
            let top = win.row(at.y0 + j)?.get(at.x0..at.x0 + stride)?;
            let bottom = win.row(at.y0 + j + below)?.get(at.x0..at.x0 + stride)?;
            for (&t, &b) in top.iter().zip(bottom) {
                self.cols.push([f32::from(t) - offset, f32::from(i16::from(b) - i16::from(t))]).ok()?;
            }
        }
        self.at = Some(at);
        Some(())
    }

    /// The sums of [`WindowSums`] over the `used` pixels (bit `i` of `used[j]` for pixel
    /// `(i, j)`) at fractions `(ax, ay)` of the block's placement, by bilinear
    /// interpolation (a translation: one pair of weights for every pixel), each paired in
    /// turn with the gradients in `tg`.
    #[inline(always)]
    fn sums(&self, ax: f32, ay: f32, iw: usize, used: &[u32], tg: &[[f32; 3]]) -> Option<WindowSums> {
        let right = usize::from(self.at?.right);
        let stride = iw + right;
        let mut sums = WindowSums { s: 0.0, q: 0.0, gx: 0.0, gy: 0.0 };
        let mut k = 0;
        let mut add = |u: f32, g: &[f32; 3]| {
            sums.s += u;
            sums.q += u * u;
            sums.gx += g[1] * u;
            sums.gy += g[2] * u;
        };
        for (row, &bits) in self.cols.chunks_exact(stride).zip(used) {
            // Each run of used pixels (a support's row is one) without a test per pixel;
            // each column blended vertically once, as one sample's right-hand column and
            // the next one's left.
            let mut rest = bits;
            while rest != 0 {
                let (i, run) = (rest.trailing_zeros() as usize, (rest >> rest.trailing_zeros()).trailing_ones() as usize);
                rest &= rest.wrapping_add(rest & rest.wrapping_neg());
                let (cols, grads) = (row.get(i..i + run + right)?, tg.get(k..k + run)?);
                k += run;
                let blend = |&[t, d]: &[f32; 2]| t + ay * d;
                if right == 1 {
                    let mut left = blend(cols.first()?);
                    for (c, g) in cols.iter().skip(1).zip(grads) {
                        let r = blend(c);
                        add(left + ax * (r - left), g);
                        left = r;
                    }
                } else {
                    for (c, g) in cols.iter().zip(grads) {
                        add(blend(c), g);
                    }
                }
            }
        }
        Some(sums)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::vec::Vec;

    /// A smooth texture with detail in both directions, sampled at any real point.
    fn texture(x: f32, y: f32) -> f32 {
        let (x, y) = (f64::from(x), f64::from(y));
        (120.0 + 40.0 * (0.45 * x).sin() * (0.3 * y).cos() + 30.0 * (0.21 * x + 0.37 * y).sin()) as f32
    }

    fn render(w: usize, h: usize, dx: f32, dy: f32) -> Vec<u8> {
        (0..w * h).map(|k| libm::roundf(texture((k % w) as f32 - dx, (k / w) as f32 - dy)) as u8).collect()
    }

    #[test]
    fn recovers_a_known_sub_pixel_shift() {
        // Independent reference: the shift the window was rendered with. The template is the
        // texture at (0, 0); the window holds it at (6.3, 5.7) (plus 8-bit rounding).
        let tpl_px = render(20, 20, 0.0, 0.0);
        let win_px = render(32, 32, 6.3, 5.7);
        let tpl = WindowView::packed(&tpl_px, 20, 20).unwrap();
        let win = WindowView::packed(&win_px, 32, 32).unwrap();
        let (x, y) = refine_translation(&win, &tpl, 6.0, 6.0).expect("textured");
        assert!((x - 6.3).abs() < 0.02 && (y - 5.7).abs() < 0.02, "({x}, {y})");
    }

    #[test]
    fn gain_and_offset_do_not_move_the_match() {
        let tpl_px = render(20, 20, 0.0, 0.0);
        let win_px: Vec<u8> = render(32, 32, 4.4, 7.1).iter().map(|&v| (f32::from(v) * 0.8 + 20.0) as u8).collect();
        let tpl = WindowView::packed(&tpl_px, 20, 20).unwrap();
        let win = WindowView::packed(&win_px, 32, 32).unwrap();
        let (x, y) = refine_translation(&win, &tpl, 4.0, 7.0).expect("textured");
        assert!((x - 4.4).abs() < 0.03 && (y - 7.1).abs() < 0.03, "({x}, {y})");
    }

    #[test]
    fn refuses_a_flat_template_a_flat_window_and_the_edge() {
        let flat = [90u8; 400];
        let tex = render(20, 20, 0.0, 0.0);
        let win_px = render(32, 32, 6.0, 6.0);
        let win = WindowView::packed(&win_px, 32, 32).unwrap();
        let flat_tpl = WindowView::packed(&flat, 20, 20).unwrap();
        assert_eq!(refine_translation(&win, &flat_tpl, 6.0, 6.0), None);
        let tpl = WindowView::packed(&tex, 20, 20).unwrap();
        let flat_win = WindowView::packed(&[90u8; 1024], 32, 32).unwrap();
        assert_eq!(refine_translation(&flat_win, &tpl, 6.0, 6.0), None);
        // Placed past the right edge: samples would fall outside. Too large a template: refused.
        assert_eq!(refine_translation(&win, &tpl, 14.5, 6.0), None);
        assert_eq!(refine_translation(&win, &tpl, f32::NAN, 6.0), None);
        let big = render(33, 33, 0.0, 0.0);
        let big_tpl = WindowView::packed(&big, 33, 33).unwrap();
        let big_win_px = render(40, 40, 3.0, 3.0);
        let big_win = WindowView::packed(&big_win_px, 40, 40).unwrap();
        assert_eq!(refine_translation(&big_win, &big_tpl, 3.0, 3.0), None);
    }

    #[test]
    fn a_template_sized_for_its_interior_refines_as_the_full_one() {
        // A 20x20 template has 18x18 interior pixels: a cache of that many refines to the
        // bit what the default (32x32) one does, the reference; one pixel fewer prepares
        // nothing rather than refine on part of the template.
        let tpl_px = render(20, 20, 0.0, 0.0);
        let win_px = render(32, 32, 6.3, 5.7);
        let tpl = WindowView::packed(&tpl_px, 20, 20).unwrap();
        let win = WindowView::packed(&win_px, 32, 32).unwrap();
        let mut full = LkTemplate::new();
        let mut sized = LkTemplate::<{ 18 * 18 }>::sized();
        assert!(full.prepare(&tpl, None) && sized.prepare(&tpl, None));
        let (a, b) = (full.refine(&win, 6.0, 6.0).expect("textured"), sized.refine(&win, 6.0, 6.0).expect("textured"));
        assert_eq!((a.0.to_bits(), a.1.to_bits()), (b.0.to_bits(), b.1.to_bits()));
        assert!(!LkTemplate::<{ 18 * 18 - 1 }>::sized().prepare(&tpl, None));
        assert!(core::mem::size_of::<LkTemplate<{ 18 * 18 }>>() < core::mem::size_of::<LkTemplate>() / 2);
    }
}
