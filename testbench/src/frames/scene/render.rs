//! A frame's pixels: the part supersampled over the background, the occluder, the lamp of
//! Fig. 4.2 and the camera's noise.
use super::super::groundtruth::Truth;
use super::rng::Rng;
use super::texture::{inside_part, part_surface, PART};
use super::Scene;

/// The lamp's highlight: peak gray levels (see [`Scene::lamp`]).
const HIGHLIGHT: f64 = 50.0;
/// The highlight's Gaussian sigma in pixels.
const HIGHLIGHT_SIGMA: f64 = 8.0;

impl Scene {
    /// The lamp's weight on frame `k`: 0, rising smoothly to 1 over the middle third of the
    /// run and back (Fig. 4.2), when the lighting ramp is on.
    pub fn lamp(&self, k: usize) -> f64 {
        if !self.cfg.lighting_ramp || self.cfg.frames < 2 {
            return 0.0;
        }
        let u = k as f64 / (self.cfg.frames - 1) as f64;
        let ramp = |a: f64, b: f64| ((u - a) / (b - a)).clamp(0.0, 1.0);
        let w = ramp(0.25, 1.0 / 3.0) - ramp(2.0 / 3.0, 0.75);
        w * w * (3.0 - 2.0 * w)
    }

    /// The lamp's light at (x, y) with weight `w`: a 10% gain and a highlight (Gaussian, sigma
    /// 8 px, up to 50 gray levels) where the part passes mid-run, so the highlight slides across
    /// the part and changes its appearance, not only its gain (4.4: "the projected light
    /// intensity was no longer the same in all of the areas of the path"). Its steepest slope,
    /// 50 / (8 sqrt(e)) = 3.8 levels/px, gives Sobel magnitudes of about 30: no edges at TH = 50.
    fn lit(&self, v: f64, x: usize, y: usize, w: f64) -> f64 {
        if w == 0.0 {
            return v;
        }
        let mid = self.corner_at((self.cfg.frames as f64 / 2.0) / self.cfg.fps);
        let (dx, dy) = (x as f64 - mid.0 - 8.0, y as f64 - mid.1 - 8.0);
        v * (1.0 + 0.10 * w) + w * HIGHLIGHT * (-(dx * dx + dy * dy) / (2.0 * HIGHLIGHT_SIGMA * HIGHLIGHT_SIGMA)).exp()
    }

    /// Renders frame `k` as 8-bit gray, row-major, with its ground truth.
    pub fn render(&self, k: usize) -> (Vec<u8>, Truth) {
        let (pixels, _, truth) = self.render_with_coverage(k);
        (pixels, truth)
    }

    /// Renders frame `k` as RGB, row-major: the gray frame's pixels as the BT.601 luma, the
    /// part tinted warm and the background cool in proportion to the part's coverage of each
    /// pixel (a colour camera's view of the same scene, for trying colour input).
    pub fn render_colour(&self, k: usize) -> (Vec<u8>, Truth) {
        let (gray, coverage, truth) = self.render_with_coverage(k);
        let mut rgb = Vec::with_capacity(3 * gray.len());
        for (&y, &c) in gray.iter().zip(&coverage) {
            let (c, y) = (f64::from(c), f64::from(y));
            // Chroma offsets (Cb, Cr) from 128: the part orange, the background blue-gray.
            let (cb, cr) = (c * -30.0 + (1.0 - c) * 12.0, c * 36.0 + (1.0 - c) * -8.0);
            let px = [y + 1.402 * cr, y - 0.344_136 * cb - 0.714_136 * cr, y + 1.772 * cb];
            rgb.extend(px.map(|v| v.round().clamp(0.0, 255.0) as u8));
        }
        (rgb, truth)
    }

