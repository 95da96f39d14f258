//! Helpers shared by the fault tests.
use coopwin_testbench::frames::scene::SceneFrames;
use coopwin_testbench::frames::{FrameError, FrameSource};

/// The scene with frames `dark` replaced by all zeros (a camera dropout).
pub struct Dropout {
    /// The scene.
    pub inner: SceneFrames,
    /// The dark frames.
    pub dark: std::ops::Range<usize>,
    /// One all-zero frame.
    pub zeros: Vec<u8>,
}

impl FrameSource for Dropout {
    fn size(&self) -> (usize, usize) {
        self.inner.size()
    }
    fn len(&self) -> usize {
        self.inner.len()
    }
    fn frame(&mut self, k: usize) -> Result<&[u8], FrameError> {
        if self.dark.contains(&k) {
            return Ok(&self.zeros);
        }
        self.inner.frame(k)
    }
}
