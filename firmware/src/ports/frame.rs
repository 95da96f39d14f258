//! Framing of the byte links (thesis 2.2's C40 comm ports between processors, 2.6's transputer
//! link to the robot controller): every payload travels as
//! ```text
//! +------+-----+-----------------+-----+
//! | 0xA5 | len | payload (len B) | crc |
//! +------+-----+-----------------+-----+
//! ```
//! `len` is 1..=[`MAX_PAYLOAD`]; `crc` is CRC-8 (polynomial 0x07, init 0, no reflection:
//! CRC-8/SMBUS) over `len` and the payload. [`FrameDecoder`] resynchronises on the next sync
//! byte after a bad length or checksum.
use embedded_io::Write;
use heapless::Vec;

/// Frame start byte.
pub const SYNC: u8 = 0xA5;
/// Largest frame payload.
pub const MAX_PAYLOAD: usize = 32;

/// CRC-8/SMBUS (polynomial 0x07, init 0) of `bytes`.
pub fn crc8(bytes: &[u8]) -> u8 {
    bytes.iter().fold(0u8, |c, &b| crc8_step(c, b))
}

/// Writes one frame `SYNC, len, payload, crc` (payload must be 1..=MAX_PAYLOAD bytes).
pub fn write_frame<W: Write>(w: &mut W, payload: &[u8]) -> Result<(), FrameWriteError<W::Error>> {
    let len = u8::try_from(payload.len()).map_err(|_| FrameWriteError::TooLong)?;
    if payload.is_empty() || payload.len() > MAX_PAYLOAD {
        return Err(FrameWriteError::TooLong);
    }
    let crc = payload.iter().fold(crc8(&[len]), |c, &b| crc8_step(c, b));
    w.write_all(&[SYNC, len]).map_err(FrameWriteError::Io)?;
    w.write_all(payload).map_err(FrameWriteError::Io)?;
    w.write_all(&[crc]).map_err(FrameWriteError::Io)
}

fn crc8_step(crc: u8, b: u8) -> u8 {
    let mut c = crc ^ b;
    for _ in 0..8 {
        c = if c & 0x80 != 0 { (c << 1) ^ 0x07 } else { c << 1 };
    }
    c
}

/// A frame could not be written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameWriteError<E> {
    /// The underlying writer failed.
    Io(E),
    /// Empty payload or longer than [`MAX_PAYLOAD`].
    TooLong,
}

error_messages!(FrameWriteError<E> {
    Io(e) => "the byte stream failed",
    TooLong => "frame payload empty or over the largest payload",
});

/// A received frame was rejected.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameError {
    /// Length byte 0 or above [`MAX_PAYLOAD`].
    BadLength,
    /// Checksum mismatch.
    BadChecksum,
}

error_messages!(FrameError {
    BadLength => "frame length byte 0 or over the largest payload",
    BadChecksum => "frame checksum mismatch",
});

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum DecoderState {
    Sync,
    Len,
    Payload(u8),
    Crc(u8),
}

/// Byte-at-a-time decoder of the frame format.
#[derive(Clone, Debug)]
pub struct FrameDecoder {
    state: DecoderState,
    buf: Vec<u8, MAX_PAYLOAD>,
}

impl Default for FrameDecoder {
    fn default() -> Self {
        Self::new()
    }
}

impl FrameDecoder {
    /// A decoder waiting for a sync byte.
    pub const fn new() -> Self {
        Self { state: DecoderState::Sync, buf: Vec::new() }
    }

    /// Feeds one byte; returns a complete payload, a framing error (after which the
    /// decoder waits for the next sync byte), or `None` while a frame is incomplete.
    pub fn feed(&mut self, b: u8) -> Option<Result<Vec<u8, MAX_PAYLOAD>, FrameError>> {
        match self.state {
            DecoderState::Sync => {
                if b == SYNC {
                    self.state = DecoderState::Len;
                }
                None
            }
            DecoderState::Len => {
                if b == 0 || usize::from(b) > MAX_PAYLOAD {
                    self.state = DecoderState::Sync;
                    return Some(Err(FrameError::BadLength));
                }
                self.buf.clear();
                self.state = DecoderState::Payload(b);
                None
            }
            DecoderState::Payload(len) => {
                // Cannot overflow: len <= MAX_PAYLOAD and the state leaves at len bytes.
                let _ = self.buf.push(b);
                if self.buf.len() >= usize::from(len) {
                    self.state = DecoderState::Crc(len);
                }
                None
            }
            DecoderState::Crc(len) => {
                self.state = DecoderState::Sync;
                let crc = self.buf.iter().fold(crc8(&[len]), |c, &x| crc8_step(c, x));
                if crc == b {
                    Some(Ok(core::mem::take(&mut self.buf)))
                } else {
                    Some(Err(FrameError::BadChecksum))
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crc8_check_value() {
        // CRC-8/SMBUS check value of "123456789".
        assert_eq!(crc8(b"123456789"), 0xF4);
    }
}
