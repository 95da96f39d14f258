//! What the scene is made of: the part's outline and surface, and the background with its
//! clutter, synthetic or from the photographs in `fixtures/real/`.
use super::rng::Rng;
use super::{Scene, SceneConfig};

/// The part's outline relative to its corner, which sits at the origin (a right-angled corner
/// with edges at 15 and 105 degrees, so neither edge is axis-aligned).
pub const PART: [(f64, f64); 4] = [(0.0, 0.0), (42.5, 11.4), (33.0, 46.0), (-10.4, 38.6)];

/// Gray level of the synthetic part (the thesis's scenes averaged about 80).
const PART_LEVEL: f64 = 150.0;
/// Gray level of the synthetic background.
const BACKGROUND_LEVEL: f64 = 60.0;

/// The photographs behind [`SceneConfig::photo`], made from scikit-image's bundled images by
/// `scripts/real_images.py extract`.
pub(super) const BACKGROUND_PHOTO: &[u8] = include_bytes!("../../../../fixtures/real/background.png");
/// The part's surface photograph.
pub(super) const PART_PHOTO: &[u8] = include_bytes!("../../../../fixtures/real/object.png");

/// Where the part's corner sits in the part photo: the outline spans x -10.4..42.5 and
/// y 0..46 from its corner, well inside the 64x64 photo.
const PART_PHOTO_ORIGIN: (f64, f64) = (12.0, 8.0);

/// The centroid of the part's outline (the mean of its vertices), from its corner.
pub fn part_centroid() -> (f64, f64) {
    let n = PART.len() as f64;
    (PART.iter().map(|p| p.0).sum::<f64>() / n, PART.iter().map(|p| p.1).sum::<f64>() / n)
}

/// Point in the (convex) part, by the sign of each edge's cross product.
pub fn inside_part(x: f64, y: f64) -> bool {
    (0..PART.len()).all(|i| {
        let (a, b) = (PART[i], PART[(i + 1) % PART.len()]);
        (b.0 - a.0) * (y - a.1) - (b.1 - a.1) * (x - a.0) >= 0.0
    })
}

/// A gray photograph sampled at real-valued coordinates.
pub(super) struct Photo {
    px: Vec<f32>,
    w: usize,
    h: usize,
}

impl Photo {
    pub(super) fn decode(png: &[u8]) -> Photo {
        // The bytes are compiled in and checked by a test, so a failure here is a build defect.
        let img = image::load_from_memory(png).map(|i| i.to_luma8()).unwrap_or_default();
        let (w, h) = (img.width() as usize, img.height() as usize);
        Photo { px: img.into_raw().into_iter().map(f32::from).collect(), w, h }
    }

    /// Pixel (x, y) with the photo mirrored at its borders, so it tiles any frame size.
    pub(super) fn mirrored(&self, x: i64, y: i64) -> f64 {
        let fold = |v: i64, n: usize| {
            let n = n.max(1) as i64;
            let m = v.rem_euclid(2 * n);
            (if m < n { m } else { 2 * n - 1 - m }) as usize
        };
        f64::from(self.px.get(fold(y, self.h) * self.w + fold(x, self.w)).copied().unwrap_or(0.0))
    }

    /// Bilinear interpolation at (x, y): the photo as a continuous surface, so that moving it by
    /// a fraction of a pixel moves its content by exactly that much.
    pub(super) fn bilinear(&self, x: f64, y: f64) -> f64 {
        let (fx, fy) = (x.floor(), y.floor());
        let (ax, ay) = (x - fx, y - fy);
        let (ix, iy) = (fx as i64, fy as i64);
        let top = self.mirrored(ix, iy) * (1.0 - ax) + self.mirrored(ix + 1, iy) * ax;
        let bottom = self.mirrored(ix, iy + 1) * (1.0 - ax) + self.mirrored(ix + 1, iy + 1) * ax;
        top * (1.0 - ay) + bottom * ay
    }
}

/// The part's surface at (ox, oy) from its corner: the part photo, or a faint texture fixed
/// to the part (machining marks) that moves with it and stays under the corner detector's edge
/// thresholds (3.4: 30 < TH < 70).
pub(super) fn part_surface(photo: Option<&Photo>, ox: f64, oy: f64) -> f64 {
    match photo {
        Some(p) => p.bilinear(ox + PART_PHOTO_ORIGIN.0, oy + PART_PHOTO_ORIGIN.1),
        None => PART_LEVEL + 6.0 * (0.35 * ox).sin() * (0.27 * oy + 0.5 * (0.11 * ox).sin()).cos(),
    }
}

/// The static background: a gentle synthetic pattern or the background photo, with 14 blobs
/// of clutter when asked for (drawn from `rng`).
pub(super) fn background(cfg: &SceneConfig, rng: &mut Rng) -> Vec<f32> {
    let (w, h) = (cfg.width, cfg.height);
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
            paint_disc(&mut background, (w, h), (cx, cy), r, level);
        }
    }
    background
}

/// Sets the pixels within `r` of `centre` to `level`.
fn paint_disc(img: &mut [f32], (w, h): (usize, usize), (cx, cy): (f64, f64), r: f64, level: f32) {
    for y in (cy - r).max(0.0) as usize..((cy + r + 1.0) as usize).min(h) {
        for x in (cx - r).max(0.0) as usize..((cx + r + 1.0) as usize).min(w) {
            if (x as f64 - cx).hypot(y as f64 - cy) <= r {
                img[y * w + x] = level;
            }
        }
    }
}

impl Scene {
    /// With photos, clutter that the tracked corner passes close by: 14 blobs at even times
    /// along the run, 9-13 px up, left or diagonally up-left of where the corner then is (the
    /// side away from the part), so they enter its Foveal windows.
    pub(super) fn clutter_beside_the_path(&mut self, rng: &mut Rng) {
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
            paint_disc(&mut self.background, (w, h), (cx, cy), r, level);
        }
    }
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
}
