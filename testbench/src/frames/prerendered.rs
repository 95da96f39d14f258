//! A scene rendered once, every frame held in memory, for runs that track the same frames
//! several times (the real-image evaluation, the pipeline benchmark).
use super::groundtruth::Truth;
use super::scene::{Scene, SceneConfig};
use super::{frames_fingerprint, FrameError, FrameSource};

/// Every frame of a scene, rendered ahead.
pub struct Prerendered {
    frames: Vec<Vec<u8>>,
    size: (usize, usize),
    /// Ground truth of every frame.
    pub truth: Vec<Truth>,
}

impl Prerendered {
    /// Renders every frame of `cfg`.
    pub fn new(cfg: &SceneConfig) -> Self {
        let scene = Scene::new(cfg.clone());
        let (frames, truth) = (0..cfg.frames).map(|k| scene.render(k)).unzip();
        Prerendered { frames, size: (cfg.width, cfg.height), truth }
    }

    /// A fingerprint of every frame's pixels, as hex: the same frames give the same text.
    pub fn fingerprint(&self) -> String {
        frames_fingerprint(self.frames.iter().map(Vec::as_slice))
    }
}

impl FrameSource for Prerendered {
    fn size(&self) -> (usize, usize) {
        self.size
    }
    fn len(&self) -> usize {
        self.frames.len()
    }
    fn frame(&mut self, k: usize) -> Result<&[u8], FrameError> {
        self.frames.get(k).map(Vec::as_slice).ok_or(FrameError::Missing(k))
    }
}
