//! The processor's side of a window unit's two ports (thesis 2.2.1, B1.1):
//!
//! - port 1, coordinates out: a window's bounds go one byte at a time, xmin, xmax, ymin, ymax
//!   (rows 0-based, bounds inclusive), with the four-phase handshake of the C40 comm port. A
//!   byte is driven with CSTRB1 high until the window logic raises CRDY1; CSTRB1 is then
//!   released, and the next byte waits for CRDY1 to fall ([`CoordinateWriter`]);
//! - port 4, pixels in: the window's pixels arrive in raster order, one per CSTRB4 strobe, and
//!   are stored into the caller's buffer until the window is whole ([`PixelReceiver`]).
//!
//! Neither blocks: each `poll` takes one step and returns, so on a board they run from a timer
//! interrupt or a DMA-complete handler, and in the testbench once a pixel clock. The writer
//! reaches its pins only through [`CoordinatePins`].
use crate::types::{Decimation, WindowRequest};
use heapless::Deque;

/// The coordinate port's pins as the processor sees them.
pub trait CoordinatePins {
    /// Pin access error.
    type Error;
    /// Drives CSTRB1, port 1's data byte and the decimation line from now on.
    fn drive(&mut self, strobe: bool, data: u8, decimate: bool) -> Result<(), Self::Error>;
    /// CRDY1 as the window logic drives it now.
    fn ready(&mut self) -> Result<bool, Self::Error>;
}

/// Why a window cannot be written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WriteError {
    /// The window is empty, or reaches past column or row 255 (8-bit coordinates).
    OutOfRange,
    /// [`QUEUE_SETS`] sets are already waiting for the port.
    QueueFull,
}

error_messages!(WriteError {
    OutOfRange => "the window is empty or reaches past column or row 255",
    QueueFull => "the coordinate port's queue is full",
});

/// Coordinate sets the writer holds before refusing more.
pub const QUEUE_SETS: usize = 4;

/// The four coordinate bytes of a window: xmin, xmax, ymin, ymax.
pub fn coordinate_bytes(req: &WindowRequest) -> Result<[u8; 4], WriteError> {
    let last = |start: u16, len: u16| {
        let end = u32::from(start) + u32::from(len);
        match (u8::try_from(start), len) {
            (Ok(first), 1..) if end <= 256 => Ok((first, (end - 1) as u8)),
            _ => Err(WriteError::OutOfRange),
        }
    };
    let (xmin, xmax) = last(req.x0, req.width)?;
    let (ymin, ymax) = last(req.y0, req.height)?;
    Ok([xmin, xmax, ymin, ymax])
}

/// Writes queued windows over the four-phase handshake, one step per [`poll`](Self::poll).
#[derive(Clone, Debug, Default)]
pub struct CoordinateWriter {
    queue: Deque<(u8, bool), { 4 * QUEUE_SETS }>,
    strobe: bool,
    data: u8,
    decimate: bool,
    bytes_taken: u32,
}

impl CoordinateWriter {
    /// An idle writer.
    pub const fn new() -> Self {
        Self { queue: Deque::new(), strobe: false, data: 0, decimate: false, bytes_taken: 0 }
    }

    /// Queues `req`'s four bytes behind any waiting. The window logic itself refuses a set
    /// with xmin = xmax or ymin = ymax (`coord_error`); only what cannot be encoded is refused
    /// here.
    pub fn write(&mut self, req: &WindowRequest) -> Result<(), WriteError> {
        self.write_bytes(&coordinate_bytes(req)?, req.decimation == Decimation::Quarter)
    }

    /// Queues a set's coordinate bytes as they are, behind any waiting, for the window logic to
    /// judge: xmin, xmax, ymin, ymax, or each as two bytes (high first) for a unit on a sensor
    /// over 256 wide or high. A set with xmin >= xmax or ymin >= ymax is refused there
    /// (`coord_error`), which is how the window unit's tests write a set [`write`](Self::write)
    /// would not. [`WriteError::QueueFull`] when the whole set does not fit the queue.
    pub fn write_bytes(&mut self, bytes: &[u8], decimate: bool) -> Result<(), WriteError> {
        if self.queue.capacity() - self.queue.len() < bytes.len() {
            return Err(WriteError::QueueFull);
        }
        for b in bytes {
            // Room was checked above.
            let _ = self.queue.push_back((*b, decimate));
        }
        Ok(())
    }

