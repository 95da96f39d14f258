//! Scores of placements from exact integer sums (thesis 2.4's SSD, SAD and NCC, and ZNCC): the
//! window energies from running column sums, the dot products from [`super::dot`].
use super::dot::{dot_placement, dot_products, dot_row, sad_row, PaddedTemplate};
#[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
use super::dot::patch_dots;
use super::{MatchError, Method, MAX_SEARCH_WIDTH, SCORE_CACHE};
use crate::kernels::view::WindowView;
use heapless::Vec;

/// A row of ones, for pixel sums as dot products.
const ONES: [u8; MAX_SEARCH_WIDTH] = [1; MAX_SEARCH_WIDTH];

/// `v` in single precision within 1.2e-7 of it (relative), in two hardware conversions and
/// a multiply-add: the library's exact conversion is a call of tens of instructions on the M4.
fn to_f32(v: i64) -> f32 {
    ((v >> 32) as i32) as f32 * 4_294_967_296.0 + (v as u32) as f32
}

/// ZNCC's rank `n |n| / v` (numerator `n`, window variance `v > 0`) in single precision,
/// within 5e-7 of the exact one (two conversions and two roundings), without the 128-bit
/// products of [`Scorer::zncc_parts`] (library calls on the M4).
#[inline(always)]
pub(super) fn zncc_rank(n: i64, v: i64) -> f32 {
    let n = to_f32(n);
    n * n.abs() / to_f32(v)
}

/// Most template pixels for ZNCC's terms in 64 bits ([`Scorer::zncc_parts64`]).
const NARROW: u64 = 1 << 23;

/// Template statistics that do not depend on the placement.
struct TemplateStats {
    energy: u64,
    /// `Σ R`, which only ZNCC reads (0 for the other methods).
    sum: u64,
    n: u64,
}

/// `Σ R²`, and `Σ R` where `SUM` (ZNCC; a constant, so the other measures' loop has no test).
fn template_stats<const SUM: bool>(tpl: &WindowView<'_>) -> TemplateStats {
    let mut energy = 0u64;
    let mut sum = 0u64;
    for v in 0..tpl.height() {
        let r = tpl.row(v).unwrap_or(&[]);
        energy += dot_row(r, r);
        // Σ p as Σ p·1: the dot product's fast path (a row is at most MAX_SEARCH_WIDTH wide).
        if SUM {
            sum += dot_row(r, &ONES);
        }
    }
    TemplateStats {
        energy,
        sum,
        n: (tpl.width() * tpl.height()) as u64,
    }
}

/// A placement's exact integer sums: `a = Σ R·I` (`Σ |R - I|` for SAD), `e = Σ I²`, `s = Σ I`.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Sums {
    pub(super) a: u64,
    pub(super) e: u64,
    pub(super) s: u64,
}

/// A placement's sums, with its ZNCC rank where it has one ([`Scorer::ranked`]).
#[derive(Clone, Copy, Debug)]
pub(super) struct Ranked {
    pub(super) sums: Sums,
    rank: Option<f32>,
}

/// Scores placements of one template under one method (see the module formulas).
pub(super) struct Scorer {
    method: Method,
    t: TemplateStats,
}

impl Scorer {
    /// The scorer of `tpl` under `method`; [`MatchError::ZeroEnergy`] for an NCC template
    /// without energy or a ZNCC one without variance.
    pub(super) fn new(method: Method, tpl: &WindowView<'_>) -> Result<Self, MatchError> {
        let t = if method == Method::Zncc { template_stats::<true>(tpl) } else { template_stats::<false>(tpl) };
        match method {
            Method::Ncc if t.energy == 0 => Err(MatchError::ZeroEnergy),
            Method::Zncc if (t.n as u128) * (t.energy as u128) == (t.sum as u128).pow(2) => Err(MatchError::ZeroEnergy),
            _ => Ok(Scorer { method, t }),
        }
    }

