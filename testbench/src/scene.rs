//! Synthetic camera scenes with ground truth, standing in for the thesis's experiments: a
//! textured metal part with a sharp corner, moved in true sub-pixel translation along the
//! pendulum path of Fig. 2.8 (in and out of the field of view) or the triangular path of
//! Fig. 3.4 (or a swing inside the view), optionally under the lamp change of Fig. 4.2, clutter,
//! an occluder and noise; the part and the background can be real photographs.
//!
//! Coordinates put pixel centres at integers: (0, 0) is the centre of the top-left pixel,
//! x to the right, y down. Each pixel is the mean of 4x4 samples over its area (8x8 with photos).

/// The target's path.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PathKind {
    /// Fig. 2.8: a swing that carries the part in through the top of the field of view and out
    /// through the bottom, and back, reversing abruptly outside it.
    Pendulum,
    /// Fig. 3.4: a closed triangle inside the field of view.
    Triangle,
    /// A pendulum's swing inside the field of view: the part sweeps left and right along a
    /// shallow arc, fastest mid-swing and stopping at the ends; `speed` is the mean speed.
    Swing,
}

/// Everything that defines a scene; the same config and seed give the same frames.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneConfig {
    /// The target's path.
    pub path: PathKind,
    /// Target speed along the path in pixels per second.
    pub speed: f64,
    /// Number of frames.
    pub frames: usize,
    /// Frame rate in frames per second (the CA-D1 ran at 114).
    pub fps: f64,
    /// Image width and height.
    pub width: usize,
    /// Image height.
    pub height: usize,
    /// The lamp brightens the scene by about 25% over the middle third of the run (Fig. 4.2).
    pub lighting_ramp: bool,
    /// Static clutter (blobs and strokes) on the background.
    pub clutter: bool,
    /// A bar that occludes part of the path for a stretch of the run.
    pub occlusion: bool,
    /// Standard deviation of additive Gaussian noise, in gray levels.
    pub noise: f64,
    /// Seed for the noise, clutter and texture.
    pub seed: u64,
    /// Real photographs for the part's surface and the background (`fixtures/real/`), in
    /// place of the synthetic texture and flat background.
    pub photo: bool,
}

impl Default for SceneConfig {
    fn default() -> Self {
        SceneConfig {
            path: PathKind::Triangle,
            speed: 100.0,
            frames: 300,
            fps: 114.0,
            width: 256,
            height: 256,
            lighting_ramp: false,
            clutter: false,
            occlusion: false,
            noise: 0.0,
            seed: 1,
            photo: false,
        }
    }
}

/// Ground truth of one frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Truth {
    /// Frame index.
    pub frame: usize,
    /// Centre of the part (the centroid of its outline).
    pub centre: (f64, f64),
    /// The tracked corner of the part.
    pub corner: (f64, f64),
    /// Whether the part's centre is inside the image.
    pub visible: bool,
}

/// The part's outline relative to its corner, which sits at the origin (a right-angled corner
/// with edges at 15 and 105 degrees, so neither edge is axis-aligned).
const PART: [(f64, f64); 4] = [(0.0, 0.0), (42.5, 11.4), (33.0, 46.0), (-10.4, 38.6)];

/// The lamp's highlight: peak gray levels and Gaussian sigma in pixels (see `Scene::lit`).
const HIGHLIGHT: f64 = 50.0;
const HIGHLIGHT_SIGMA: f64 = 8.0;

/// Gray levels: the part and the background (the thesis's scenes averaged about 80).
const PART_LEVEL: f64 = 150.0;
const BACKGROUND_LEVEL: f64 = 60.0;

fn part_centroid() -> (f64, f64) {
    let n = PART.len() as f64;
    (PART.iter().map(|p| p.0).sum::<f64>() / n, PART.iter().map(|p| p.1).sum::<f64>() / n)
}

/// A small deterministic generator (SplitMix64) so scenes need no external crate.
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A generator for `seed`.
    pub fn new(seed: u64) -> Self {
        Rng(seed ^ 0x9E37_79B9_7F4A_7C15)
    }
    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Standard normal (Box-Muller).
    pub fn normal(&mut self) -> f64 {
        let u1 = self.uniform().max(1e-300);
        let u2 = self.uniform();
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    }
}

/// The photographs behind [`SceneConfig::photo`], made from scikit-image's bundled images by
/// `scripts/real_images.py extract`.
const BACKGROUND_PHOTO: &[u8] = include_bytes!("../../fixtures/real/background.png");
const PART_PHOTO: &[u8] = include_bytes!("../../fixtures/real/object.png");