    /// True while bytes wait or a byte is being handed over.
    pub fn busy(&self) -> bool {
        !self.queue.is_empty() || self.strobe
    }

    /// Complete four-byte sets the window logic has taken (fourth byte answered by CRDY1).
    pub fn sets_taken(&self) -> u32 {
        self.bytes_taken / 4
    }

    /// One step of the handshake: release CSTRB1 once CRDY1 answers; offer the next byte
    /// once CRDY1 has fallen.
    pub fn poll<P: CoordinatePins>(&mut self, pins: &mut P) -> Result<(), P::Error> {
        let ready = pins.ready()?;
        if self.strobe && ready {
            self.strobe = false;
            self.bytes_taken += 1;
        } else if !self.strobe && !ready {
            if let Some((data, decimate)) = self.queue.pop_front() {
                (self.strobe, self.data, self.decimate) = (true, data, decimate);
            }
        }
        pins.drive(self.strobe, self.data, self.decimate)
    }
}

/// Why a strobed pixel could not be stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReceiveError {
    /// A pixel strobed with no window expected, or after the window was whole.
    Unexpected,
    /// The buffer is smaller than the window.
    BufferTooSmall,
}

error_messages!(ReceiveError {
    Unexpected => "a pixel was strobed with no window expected",
    BufferTooSmall => "the buffer is smaller than the window",
});

/// Collects one window's strobed pixels into a caller's buffer.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PixelReceiver {
    expected: usize,
    got: usize,
}

impl PixelReceiver {
    /// Expects the window `req`: its delivered size in pixels (a quarter of it at 25%).
    pub fn expect(req: &WindowRequest) -> Self {
        let (w, h) = req.delivered_size();
        Self { expected: w * h, got: 0 }
    }

