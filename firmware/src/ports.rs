//! Ports to the hardware: the kernels reach cameras, processors and the robot only
//! through these small traits, so a board port is wiring and the testbench can simulate.
//!
//! * [`WindowPort`]: request a window from the window logic (coordinates, decimation)
//!   and receive its pixels;
//! * [`Link`]: exchange the processors' messages ([`Msg`]) with another processor (the
//!   C40 comm ports of thesis 2.2, e.g. Fw1 <-> Fw2 in COOP); [`FramedLink`] implements it
//!   over any `embedded_io` byte stream, and the testbench runs every message through it;
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
//! pixels), `source: u8` (0 = NCC, 1 = corner detector).
//!
//! A message is a tag byte and little-endian fields: `Motion` (1) four `u16` bounds;
//! `Approx` (2), `Tracked` (3), `Lost` (4), `Result` (6) and `Follow` (7) a point as two `f32`;
//! `Result(None)` (5) the tag alone. A template (8) is a header (anchor point, side N as `u8`)
//! and then its N x N pixels in chunk payloads (9), each a sequence number and up to
//! [`MAX_PAYLOAD`] - 2 pixels; a template missing a chunk is dropped whole.

use crate::confidence::Source;
use crate::tracker::{Msg, Point, Template, MAX_TEMPLATE};
use crate::view::WindowView;
use embedded_io::{Read, Write};
use heapless::Vec;

/// Frame start byte.
pub const SYNC: u8 = 0xA5;
/// Largest frame payload.
pub const MAX_PAYLOAD: usize = 32;
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

error_messages!(PortError {
    NoRequest => "receive without a window requested",
    OutOfFrame => "the window leaves the frame",
    BufferTooSmall => "the receive buffer is too small",
});

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


/// A received message or frame could not be decoded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DecodeError {
    /// Unknown tag or source byte.
    BadTag,
    /// Wrong payload length.
    BadLength,
    /// A position that is NaN or infinite.
    NotFinite,
    /// A template chunk out of sequence, or without its header.
    BrokenTemplate,
}

error_messages!(DecodeError {
    BadTag => "unknown message tag or source byte",
    BadLength => "wrong payload length",
    NotFinite => "a position that is not a finite number",
    BrokenTemplate => "a template chunk out of sequence or without its header",
});

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

error_messages!(FrameError {
    BadLength => "frame length byte 0 or over the largest payload",
    BadChecksum => "frame checksum mismatch",
});

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

/// Tags of the message payloads on a link.
mod tag {
    pub const MOTION: u8 = 1;
    pub const APPROX: u8 = 2;
    pub const TRACKED: u8 = 3;
    pub const LOST: u8 = 4;
    pub const NO_RESULT: u8 = 5;
    pub const RESULT: u8 = 6;
    pub const FOLLOW: u8 = 7;
    pub const TEMPLATE: u8 = 8;
    pub const TEMPLATE_PIXELS: u8 = 9;
}

/// Template pixels in one chunk payload (after its tag and sequence number).
const CHUNK: usize = MAX_PAYLOAD - 2;

fn point_payload(t: u8, p: &Point) -> Vec<u8, MAX_PAYLOAD> {
    let mut v = Vec::new();
    // 9 bytes always fit a payload.
    let _ = v.push(t);
    let _ = v.extend_from_slice(&p.x.to_le_bytes());
    let _ = v.extend_from_slice(&p.y.to_le_bytes());
    v
}

fn payload_point(b: &[u8]) -> Result<Point, DecodeError> {
    if b.len() != 9 {
        return Err(DecodeError::BadLength);
    }
    let p = Point { x: f32::from_bits(le32(b, 1)), y: f32::from_bits(le32(b, 5)) };
    // No processor sends a NaN or infinite position; one on the link would poison tracking.
    match p.x.is_finite() && p.y.is_finite() {
        true => Ok(p),
        false => Err(DecodeError::NotFinite),
    }
}