/// A gray photograph sampled at real-valued coordinates.
struct Photo {
    px: Vec<f32>,
    w: usize,
    h: usize,
}

impl Photo {
    fn decode(png: &[u8]) -> Photo {
        // The bytes are compiled in and checked by a test, so a failure here is a build defect.
        let img = image::load_from_memory(png).map(|i| i.to_luma8()).unwrap_or_default();
        let (w, h) = (img.width() as usize, img.height() as usize);
        Photo { px: img.into_raw().into_iter().map(f32::from).collect(), w, h }
    }

    /// Pixel (x, y) with the photo mirrored at its borders, so it tiles any frame size.
    fn mirrored(&self, x: i64, y: i64) -> f64 {
        let fold = |v: i64, n: usize| {
            let n = n.max(1) as i64;
            let m = v.rem_euclid(2 * n);
            (if m < n { m } else { 2 * n - 1 - m }) as usize
        };
        f64::from(self.px.get(fold(y, self.h) * self.w + fold(x, self.w)).copied().unwrap_or(0.0))
    }

    /// Bilinear interpolation at (x, y): the photo as a continuous surface, so that moving it by
    /// a fraction of a pixel moves its content by exactly that much.
    fn bilinear(&self, x: f64, y: f64) -> f64 {
        let (fx, fy) = (x.floor(), y.floor());
        let (ax, ay) = (x - fx, y - fy);
        let (ix, iy) = (fx as i64, fy as i64);
        let top = self.mirrored(ix, iy) * (1.0 - ax) + self.mirrored(ix + 1, iy) * ax;
        let bottom = self.mirrored(ix, iy + 1) * (1.0 - ax) + self.mirrored(ix + 1, iy + 1) * ax;
        top * (1.0 - ay) + bottom * ay
    }
}

/// Where the part's corner sits in the part photo: the outline spans x -10.4..42.5 and
/// y 0..46 from its corner, well inside the 64x64 photo.
const PART_PHOTO_ORIGIN: (f64, f64) = (12.0, 8.0);

/// A scene ready to render frame by frame.
pub struct Scene {
    cfg: SceneConfig,
    background: Vec<f32>,
    part_photo: Option<Photo>,
    waypoints: Vec<(f64, f64)>,
    closed: bool,
}

impl Scene {
    /// Prepares the static background (texture and clutter) and the path.
    pub fn new(cfg: SceneConfig) -> Scene {
        let (w, h) = (cfg.width, cfg.height);
        let mut rng = Rng::new(cfg.seed);
        let (fx, fy) = (0.05 + 0.05 * rng.uniform(), 0.07 + 0.05 * rng.uniform());
        let photo = cfg.photo.then(|| Photo::decode(BACKGROUND_PHOTO));
        let mut background: Vec<f32> = (0..w * h)
            .map(|i| {
                let (x, y) = ((i % w) as f64, (i / w) as f64);
                match &photo {
                    Some(p) => p.mirrored(x as i64, y as i64) as f32,
                    None => (BACKGROUND_LEVEL + 8.0 * (fx * x).sin() * (fy * y).cos()) as f32,
                }
            })
            .collect();
        if cfg.clutter {
            for _ in 0..14 {
                let (cx, cy) = (rng.uniform() * w as f64, rng.uniform() * h as f64);
                let r = 2.0 + 4.0 * rng.uniform();
                let level = (30.0 + 170.0 * rng.uniform()) as f32;
                for y in (cy - r).max(0.0) as usize..((cy + r + 1.0) as usize).min(h) {
                    for x in (cx - r).max(0.0) as usize..((cx + r + 1.0) as usize).min(w) {
                        if (x as f64 - cx).hypot(y as f64 - cy) <= r {
                            background[y * w + x] = level;
                        }
                    }
                }
            }
        }
        let (sw, sh) = (w as f64, h as f64);
        let (waypoints, closed) = match cfg.path {
            // A shallow arc from above the image to below it, so the part crosses the top and
            // bottom rows where MPDF's Watch strips look (Fig. 2.6).
            PathKind::Pendulum => {
                let pivot = (-2.2 * sw, sh / 2.0);
                let radius = 2.2 * sw + sw * 0.45;
                let half = ((sh / 2.0 + 70.0) / radius).asin();
                let pts = (0..=64)
                    .map(|k| {
                        let a = -half + 2.0 * half * k as f64 / 64.0;
                        (pivot.0 + radius * a.cos(), pivot.1 + radius * a.sin())
                    })
                    .collect();
                (pts, false)
            }
            PathKind::Triangle => (
                vec![(0.22 * sw, 0.22 * sh), (0.72 * sw, 0.32 * sh), (0.40 * sw, 0.70 * sh)],
                true,
            ),
            PathKind::Swing => (Vec::new(), false),
        };
        let part_photo = cfg.photo.then(|| Photo::decode(PART_PHOTO));
        let mut scene = Scene { cfg, background, part_photo, waypoints, closed };
        if scene.cfg.clutter && scene.cfg.photo {
            scene.clutter_beside_the_path(&mut rng);
        }
        scene
    }

