//! Position updates for the robot controller (thesis 2.6: the tracked point sent over a
//! transputer link). A payload is 13 bytes: `t_us: u32 LE`, `x: f32 LE`, `y: f32 LE` (frame
//! pixels), `source: u8` (0 = NCC, 1 = corner detector), framed as in [`super::frame`].
use super::frame::{write_frame, FrameWriteError};
use super::payload::{le32, DecodeError};
use crate::types::Source;
use embedded_io::Write;

/// Bytes of an encoded [`PositionUpdate`].
pub const POSITION_LEN: usize = 13;

fn source_byte(s: Source) -> u8 {
    match s {
        Source::Ncc => 0,
        Source::Cd => 1,
    }
}

fn byte_source(b: u8) -> Result<Source, DecodeError> {
    match b {
        0 => Ok(Source::Ncc),
        1 => Ok(Source::Cd),
        _ => Err(DecodeError::BadTag),
    }
}

/// A position update for the robot controller.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PositionUpdate {
    /// Time stamp in microseconds.
    pub t_us: u32,
    /// Column in frame pixels.
    pub x: f32,
    /// Row in frame pixels.
    pub y: f32,
    /// Algorithm that produced it.
    pub source: Source,
}

impl PositionUpdate {
    /// The 13-byte payload (see the module docs).
    pub fn encode(&self) -> [u8; POSITION_LEN] {
        let mut b = [0u8; POSITION_LEN];
        b[0..4].copy_from_slice(&self.t_us.to_le_bytes());
        b[4..8].copy_from_slice(&self.x.to_le_bytes());
        b[8..12].copy_from_slice(&self.y.to_le_bytes());
        b[12] = source_byte(self.source);
        b
    }

    /// Decodes a 13-byte payload.
    pub fn decode(b: &[u8]) -> Result<Self, DecodeError> {
        if b.len() != POSITION_LEN {
            return Err(DecodeError::BadLength);
        }
        Ok(Self {
            t_us: le32(b, 0),
            x: f32::from_bits(le32(b, 4)),
            y: f32::from_bits(le32(b, 8)),
            source: byte_source(b.get(12).copied().unwrap_or(u8::MAX))?,
        })
    }
}


/// Where position updates go (a robot controller).
pub trait PositionSink {
    /// Transport error.
    type Error;
    /// Emits one update.
    fn emit(&mut self, p: &PositionUpdate) -> Result<(), Self::Error>;
}

/// A [`PositionSink`] writing framed 13-byte position payloads to any
/// `embedded_io::Write` (a UART, a transputer link adapter, a test buffer).
pub struct FramedPositionSink<W> {
    w: W,
}

impl<W: Write> FramedPositionSink<W> {
    /// Wraps a writer.
    pub fn new(w: W) -> Self {
        Self { w }
    }

    /// Returns the writer.
    pub fn into_inner(self) -> W {
        self.w
    }
}

impl<W: Write> PositionSink for FramedPositionSink<W> {
    type Error = FrameWriteError<W::Error>;

    fn emit(&mut self, p: &PositionUpdate) -> Result<(), Self::Error> {
        write_frame(&mut self.w, &p.encode())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ports::frame::{FrameDecoder, FrameError, SYNC};
    use std::vec::Vec as StdVec;

    #[test]
    fn position_frames_round_trip_and_resync() {
        let mut out = [0u8; 64];
        let p = PositionUpdate { t_us: 8800, x: 12.5, y: -3.25, source: Source::Cd };
        let n = {
            let mut w: &mut [u8] = &mut out;
            let mut sink = FramedPositionSink::new(&mut w);
            sink.emit(&p).unwrap();
            sink.emit(&p).unwrap();
            64 - w.len()
        };
        assert_eq!(n, 2 * (POSITION_LEN + 3));
        assert_eq!(&out[..2], &[SYNC, 13]);
        assert_eq!(&out[2..6], &8800u32.to_le_bytes());
        // Corrupt the first frame's payload: it is rejected, the second still decodes.
        out[5] ^= 0xFF;
        let mut dec = FrameDecoder::new();
        let got: StdVec<_> = out[..n].iter().filter_map(|&b| dec.feed(b)).collect();
        assert_eq!(got.len(), 2);
        assert_eq!(got[0], Err(FrameError::BadChecksum));
        assert_eq!(PositionUpdate::decode(got[1].as_ref().unwrap()), Ok(p));
    }
}
