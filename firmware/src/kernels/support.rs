//! The object's part of a corner template, and NCC over it alone (beyond the thesis).
//!
//! A template centred on an object's corner (thesis 3.1: the corner detector's target) is
//! three parts background. As the object moves, that background changes under it: texture
//! slides past, and clutter the corner passes enters the template. NCC over the whole
//! template (thesis 2.4) then scores the background as much as the object, its best
//! placement drifts and its score falls under the acceptance level exactly where tracking
//! matters. The pixels that move with the object are those inside the corner: the cone
//! between the two edges, seen from the apex. The corner detector's line fit
//! ([`crate::kernels::corner`]) gives the apex and the edge directions, so the template's
//! *support* is that cone, shrunk by a margin so that no pixel blurred across an edge counts:
//!
//! `S = { p : n₁·(p - a) >= m  and  n₂·(p - a) >= m }`, where `a` is the apex, `n₁`, `n₂`
//! the unit normals of the two edges pointing into the cone, and `m` the margin.
//!
//! Over the object's interior alone the template has little contrast, and the thesis's NCC,
//! which is not mean-free, scores any patch of similar brightness nearly 1 (the background,
//! an occluder passing over). The placement is therefore found by the zero-mean NCC over the
//! support, `ZNCC = (n Σ_S R·I - Σ_S R Σ_S I) / sqrt((n Σ_S R² - (Σ_S R)²)(n Σ_S I² - (Σ_S I)²))`
//! with `n = |S|`, refused under [`MIN_ZNCC`] or where the patch has under half the template's
//! standard deviation ([`MIN_CONTRAST_RATIO`]); the score reported, on the scale the
//! processors' thresholds use, is the thesis's NCC over the support at that placement,
//! `Σ_S R·I / sqrt(Σ_S R² · Σ_S I²)` (OpenCV's `TM_CCORR_NORMED` with a mask).
//!
//! Measured with OpenCV on the real-image corner beside clutter (`scripts/support_check.py`,
//! a plain `TM_CCORR_NORMED` tracker): over the whole template the best score falls to 0.944
//! and 42% of the frames end more than 5 px off; over the support it stays at 0.9986 or above,
//! 0.43 px RMS, none lost. The convex cone is the object only for a convex corner; a
//! template that holds no corner near its centre keeps the whole template
//! ([`Support::of_template`]).

use crate::kernels::corner::{CornerDetector, CornerParams};
use crate::kernels::matching::{parabola, Match, MatchError};
use crate::kernels::view::WindowView;

/// Largest template side a support covers (the processors' templates are at most 32 x 32).
pub const MAX_SIDE: usize = 32;

/// Pixels kept clear of each edge, inside the cone: the lens blur spreads an edge over
/// about a pixel to either side, and a mixed pixel carries background.
pub const MARGIN: f32 = 1.0;

/// Farthest the corner may lie from the template's tracked point, in pixels, for the
/// template to be a corner template (the guard's anchoring distance).
pub const NEAR: f32 = 3.0;

/// Fewest support pixels for NCC over the support: fewer do not tell placements apart.
pub const MIN_PIXELS: u32 = 24;

/// Least standard deviation, in gray levels, of the template over its support: an object
/// whose surface is nearly flat is located by its edges, so the whole template serves better
/// (the synthetic scenes' part varies by about 2 levels, the real photographs' by 11).
pub const MIN_STD: u64 = 6;

/// Lowest zero-mean NCC over the support of a placement that is the object: on the real-image
/// corner sequences (`scripts/support_check.py`) the object in plain view scores at least 0.81
/// at the nearest whole pixel (0.68 under the lamp's highlight, where the whole template takes
/// over), and any placement 3 to 10 px away at most 0.67.
pub const MIN_ZNCC: f64 = 0.7;

/// A placement counts only where the window's standard deviation over the support is at
/// least the template's divided by this (a flat or faint patch is not the object).
pub const MIN_CONTRAST_RATIO: u64 = 2;

/// The pixels of a template that belong to the object (see the module docs): one bit per
/// pixel, row by row.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Support {
    rows: [u32; MAX_SIDE],
    width: usize,
    height: usize,
    count: u32,
}