/// The frame payloads carrying `msg` on a link, in order: one payload, or for a template a
/// header (side N, anchor) followed by its N x N pixels in chunks of up to [`MAX_PAYLOAD`] - 2
/// bytes, each with a sequence number.
pub fn message_payloads(msg: &Msg) -> MessagePayloads<'_> {
    MessagePayloads { msg, next: 0 }
}

/// Iterator of [`message_payloads`].
pub struct MessagePayloads<'m> {
    msg: &'m Msg,
    next: usize,
}

impl Iterator for MessagePayloads<'_> {
    type Item = Vec<u8, MAX_PAYLOAD>;

    fn next(&mut self) -> Option<Self::Item> {
        let i = self.next;
        self.next += 1;
        let single = |v: Vec<u8, MAX_PAYLOAD>| (i == 0).then_some(v);
        match self.msg {
            Msg::Motion { xmin, xmax, ymin, ymax } => {
                let mut v = Vec::new();
                let _ = v.push(tag::MOTION);
                for c in [xmin, xmax, ymin, ymax] {
                    let _ = v.extend_from_slice(&c.to_le_bytes());
                }
                single(v)
            }
            Msg::Approx(p) => single(point_payload(tag::APPROX, p)),
            Msg::Tracked(p) => single(point_payload(tag::TRACKED, p)),
            Msg::Lost(p) => single(point_payload(tag::LOST, p)),
            Msg::Result(None) => single(Vec::from_slice(&[tag::NO_RESULT]).unwrap_or_default()),
            Msg::Result(Some(p)) => single(point_payload(tag::RESULT, p)),
            Msg::Follow(p) => single(point_payload(tag::FOLLOW, p)),
            Msg::Template(t) => {
                if i == 0 {
                    let mut v = point_payload(tag::TEMPLATE, &t.anchor());
                    let _ = v.push(t.side() as u8);
                    return Some(v);
                }
                let chunk = t.pixels().chunks(CHUNK).nth(i - 1)?;
                let mut v = Vec::new();
                let _ = v.push(tag::TEMPLATE_PIXELS);
                let _ = v.push((i - 1) as u8);
                let _ = v.extend_from_slice(chunk);
                Some(v)
            }
        }
    }
}

/// A template being received: side, anchor, pixels so far.
#[derive(Clone, Debug)]
struct PartialTemplate {
    n: usize,
    anchor: Point,
    px: [u8; MAX_TEMPLATE * MAX_TEMPLATE],
    got: usize,
}

/// Turns link payloads back into messages, reassembling templates.
#[derive(Clone, Debug, Default)]
pub struct MessageDecoder {
    template: Option<PartialTemplate>,
}

impl MessageDecoder {
    /// A decoder with no template under way.
    pub const fn new() -> Self {
        Self { template: None }
    }

    /// Feeds one payload: a complete message, an error (a template broken by a lost or
    /// foreign chunk is dropped whole), or `None` while a template is incomplete.
    pub fn feed(&mut self, b: &[u8]) -> Option<Result<Msg, DecodeError>> {
        let t = *b.first()?;
        if t == tag::TEMPLATE_PIXELS {
            return self.chunk(b);
        }
        // Any other payload ends a template still under way: that template is lost.
        self.template = None;
        if t == tag::TEMPLATE {
            return self.header(b).err().map(Err);
        }
        Some(single(t, b))
    }

    fn header(&mut self, b: &[u8]) -> Result<(), DecodeError> {
        let n = usize::from(b.get(9).copied().unwrap_or(0));
        if b.len() != 10 || n == 0 || n > MAX_TEMPLATE {
            return Err(DecodeError::BadLength);
        }
        let anchor = payload_point(&b[..9])?;
        self.template = Some(PartialTemplate { n, anchor, px: [0; MAX_TEMPLATE * MAX_TEMPLATE], got: 0 });
        Ok(())
    }