    /// The score of a placement; `None` without energy (variance for ZNCC).
    pub(super) fn score(&self, x: &Sums) -> Option<f64> {
        let t = &self.t;
        match self.method {
            Method::Sad => Some(x.a as f64),
            Method::Ssd => Some(self.ssd(x) as f64),
            Method::Ncc => {
                if x.e == 0 {
                    return None;
                }
                let q = libm::sqrt(t.energy as f64 * x.e as f64);
                Some((x.a as f64 / q).min(1.0))
            }
            Method::Zncc => {
                // The same integers converted from 64 bits where they fit: a conversion is
                // exact rounding either way, and from 128 bits a longer library call on the M4.
                let (num, vw, vt) = match (self.zncc_parts64(x), self.zncc_template_var64()) {
                    (Some((num, vw)), Some(vt)) if vw > 0 && vt > 0 => (num as f64, vw as f64, vt as f64),
                    (Some(_), Some(_)) => return None,
                    _ => {
                        let (num, vw, vt) = self.zncc_defined(x)?;
                        (num as f64, vw as f64, vt as f64)
                    }
                };
                let q = libm::sqrt(vt * vw);
                Some((num / q).clamp(-1.0, 1.0))
            }
        }
    }

    /// Placement `x` with what [`Scorer::better`] compares, or `None` when it has no score
    /// (see [`Scorer::score`]). A search ranks each placement once and keeps the best's.
    pub(super) fn ranked(&self, x: Sums) -> Option<Ranked> {
        let (scores, rank) = match self.method {
            Method::Sad | Method::Ssd => (true, None),
            Method::Ncc => (x.e != 0, None),
            // The template's variance is positive ([`Scorer::new`]): the window's decides.
            Method::Zncc => match self.zncc_parts64(&x) {
                Some((n, v)) => (v > 0, Some(zncc_rank(n, v))),
                None => (self.zncc_parts(&x).1 > 0, None),
            },
        };
        scores.then_some(Ranked { sums: x, rank })
    }

    /// Whether `x` scores strictly better than `y`, from their exact integer sums, without
    /// computing a score: for NCC `a_x / sqrt(e_x) > a_y / sqrt(e_y)` as
    /// `a_x² e_y > a_y² e_x` (dot products are not negative), for ZNCC the same with the
    /// numerator's sign and the window's variance, where the single-precision ranks do not
    /// decide (a near-tie; `f64` scores only if the products overflow, for templates of
    /// tens of thousands of pixels).
    /// Inlined where a search ranks each placement (`rank_all`): a call a placement costs
    /// more than the single-precision comparison that decides most of them.
    #[inline(always)]
    pub(super) fn better(&self, x: &Ranked, y: &Ranked) -> bool {
        let (x, y) = match (x.rank, y.rank) {
            (Some(rx), Some(ry)) if (rx - ry).abs() > 1e-5 * rx.abs().max(ry.abs()) => return rx > ry,
            _ => (&x.sums, &y.sums),
        };
        match self.method {
            Method::Sad => x.a < y.a,
            Method::Ssd => self.ssd(x) < self.ssd(y),
            Method::Ncc => {
                let side = |a: u64, e: u64| u128::from(a) * u128::from(a) * u128::from(e);
                side(x.a, y.e) > side(y.a, x.e)
            }
            Method::Zncc => {
                let (nx, vx) = self.zncc_parts(x);
                let (ny, vy) = self.zncc_parts(y);
                // |n|² v: both variances are positive (the placements have scores).
                let side = |n: i128, v: i128| n.unsigned_abs().checked_mul(n.unsigned_abs())?.checked_mul(v.unsigned_abs());
                match (nx >= 0, ny >= 0) {
                    (true, false) => true,
                    (false, true) => false,
                    (positive, _) => match (side(nx, vy), side(ny, vx)) {
                        (Some(l), Some(r)) => if positive { l > r } else { l < r },
                        _ => self.score(x) > self.score(y),
                    },
                }
            }
        }
    }

    /// ZNCC's numerator, window variance and template variance (`n Σ R² - (Σ R)²`), when both
    /// variances are positive (the score is defined).
    fn zncc_defined(&self, x: &Sums) -> Option<(i128, i128, i128)> {
        let t = &self.t;
        let (num, vw) = self.zncc_parts(x);
        let vt = i128::from(t.n) * i128::from(t.energy) - i128::from(t.sum) * i128::from(t.sum);
        (vw > 0 && vt > 0).then_some((num, vw, vt))
    }