impl Support {
    /// The cone at `apex` between the edges along the unit `rays` (template pixels), shrunk by
    /// `margin`; `None` when the template is larger than [`MAX_SIDE`], the rays are parallel
    /// or not finite, or fewer than [`MIN_PIXELS`] pixels are inside.
    pub fn cone(width: usize, height: usize, apex: (f32, f32), rays: [(f32, f32); 2], margin: f32) -> Option<Support> {
        if width == 0 || height == 0 || width > MAX_SIDE || height > MAX_SIDE {
            return None;
        }
        let [r1, r2] = rays;
        // The normal of each edge that points towards the other edge's ray.
        let cross = r1.0 * r2.1 - r1.1 * r2.0;
        if !cross.is_finite() || cross.abs() < 1e-3 || !apex.0.is_finite() || !apex.1.is_finite() {
            return None;
        }
        let s = cross.signum();
        let n1 = (-r1.1 * s, r1.0 * s);
        let n2 = (r2.1 * s, -r2.0 * s);
        let mut rows = [0u32; MAX_SIDE];
        let mut count = 0;
        for (y, row) in rows.iter_mut().enumerate().take(height) {
            for x in 0..width {
                let (dx, dy) = (x as f32 - apex.0, y as f32 - apex.1);
                if n1.0 * dx + n1.1 * dy >= margin && n2.0 * dx + n2.1 * dy >= margin {
                    *row |= 1 << x;
                    count += 1;
                }
            }
        }
        (count >= MIN_PIXELS).then_some(Support { rows, width, height, count })
    }

    /// The support of the template `tpl` whose tracked point sits at `point` (template
    /// pixels): the cone of the corner the detector finds within [`NEAR`] px of the point,
    /// or `None` (the whole template counts) when there is none, the detector finds no edge
    /// directions (the thesis's rules), or the cone is too small.
    pub fn of_template<const N: usize>(
        tpl: &WindowView<'_>,
        point: (f32, f32),
        detector: &mut CornerDetector<N>,
        params: &CornerParams,
    ) -> Option<Support> {
        let c = detector.detect(tpl, params).ok()?;
        let (ox, oy) = tpl.origin();
        let apex = (c.x - ox as f32, c.y - oy as f32);
        if libm::hypotf(apex.0 - point.0, apex.1 - point.1) > NEAR {
            return None;
        }
        Support::cone(tpl.width(), tpl.height(), apex, c.rays?, MARGIN).filter(|s| s.textured(tpl))
    }

    /// Whether `tpl` varies over the support by at least [`MIN_STD`] gray levels.
    fn textured(&self, tpl: &WindowView<'_>) -> bool {
        let n = u64::from(self.count);
        let (sum, energy) = self.sums(tpl);
        n2_variance(n, sum, energy) >= n * n * MIN_STD * MIN_STD
    }

    /// `Σ v` and `Σ v²` of `view`'s pixels over the support.
    fn sums(&self, view: &WindowView<'_>) -> (u64, u64) {
        let (mut sum, mut energy) = (0u64, 0u64);
        for y in 0..self.height {
            for x in (0..self.width).filter(|&x| self.contains(x, y)) {
                let v = u64::from(view.get(x, y).unwrap_or(0));
                sum += v;
                energy += v * v;
            }
        }
        (sum, energy)
    }

    /// Whether template pixel `(x, y)` is in the support.
    pub fn contains(&self, x: usize, y: usize) -> bool {
        x < self.width && self.rows.get(y).is_some_and(|r| r >> x & 1 == 1)
    }

    /// Pixels in the support.
    pub fn count(&self) -> u32 {
        self.count
    }

    /// Template width and height.
    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }
}

/// `n²` times the variance of `n` values with sum `sum` and energy `energy` (exact in
/// integers).
fn n2_variance(n: u64, sum: u64, energy: u64) -> u64 {
    (n * energy).saturating_sub(sum * sum)
}