    /// With photos, clutter that the tracked corner passes close by: 14 blobs at even times
    /// along the run, 9-13 px up, left or diagonally up-left of where the corner then is (the
    /// side away from the part), so they enter its Foveal windows.
    fn clutter_beside_the_path(&mut self, rng: &mut Rng) {
        let (w, h) = (self.cfg.width, self.cfg.height);
        let run = self.cfg.frames as f64 / self.cfg.fps;
        for i in 0..14 {
            let c = self.corner_at(run * (i as f64 + 0.5) / 14.0);
            let d = 9.0 + 4.0 * rng.uniform();
            let diagonal = -std::f64::consts::FRAC_1_SQRT_2;
            let (ux, uy) = [(-1.0, 0.0), (0.0, -1.0), (diagonal, diagonal)][(rng.next_u64() % 3) as usize];
            let (cx, cy) = (c.0 + d * ux, c.1 + d * uy);
            let r = 2.0 + 3.0 * rng.uniform();
            let level = (30.0 + 170.0 * rng.uniform()) as f32;
            for y in (cy - r).max(0.0) as usize..((cy + r + 1.0) as usize).min(h) {
                for x in (cx - r).max(0.0) as usize..((cx + r + 1.0) as usize).min(w) {
                    if (x as f64 - cx).hypot(y as f64 - cy) <= r {
                        self.background[y * w + x] = level;
                    }
                }
            }
        }
    }

    /// The configuration.
    pub fn config(&self) -> &SceneConfig {
        &self.cfg
    }

    /// The corner position at time `t` seconds: constant speed along the path, bouncing back
    /// at the ends of an open path and going round a closed one.
    pub fn corner_at(&self, t: f64) -> (f64, f64) {
        if self.cfg.path == PathKind::Swing {
            return self.swing_at(t);
        }
        let mut pts = self.waypoints.clone();
        if self.closed {
            pts.push(pts[0]);
        }
        let lens: Vec<f64> =
            pts.windows(2).map(|p| (p[1].0 - p[0].0).hypot(p[1].1 - p[0].1)).collect();
        let total: f64 = lens.iter().sum();
        let mut s = self.cfg.speed * t;
        s = if self.closed {
            s.rem_euclid(total)
        } else {
            let m = s.rem_euclid(2.0 * total);
            if m > total {
                2.0 * total - m
            } else {
                m
            }
        };
        for (k, len) in lens.iter().enumerate() {
            if s <= *len || k + 1 == lens.len() {
                let f = if *len > 0.0 { (s / len).min(1.0) } else { 0.0 };
                return (pts[k].0 + f * (pts[k + 1].0 - pts[k].0), pts[k].1 + f * (pts[k + 1].1 - pts[k].1));
            }
            s -= len;
        }
        pts[0]
    }

    /// [`PathKind::Swing`]: the part's centre at `(cx + A sin φ, cy - A/5 sin² φ)` with
    /// `φ = 2π t v / 4A`, so the horizontal speed averages `v` over a swing; A is 30% of the width.
    fn swing_at(&self, t: f64) -> (f64, f64) {
        let (w, h) = (self.cfg.width as f64, self.cfg.height as f64);
        let amplitude = 0.3 * w;
        let phi = std::f64::consts::TAU * t * self.cfg.speed / (4.0 * amplitude);
        let g = part_centroid();
        let s = phi.sin();
        (0.5 * w + amplitude * s - g.0, 0.55 * h - 0.2 * amplitude * s * s - g.1)
    }

