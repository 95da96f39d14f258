//! The camera's side of the data flow: where frames come from (a user's folder of PNG files
//! or video, [`input`]; the synthetic scene rendered on demand, or frames rendered ahead),
//! and their ground truth.
//!
//! Thesis 2.4 and 4.4: the experiments' scenes, here synthetic with an exact ground truth.
pub mod binned;
pub mod folder;
pub mod gray;
pub mod groundtruth;
pub mod input;
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

/// `inner`'s frames `first..end`, numbered from 0 (a run that starts later in a clip, or
/// stops before its end).
pub struct Skip<'a> {
    inner: &'a mut dyn FrameSource,
    first: usize,
    end: usize,
}

impl<'a> Skip<'a> {
    /// `inner`'s frames `range`; `None` when the range is empty or runs past the last frame.
    pub fn new(inner: &'a mut dyn FrameSource, range: std::ops::Range<usize>) -> Option<Skip<'a>> {
        (range.start < range.end && range.end <= inner.len()).then_some(Skip { inner, first: range.start, end: range.end })
    }
}

impl FrameSource for Skip<'_> {
    fn size(&self) -> (usize, usize) {
        self.inner.size()
    }
    fn len(&self) -> usize {
        self.end - self.first
    }
    fn frame(&mut self, k: usize) -> Result<&[u8], FrameError> {
        if k >= self.len() {
            return Err(FrameError::Missing(k));
        }
        self.inner.frame(k + self.first)
    }
}

/// A frame source that stops handing out frames once its second field says so (the run then
/// ends with [`FrameError::Interrupted`]): Ctrl-C for the CLI, the caller gone for the Python
/// package.
pub struct Interruptible<'a>(pub &'a mut dyn FrameSource, pub &'a dyn Fn() -> bool);

impl FrameSource for Interruptible<'_> {
    fn size(&self) -> (usize, usize) {
        self.0.size()
    }
    fn len(&self) -> usize {
        self.0.len()
    }
    fn frame(&mut self, k: usize) -> Result<&[u8], FrameError> {
        if (self.1)() {
            return Err(FrameError::Interrupted);
        }
        self.0.frame(k)
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

/// FNV-1a's 64-bit prime, the fingerprint's multiplier.
const FNV_PRIME: u64 = 0x0100_0000_01b3;

/// A fingerprint of a sequence's frames, as hex (each frame's [`fingerprint`], folded in
/// order): the same frames give the same text. The OpenCV fixtures store it, to tell that they
/// were made from the frames the renderer makes now.
pub fn frames_fingerprint<'a>(frames: impl IntoIterator<Item = &'a [u8]>) -> String {
    let per_frame: Vec<u8> = frames.into_iter().flat_map(|f| fingerprint(f).to_le_bytes()).collect();
    format!("{:016x}", fingerprint(&per_frame))
}

/// One 8-byte word into a fingerprint chain: a bijection of `h` for every word, so a changed
/// word changes the chain's end.
fn mix(h: u64, word: u64) -> u64 {
    (h ^ word).wrapping_mul(FNV_PRIME).rotate_left(29)
}

/// A 64-bit fingerprint of pixels: FNV-1a's multiply over 8-byte words in four interleaved
/// chains (independent multiplies, so a full frame, fingerprinted for every window the
/// Watch gets, takes a quarter of one chain's time), folded in order, then the words and
/// bytes left over. Equal pixels give equal fingerprints, and a changed pixel changes it.
pub fn fingerprint(bytes: &[u8]) -> u64 {
    let seed = 0xcbf2_9ce4_8422_2325_u64 ^ bytes.len() as u64;
    let word = |c: &[u8]| c.try_into().map_or(0, u64::from_le_bytes);
    let mut lanes = [seed, seed.rotate_left(16), seed.rotate_left(32), seed.rotate_left(48)];
    let mut blocks = bytes.chunks_exact(32);
    for b in blocks.by_ref() {
        for (l, c) in lanes.iter_mut().zip(b.chunks_exact(8)) {
            *l = mix(*l, word(c));
        }
    }
    let h = lanes.iter().fold(seed, |h, &l| mix(h, l));
    let mut words = blocks.remainder().chunks_exact(8);
    let h = words.by_ref().fold(h, |h, c| mix(h, word(c)));
    words.remainder().iter().fold(h, |h, &b| (h ^ u64::from(b)).wrapping_mul(FNV_PRIME))
}

#[cfg(test)]
mod tests {
    use super::fingerprint;

    #[test]
    fn fingerprint_sees_every_changed_pixel() {
        // Reference: by construction, the same bytes give the same value; flip any one byte of
        // a buffer of two 32-byte blocks (the four chains), a word and a ragged tail, and the
        // value changes; so does swapping two words between chains.
        let base: Vec<u8> = (0..77u32).map(|i| (i * 29 + 7) as u8).collect();
        let h = fingerprint(&base);
        assert_eq!(h, fingerprint(&base.clone()));
        for i in 0..base.len() {
            let mut b = base.clone();
            b[i] ^= 1;
            assert_ne!(fingerprint(&b), h, "byte {i}");
        }
        assert_ne!(fingerprint(&base[..76]), h, "length counts");
        let mut swapped = base.clone();
        swapped.copy_within(0..8, 8);
        swapped[..8].copy_from_slice(&base[8..16]);
        assert_ne!(fingerprint(&swapped), h, "words swapped between chains");
    }
}