    /// Frame `k` as 8-bit gray, the share of each pixel the part covers, and the truth.
    fn render_with_coverage(&self, k: usize) -> (Vec<u8>, Vec<f32>, Truth) {
        let (w, h) = (self.cfg.width, self.cfg.height);
        let mut coverage = vec![0f32; w * h];
        let truth = self.truth(k);
        let mut img = self.background.clone();
        let (covered, _) = self.cfg.appearance.cover(k, self.cfg.frames);
        // A blurred frame averages the part over sub-frames spread across the frame period.
        let exposure: Vec<f64> = self.cfg.appearance.exposure().collect();
        let mut sum = vec![0f64; w * h];
        let mut hits = vec![0u32; w * h];
        let clampi = |v: f64, hi: usize| (v.max(0.0) as usize).min(hi);
        // Samples per pixel side: 4 for the synthetic part; 8 for a photo, whose texture has
        // detail at the pixel scale that a coarser grid would alias.
        let grid: usize = if self.part_photo.is_some() { 8 } else { 4 };
        let step = 1.0 / grid as f64;
        let mut span = (usize::MAX, 0, usize::MAX, 0);
        for dt in &exposure {
            let placed = self.placed((k as f64 + dt) / self.cfg.fps);
            // Only pixels near the part are supersampled.
            let corners: Vec<(f64, f64)> = PART.iter().map(|&o| placed.frame_point(o)).collect();
            let (x0, x1) = corners.iter().fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.0), b.max(p.0)));
            let (y0, y1) = corners.iter().fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.1), b.max(p.1)));
            let (px0, px1, py0, py1) = (clampi(x0 - 1.0, w), clampi(x1 + 2.0, w), clampi(y0 - 1.0, h), clampi(y1 + 2.0, h));
            span = (span.0.min(px0), span.1.max(px1), span.2.min(py0), span.3.max(py1));
            for py in py0..py1 {
                for px in px0..px1 {
                    for sy in 0..grid {
                        for sx in 0..grid {
                            let (x, y) = (px as f64 + step * (sx as f64 + 0.5) - 0.5, py as f64 + step * (sy as f64 + 0.5) - 0.5);
                            let (ox, oy) = placed.part_point(x, y);
                            if inside_part(ox, oy) {
                                hits[py * w + px] += 1;
                                sum[py * w + px] += part_surface(self.part_photo.as_ref(), ox, oy);
                            }
                        }
                    }
                }
            }
        }
        let samples = grid * grid * exposure.len();
        for py in span.2..span.3 {
            for px in span.0..span.1 {
                let (n, acc) = (hits[py * w + px] as usize, sum[py * w + px]);
                if n > 0 {
                    let bg = img[py * w + px] as f64;
                    coverage[py * w + px] = n as f32 / samples as f32;
                    img[py * w + px] = ((acc + bg * (samples - n) as f64) / samples as f64) as f32;
                }
            }
        }
        if covered {
            // A flat gray object over the whole part while it is covered.
            let (cx, cy) = truth.centre;
            for py in clampi(cy - 40.0, h)..clampi(cy + 41.0, h) {
                for px in clampi(cx - 40.0, w)..clampi(cx + 41.0, w) {
                    img[py * w + px] = 90.0;
                    coverage[py * w + px] = 0.0;
                }
            }
        }
        if self.cfg.occlusion {
            let c = truth.corner;
            let n = self.cfg.frames.max(1) as f64;
            let u = k as f64 / n;
            if (0.45..0.55).contains(&u) {
                // A dark bar over the part's path, for a tenth of the run.
                let bx = c.0 - 6.0;
                for py in 0..h {
                    for px in clampi(bx, w)..clampi(bx + 12.0, w) {
                        img[py * w + px] = 20.0;
                    }
                }
            }
        }
        let lamp = self.lamp(k);
        let u = k as f64 / self.cfg.frames.max(1) as f64;
        let mut rng = Rng::new(self.cfg.seed.wrapping_mul(1_000_003).wrapping_add(k as u64));
        let pixels = img
            .iter()
            .enumerate()
            .map(|(i, &v)| {
                let n = if self.cfg.noise > 0.0 { self.cfg.noise * rng.normal() } else { 0.0 };
                let v = self.lit(v as f64, i % w, i / w, lamp) * self.cfg.appearance.gain((i % w) as f64, w as f64, u);
                (v + n).round().clamp(0.0, 255.0) as u8
            })
            .collect();
        (pixels, coverage, truth)
    }
}

#[cfg(test)]
mod tests {
    use super::super::texture::PART;
    use super::super::{Scene, SceneConfig};

    #[test]
    fn rendered_part_has_the_true_area_and_centroid() {
        // Independent reference: the shoelace area of the outline, against the rendered
        // excess brightness over the background (part level constant up to its texture).
        let cfg = SceneConfig { seed: 3, ..SceneConfig::default() };
        let s = Scene::new(cfg);
        let (img, t) = s.render(10);
        let area: f64 = (0..4)
            .map(|i| {
                let (a, b) = (PART[i], PART[(i + 1) % 4]);
                a.0 * b.1 - b.0 * a.1
            })
            .sum::<f64>()
            / 2.0;
        let mask: Vec<usize> = (0..img.len()).filter(|&i| img[i] as f64 > 110.0).collect();
        assert!((mask.len() as f64 - area.abs()).abs() < 0.08 * area.abs(), "{} vs {area}", mask.len());
        let cx = mask.iter().map(|&i| (i % 256) as f64).sum::<f64>() / mask.len() as f64;
        let cy = mask.iter().map(|&i| (i / 256) as f64).sum::<f64>() / mask.len() as f64;
        // The area centroid of this quadrilateral is within 2 px of its vertex mean.
        assert!((cx - t.centre.0).abs() < 2.0 && (cy - t.centre.1).abs() < 2.0);
    }

    #[test]
    fn lighting_ramp_brightens_the_middle_third_by_about_a_quarter() {
        // Fig. 4.2 measures the Foveal windows' mean gray level: here the 24x24 block at the
        // corner, the same frames rendered with and without the lamp.
        let cfg = SceneConfig { lighting_ramp: true, frames: 300, ..SceneConfig::default() };
        let (lit, dark) = (Scene::new(cfg.clone()), Scene::new(SceneConfig { lighting_ramp: false, ..cfg }));
        let window_mean = |s: &Scene, k: usize| {
            let (img, t) = s.render(k);
            let (cx, cy) = (t.corner.0.round() as usize, t.corner.1.round() as usize);
            let mut sum = 0.0;
            for y in cy - 12..cy + 12 {
                for x in cx - 12..cx + 12 {
                    sum += img[y * 256 + x] as f64;
                }
            }
            sum / 576.0
        };
        let ratio = window_mean(&lit, 150) / window_mean(&dark, 150);
        assert!((1.2..1.35).contains(&ratio), "{ratio}");
        assert_eq!(lit.render(10).0, dark.render(10).0, "no lamp in the first quarter");
    }
}