    fn chunk(&mut self, b: &[u8]) -> Option<Result<Msg, DecodeError>> {
        let Some(mut t) = self.template.take() else { return Some(Err(DecodeError::BrokenTemplate)) };
        let seq = usize::from(b.get(1).copied().unwrap_or(u8::MAX));
        let pixels = b.get(2..).unwrap_or(&[]);
        let total = t.n * t.n;
        if seq * CHUNK != t.got || pixels.is_empty() || t.got + pixels.len() > total {
            return Some(Err(DecodeError::BrokenTemplate));
        }
        t.px[t.got..t.got + pixels.len()].copy_from_slice(pixels);
        t.got += pixels.len();
        if t.got < total {
            self.template = Some(t);
            return None;
        }
        Some(Template::from_parts(t.n, t.anchor, &t.px[..total]).map(Msg::Template).ok_or(DecodeError::BadLength))
    }
}

/// A message that travels in one payload.
fn single(t: u8, b: &[u8]) -> Result<Msg, DecodeError> {
    match t {
        tag::MOTION if b.len() == 9 => Ok(Msg::Motion { xmin: le16(b, 1), xmax: le16(b, 3), ymin: le16(b, 5), ymax: le16(b, 7) }),
        tag::APPROX => payload_point(b).map(Msg::Approx),
        tag::TRACKED => payload_point(b).map(Msg::Tracked),
        tag::LOST => payload_point(b).map(Msg::Lost),
        tag::NO_RESULT if b.len() == 1 => Ok(Msg::Result(None)),
        tag::RESULT => payload_point(b).map(|p| Msg::Result(Some(p))),
        tag::FOLLOW => payload_point(b).map(Msg::Follow),
        tag::MOTION | tag::NO_RESULT => Err(DecodeError::BadLength),
        _ => Err(DecodeError::BadTag),
    }
}

/// A link to another processor.
pub trait Link {
    /// Transport error.
    type Error;
    /// Sends one message.
    fn send(&mut self, msg: &Msg) -> Result<(), Self::Error>;
    /// Blocks until one valid message arrives.
    fn receive(&mut self) -> Result<Msg, Self::Error>;
}

/// Errors of [`FramedLink`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LinkError<E> {
    /// The byte stream failed.
    Io(E),
    /// The byte stream ended (a read returned 0 bytes).
    Eof,
}

/// A [`Link`] sending framed messages over an `embedded_io` byte stream; bad frames,
/// undecodable messages and broken templates are skipped on receive.
pub struct FramedLink<T> {
    io: T,
    frames: FrameDecoder,
    messages: MessageDecoder,
}

impl<T> FramedLink<T> {
    /// Wraps a byte stream.
    pub fn new(io: T) -> Self {
        Self { io, frames: FrameDecoder::new(), messages: MessageDecoder::new() }
    }

    /// The byte stream.
    pub fn io_mut(&mut self) -> &mut T {
        &mut self.io
    }

    /// Returns the byte stream.
    pub fn into_inner(self) -> T {
        self.io
    }
}

impl<T: Read + Write> Link for FramedLink<T> {
    type Error = LinkError<T::Error>;

    fn send(&mut self, msg: &Msg) -> Result<(), Self::Error> {
        for payload in message_payloads(msg) {
            write_frame(&mut self.io, &payload).map_err(|e| match e {
                FrameWriteError::Io(e) => LinkError::Io(e),
                // Every payload is 1..=MAX_PAYLOAD bytes by construction.
                FrameWriteError::TooLong => LinkError::Eof,
            })?;
        }
        Ok(())
    }