    /// One clock of port 4: with `strobe`, `data` is the next pixel and goes into `buf`.
    /// True once the window is whole.
    pub fn poll(&mut self, strobe: bool, data: u8, buf: &mut [u8]) -> Result<bool, ReceiveError> {
        if strobe {
            if self.got >= self.expected {
                return Err(ReceiveError::Unexpected);
            }
            *buf.get_mut(self.got).ok_or(ReceiveError::BufferTooSmall)? = data;
            self.got += 1;
        }
        Ok(self.expected > 0 && self.got == self.expected)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::vec::Vec;

    fn window(x0: u16, y0: u16, width: u16, height: u16) -> WindowRequest {
        WindowRequest { x0, y0, width, height, decimation: Decimation::Full }
    }

    #[test]
    fn bytes_are_inclusive_bounds_in_port_order() {
        // By hand: columns 10..=29, rows 200..=255.
        assert_eq!(coordinate_bytes(&window(10, 200, 20, 56)), Ok([10, 29, 200, 255]));
        assert_eq!(coordinate_bytes(&window(0, 0, 256, 256)), Ok([0, 255, 0, 255]));
        assert_eq!(coordinate_bytes(&window(5, 5, 1, 1)), Ok([5, 5, 5, 5]));
        for bad in [window(0, 0, 0, 4), window(0, 0, 4, 0), window(250, 0, 7, 4), window(256, 0, 1, 1), window(0, 300, 4, 4)] {
            assert_eq!(coordinate_bytes(&bad), Err(WriteError::OutOfRange), "{bad:?}");
        }
    }

    /// A window logic that answers CRDY1 `delay` polls after it sees CSTRB1 and releases it
    /// `delay` polls after CSTRB1 falls, recording each byte it takes.
    struct Responder {
        delay: usize,
        seen: usize,
        ready: bool,
        taken: Vec<(u8, bool)>,
        driven: (bool, u8, bool),
    }

    impl CoordinatePins for Responder {
        type Error = core::convert::Infallible;
        fn drive(&mut self, strobe: bool, data: u8, decimate: bool) -> Result<(), Self::Error> {
            self.driven = (strobe, data, decimate);
            Ok(())
        }
        fn ready(&mut self) -> Result<bool, Self::Error> {
            let strobe = self.driven.0;
            if strobe != self.ready {
                self.seen += 1;
                if self.seen > self.delay {
                    self.ready = strobe;
                    self.seen = 0;
                    if strobe {
                        self.taken.push((self.driven.1, self.driven.2));
                    }
                }
            }
            Ok(self.ready)
        }
    }

    #[test]
    fn sets_go_out_byte_by_byte_in_order_at_any_response_delay() {
        for delay in 0..4 {
            let mut w = CoordinateWriter::new();
            let mut pins = Responder { delay, seen: 0, ready: false, taken: Vec::new(), driven: (false, 0, false) };
            w.write(&window(1, 2, 3, 4)).unwrap();
            w.write(&WindowRequest { decimation: Decimation::Quarter, ..window(100, 50, 40, 40) }).unwrap();
            let mut polls = 0;
            while w.busy() || pins.ready {
                w.poll(&mut pins).unwrap();
                polls += 1;
                assert!(polls < 200, "delay {delay}: the handshake stalled");
            }
            let expected = [(1, false), (3, false), (2, false), (5, false), (100, true), (139, true), (50, true), (89, true)];
            assert_eq!(pins.taken, expected, "delay {delay}");
            assert_eq!(w.sets_taken(), 2);
        }
    }

    #[test]
    fn a_full_queue_refuses_and_keeps_what_it_holds() {
        let mut w = CoordinateWriter::new();
        for k in 0..QUEUE_SETS as u16 {
            w.write(&window(k, 0, 2, 2)).unwrap();
        }
        assert_eq!(w.write(&window(9, 9, 2, 2)), Err(WriteError::QueueFull));
        assert_eq!(w.write(&window(0, 0, 0, 2)), Err(WriteError::OutOfRange));
        let mut pins = Responder { delay: 0, seen: 0, ready: false, taken: Vec::new(), driven: (false, 0, false) };
        while w.busy() || pins.ready {
            w.poll(&mut pins).unwrap();
        }
        let xmins: Vec<u8> = pins.taken.chunks(4).map(|c| c[0].0).collect();
        assert_eq!(xmins, [0, 1, 2, 3]);
    }

    #[test]
    fn the_receiver_stores_strobed_pixels_until_the_window_is_whole() {
        // A 5x3 window at 25%: 3 x 2 = 6 pixels, taken only on strobes.
        let req = WindowRequest { decimation: Decimation::Quarter, ..window(0, 0, 5, 3) };
        let mut rx = PixelReceiver::expect(&req);
        let mut buf = [0u8; 6];
        let clocks = [(true, 1), (false, 99), (true, 2), (true, 3), (false, 98), (true, 4), (true, 5), (true, 6)];
        let done: Vec<bool> = clocks.iter().map(|&(s, d)| rx.poll(s, d, &mut buf).unwrap()).collect();
        assert_eq!(buf, [1, 2, 3, 4, 5, 6]);
        assert_eq!(done, [false, false, false, false, false, false, false, true]);
        assert_eq!(rx.poll(true, 7, &mut buf), Err(ReceiveError::Unexpected));
        assert_eq!(rx.poll(false, 7, &mut buf), Ok(true));
        let mut small = [0u8; 2];
        let mut rx = PixelReceiver::expect(&window(0, 0, 2, 2));
        assert_eq!(rx.poll(true, 1, &mut small), Ok(false));
        assert_eq!(rx.poll(true, 2, &mut small), Ok(false));
        assert_eq!(rx.poll(true, 3, &mut small), Err(ReceiveError::BufferTooSmall));
        assert_eq!(PixelReceiver::default().poll(true, 1, &mut small), Err(ReceiveError::Unexpected));
    }
}
