//! The window unit's ports (thesis 2.2.1) on the board through embedded-hal pins.
//!
//! QEMU's mps2-an386 leaves the CMSDK GPIO blocks unimplemented (writes are dropped, reads
//! give 0), so nothing loops back from a real GPIO. The pins here are bits of a
//! memory-mapped port register in RAM, laid out as a GPIO data register would be (bits 0-7
//! data, 8 strobe, 9 decimate, 10 CRDY1), read and written with volatile accesses; a small
//! software window logic answers the handshake and strobes pixels on the same register.
//! The driver is the firmware's `CoordinateWriter`/`PixelReceiver` over
//! `coopwin_firmware::ports::hal_pins`, exactly as the testbench runs it on its simulated pins.
use coopwin_firmware::ports::hal_pins::{HalCoordinatePins, HalPixelPins};
use coopwin_firmware::types::{Decimation, WindowRequest};
use coopwin_firmware::ports::window::{coordinate_bytes, CoordinateWriter, PixelReceiver};
use coopwin_parity::stream::Stream;
use coopwin_parity::suite::{fnv1a, inputs, Meter};
use core::convert::Infallible;
use core::ptr::{addr_of, addr_of_mut};
use embedded_hal::digital::{ErrorType, InputPin, OutputPin};

static mut PORT: u32 = 0;

fn read() -> u32 {
    // SAFETY: single core, no interrupts touch PORT; volatile as for a device register.
    unsafe { core::ptr::read_volatile(addr_of!(PORT)) }
}

fn write(v: u32) {
    // SAFETY: as in `read`.
    unsafe { core::ptr::write_volatile(addr_of_mut!(PORT), v) }
}

/// One bit of the port register.
struct Pin(u8);

impl ErrorType for Pin {
    type Error = Infallible;
}

impl OutputPin for Pin {
    fn set_low(&mut self) -> Result<(), Infallible> {
        write(read() & !(1 << self.0));
        Ok(())
    }
    fn set_high(&mut self) -> Result<(), Infallible> {
        write(read() | 1 << self.0);
        Ok(())
    }
}

impl InputPin for Pin {
    fn is_high(&mut self) -> Result<bool, Infallible> {
        Ok(read() >> self.0 & 1 == 1)
    }
    fn is_low(&mut self) -> Result<bool, Infallible> {
        Ok(read() >> self.0 & 1 == 0)
    }
}

const STROBE: u8 = 8;
const DECIMATE: u8 = 9;
const READY: u8 = 10;

/// Why the port exercise failed.
#[derive(Debug)]
pub enum PinsError {
    /// The stream did not parse.
    Stream,
    /// The writer refused a window.
    Write,
    /// The handshake stalled.
    Stalled,
    /// The window logic took other bytes than this frame's window coordinates.
    WrongBytes(#[allow(dead_code)] usize),
    /// The pixel port failed or delivered other pixels at this frame.
    Pixels(#[allow(dead_code)] usize),
}

/// Writes every recorded window's coordinates over port 1 and strobes its pixels in over
/// port 4; checks the bytes taken against `coordinate_bytes` and the pixels against the
/// recording. Returns a summary line (a measurement line, `#`). Never inlined: its 4 KiB
/// pixel buffer is not in `main`'s frame, under the suite's calls.
#[inline(never)]
pub fn exercise<M: Meter>(meter: &mut M) -> Result<Line, PinsError> {
    let s = Stream::parse(inputs::WINDOWS).map_err(|_| PinsError::Stream)?;
    let mut coord = HalCoordinatePins { data: core::array::from_fn(|b| Pin(b as u8)), strobe: Pin(STROBE), decimate: Pin(DECIMATE), ready: Pin(READY) };
    let mut pixel = HalPixelPins { data: core::array::from_fn(|b| Pin(b as u8)), strobe: Pin(STROBE) };
    let mut buf = [0u8; 64 * 64];
    let mut line = Line::default();
    for (k, f) in s.frames().enumerate() {
        let req = WindowRequest { x0: f.x0, y0: f.y0, width: f.w, height: f.h, decimation: Decimation::Full };
        let want = coordinate_bytes(&req).map_err(|_| PinsError::Write)?;
        let mut w = CoordinateWriter::new();
        w.write(&req).map_err(|_| PinsError::Write)?;
        let mut taken = [0u8; 4];
        let mut n = 0;
        let polls = meter.once("port1_set", &mut || {
            let mut polls = 0u32;
            // The window logic's side: CRDY1 follows CSTRB1 a poll later, taking the byte.
            while (w.busy() || read() >> READY & 1 == 1) && polls < 64 {
                let Ok(()) = w.poll(&mut coord);
                let r = read();
                let (strobe, ready) = (r >> STROBE & 1 == 1, r >> READY & 1 == 1);
                if strobe && !ready && n < 4 {
                    taken[n] = r as u8;
                    n += 1;
                }
                write(if strobe { r | 1 << READY } else { r & !(1 << READY) });
                polls += 1;
            }
            polls
        });
        if polls >= 64 {
            return Err(PinsError::Stalled);
        }
        if taken != want || w.sets_taken() != 1 {
            return Err(PinsError::WrongBytes(k));
        }
        // Port 4: a strobe and a byte per pixel clock, an idle clock after every row.
        let mut rx = PixelReceiver::expect(&req);
        let mut whole = false;
        for row in f.pixels.chunks(usize::from(f.w)) {
            for &p in row {
                write(1 << STROBE | u32::from(p));
                pixel.poll(&mut rx, &mut buf).map_err(|_| PinsError::Pixels(k))?;
            }
            write(0);
            whole = pixel.poll(&mut rx, &mut buf).map_err(|_| PinsError::Pixels(k))?;
        }
        if !whole || buf.get(..f.pixels.len()) != Some(f.pixels) {
            return Err(PinsError::Pixels(k));
        }
        line.sets += 1;
        line.pixels = line.pixels.wrapping_add(fnv1a(f.pixels));
    }
    Ok(line)
}

/// What went through the ports.
#[derive(Default)]
pub struct Line {
    sets: u32,
    pixels: u64,
}

impl core::fmt::Display for Line {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "# pins ok: {} coordinate sets over port 1, their windows over port 4 (sum of fnv {:016x})", self.sets, self.pixels)
    }
}

