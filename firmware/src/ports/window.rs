//! The processor's side of a window unit's two ports (thesis 2.2.1, B1.1):
//!
//! - port 1, coordinates out: a window's bounds go one byte at a time, xmin, xmax, ymin, ymax
//!   (rows 0-based, bounds inclusive), each as two bytes, high first, when the unit's sensor is
//!   over 256 wide or high ([`set_bytes`], the rule the window logic's `CoordPort` is built
//!   with), with the four-phase handshake of the C40 comm port. A byte is driven with CSTRB1
//!   high until the window logic raises CRDY1; CSTRB1 is then released, and the next byte waits
//!   for CRDY1 to fall ([`CoordinateWriter`]);
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
    /// The unit would refuse the window: it is under 2 columns or rows (thesis 2.2.1: xmin <
    /// xmax, ymin < ymax), or reaches past the sensor's last column or row; or, as raw
    /// bounds, a coordinate does not fit its bytes.
    OutOfRange,
    /// [`QUEUE_SETS`] sets are already waiting for the port.
    QueueFull,
}

error_messages!(WriteError {
    OutOfRange => "the window is under 2 pixels wide or high or reaches past the sensor's last column or row",
    QueueFull => "the coordinate port's queue is full",
});

/// Coordinate sets the writer holds before refusing more.
pub const QUEUE_SETS: usize = 4;

/// The thesis's sensor (2.2): 256 x 256, one byte a coordinate.
pub const THESIS_SENSOR: (u16, u16) = (256, 256);

/// True when a `width` x `height` sensor's coordinates take two bytes each (over 256 columns
/// or rows). The one rule: the window logic (`coopwin-hdl`'s `CoordPort`) is built with it.
pub const fn wide_coordinates(width: usize, height: usize) -> bool {
    width > 256 || height > 256
}

/// Bytes in a coordinate set for a `width` x `height` sensor: 4, or 8 with two-byte
/// coordinates ([`wide_coordinates`]).
pub const fn set_bytes(width: usize, height: usize) -> usize {
    if wide_coordinates(width, height) {
        8
    } else {
        4
    }
}

/// A coordinate set's bytes as port 1 carries them (4 or 8).
pub type CoordinateSet = heapless::Vec<u8, 8>;

/// The bytes of the bounds `[xmin, xmax, ymin, ymax]` as they are, valid or not: one byte a
/// coordinate, or two (high first) when `wide`; [`WriteError::OutOfRange`] when a
/// coordinate does not fit its bytes.
pub fn bound_bytes(bounds: [u32; 4], wide: bool) -> Result<CoordinateSet, WriteError> {
    let mut set = CoordinateSet::new();
    for c in bounds {
        let fits = if wide {
            let c = u16::try_from(c).map_err(|_| WriteError::OutOfRange)?;
            set.extend_from_slice(&c.to_be_bytes()).is_ok()
        } else {
            set.push(u8::try_from(c).map_err(|_| WriteError::OutOfRange)?).is_ok()
        };
        // Eight bytes hold four two-byte coordinates: always true.
        if !fits {
            return Err(WriteError::OutOfRange);
        }
    }
    Ok(set)
}

/// The coordinate set of `req` for a unit on a `sensor` = (width, height) sensor, refused as
/// the unit would refuse it: the window must have xmin < xmax < width and ymin < ymax < height.
pub fn coordinate_set(req: &WindowRequest, sensor: (u16, u16)) -> Result<CoordinateSet, WriteError> {
    let last = |start: u16, len: u16, size: u16| {
        let end = u32::from(start) + u32::from(len);
        if len >= 2 && end <= u32::from(size) {
            Ok((u32::from(start), end - 1))
        } else {
            Err(WriteError::OutOfRange)
        }
    };
    let (xmin, xmax) = last(req.x0, req.width, sensor.0)?;
    let (ymin, ymax) = last(req.y0, req.height, sensor.1)?;
    bound_bytes([xmin, xmax, ymin, ymax], wide_coordinates(usize::from(sensor.0), usize::from(sensor.1)))
}

/// The four coordinate bytes of a window for the thesis's 256 x 256 sensor
/// ([`coordinate_set`] at [`THESIS_SENSOR`]): xmin, xmax, ymin, ymax.
pub fn coordinate_bytes(req: &WindowRequest) -> Result<[u8; 4], WriteError> {
    let set = coordinate_set(req, THESIS_SENSOR)?;
    <[u8; 4]>::try_from(set.as_slice()).map_err(|_| WriteError::OutOfRange)
}

/// Writes queued windows over the four-phase handshake, one step per [`poll`](Self::poll),
/// for a unit on a sensor of a given size (which sets the bytes a set takes).
#[derive(Clone, Debug)]
pub struct CoordinateWriter {
    queue: Deque<(u8, bool), { 8 * QUEUE_SETS }>,
    sensor: (u16, u16),
    strobe: bool,
    data: u8,
    decimate: bool,
    bytes_taken: u32,
}

impl Default for CoordinateWriter {
    fn default() -> Self {
        Self::new()
    }
}

impl CoordinateWriter {
    /// An idle writer for a unit on the thesis's 256 x 256 sensor (four-byte sets).
    pub const fn new() -> Self {
        Self::for_sensor(THESIS_SENSOR.0, THESIS_SENSOR.1)
    }

