//! Ports to the hardware: the kernels reach cameras, processors and the robot only
//! through these small traits, so a board port is wiring and the testbench can simulate.
//!
//! * [`WindowPort`]: request a window from the window logic (coordinates, decimation)
//!   and receive its pixels;
//! * [`Link`]: exchange [`Message`]s with another processor (the C40 comm ports of
//!   thesis 2.2, e.g. Fw1 <-> Fw2 in COOP); [`FramedLink`] implements it over any
//!   `embedded_io` byte stream;
//! * [`PositionSink`]: emit position updates to a robot controller (the transputer link
//!   of thesis 2.6); [`FramedPositionSink`] implements it over any `embedded_io::Write`.
//!
//! ## Frame format (both framed implementations)
//! ```text
//! +------+-----+-----------------+-----+
//! | 0xA5 | len | payload (len B) | crc |
//! +------+-----+-----------------+-----+
//! ```
//! `len` is 1..=[`MAX_PAYLOAD`]; `crc` is CRC-8 (polynomial 0x07, init 0, no
//! reflection: CRC-8/SMBUS) over `len` and the payload. [`FrameDecoder`] resynchronises
//! on the next sync byte after a bad length or checksum.
//!
//! A position payload is 13 bytes: `t_us: u32 LE`, `x: f32 LE`, `y: f32 LE` (frame
//! pixels), `source: u8` (0 = NCC, 1 = corner detector). A [`Message`] payload is its
//! 16-byte fixed encoding.

use crate::confidence::Source;
use crate::view::WindowView;
use embedded_io::{Read, Write};
use heapless::Vec;

/// Frame start byte.
pub const SYNC: u8 = 0xA5;
/// Largest frame payload.
pub const MAX_PAYLOAD: usize = 32;
/// Bytes of an encoded [`Message`].
pub const MESSAGE_LEN: usize = 16;
/// Bytes of an encoded [`PositionUpdate`].
pub const POSITION_LEN: usize = 13;

/// Resolution of a requested window (thesis 2.3).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Decimation {
    /// Every pixel.
    Full,
    /// 25 %: every other pixel of every other row.
    Quarter,
}

/// A window to acquire, in frame coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WindowRequest {
    /// Left column.
    pub x0: u16,
    /// Top row.
    pub y0: u16,
    /// Width in frame pixels.
    pub width: u16,
    /// Height in frame pixels.
    pub height: u16,
    /// Resolution of the delivered pixels.
    pub decimation: Decimation,
}

impl WindowRequest {
    /// Width and height of the delivered pixel block.
    pub fn delivered_size(&self) -> (usize, usize) {
        let (w, h) = (usize::from(self.width), usize::from(self.height));
        match self.decimation {
            Decimation::Full => (w, h),
            Decimation::Quarter => (w.div_ceil(2), h.div_ceil(2)),
        }
    }
}

/// The window logic seen from a processor: request a window, then receive its pixels.
pub trait WindowPort {
    /// Transport error.
    type Error;
    /// Asks the window logic for `req` (the next frame's window).
    fn request(&mut self, req: &WindowRequest) -> Result<(), Self::Error>;
    /// Receives the pixels of the last requested window into `buf` and returns a view of
    /// them (packed rows, origin in frame coordinates).
    fn receive<'b>(&mut self, buf: &'b mut [u8]) -> Result<WindowView<'b>, Self::Error>;
}

/// Errors of [`MemoryFramePort`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PortError {
    /// `receive` without a previous `request`.
    NoRequest,
    /// The window leaves the frame.
    OutOfFrame,
    /// The receive buffer is too small.
    BufferTooSmall,
}

/// A [`WindowPort`] cutting windows out of a frame held in memory (simulation).
pub struct MemoryFramePort<'f> {
    frame: WindowView<'f>,
    pending: Option<WindowRequest>,
}

impl<'f> MemoryFramePort<'f> {
    /// A port over a full frame view.
    pub fn new(frame: WindowView<'f>) -> Self {
        Self { frame, pending: None }
    }
}

impl WindowPort for MemoryFramePort<'_> {
    type Error = PortError;

    fn request(&mut self, req: &WindowRequest) -> Result<(), PortError> {
        self.pending = Some(*req);
        Ok(())
    }

    fn receive<'b>(&mut self, buf: &'b mut [u8]) -> Result<WindowView<'b>, PortError> {
        let req = self.pending.ok_or(PortError::NoRequest)?;
        let sub = self
            .frame
            .sub(req.x0.into(), req.y0.into(), req.width.into(), req.height.into())
            .ok_or(PortError::OutOfFrame)?;
        let sub = match req.decimation {
            Decimation::Full => sub,
            Decimation::Quarter => sub.decimated(),
        };
        sub.pack_into(buf).ok_or(PortError::BufferTooSmall)
    }
}

