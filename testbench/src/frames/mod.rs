//! The camera's side of the data flow: where frames come from (a folder of PNG files, the
//! synthetic scene rendered on demand, or frames rendered ahead), and their ground truth.
//!
//! Thesis 2.4 and 4.4: the experiments' scenes, here synthetic with an exact ground truth.
pub mod folder;
pub mod gray;
pub mod groundtruth;
pub mod prerendered;
pub mod scene;
pub mod video;

use std::collections::VecDeque;
use std::path::PathBuf;

/// Frames by index, as a run needs them (in nearly increasing order).
pub trait FrameSource {
    /// Width and height of every frame.
    fn size(&self) -> (usize, usize);
    /// Number of frames.
    fn len(&self) -> usize;
    /// True when the source has no frame.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Frame `k`, row-major 8-bit gray.
    fn frame(&mut self, k: usize) -> Result<&[u8], FrameError>;
}

/// Why a frame could not be had.
#[derive(Debug)]
pub enum FrameError {
    /// The source has no frame with this index.
    Missing(usize),
    /// The frame's file could not be decoded.
    Decode {
        /// The file.
        path: PathBuf,
        /// The decoder's reason.
        source: image::ImageError,
    },
    /// A video's decoder stopped or disagreed with its scan: the reason.
    Video(String),
    /// The run was interrupted (Ctrl-C).
    Interrupted,
}

impl std::fmt::Display for FrameError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FrameError::Missing(k) => write!(f, "no frame {k}"),
            FrameError::Decode { path, source } => write!(f, "{}: {source}", path.display()),
            FrameError::Video(why) => f.write_str(why),
            FrameError::Interrupted => f.write_str("interrupted"),
        }
    }
}

impl std::error::Error for FrameError {}

/// `inner`'s frames from `first` on, numbered from 0 (a run that starts later in a clip).
pub struct Skip<'a> {
    inner: &'a mut dyn FrameSource,
    first: usize,
}

impl<'a> Skip<'a> {
    /// `inner` from frame `first`; `None` when it has no such frame.
    pub fn new(inner: &'a mut dyn FrameSource, first: usize) -> Option<Skip<'a>> {
        (first < inner.len()).then_some(Skip { inner, first })
    }
}

impl FrameSource for Skip<'_> {
    fn size(&self) -> (usize, usize) {
        self.inner.size()
    }
    fn len(&self) -> usize {
        self.inner.len() - self.first
    }
    fn frame(&mut self, k: usize) -> Result<&[u8], FrameError> {
        self.inner.frame(k + self.first)
    }
}

/// The last few frames made, for sources that decode or render on demand.
#[derive(Default)]
pub struct FrameCache {
    frames: VecDeque<(usize, Vec<u8>)>,
}

impl FrameCache {
    /// Frames kept.
    const FRAMES: usize = 4;

    /// Frame `k`, made by `make` unless it is still held.
    pub fn get_or_make(&mut self, k: usize, make: impl FnOnce() -> Result<Vec<u8>, FrameError>) -> Result<&[u8], FrameError> {
        match self.frames.iter().position(|(j, _)| *j == k) {
            Some(i) => Ok(&self.frames[i].1),
            None => {
                let pixels = make()?;
                if self.frames.len() >= Self::FRAMES {
                    self.frames.pop_front();
                }
                self.frames.push_back((k, pixels));
                Ok(self.frames.back().map(|(_, p)| p.as_slice()).unwrap_or_default())
            }
        }
    }
}

/// A 64-bit fingerprint of pixels (FNV-1a's multiply over 8-byte words, so a full frame takes
/// microseconds): equal pixels give equal fingerprints, and a changed pixel changes it.
pub fn fingerprint(bytes: &[u8]) -> u64 {
    let mut chunks = bytes.chunks_exact(8);
    let mut h = 0xcbf2_9ce4_8422_2325_u64 ^ bytes.len() as u64;
    for c in chunks.by_ref() {
        let word = u64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]);
        h = (h ^ word).wrapping_mul(0x0100_0000_01b3).rotate_left(29);
    }
    for &b in chunks.remainder() {
        h = (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
    }
    h
}

#[cfg(test)]
mod tests {
    use super::fingerprint;

    #[test]
    fn fingerprint_sees_every_changed_pixel() {
        // Reference: by construction, the same bytes give the same value; flip any one byte of
        // a buffer with a ragged tail and the value changes.
        let base: Vec<u8> = (0..37u32).map(|i| (i * 29 + 7) as u8).collect();
        let h = fingerprint(&base);
        assert_eq!(h, fingerprint(&base.clone()));
        for i in 0..base.len() {
            let mut b = base.clone();
            b[i] ^= 1;
            assert_ne!(fingerprint(&b), h, "byte {i}");
        }
        assert_ne!(fingerprint(&base[..36]), h, "length counts");
    }
}
