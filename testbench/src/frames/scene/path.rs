//! Where the part's corner is at each moment: constant speed along the pendulum arc of
//! Fig. 2.8 or the triangle of Fig. 3.4, or a swing inside the view.
use super::texture::part_centroid;
use super::{PathKind, Scene, SceneConfig};

/// The path's waypoints for `cfg`'s frame size, and whether the path is closed.
pub(super) fn waypoints(cfg: &SceneConfig) -> (Vec<(f64, f64)>, bool) {
    let (sw, sh) = (cfg.width as f64, cfg.height as f64);
    match cfg.path {
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
        PathKind::Triangle => (vec![(0.22 * sw, 0.22 * sh), (0.72 * sw, 0.32 * sh), (0.40 * sw, 0.70 * sh)], true),
        PathKind::Swing => (Vec::new(), false),
    }
}

impl Scene {
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
        let lens: Vec<f64> = pts.windows(2).map(|p| (p[1].0 - p[0].0).hypot(p[1].1 - p[0].1)).collect();
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
}

#[cfg(test)]
mod tests {
    use super::super::{Scene, SceneConfig};

    #[test]
    fn corner_moves_at_the_configured_speed() {
        let s = Scene::new(SceneConfig { speed: 100.0, ..SceneConfig::default() });
        // Along a straight leg, 1/114 s moves the corner 100/114 px.
        let (a, b) = (s.corner_at(0.1), s.corner_at(0.1 + 1.0 / 114.0));
        assert!(((b.0 - a.0).hypot(b.1 - a.1) - 100.0 / 114.0).abs() < 1e-9);
    }
}
