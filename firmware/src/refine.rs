//! Sub-pixel refinement of a template match (beyond the thesis, which stops at the best
//! integer placement; [`crate::matching`] adds a parabola through three scores).
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
//!   `(x, y) -= H⁻¹ Σ g (Ŵ - T)` until the step is under 0.01 px (at most 8 iterations).
//!
//! Arithmetic is `f32` (the Cortex-M4F's single-precision FPU); no allocation, no panic.

use crate::view::WindowView;

/// Iterations at most.
const ITERATIONS: usize = 8;
/// A step under this many pixels ends the iteration.
const CONVERGED: f32 = 0.01;
/// Farthest the refined placement may be from the start before it is refused (the parabola
/// is within half a pixel of the truth, so a longer walk means the iteration diverged).
const MAX_WALK: f32 = 1.0;

/// The refined top-left placement of `tpl` in `win`, starting from `(x, y)` (window pixels,
/// real-valued, e.g. the parabola fit), or `None` when the template has no texture in some
/// direction (singular `H`), the window is flat, a sample would fall outside the window, or
/// the iteration walks more than a pixel.
pub fn refine_translation(win: &WindowView<'_>, tpl: &WindowView<'_>, x: f32, y: f32) -> Option<(f32, f32)> {
    let (tw, th) = (tpl.width(), tpl.height());
    if tw < 3 || th < 3 || !x.is_finite() || !y.is_finite() {
        return None;
    }
    let t = |i: usize, j: usize| tpl.get(i, j).map(f32::from);
    let interior = || (1..th - 1).flat_map(move |j| (1..tw - 1).map(move |i| (i, j)));
    let count = ((tw - 2) * (th - 2)) as f32;
    let (mut h11, mut h12, mut h22, mut t_sum) = (0.0f32, 0.0f32, 0.0f32, 0.0f32);
    for (i, j) in interior() {
        let gx = (t(i + 1, j)? - t(i - 1, j)?) / 2.0;
        let gy = (t(i, j + 1)? - t(i, j - 1)?) / 2.0;
        h11 += gx * gx;
        h12 += gx * gy;
        h22 += gy * gy;
        t_sum += t(i, j)?;
    }
    let det = h11 * h22 - h12 * h12;
    if det.is_nan() || det <= 1e-3 * (h11 + h22) * (h11 + h22) {
        return None;
    }
    let t_mean = t_sum / count;
    let t_dev = libm::sqrtf(interior().filter_map(|(i, j)| t(i, j)).map(|v| (v - t_mean) * (v - t_mean)).sum());
    let (mut px, mut py) = (x, y);
    for _ in 0..ITERATIONS {
        let mut w_sum = 0.0f32;
        let mut w_sq = 0.0f32;
        for (i, j) in interior() {
            let v = bilinear(win, px + i as f32, py + j as f32)?;
            w_sum += v;
            w_sq += v * v;
        }
        let w_mean = w_sum / count;
        let w_dev = libm::sqrtf((w_sq - w_sum * w_mean).max(0.0));
        if w_dev.is_nan() || w_dev <= 0.0 {
            return None;
        }
        let gain = t_dev / w_dev;
        let (mut b1, mut b2) = (0.0f32, 0.0f32);
        for (i, j) in interior() {
            let v = bilinear(win, px + i as f32, py + j as f32)?;
            let e = (v - w_mean) * gain + t_mean - t(i, j)?;
            b1 += (t(i + 1, j)? - t(i - 1, j)?) / 2.0 * e;
            b2 += (t(i, j + 1)? - t(i, j - 1)?) / 2.0 * e;
        }
        let (dx, dy) = ((h22 * b1 - h12 * b2) / det, (h11 * b2 - h12 * b1) / det);
        px -= dx;
        py -= dy;
        if libm::hypotf(px - x, py - y) > MAX_WALK || !px.is_finite() || !py.is_finite() {
            return None;
        }
        if libm::hypotf(dx, dy) < CONVERGED {
            break;
        }
    }
    Some((px, py))
}

/// The window's gray level at real-valued `(x, y)` by bilinear interpolation, or `None`
/// outside the window.
fn bilinear(win: &WindowView<'_>, x: f32, y: f32) -> Option<f32> {
    if !(x >= 0.0 && y >= 0.0) {
        return None;
    }
    let (fx, fy) = (libm::floorf(x), libm::floorf(y));
    let (ax, ay) = (x - fx, y - fy);
    let (ix, iy) = (fx as usize, fy as usize);
    let g = |i: usize, j: usize| win.get(i, j).map(f32::from);
    // On the last row or column the weight of the next one is 0: do not read past the edge.
    let right = |j: usize| if ax > 0.0 { g(ix + 1, j) } else { Some(0.0) };
    let top = g(ix, iy)? * (1.0 - ax) + right(iy)? * ax;
    let bottom = if ay > 0.0 { g(ix, iy + 1)? * (1.0 - ax) + right(iy + 1)? * ax } else { 0.0 };
    Some(top * (1.0 - ay) + bottom * ay)
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
        // Placed past the right edge: samples would fall outside.
        assert_eq!(refine_translation(&win, &tpl, 14.5, 6.0), None);
        assert_eq!(refine_translation(&win, &tpl, f32::NAN, 6.0), None);
    }
}