    /// Ground truth of frame `k`.
    pub fn truth(&self, k: usize) -> Truth {
        let c = self.corner_at(k as f64 / self.cfg.fps);
        let g = part_centroid();
        let inside = |p: (f64, f64)| {
            p.0 >= 0.0 && p.1 >= 0.0 && p.0 <= self.cfg.width as f64 - 1.0 && p.1 <= self.cfg.height as f64 - 1.0
        };
        let centre = (c.0 + g.0, c.1 + g.1);
        Truth { frame: k, centre, corner: c, visible: inside(centre) }
    }

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
        let (w, h) = (self.cfg.width, self.cfg.height);
        let truth = self.truth(k);
        let c = truth.corner;
        let mut img = self.background.clone();
        // Only pixels near the part are supersampled.
        let xs = PART.iter().map(|p| p.0 + c.0);
        let ys = PART.iter().map(|p| p.1 + c.1);
        let (x0, x1) = (xs.clone().fold(f64::MAX, f64::min), xs.fold(f64::MIN, f64::max));
        let (y0, y1) = (ys.clone().fold(f64::MAX, f64::min), ys.fold(f64::MIN, f64::max));
        let clampi = |v: f64, hi: usize| (v.max(0.0) as usize).min(hi);
        // Samples per pixel side: 4 for the synthetic part; 8 for a photo, whose texture has
        // detail at the pixel scale that a coarser grid would alias.
        let grid: usize = if self.part_photo.is_some() { 8 } else { 4 };
        let step = 1.0 / grid as f64;
        for py in clampi(y0 - 1.0, h)..clampi(y1 + 2.0, h) {
            for px in clampi(x0 - 1.0, w)..clampi(x1 + 2.0, w) {
                let mut acc = 0.0;
                let mut covered = 0;
                for sy in 0..grid {
                    for sx in 0..grid {
                        let (x, y) = (px as f64 + step * (sx as f64 + 0.5) - 0.5, py as f64 + step * (sy as f64 + 0.5) - 0.5);
                        let (ox, oy) = (x - c.0, y - c.1);
                        if inside_part(ox, oy) {
                            covered += 1;
                            acc += match &self.part_photo {
                                Some(p) => p.bilinear(ox + PART_PHOTO_ORIGIN.0, oy + PART_PHOTO_ORIGIN.1),
                                // A faint texture fixed to the part (machining marks): it moves with it, and
                                // stays under the corner detector's edge thresholds (3.4: 30 < TH < 70).
                                None => PART_LEVEL + 6.0 * (0.35 * ox).sin() * (0.27 * oy + 0.5 * (0.11 * ox).sin()).cos(),
                            };
                        }
                    }
                }
                if covered > 0 {
                    let bg = img[py * w + px] as f64;
                    let samples = grid * grid;
                    img[py * w + px] = ((acc + bg * (samples - covered) as f64) / samples as f64) as f32;
                }
            }
        }
        if self.cfg.occlusion {
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
        let mut rng = Rng::new(self.cfg.seed.wrapping_mul(1_000_003).wrapping_add(k as u64));
        let pixels = img
            .iter()
            .enumerate()
            .map(|(i, &v)| {
                let n = if self.cfg.noise > 0.0 { self.cfg.noise * rng.normal() } else { 0.0 };
                (self.lit(v as f64, i % w, i / w, lamp) + n).round().clamp(0.0, 255.0) as u8
            })
            .collect();
        (pixels, truth)
    }
}

/// Point in the (convex) part, by the sign of each edge's cross product.
fn inside_part(x: f64, y: f64) -> bool {
    (0..PART.len()).all(|i| {
        let (a, b) = (PART[i], PART[(i + 1) % PART.len()]);
        (b.0 - a.0) * (y - a.1) - (b.1 - a.1) * (x - a.0) >= 0.0
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn part_outline_is_convex_and_clockwise_in_image_coordinates() {
        // Every vertex is on the inner side of every edge (the inside test's assumption).
        let centre = part_centroid();
        assert!(inside_part(centre.0, centre.1));
        assert!(!inside_part(-1.0, -1.0));
    }

    #[test]
    fn corner_moves_at_the_configured_speed() {
        let s = Scene::new(SceneConfig { speed: 100.0, ..SceneConfig::default() });
        // Along a straight leg, 1/114 s moves the corner 100/114 px.
        let (a, b) = (s.corner_at(0.1), s.corner_at(0.1 + 1.0 / 114.0));
        assert!(((b.0 - a.0).hypot(b.1 - a.1) - 100.0 / 114.0).abs() < 1e-9);
    }

    #[test]
    fn pendulum_leaves_and_reenters_the_field_of_view() {
        let cfg = SceneConfig { path: PathKind::Pendulum, frames: 2000, ..SceneConfig::default() };
        let s = Scene::new(cfg);
        let vis: Vec<bool> = (0..2000).map(|k| s.truth(k).visible).collect();
        assert!(vis.iter().any(|v| *v) && vis.iter().any(|v| !*v));
        let changes = vis.windows(2).filter(|p| p[0] != p[1]).count();
        assert!(changes >= 2, "enters and leaves: {changes}");
    }

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

    #[test]
    fn same_seed_same_frames() {
        let cfg = SceneConfig { noise: 3.0, clutter: true, seed: 9, ..SceneConfig::default() };
        assert_eq!(Scene::new(cfg.clone()).render(5).0, Scene::new(cfg).render(5).0);
    }
}