/// A message between processors, with a fixed 16-byte encoding (tag byte, then
/// little-endian fields, zero padded).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Message {
    /// Acquire the next window at these frame coordinates (tag 1).
    WindowCoords {
        /// Left column.
        x: u16,
        /// Top row.
        y: u16,
    },
    /// A tracked position (tag 2).
    Position(PositionUpdate),
    /// A motion area from a Watch window (tag 3), inclusive bounds.
    Motion {
        /// Leftmost column.
        xmin: u16,
        /// Rightmost column.
        xmax: u16,
        /// Top row.
        ymin: u16,
        /// Bottom row.
        ymax: u16,
        /// Moving pixels.
        count: u32,
    },
    /// The target was lost (tag 4).
    TargetLost,
    /// Acquire both cooperative Foveal windows in frame `frame` (tag 5).
    Sync {
        /// Frame number.
        frame: u32,
    },
}

/// A received message or frame could not be decoded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DecodeError {
    /// Unknown tag or source byte.
    BadTag,
    /// Wrong payload length.
    BadLength,
}

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

fn le16(b: &[u8], i: usize) -> u16 {
    u16::from_le_bytes([b.get(i).copied().unwrap_or(0), b.get(i + 1).copied().unwrap_or(0)])
}

fn le32(b: &[u8], i: usize) -> u32 {
    let g = |k: usize| b.get(i + k).copied().unwrap_or(0);
    u32::from_le_bytes([g(0), g(1), g(2), g(3)])
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

impl Message {
    /// The fixed 16-byte encoding.
    pub fn encode(&self) -> [u8; MESSAGE_LEN] {
        let mut b = [0u8; MESSAGE_LEN];
        match *self {
            Message::WindowCoords { x, y } => {
                b[0] = 1;
                b[1..3].copy_from_slice(&x.to_le_bytes());
                b[3..5].copy_from_slice(&y.to_le_bytes());
            }
            Message::Position(p) => {
                b[0] = 2;
                b[1..14].copy_from_slice(&p.encode());
            }
            Message::Motion { xmin, xmax, ymin, ymax, count } => {
                b[0] = 3;
                for (i, v) in [xmin, xmax, ymin, ymax].into_iter().enumerate() {
                    b[1 + 2 * i..3 + 2 * i].copy_from_slice(&v.to_le_bytes());
                }
                b[9..13].copy_from_slice(&count.to_le_bytes());
            }
            Message::TargetLost => b[0] = 4,
            Message::Sync { frame } => {
                b[0] = 5;
                b[1..5].copy_from_slice(&frame.to_le_bytes());
            }
        }
        b
    }

    /// Decodes the fixed 16-byte encoding.
    pub fn decode(b: &[u8]) -> Result<Self, DecodeError> {
        if b.len() != MESSAGE_LEN {
            return Err(DecodeError::BadLength);
        }
        match b.first().copied().unwrap_or(0) {
            1 => Ok(Message::WindowCoords { x: le16(b, 1), y: le16(b, 3) }),
            2 => Ok(Message::Position(PositionUpdate::decode(b.get(1..14).unwrap_or(&[]))?)),
            3 => Ok(Message::Motion {
                xmin: le16(b, 1),
                xmax: le16(b, 3),
                ymin: le16(b, 5),
                ymax: le16(b, 7),
                count: le32(b, 9),
            }),
            4 => Ok(Message::TargetLost),
            5 => Ok(Message::Sync { frame: le32(b, 1) }),
            _ => Err(DecodeError::BadTag),
        }
    }
}

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

/// A received frame was rejected.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameError {
    /// Length byte 0 or above [`MAX_PAYLOAD`].
    BadLength,
    /// Checksum mismatch.
    BadChecksum,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum DecState {
    Sync,
    Len,
    Payload(u8),
    Crc(u8),
}

/// Byte-at-a-time decoder of the frame format.
#[derive(Clone, Debug)]
pub struct FrameDecoder {
    state: DecState,
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
        Self { state: DecState::Sync, buf: Vec::new() }
    }

    /// Feeds one byte; returns a complete payload, a framing error (after which the
    /// decoder waits for the next sync byte), or `None` while a frame is incomplete.
    pub fn feed(&mut self, b: u8) -> Option<Result<Vec<u8, MAX_PAYLOAD>, FrameError>> {
        match self.state {
            DecState::Sync => {
                if b == SYNC {
                    self.state = DecState::Len;
                }
                None
            }
            DecState::Len => {
                if b == 0 || usize::from(b) > MAX_PAYLOAD {
                    self.state = DecState::Sync;
                    return Some(Err(FrameError::BadLength));
                }
                self.buf.clear();
                self.state = DecState::Payload(b);
                None
            }
            DecState::Payload(len) => {
                // Cannot overflow: len <= MAX_PAYLOAD and the state leaves at len bytes.
                let _ = self.buf.push(b);
                if self.buf.len() >= usize::from(len) {
                    self.state = DecState::Crc(len);
                }
                None
            }
            DecState::Crc(len) => {
                self.state = DecState::Sync;
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

/// A link to another processor.
pub trait Link {
    /// Transport error.
    type Error;
    /// Sends one message.
    fn send(&mut self, msg: &Message) -> Result<(), Self::Error>;
    /// Blocks until one valid message arrives.
    fn receive(&mut self) -> Result<Message, Self::Error>;
}

/// Errors of [`FramedLink`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LinkError<E> {
    /// The byte stream failed.
    Io(E),
    /// The byte stream ended (a read returned 0 bytes).
    Eof,
}

/// A [`Link`] sending framed 16-byte messages over an `embedded_io` byte stream; bad
/// frames and undecodable messages are skipped on receive.
pub struct FramedLink<T> {
    io: T,
    dec: FrameDecoder,
}

impl<T> FramedLink<T> {
    /// Wraps a byte stream.
    pub fn new(io: T) -> Self {
        Self { io, dec: FrameDecoder::new() }
    }

    /// Returns the byte stream.
    pub fn into_inner(self) -> T {
        self.io
    }
}

impl<T: Read + Write> Link for FramedLink<T> {
    type Error = LinkError<T::Error>;

    fn send(&mut self, msg: &Message) -> Result<(), Self::Error> {
        write_frame(&mut self.io, &msg.encode()).map_err(|e| match e {
            FrameWriteError::Io(e) => LinkError::Io(e),
            // A 16-byte payload always fits a frame.
            FrameWriteError::TooLong => LinkError::Eof,
        })
    }

    fn receive(&mut self) -> Result<Message, Self::Error> {
        loop {
            let mut b = [0u8; 1];
            if self.io.read(&mut b).map_err(LinkError::Io)? == 0 {
                return Err(LinkError::Eof);
            }
            if let Some(Ok(payload)) = self.dec.feed(b[0]) {
                if let Ok(m) = Message::decode(&payload) {
                    return Ok(m);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::vec::Vec as StdVec;

    #[test]
    fn crc8_check_value() {
        // CRC-8/SMBUS check value of "123456789".
        assert_eq!(crc8(b"123456789"), 0xF4);
    }

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

    #[test]
    fn message_encoding_round_trips() {
        let msgs = [
            Message::WindowCoords { x: 300, y: 7 },
            Message::Position(PositionUpdate { t_us: 1, x: 2.0, y: 3.0, source: Source::Ncc }),
            Message::Motion { xmin: 1, xmax: 2, ymin: 3, ymax: 4, count: 99 },
            Message::TargetLost,
            Message::Sync { frame: 123_456 },
        ];
        for m in msgs {
            assert_eq!(Message::decode(&m.encode()), Ok(m));
        }
        assert_eq!(Message::decode(&[9; 16]), Err(DecodeError::BadTag));
        assert_eq!(Message::decode(&[1; 3]), Err(DecodeError::BadLength));
        assert_eq!(FrameDecoder::new().feed(SYNC), None);
    }

    /// An in-memory full-duplex byte pipe looping writes back to reads.
    struct Loopback(std::collections::VecDeque<u8>);
    impl embedded_io::ErrorType for Loopback {
        type Error = core::convert::Infallible;
    }
    impl Read for Loopback {
        fn read(&mut self, buf: &mut [u8]) -> Result<usize, Self::Error> {
            let mut n = 0;
            for b in buf.iter_mut() {
                match self.0.pop_front() {
                    Some(v) => {
                        *b = v;
                        n += 1;
                    }
                    None => break,
                }
            }
            Ok(n)
        }
    }
    impl Write for Loopback {
        fn write(&mut self, buf: &[u8]) -> Result<usize, Self::Error> {
            self.0.extend(buf);
            Ok(buf.len())
        }
        fn flush(&mut self) -> Result<(), Self::Error> {
            Ok(())
        }
    }

    #[test]
    fn framed_link_loops_back() {
        let mut link = FramedLink::new(Loopback(Default::default()));
        link.send(&Message::Sync { frame: 5 }).unwrap();
        link.send(&Message::TargetLost).unwrap();
        assert_eq!(link.receive(), Ok(Message::Sync { frame: 5 }));
        assert_eq!(link.receive(), Ok(Message::TargetLost));
        assert_eq!(link.receive(), Err(LinkError::Eof));
    }

    #[test]
    fn memory_port_cuts_windows() {
        let frame: [u8; 64] = core::array::from_fn(|i| i as u8);
        let mut port = MemoryFramePort::new(WindowView::packed(&frame, 8, 8).unwrap());
        let mut buf = [0u8; 16];
        assert_eq!(port.receive(&mut buf).err(), Some(PortError::NoRequest));
        let req = WindowRequest { x0: 2, y0: 4, width: 4, height: 4, decimation: Decimation::Quarter };
        assert_eq!(req.delivered_size(), (2, 2));
        port.request(&req).unwrap();
        let v = port.receive(&mut buf).unwrap();
        assert_eq!((v.get(0, 0), v.get(1, 1), v.origin()), (Some(34), Some(52), (2, 4)));
        let bad = WindowRequest { x0: 6, ..req };
        port.request(&bad).unwrap();
        assert_eq!(port.receive(&mut buf).err(), Some(PortError::OutOfFrame));
    }
}