    /// [`Scorer::zncc_parts`] in 64 bits for templates of up to [`NARROW`] pixels (a few
    /// instructions on the M4, where 128-bit and checked 64-bit products are library calls):
    /// with `Σ R·I, Σ I² <= 255² n` and `Σ R, Σ I <= 255 n`, every product is below
    /// `255² n² < 2⁶²`.
    fn zncc_parts64(&self, x: &Sums) -> Option<(i64, i64)> {
        if self.t.n > NARROW {
            return None;
        }
        let (n, sum) = (self.t.n as i64, self.t.sum as i64);
        let (a, e, s) = (x.a as i64, x.e as i64, x.s as i64);
        Some((n * a - sum * s, n * e - s * s))
    }

    /// The template's variance term `n Σ R² - (Σ R)²` in 64 bits, for templates of up to
    /// [`NARROW`] pixels (as [`Scorer::zncc_parts64`]).
    fn zncc_template_var64(&self) -> Option<i64> {
        let t = &self.t;
        (t.n <= NARROW).then(|| t.n as i64 * t.energy as i64 - t.sum as i64 * t.sum as i64)
    }

    /// ZNCC's numerator `n Σ R·I - Σ R Σ I` and window variance `n Σ I² - (Σ I)²`.
    fn zncc_parts(&self, x: &Sums) -> (i128, i128) {
        let (t, n) = (&self.t, i128::from(self.t.n));
        (n * i128::from(x.a) - i128::from(t.sum) * i128::from(x.s), n * i128::from(x.e) - i128::from(x.s) * i128::from(x.s))
    }

    /// `Σ(R-I)² = ΣR² + ΣI² - 2ΣRI >= 0` exactly in integers.
    pub(super) fn ssd(&self, x: &Sums) -> u64 {
        (self.t.energy + x.e).saturating_sub(2 * x.a)
    }
}

/// Validates sizes and returns `(placements_x, placements_y)`.
pub(super) fn placements(win: &WindowView<'_>, tpl: &WindowView<'_>) -> Result<(usize, usize), MatchError> {
    if win.is_empty() || tpl.is_empty() {
        return Err(MatchError::Empty);
    }
    if tpl.width() > win.width() || tpl.height() > win.height() {
        return Err(MatchError::TemplateLarger);
    }
    if win.width() > MAX_SEARCH_WIDTH {
        return Err(MatchError::TooLarge);
    }
    Ok((
        win.width() - tpl.width() + 1,
        win.height() - tpl.height() + 1,
    ))
}

/// Visits every placement in raster order with its sums over two full-resolution (step 1)
/// views, for `scorer`'s method. The visitor sees placement `(px, py)`.
pub(super) fn for_each_score(
    scorer: &Scorer,
    win: &WindowView<'_>,
    tpl: &WindowView<'_>,
    visit: impl FnMut(usize, usize, Sums),
) -> Result<(), MatchError> {
    // A column of `th` squared pixels fits `u32` while th·255² < 2³² (th <= 66051); the
    // narrow columns halve the running-sum work.
    if tpl.height() <= 66_051 {
        for_each_score_in::<u32>(scorer.method, win, tpl, visit)
    } else {
        for_each_score_in::<u64>(scorer.method, win, tpl, visit)
    }
}

/// An exact column-sum accumulator (`u32` for columns short enough, else `u64`).
trait ColSum: Copy + Default {
    /// `self + add - sub`, exact when the true result is representable.
    fn update(self, add: u32, sub: u32) -> Self;
    fn wide(self) -> u64;
}

impl ColSum for u32 {
    #[inline(always)]
    fn update(self, add: u32, sub: u32) -> Self {
        self.wrapping_add(add).wrapping_sub(sub)
    }
    #[inline(always)]
    fn wide(self) -> u64 {
        u64::from(self)
    }
}