/// The best placement of `tpl` in `win` by ZNCC over `support`, scored by NCC over it (see
/// the module docs), with the parabola's sub-pixel position through the ZNCC scores as in
/// [`crate::kernels::matching::best_match`]. Errors: the support does not fit the template, either
/// view is empty or strided, the template is larger than the window, its support is flat
/// ([`MatchError::ZeroEnergy`]), or no placement has the texture and the ZNCC of the object
/// ([`MatchError::NoMatch`]).
pub fn best_match_on(win: &WindowView<'_>, tpl: &WindowView<'_>, support: &Support) -> Result<Match, MatchError> {
    let (tw, th) = (tpl.width(), tpl.height());
    if support.size() != (tw, th) {
        return Err(MatchError::TemplateLarger);
    }
    if win.is_empty() || tpl.is_empty() || win.step() != 1 || tpl.step() != 1 {
        return Err(MatchError::Empty);
    }
    if tw > win.width() || th > win.height() {
        return Err(MatchError::TemplateLarger);
    }
    let masked = |y: usize| (0..tw).filter(move |&x| support.contains(x, y));
    let n = u64::from(support.count());
    let (t_sum, t_energy) = support.sums(tpl);
    let t_var = n2_variance(n, t_sum, t_energy);
    if t_var == 0 {
        return Err(MatchError::ZeroEnergy);
    }
    // (ZNCC, NCC) of a placement; `None` for a patch without the template's texture.
    let score_at = |px: usize, py: usize| -> Option<(f64, f64)> {
        let (mut dot, mut energy, mut sum) = (0u64, 0u64, 0u64);
        for y in 0..th {
            let (t, w) = (tpl.row(y)?, win.row(py + y)?.get(px..px + tw)?);
            for x in masked(y) {
                let (a, b) = (u64::from(*t.get(x)?), u64::from(*w.get(x)?));
                dot += a * b;
                energy += b * b;
                sum += b;
            }
        }
        let var = n2_variance(n, sum, energy);
        if var == 0 || var.saturating_mul(MIN_CONTRAST_RATIO * MIN_CONTRAST_RATIO) < t_var {
            return None;
        }
        let cov = (n * dot) as f64 - (t_sum * sum) as f64;
        let zncc = cov / libm::sqrt(t_var as f64 * var as f64);
        Some((zncc, dot as f64 / libm::sqrt(t_energy as f64 * energy as f64)))
    };
    let (nx, ny) = (win.width() - tw + 1, win.height() - th + 1);
    let mut best: Option<(usize, usize, (f64, f64))> = None;
    for py in 0..ny {
        for px in 0..nx {
            if let Some(s) = score_at(px, py) {
                if best.is_none_or(|(_, _, b)| s.0 > b.0) {
                    best = Some((px, py, s));
                }
            }
        }
    }
    let (bx, by, (zncc, ncc)) = best.filter(|b| b.2 .0 >= MIN_ZNCC).ok_or(MatchError::NoMatch)?;
    let at = |x: Option<usize>, y: Option<usize>| {
        x.zip(y).filter(|&(x, y)| x < nx && y < ny).and_then(|(x, y)| score_at(x, y)).map(|s| s.0)
    };
    let dx = parabola(at(bx.checked_sub(1), Some(by)), zncc, at(Some(bx + 1), Some(by)), true);
    let dy = parabola(at(Some(bx), by.checked_sub(1)), zncc, at(Some(bx), Some(by + 1)), true);
    let (sub_x, sub_y) = ((bx as f64 + dx) as f32, (by as f64 + dy) as f32);
    let (ox, oy) = win.origin();
    Ok(Match { x: bx, y: by, score: ncc, sub_x, sub_y, frame_x: ox as f32 + sub_x, frame_y: oy as f32 + sub_y })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernels::matching::{best_match, Method};
    use std::vec::Vec;

    /// A textured object whose corner is at `(cx, cy)` with edges along +x and +y, on a
    /// background `bg(x, y)`.
    fn scene(w: usize, h: usize, cx: usize, cy: usize, bg: impl Fn(usize, usize) -> u8) -> Vec<u8> {
        (0..w * h)
            .map(|k| {
                let (x, y) = (k % w, k / w);
                if x >= cx && y >= cy {
                    (120 + ((x - cx) * 7 + (y - cy) * 13) % 50) as u8
                } else {
                    bg(x, y)
                }
            })
            .collect()
    }

    #[test]
    fn the_cone_of_an_axis_aligned_corner_is_its_quadrant_less_the_margin() {
        // Hand calculation: apex (4, 4), edges along +x and +y, margin 1: x >= 5 and y >= 5,
        // so 7 x 7 = 49 pixels of a 12 x 12 template.
        let s = Support::cone(12, 12, (4.0, 4.0), [(1.0, 0.0), (0.0, 1.0)], 1.0).expect("cone");
        assert_eq!(s.count(), 49);
        assert!(s.contains(5, 5) && s.contains(11, 11) && !s.contains(4, 8) && !s.contains(8, 4));
        // The rays' order does not matter.
        assert_eq!(Support::cone(12, 12, (4.0, 4.0), [(0.0, 1.0), (1.0, 0.0)], 1.0), Some(s));
        // Parallel rays, a template over MAX_SIDE, or too few pixels: no support.
        assert_eq!(Support::cone(12, 12, (4.0, 4.0), [(1.0, 0.0), (1.0, 0.0)], 1.0), None);
        assert_eq!(Support::cone(33, 12, (4.0, 4.0), [(1.0, 0.0), (0.0, 1.0)], 1.0), None);
        assert_eq!(Support::cone(12, 12, (9.0, 9.0), [(1.0, 0.0), (0.0, 1.0)], 1.0), None);
    }

    #[test]
    fn ncc_on_the_support_ignores_a_background_that_changed() {
        // The template: the corner at (8, 8) of a 20 x 20 block over a flat background. In the
        // window the object sits 5 px right and 3 px down, and the background behind it is
        // now a bright blob pattern. The whole template's NCC is pulled off; over the
        // support it finds the true placement (5, 3) with a score of 1 (the reference: the
        // placement the window was built with).
        let tpl_px = scene(20, 20, 8, 8, |_, _| 40);
        let win_px = scene(30, 30, 13, 11, |x, y| if (x / 3 + y / 3) % 2 == 0 { 230 } else { 10 });
        let tpl = WindowView::packed(&tpl_px, 20, 20).unwrap();
        let win = WindowView::packed(&win_px, 30, 30).unwrap();
        let support = Support::cone(20, 20, (7.5, 7.5), [(1.0, 0.0), (0.0, 1.0)], MARGIN).unwrap();
        let m = best_match_on(&win, &tpl, &support).expect("match");
        assert_eq!((m.x, m.y), (5, 3));
        assert!(m.score > 0.999_999, "{}", m.score);
        let whole = best_match(Method::Ncc, &win, &tpl).expect("match");
        assert!(whole.score < 0.95, "the whole template scores the background too: {}", whole.score);
    }

    #[test]
    fn a_corner_template_gets_the_cone_and_a_flat_or_cornerless_one_none() {
        // A 20 x 20 template whose corner (edges along +x and +y) is at (8, 8), the tracked
        // point at (8.5, 8.5): the detector's line fit gives the apex near (7.5, 7.5) and the
        // cone is the quadrant x, y >= 9 (margin 1): 11 x 11 = 121 pixels, give or take a
        // column of the fit's sub-pixel apex.
        let mut det = CornerDetector::default();
        let params = CornerParams::new(50);
        let textured = scene(20, 20, 8, 8, |_, _| 40);
        let tpl = WindowView::packed(&textured, 20, 20).unwrap();
        let s = Support::of_template(&tpl, (8.5, 8.5), &mut det, &params).expect("a corner template");
        assert!((110..=144).contains(&s.count()), "{}", s.count());
        assert!(s.contains(15, 15) && !s.contains(3, 15) && !s.contains(15, 3));
        // The tracked point 6 px from the corner: not a corner template.
        assert_eq!(Support::of_template(&tpl, (14.5, 14.5), &mut det, &params), None);
        // A flat object (one gray level): located by its edges, the whole template serves.
        let flat = scene(20, 20, 8, 8, |_, _| 40).iter().map(|&v| if v > 100 { 150 } else { v }).collect::<Vec<u8>>();
        let tpl = WindowView::packed(&flat, 20, 20).unwrap();
        assert_eq!(Support::of_template(&tpl, (8.5, 8.5), &mut det, &params), None);
    }

    #[test]
    fn refuses_mismatched_or_flat_inputs() {
        let tpl_px = scene(20, 20, 8, 8, |_, _| 40);
        let tpl = WindowView::packed(&tpl_px, 20, 20).unwrap();
        let support = Support::cone(20, 20, (7.5, 7.5), [(1.0, 0.0), (0.0, 1.0)], MARGIN).unwrap();
        let small = WindowView::packed(&tpl_px[..100], 10, 10).unwrap();
        assert_eq!(best_match_on(&small, &tpl, &support), Err(MatchError::TemplateLarger));
        let other = Support::cone(16, 16, (5.5, 5.5), [(1.0, 0.0), (0.0, 1.0)], MARGIN).unwrap();
        let win_px = scene(30, 30, 13, 11, |_, _| 40);
        let win = WindowView::packed(&win_px, 30, 30).unwrap();
        assert_eq!(best_match_on(&win, &tpl, &other), Err(MatchError::TemplateLarger));
        let flat = WindowView::packed(&[0u8; 400], 20, 20).unwrap();
        assert_eq!(best_match_on(&win, &flat, &support), Err(MatchError::ZeroEnergy));
        let dark = WindowView::packed(&[0u8; 900], 30, 30).unwrap();
        assert_eq!(best_match_on(&dark, &tpl, &support), Err(MatchError::NoMatch));
        // A flat bright patch (an occluder) scores 0.99 by NCC alone, but has no texture.
        let bright = WindowView::packed(&[140u8; 900], 30, 30).unwrap();
        assert_eq!(best_match_on(&bright, &tpl, &support), Err(MatchError::NoMatch));
    }
}
