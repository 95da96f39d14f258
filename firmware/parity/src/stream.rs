//! A recorded Foveal window stream (thesis 4.2: the COOP pair's windows, one a frame): the
//! template, the start point, and each frame's time, window coordinates and pixels, so a
//! board can replay a tracking run without a camera. Written by the testbench
//! (`cargo run -p coopwin-testbench --example record_board_windows`), read here.
//!
//! Layout, little-endian: `b"CWW1"`, template side `n: u8`, anchor `x, y: f32`, `n*n`
//! template pixels, start `x, y: f32`, frame count `u16`, then per frame `t: f64`,
//! `x0, y0, w, h: u16` and `w*h` pixels.

/// The file's first four bytes.
pub const MAGIC: &[u8; 4] = b"CWW1";

/// Why bytes are not a window stream.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StreamError {
    /// Wrong magic.
    BadMagic,
    /// The bytes end inside a field.
    Truncated,
    /// Bytes follow the last frame.
    TrailingBytes,
}

/// One delivered window.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame<'a> {
    /// Time of the frame, seconds.
    pub t: f64,
    /// Left column in the camera frame.
    pub x0: u16,
    /// Top row.
    pub y0: u16,
    /// Width.
    pub w: u16,
    /// Height.
    pub h: u16,
    /// Row-major pixels, `w * h`.
    pub pixels: &'a [u8],
}

/// A parsed stream header; [`Stream::frames`] walks the frames.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stream<'a> {
    /// Template side N.
    pub side: u8,
    /// Offset of the tracked point from the template's top-left pixel.
    pub anchor: (f32, f32),
    /// Template pixels, `N * N`.
    pub template: &'a [u8],
    /// The point tracking starts at.
    pub start: (f32, f32),
    /// Number of frames.
    pub count: u16,
    body: &'a [u8],
}

struct Reader<'a>(&'a [u8]);

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize) -> Result<&'a [u8], StreamError> {
        let (head, rest) = (self.0.get(..n), self.0.get(n..));
        let (Some(head), Some(rest)) = (head, rest) else { return Err(StreamError::Truncated) };
        self.0 = rest;
        Ok(head)
    }
    fn arr<const N: usize>(&mut self) -> Result<[u8; N], StreamError> {
        self.take(N)?.try_into().map_err(|_| StreamError::Truncated)
    }
    fn f32(&mut self) -> Result<f32, StreamError> {
        Ok(f32::from_le_bytes(self.arr()?))
    }
    fn u16(&mut self) -> Result<u16, StreamError> {
        Ok(u16::from_le_bytes(self.arr()?))
    }
    fn frame(&mut self) -> Result<Frame<'a>, StreamError> {
        let t = f64::from_le_bytes(self.arr()?);
        let (x0, y0, w, h) = (self.u16()?, self.u16()?, self.u16()?, self.u16()?);
        let pixels = self.take(usize::from(w) * usize::from(h))?;
        Ok(Frame { t, x0, y0, w, h, pixels })
    }
}

impl<'a> Stream<'a> {
    /// Parses the header and checks that exactly `count` frames follow.
    pub fn parse(bytes: &'a [u8]) -> Result<Self, StreamError> {
        let mut r = Reader(bytes);
        if r.take(4)? != MAGIC {
            return Err(StreamError::BadMagic);
        }
        let side = r.arr::<1>()?[0];
        let anchor = (r.f32()?, r.f32()?);
        let template = r.take(usize::from(side) * usize::from(side))?;
        let start = (r.f32()?, r.f32()?);
        let count = r.u16()?;
        let s = Stream { side, anchor, template, start, count, body: r.0 };
        let mut walk = Reader(s.body);
        for _ in 0..count {
            walk.frame()?;
        }
        if !walk.0.is_empty() {
            return Err(StreamError::TrailingBytes);
        }
        Ok(s)
    }

    /// The frames in order (checked by [`Stream::parse`]).
    pub fn frames(&self) -> impl Iterator<Item = Frame<'a>> + 'a {
        let mut r = Reader(self.body);
        (0..self.count).map_while(move |_| r.frame().ok())
    }
}

/// Writes a stream through `out` (the testbench's recorder; no allocation needed here).
pub fn encode<'f>(
    side: u8,
    anchor: (f32, f32),
    template: &[u8],
    start: (f32, f32),
    frames: &[Frame<'f>],
    out: &mut dyn FnMut(&[u8]),
) {
    out(MAGIC);
    out(&[side]);
    for v in [anchor.0, anchor.1] {
        out(&v.to_le_bytes());
    }
    out(template);
    for v in [start.0, start.1] {
        out(&v.to_le_bytes());
    }
    // Callers hold at most a few hundred frames; more would not fit a board's flash anyway.
    out(&(frames.len().min(usize::from(u16::MAX)) as u16).to_le_bytes());
    for f in frames.iter().take(usize::from(u16::MAX)) {
        out(&f.t.to_le_bytes());
        for v in [f.x0, f.y0, f.w, f.h] {
            out(&v.to_le_bytes());
        }
        out(f.pixels);
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::vec::Vec;

    #[test]
    fn encode_then_parse_round_trips_and_bad_bytes_are_refused() {
        let px = [7u8; 6];
        let frames = [Frame { t: 0.5, x0: 1, y0: 2, w: 3, h: 2, pixels: &px }, Frame { t: 1.0, x0: 9, y0: 8, w: 1, h: 1, pixels: &px[..1] }];
        let mut bytes = Vec::new();
        encode(2, (0.5, 0.5), &[1, 2, 3, 4], (10.0, 20.0), &frames, &mut |b| bytes.extend_from_slice(b));
        // By hand: 4 magic + 1 + 8 + 4 + 8 + 2 header, then 16 + 6 and 16 + 1 bytes.
        assert_eq!(bytes.len(), 27 + 22 + 17);
        let s = Stream::parse(&bytes).unwrap();
        assert_eq!((s.side, s.anchor, s.template, s.start, s.count), (2, (0.5, 0.5), &[1u8, 2, 3, 4][..], (10.0, 20.0), 2));
        assert_eq!(s.frames().collect::<Vec<_>>(), frames);
        assert_eq!(Stream::parse(&bytes[..bytes.len() - 1]), Err(StreamError::Truncated));
        let mut extra = bytes.clone();
        extra.push(0);
        assert_eq!(Stream::parse(&extra), Err(StreamError::TrailingBytes));
        assert_eq!(Stream::parse(b"CWW0"), Err(StreamError::BadMagic));
        assert_eq!(Stream::parse(b"CW"), Err(StreamError::Truncated));
    }
}