impl ColSum for u64 {
    #[inline(always)]
    fn update(self, add: u32, sub: u32) -> Self {
        self.wrapping_add(u64::from(add)).wrapping_sub(u64::from(sub))
    }
    #[inline(always)]
    fn wide(self) -> u64 {
        self
    }
}

/// Adds row `add` and removes row `sub` (if any) from the column sums of `I²` (and of
/// `I` when `sums` is set): one fused pass per placement row.
#[inline(never)]
fn update_cols<C: ColSum>(sq: &mut [C], sum: &mut [C], add: &[u8], sub: Option<&[u8]>, sums: bool) {
    let sq2 = |p: u8| u32::from(p) * u32::from(p);
    match sub {
        Some(sub) => {
            for ((q, &a), &b) in sq.iter_mut().zip(add).zip(sub) {
                *q = q.update(sq2(a), sq2(b));
            }
            if sums {
                for ((s, &a), &b) in sum.iter_mut().zip(add).zip(sub) {
                    *s = s.update(u32::from(a), u32::from(b));
                }
            }
        }
        None => {
            for (q, &a) in sq.iter_mut().zip(add) {
                *q = q.update(sq2(a), 0);
            }
            if sums {
                for (s, &a) in sum.iter_mut().zip(add) {
                    *s = s.update(u32::from(a), 0);
                }
            }
        }
    }
}

fn for_each_score_in<C: ColSum>(
    method: Method,
    win: &WindowView<'_>,
    tpl: &WindowView<'_>,
    mut visit: impl FnMut(usize, usize, Sums),
) -> Result<(), MatchError> {
    let (nx, ny) = placements(win, tpl)?;
    let (tw, th, ww) = (tpl.width(), tpl.height(), win.width());
    let needs_energy = method != Method::Sad;
    // The dot products of a band of placement rows at a time, as many as the cache holds: a
    // map larger than it (a Peripheral sweep's 64x64 window at 25 %, 3,025 placements) keeps
    // the fast path. Several bands are whole groups of four rows where they can be (the M4
    // sums four placement rows at once). `banded` is false where the first band has no dot
    // products (then every placement is summed with the padded template, or row by row).
    let band = match (SCORE_CACHE / nx.max(1)).clamp(1, ny.max(1)) {
        b if b >= 4 && b < ny => b - b % 4,
        b => b,
    };
    let mut dots = Vec::new();
    let band_dots = |py: usize, dots: &mut Vec<u32, SCORE_CACHE>| {
        let rows = band.min(ny - py);
        win.sub(0, py, ww, rows + th - 1).and_then(|band_win| dot_products(&band_win, tpl, dots))
    };
    let banded = needs_energy && band_dots(0, &mut dots).is_some();
    let padded = if needs_energy && !banded { PaddedTemplate::new(tpl) } else { None };
    // Column sums of I² and I over the `th` rows of the current placement row.
    let mut col_sq: Vec<C, MAX_SEARCH_WIDTH> = Vec::new();
    let mut col_sum: Vec<C, MAX_SEARCH_WIDTH> = Vec::new();
    let sums = method == Method::Zncc;
    let mut acc: Vec<u64, MAX_SEARCH_WIDTH> = Vec::new();
    // Capacity checked in `placements` (ww <= MAX_SEARCH_WIDTH, nx <= ww).
    let _ = col_sq.resize(ww, C::default());
    let _ = col_sum.resize(ww, C::default());
    let _ = acc.resize(nx, 0);
    if needs_energy {
        for v in 0..th {
            update_cols(&mut col_sq, &mut col_sum, win.row(v).unwrap_or(&[]), None, sums);
        }
    }
    for py in 0..ny {
        if needs_energy && py > 0 {
            let (add, sub) = (win.row(py + th - 1).unwrap_or(&[]), win.row(py - 1));
            update_cols(&mut col_sq, &mut col_sum, add, sub, sums);
        }
        if banded {
            if py % band == 0 && py > 0 && band_dots(py, &mut dots).is_none() {
                return Err(MatchError::TooLarge);
            }
            for (a, &v) in acc.iter_mut().zip(dots.iter().skip(py % band * nx)) {
                *a = u64::from(v);
            }
        } else if let Some(pt) = padded.as_ref() {
            for (px, a) in acc.iter_mut().enumerate() {
                *a = if pt.lanes == 16 {
                    dot_placement::<16>(pt, win, tw, th, px, py)
                } else {
                    dot_placement::<8>(pt, win, tw, th, px, py)
                };
            }
        } else {
            acc.iter_mut().for_each(|a| *a = 0);
        }
        for v in (0..th).filter(|_| padded.is_none() && !banded) {
            let trow = tpl.row(v).unwrap_or(&[]);
            let wrow = win.row(py + v).unwrap_or(&[]);
            if method == Method::Sad {
                for (a, w) in acc.iter_mut().zip(wrow.windows(tw)) {
                    *a += sad_row(trow, w);
                }
            } else {
                for (a, w) in acc.iter_mut().zip(wrow.windows(tw)) {
                    *a += dot_row(trow, w);
                }
            }
        }
        // Running sums along the row of the column sums give each placement's energy.
        let col = |c: &[C], i: usize| c.get(i).map_or(0, |v| v.wide());
        let mut e: u64 = col_sq.iter().take(tw).map(|v| v.wide()).sum();
        let mut s: u64 = col_sum.iter().take(tw).map(|v| v.wide()).sum();
        for (px, &a) in acc.iter().enumerate() {
            if px > 0 && needs_energy {
                e = e + col(&col_sq, px + tw - 1) - col(&col_sq, px - 1);
                if sums {
                    s = s + col(&col_sum, px + tw - 1) - col(&col_sum, px - 1);
                }
            }
            visit(px, py, Sums { a, e, s });
        }
    }
    Ok(())
}

