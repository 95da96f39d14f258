//! Synthetic camera scenes with ground truth, standing in for the thesis's experiments (2.4,
//! 3.4, 4.4): a textured metal part with a sharp corner, moved in true sub-pixel translation
//! along the pendulum path of Fig. 2.8 (in and out of the field of view) or the triangular path
//! of Fig. 3.4 (or a swing inside the view), optionally under the lamp change of Fig. 4.2,
//! clutter, an occluder and noise; the part and the background can be real photographs.
//!
//! Coordinates put pixel centres at integers: (0, 0) is the centre of the top-left pixel,
//! x to the right, y down. Each pixel is the mean of 4x4 samples over its area (8x8 with photos).
//!
//! - [`texture`]: the part's outline, its surface and the background (synthetic or photos);
//! - [`path`]: where the part's corner is at each moment;
//! - [`render`]: a frame's pixels (supersampling, occluder, lamp, noise);
//! - [`rng`]: the deterministic generator behind texture, clutter and noise.
pub mod appearance;
pub mod longterm;
pub mod path;
pub mod render;
pub mod rng;
pub mod texture;

use super::groundtruth::Truth;
use super::{FrameCache, FrameError, FrameSource};
pub use appearance::{Appearance, Pose};
use rng::Rng;
use texture::Photo;

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
    /// Rotation, scale, tilt, blur, shadow and cover ([`appearance`]); none by default.
    pub appearance: Appearance,
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
            appearance: Appearance::default(),
        }
    }
}

/// The part's placement at one moment (see [`Scene::placed`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Placed {
    /// Where the part's corner would be without the pose (the path's point).
    corner: (f64, f64),
    /// The map from part coordinates about the centroid to the frame.
    pose: Pose,
}

impl Placed {
    /// The centroid in the frame.
    pub(super) fn pivot(&self) -> (f64, f64) {
        let g = texture::part_centroid();
        (self.corner.0 + g.0, self.corner.1 + g.1)
    }

    /// The frame position of part point `o` (part coordinates from its corner).
    pub(super) fn frame_point(&self, o: (f64, f64)) -> (f64, f64) {
        if self.pose == Pose::RIGID {
            // The rigid part's own arithmetic, so rigid scenes stay bit for bit as they were.
            return (self.corner.0 + o.0, self.corner.1 + o.1);
        }
        let (g, p) = (texture::part_centroid(), self.pivot());
        let d = self.pose.apply((o.0 - g.0, o.1 - g.1));
        (p.0 + d.0, p.1 + d.1)
    }

    /// The part coordinates of frame point `(x, y)`: [`Placed::frame_point`]'s inverse.
    pub(super) fn part_point(&self, x: f64, y: f64) -> (f64, f64) {
        if self.pose == Pose::RIGID {
            return (x - self.corner.0, y - self.corner.1);
        }
        let (g, p) = (texture::part_centroid(), self.pivot());
        let d = self.pose.invert((x - p.0, y - p.1));
        (g.0 + d.0, g.1 + d.1)
    }
}

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
        let mut rng = Rng::new(cfg.seed);
        let background = texture::background(&cfg, &mut rng);
        let (waypoints, closed) = path::waypoints(&cfg);
        let part_photo = cfg.photo.then(|| Photo::decode(texture::PART_PHOTO));
        let mut scene = Scene { cfg, background, part_photo, waypoints, closed };
        if scene.cfg.clutter && scene.cfg.photo {
            scene.clutter_beside_the_path(&mut rng);
        }
        scene
    }

    /// The configuration.
    pub fn config(&self) -> &SceneConfig {
        &self.cfg
    }

    /// Ground truth of frame `k`.
    pub fn truth(&self, k: usize) -> Truth {
        let placed = self.placed(k as f64 / self.cfg.fps);
        let inside = |p: (f64, f64)| {
            p.0 >= 0.0 && p.1 >= 0.0 && p.0 <= self.cfg.width as f64 - 1.0 && p.1 <= self.cfg.height as f64 - 1.0
        };
        let centre = placed.pivot();
        let covered = self.cfg.appearance.cover(k, self.cfg.frames).0;
        Truth { frame: k, centre, corner: placed.frame_point((0.0, 0.0)), visible: inside(centre) && !covered }
    }

    /// Where the part is at `t` seconds: the path's corner (displaced after a cover) and the
    /// part's pose about its centroid.
    pub(super) fn placed(&self, t: f64) -> Placed {
        let c = self.corner_at(t);
        let k = (t * self.cfg.fps).round().max(0.0) as usize;
        let jump = self.cfg.appearance.cover(k, self.cfg.frames).1;
        let u = t * self.cfg.fps / self.cfg.frames.max(1) as f64;
        Placed { corner: (c.0 + jump.0, c.1 + jump.1), pose: self.cfg.appearance.pose(u) }
    }

    /// Ground truth of every frame.
    pub fn all_truth(&self) -> Vec<Truth> {
        (0..self.cfg.frames).map(|k| self.truth(k)).collect()
    }
}

/// A scene rendered on demand (deterministic), so runs need no files.
pub struct SceneFrames {
    scene: Scene,
    cache: FrameCache,
}

impl SceneFrames {
    /// Frames of `cfg`.
    pub fn new(cfg: SceneConfig) -> Self {
        SceneFrames { scene: Scene::new(cfg), cache: FrameCache::default() }
    }
    /// Ground truth of every frame.
    pub fn truth(&self) -> Vec<Truth> {
        self.scene.all_truth()
    }
}

impl FrameSource for SceneFrames {
    fn size(&self) -> (usize, usize) {
        (self.scene.config().width, self.scene.config().height)
    }
    fn len(&self) -> usize {
        self.scene.config().frames
    }
    fn frame(&mut self, k: usize) -> Result<&[u8], FrameError> {
        let scene = &self.scene;
        self.cache.get_or_make(k, || Ok(scene.render(k).0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
    fn same_seed_same_frames() {
        let cfg = SceneConfig { noise: 3.0, clutter: true, seed: 9, ..SceneConfig::default() };
        assert_eq!(Scene::new(cfg.clone()).render(5).0, Scene::new(cfg).render(5).0);
    }
}
