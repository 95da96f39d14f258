//! The peak-to-sidelobe ratio (PSR) of a zero-mean NCC surface, the baseline issue 21 sets
//! beside `track`'s `confidence`: Bolme et al. (MOSSE, CVPR 2010) judge a correlation
//! tracker's match by `(peak - mean of the sidelobe) / standard deviation of the sidelobe`,
//! the sidelobe being the surface without the peak's neighbourhood. Written here from those
//! definitions in `f64`, not with the firmware's matcher, so that it is an independent
//! baseline.

/// Placements on each side of the peak left out of the sidelobe: a 5x5 neighbourhood, the
/// peak's own width for a textured template.
pub const EXCLUDE: usize = 2;

/// A gray frame, row by row.
#[derive(Clone, Copy, Debug)]
pub struct Gray<'a> {
    /// The pixels, `width * height` of them.
    pub pixels: &'a [u8],
    /// Pixels per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
}

impl Gray<'_> {
    /// The `side`x`side` patch with its top-left pixel at `(x0, y0)`, or `None` when it is not
    /// wholly inside the frame.
    pub fn patch(&self, x0: i64, y0: i64, side: usize) -> Option<Vec<f64>> {
        let (x0, y0) = (usize::try_from(x0).ok()?, usize::try_from(y0).ok()?);
        if x0 + side > self.width || y0 + side > self.height || self.pixels.len() < self.width * self.height {
            return None;
        }
        Some((y0..y0 + side).flat_map(|y| self.pixels[y * self.width + x0..][..side].iter().map(|&v| f64::from(v))).collect())
    }

    /// The `side`x`side` patch centred on `c` (its top-left pixel at `round(c - (side - 1) / 2)`).
    pub fn patch_at(&self, c: (f64, f64), side: usize) -> Option<Vec<f64>> {
        let half = (side as f64 - 1.0) / 2.0;
        self.patch((c.0 - half).round() as i64, (c.1 - half).round() as i64, side)
    }
}

/// Zero-mean NCC of two patches of the same size:
/// `sum((a - mean a)(b - mean b)) / sqrt(sum (a - mean a)^2 * sum (b - mean b)^2)`, in -1..1;
/// `None` when either is flat or their sizes differ.
pub fn zncc(a: &[f64], b: &[f64]) -> Option<f64> {
    if a.len() != b.len() || a.is_empty() {
        return None;
    }
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let (mut ab, mut aa, mut bb) = (0.0, 0.0, 0.0);
    for (x, y) in a.iter().zip(b) {
        let (dx, dy) = (x - ma, y - mb);
        ab += dx * dy;
        aa += dx * dx;
        bb += dy * dy;
    }
    (aa > 0.0 && bb > 0.0).then(|| ab / (aa * bb).sqrt())
}

/// The PSR of a surface of `width` columns (row by row; `None` for a placement that has no
/// value): its peak, and as the sidelobe every other value more than [`EXCLUDE`] placements
/// from the peak in either direction. `None` with fewer than two sidelobe values or a flat
/// sidelobe.
pub fn psr_of(surface: &[Option<f64>], width: usize) -> Option<f64> {
    let (peak_at, peak) = surface.iter().enumerate().filter_map(|(i, v)| Some((i, (*v)?))).max_by(|a, b| a.1.total_cmp(&b.1))?;
    let (px, py) = (peak_at % width, peak_at / width);
    let side: Vec<f64> = surface
        .iter()
        .enumerate()
        .filter(|(i, _)| (i % width).abs_diff(px) > EXCLUDE || (i / width).abs_diff(py) > EXCLUDE)
        .filter_map(|(_, v)| *v)
        .collect();
    if side.len() < 2 {
        return None;
    }
    let n = side.len() as f64;
    let mean = side.iter().sum::<f64>() / n;
    let sd = (side.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / n).sqrt();
    (sd > 0.0).then(|| (peak - mean) / sd)
}