    /// An idle writer for a unit on a `width` x `height` sensor: eight-byte sets when either is
    /// over 256 ([`set_bytes`]).
    pub const fn for_sensor(width: u16, height: u16) -> Self {
        Self { queue: Deque::new(), sensor: (width, height), strobe: false, data: 0, decimate: false, bytes_taken: 0 }
    }

    /// Bytes in one of this unit's sets (4 or 8).
    pub fn set_len(&self) -> usize {
        set_bytes(usize::from(self.sensor.0), usize::from(self.sensor.1))
    }

    /// Queues `req`'s set behind any waiting; [`WriteError::OutOfRange`] for a window the unit
    /// would refuse ([`coordinate_set`]).
    pub fn write(&mut self, req: &WindowRequest) -> Result<(), WriteError> {
        self.write_bytes(&coordinate_set(req, self.sensor)?, req.decimation == Decimation::Quarter)
    }

    /// Queues a set's coordinate bytes as they are, behind any waiting, for the window logic to
    /// judge (from [`bound_bytes`]: xmin, xmax, ymin, ymax, each as two bytes, high first, for a
    /// unit on a sensor over 256 wide or high). A set with xmin >= xmax or ymin >= ymax is
    /// refused there (`coord_error`), which is how the window unit's tests write a set
    /// [`write`](Self::write) would not. [`WriteError::QueueFull`] when the whole set does not
    /// fit the [`QUEUE_SETS`] sets' room.
    pub fn write_bytes(&mut self, bytes: &[u8], decimate: bool) -> Result<(), WriteError> {
        if QUEUE_SETS * self.set_len() < self.queue.len() + bytes.len() {
            return Err(WriteError::QueueFull);
        }
        for b in bytes {
            // Room was checked above (the deque holds QUEUE_SETS eight-byte sets).
            if self.queue.push_back((*b, decimate)).is_err() {
                return Err(WriteError::QueueFull);
            }
        }
        Ok(())
    }

    /// True while bytes wait or a byte is being handed over.
    pub fn busy(&self) -> bool {
        !self.queue.is_empty() || self.strobe
    }

    /// Complete sets the window logic has taken (a set's last byte answered by CRDY1).
    pub fn sets_taken(&self) -> u32 {
        self.bytes_taken / self.set_len() as u32
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
        assert_eq!(coordinate_bytes(&window(5, 5, 2, 2)), Ok([5, 6, 5, 6]));
        // The unit refuses xmin = xmax (thesis 2.2.1: xmin < xmax), so the writer does too.
        for bad in [window(0, 0, 0, 4), window(0, 0, 4, 0), window(5, 5, 1, 4), window(5, 5, 4, 1), window(250, 0, 7, 4), window(256, 0, 2, 2), window(0, 300, 4, 4)] {
            assert_eq!(coordinate_bytes(&bad), Err(WriteError::OutOfRange), "{bad:?}");
        }
    }

    #[test]
    fn a_sensor_over_256_takes_two_bytes_a_coordinate_high_first() {
        // The rule: 8 bytes once either side is over 256.
        assert_eq!([set_bytes(256, 256), set_bytes(257, 10), set_bytes(10, 257), set_bytes(640, 480)], [4, 8, 8, 8]);
        // By hand at 640x480: columns 300..=323 (0x012c, 0x0143), rows 400..=423 (0x0190, 0x01a7).
        let set = coordinate_set(&window(300, 400, 24, 24), (640, 480)).unwrap();
        assert_eq!(set.as_slice(), [0x01, 0x2c, 0x01, 0x43, 0x01, 0x90, 0x01, 0xa7]);
        assert_eq!(coordinate_set(&window(0, 0, 640, 480), (640, 480)).unwrap().as_slice(), [0, 0, 0x02, 0x7f, 0, 0, 0x01, 0xdf]);
        // Refused as the unit refuses them: past the last column or row, or under 2 pixels.
        for bad in [window(617, 0, 24, 24), window(0, 457, 24, 24), window(0, 0, 1, 24), window(0, 0, 24, 1)] {
            assert_eq!(coordinate_set(&bad, (640, 480)), Err(WriteError::OutOfRange), "{bad:?}");
        }
        // A smaller sensor than 256 bounds the window too (the unit checks xmax < width).
        assert_eq!(coordinate_set(&window(190, 0, 20, 20), (200, 200)), Err(WriteError::OutOfRange));
        assert_eq!(bound_bytes([0, 256, 0, 1], false), Err(WriteError::OutOfRange));
        assert_eq!(bound_bytes([0, 65_536, 0, 1], true), Err(WriteError::OutOfRange));
    }

    #[test]
    fn a_wide_writer_sends_eight_bytes_a_set_and_counts_sets() {
        let mut w = CoordinateWriter::for_sensor(640, 480);
        let mut pins = Responder { delay: 1, seen: 0, ready: false, taken: Vec::new(), driven: (false, 0, false) };
        for k in 0..QUEUE_SETS as u16 {
            w.write(&window(300 + k, 400, 24, 24)).unwrap();
        }
        assert_eq!(w.write(&window(0, 0, 2, 2)), Err(WriteError::QueueFull));
        while w.busy() || pins.ready {
            w.poll(&mut pins).unwrap();
        }
        assert_eq!(w.sets_taken(), QUEUE_SETS as u32);
        let first: Vec<u8> = pins.taken.iter().take(8).map(|t| t.0).collect();
        assert_eq!(first, [0x01, 0x2c, 0x01, 0x43, 0x01, 0x90, 0x01, 0xa7]);
        assert_eq!(pins.taken.len(), 8 * QUEUE_SETS);
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