/// The sums of the single placement `(px, py)` computed directly (used for the sub-pixel
/// neighbours of the peak); `None` outside.
pub(super) fn sums_at(method: Method, win: &WindowView<'_>, tpl: &WindowView<'_>, px: usize, py: usize) -> Option<Sums> {
    let (tw, th) = (tpl.width(), tpl.height());
    if px + tw > win.width() || py + th > win.height() {
        return None;
    }
    #[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
    if matches!(method, Method::Ssd | Method::Ncc) {
        if let Some((a, e)) = patch_dots(tpl, win, px, py) {
            return Some(Sums { a, e, s: 0 });
        }
    }
    let mut x = Sums::default();
    for v in 0..th {
        let trow = tpl.row(v)?;
        let w = win.row(py + v)?.get(px..px + tw)?;
        x.a += if method == Method::Sad { sad_row(trow, w) } else { dot_row(trow, w) };
        x.e += dot_row(w, w);
        // Only ZNCC reads the pixel sum.
        if method == Method::Zncc {
            x.s += w.iter().map(|&p| u64::from(p)).sum::<u64>();
        }
    }
    Some(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 64-bit ZNCC terms against the 128-bit ones (exact integers: the reference), at the
    /// largest sums a template of each size allows (up to [`NARROW`] pixels) and at smaller ones.
    #[test]
    fn zncc_terms_in_64_bits_equal_the_128_bit_ones() {
        for n in [1u64, 400, 1024, 1 << 16, NARROW - 1, NARROW] {
            let full = Sums { a: 255 * 255 * n, e: 255 * 255 * n, s: 255 * n };
            let some = Sums { a: 97 * 131 * n, e: 131 * 131 * n, s: 131 * n - 7 };
            for (sum, energy) in [(255 * n, 255 * 255 * n), (97 * n + 3, 97 * 97 * n + 11)] {
                let scorer = Scorer { method: Method::Zncc, t: TemplateStats { energy, sum, n } };
                for x in [full, some, Sums::default()] {
                    let (num, var) = scorer.zncc_parts(&x);
                    assert_eq!(scorer.zncc_parts64(&x), Some((num as i64, var as i64)), "n {n}, sums {x:?}");
                    let vt = i128::from(n) * i128::from(energy) - i128::from(sum) * i128::from(sum);
                    assert_eq!(scorer.zncc_template_var64(), Some(vt as i64), "n {n}");
                }
            }
        }
    }
}