    fn receive(&mut self) -> Result<Msg, Self::Error> {
        loop {
            let mut b = [0u8; 1];
            if self.io.read(&mut b).map_err(LinkError::Io)? == 0 {
                return Err(LinkError::Eof);
            }
            if let Some(Ok(payload)) = self.frames.feed(b[0]) {
                if let Some(Ok(m)) = self.messages.feed(&payload) {
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

    fn template(n: usize) -> Template {
        let px: StdVec<u8> = (0..n * n).map(|i| (i * 7 % 251) as u8).collect();
        Template::from_parts(n, Point { x: 9.5, y: -0.25 }, &px).unwrap()
    }

    fn decode_all(payloads: impl Iterator<Item = Vec<u8, MAX_PAYLOAD>>) -> StdVec<Result<Msg, DecodeError>> {
        let mut dec = MessageDecoder::new();
        payloads.filter_map(|p| dec.feed(&p)).collect()
    }

    #[test]
    fn message_encoding_round_trips() {
        let p = Point { x: 123.25, y: -7.5 };
        let msgs = [
            Msg::Motion { xmin: 1, xmax: 300, ymin: 3, ymax: 4 },
            Msg::Approx(p),
            Msg::Tracked(p),
            Msg::Lost(p),
            Msg::Result(None),
            Msg::Result(Some(p)),
            Msg::Follow(p),
            Msg::Template(template(20)),
            Msg::Template(template(MAX_TEMPLATE)),
            Msg::Template(template(1)),
        ];
        for m in &msgs {
            assert_eq!(decode_all(message_payloads(m)), [Ok(m.clone())]);
        }
        // By hand: a point message is its tag and two little-endian f32s; a 20x20 template is
        // a header and ceil(400 / 30) = 14 chunks.
        let tracked: StdVec<_> = message_payloads(&Msg::Tracked(p)).collect();
        assert_eq!(tracked.len(), 1);
        assert_eq!(&tracked[0][..], &[&[3u8][..], &p.x.to_le_bytes(), &p.y.to_le_bytes()].concat()[..]);
        assert_eq!(message_payloads(&Msg::Template(template(20))).count(), 15);
        assert_eq!(MessageDecoder::new().feed(&[42, 0]), Some(Err(DecodeError::BadTag)));
        assert_eq!(MessageDecoder::new().feed(&[3, 0, 0]), Some(Err(DecodeError::BadLength)));
        let nan = [&[3u8][..], &f32::NAN.to_le_bytes(), &1.0f32.to_le_bytes()].concat();
        assert_eq!(MessageDecoder::new().feed(&nan), Some(Err(DecodeError::NotFinite)));
        assert_eq!(MessageDecoder::new().feed(&[9, 0, 1, 2]), Some(Err(DecodeError::BrokenTemplate)));
        assert_eq!(MessageDecoder::new().feed(&[]), None);
        assert_eq!(FrameDecoder::new().feed(SYNC), None);
    }

    #[test]
    fn a_template_missing_a_chunk_is_dropped_and_the_next_message_survives() {
        let mut payloads: StdVec<_> = message_payloads(&Msg::Template(template(20))).collect();
        payloads.remove(5);
        payloads.extend(message_payloads(&Msg::Lost(Point { x: 1.0, y: 2.0 })));
        let got = decode_all(payloads.into_iter());
        assert_eq!(got.first(), Some(&Err(DecodeError::BrokenTemplate)));
        assert_eq!(got.last(), Some(&Ok(Msg::Lost(Point { x: 1.0, y: 2.0 }))));
        assert!(!got.iter().any(|m| matches!(m, Ok(Msg::Template(_)))));
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
        link.send(&Msg::Template(template(24))).unwrap();
        link.send(&Msg::Follow(Point { x: 5.0, y: 6.0 })).unwrap();
        // A corrupted byte inside the second template's pixels: that frame fails its checksum,
        // the template is dropped, and the message after it still arrives.
        link.send(&Msg::Template(template(20))).unwrap();
        link.send(&Msg::Result(None)).unwrap();
        let bytes = &mut link.io_mut().0;
        let at = bytes.len() - 2 * (MAX_PAYLOAD + 3);
        bytes[at] ^= 0x55;
        assert_eq!(link.receive(), Ok(Msg::Template(template(24))));
        assert_eq!(link.receive(), Ok(Msg::Follow(Point { x: 5.0, y: 6.0 })));
        assert_eq!(link.receive(), Ok(Msg::Result(None)));
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