/// The PSR of template `tpl` (`side`x`side`) in `frame` around `c`: the zero-mean NCC surface
/// of the `(2 radius + 1)^2` placements whose centres lie within `radius` px of `c` in each
/// direction (placements outside the frame, or flat, have no value), by [`psr_of`].
pub fn psr(frame: &Gray<'_>, tpl: &[f64], side: usize, c: (f64, f64), radius: usize) -> Option<f64> {
    let r = radius as i64;
    let width = 2 * radius + 1;
    let surface: Vec<Option<f64>> = (-r..=r)
        .flat_map(|dy| (-r..=r).map(move |dx| (dx, dy)))
        .map(|(dx, dy)| frame.patch_at((c.0 + dx as f64, c.1 + dy as f64), side).and_then(|p| zncc(tpl, &p)))
        .collect();
    psr_of(&surface, width)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zncc_is_one_on_itself_minus_one_on_its_negative_and_blind_to_gain_and_offset() {
        let a = [1.0, 5.0, 2.0, 8.0];
        let brighter: Vec<f64> = a.iter().map(|v| 3.0 * v + 10.0).collect();
        let negative: Vec<f64> = a.iter().map(|v| -v).collect();
        assert!((zncc(&a, &a).unwrap() - 1.0).abs() < 1e-12);
        assert!((zncc(&a, &brighter).unwrap() - 1.0).abs() < 1e-12);
        assert!((zncc(&a, &negative).unwrap() + 1.0).abs() < 1e-12);
        assert_eq!(zncc(&a, &[4.0; 4]), None, "a flat patch");
        // Hand calculation: a = (1, 2, 3), b = (1, 3, 2): deviations (-1, 0, 1) and (-1, 1, 0),
        // sum of products 1, sums of squares 2 and 2: 1 / 2.
        assert!((zncc(&[1.0, 2.0, 3.0], &[1.0, 3.0, 2.0]).unwrap() - 0.5).abs() < 1e-12);
    }

    #[test]
    fn psr_by_hand() {
        // 5x5 surface, peak 1 in the middle: with EXCLUDE = 2 nothing is left; on a 7x7 one the
        // border ring (24 values) alternates 0.1 and -0.1: mean 0, deviation 0.1, PSR 10.
        let mut s = vec![Some(0.0); 49];
        s[24] = Some(1.0);
        let mut sign = 1.0;
        for (i, v) in s.iter_mut().enumerate() {
            let (x, y) = (i % 7, i / 7);
            if x == 0 || y == 0 || x == 6 || y == 6 {
                *v = Some(0.1 * sign);
                sign = -sign;
            }
        }
        assert!((psr_of(&s, 7).unwrap() - 10.0).abs() < 1e-9);
        let mut small = vec![Some(0.0); 25];
        small[12] = Some(1.0);
        assert_eq!(psr_of(&small, 5), None, "5x5 around its peak: no sidelobe");
    }

    #[test]
    fn a_unique_match_has_a_higher_psr_than_a_periodic_one() {
        // Pseudo-random texture: one peak of 1 over a sidelobe of about N(0, 1/8) for an 8x8
        // template, PSR near 8. Vertical stripes of period 4: a peak of 1 every 4 columns,
        // the sidelobe swinging between -1 and 1, PSR near 1.
        let (w, h) = (48usize, 48usize);
        let mut seed = 7u32;
        let random: Vec<u8> = (0..w * h)
            .map(|_| {
                seed = seed.wrapping_mul(1_103_515_245).wrapping_add(12_345);
                (seed >> 24) as u8
            })
            .collect();
        let stripes: Vec<u8> = (0..w * h).map(|i| [0, 80, 200, 80][i % w % 4]).collect();
        let c = (20.0, 24.0);
        let at = |pixels: &[u8]| {
            let g = Gray { pixels, width: w, height: h };
            psr(&g, &g.patch_at(c, 8).unwrap(), 8, c, 8).unwrap()
        };
        let (unique, periodic) = (at(&random), at(&stripes));
        assert!(unique > 6.0 && periodic < 3.0, "unique {unique:.1}, periodic {periodic:.1}");
    }
}
