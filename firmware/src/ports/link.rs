//! The processors' messages on a link (thesis 2.3.2: the C40 comm ports that carry
//! coordinates and the template between processors, e.g. Fw1 <-> Fw2 in COOP).
//!
//! A message is a tag byte and little-endian fields: `Motion` (1) four `u16` bounds;
//! `Approx` (2), `Tracked` (3), `Lost` (4), `Result` (6), `Follow` (7), `Coasting` (10) and
//! `Doubted` (11) a point as two `f32`;
//! `Result(None)` (5) the tag alone. A template (8) is a header (anchor point, side N as `u8`)
//! and then its N x N pixels in chunk payloads (9), each a sequence number and up to
//! [`MAX_PAYLOAD`] - 2 pixels; a template missing a chunk is dropped whole. Each payload is one
//! frame ([`super::frame`]); [`FramedLink`] sends and receives them over any `embedded_io` byte
//! stream, and the testbench runs every message through it.
use super::frame::{write_frame, FrameDecoder, FrameWriteError, MAX_PAYLOAD};
use super::payload::{le16, le32, DecodeError};
use crate::processors::{Msg, Template, MAX_TEMPLATE};
use crate::types::Point;
use embedded_io::{Read, Write};
use heapless::Vec;

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
    pub const COASTING: u8 = 10;
    pub const DOUBTED: u8 = 11;
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
            Msg::Coasting(p) => single(point_payload(tag::COASTING, p)),
            Msg::Doubted(p) => single(point_payload(tag::DOUBTED, p)),
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
        tag::COASTING => payload_point(b).map(Msg::Coasting),
        tag::DOUBTED => payload_point(b).map(Msg::Doubted),
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

error_messages!(LinkError<E> {
    Io(e) => "the byte stream failed",
    Eof => "the byte stream ended",
});

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
    use crate::ports::frame::SYNC;
    use std::vec::Vec as StdVec;

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
            Msg::Coasting(p),
            Msg::Doubted(p),
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

    #[test]
    fn framed_link_loops_back() {
        // embedded-io's VecDeque<u8>: writes go to the back, reads come from the front.
        let mut link = FramedLink::new(std::collections::VecDeque::<u8>::new());
        link.send(&Msg::Template(template(24))).unwrap();
        link.send(&Msg::Follow(Point { x: 5.0, y: 6.0 })).unwrap();
        // A corrupted byte inside the second template's pixels: that frame fails its checksum,
        // the template is dropped, and the message after it still arrives.
        link.send(&Msg::Template(template(20))).unwrap();
        link.send(&Msg::Result(None)).unwrap();
        let bytes = link.io_mut();
        let at = bytes.len() - 2 * (MAX_PAYLOAD + 3);
        bytes[at] ^= 0x55;
        assert_eq!(link.receive(), Ok(Msg::Template(template(24))));
        assert_eq!(link.receive(), Ok(Msg::Follow(Point { x: 5.0, y: 6.0 })));
        assert_eq!(link.receive(), Ok(Msg::Result(None)));
        assert_eq!(link.receive(), Err(LinkError::Eof));
    }

    #[test]
    fn link_errors_read_as_sentences() {
        use std::string::ToString;
        assert_eq!(LinkError::Io(7u8).to_string(), "the byte stream failed: 7");
        assert_eq!(LinkError::<u8>::Eof.to_string(), "the byte stream ended");
        assert_eq!(FrameWriteError::<u8>::TooLong.to_string(), "frame payload empty or over the largest payload");
    }
}
