//! The window unit's ports (thesis 2.2.1, B1.1) on `embedded-hal` 1.0 digital pins, so the
//! same driver runs on a board's GPIO and on the testbench's simulated pins:
//!
//! - [`HalCoordinatePins`]: port 1 (eight data lines, CSTRB1 and the decimation line out,
//!   CRDY1 in) as a [`CoordinatePins`] for [`CoordinateWriter`](crate::ports::window::CoordinateWriter);
//! - [`HalPixelPins`]: port 4 (eight data lines and CSTRB4 in), sampled once a pixel clock
//!   into a [`PixelReceiver`].
use crate::ports::window::{CoordinatePins, PixelReceiver, ReceiveError};
use embedded_hal::digital::{InputPin, OutputPin};

/// A pin failed, or (pixels) the receiver refused the pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PinError<O, I> {
    /// An output pin's error.
    Output(O),
    /// An input pin's error.
    Input(I),
}

error_messages!(PinError<O, I> {
    Output(e) => "an output pin failed",
    Input(e) => "an input pin failed",
});

/// Port 1 on embedded-hal pins: `data[0]` is bit 0.
pub struct HalCoordinatePins<O, I> {
    /// D0..D7.
    pub data: [O; 8],
    /// CSTRB1.
    pub strobe: O,
    /// The decimation line (25 % windows).
    pub decimate: O,
    /// CRDY1.
    pub ready: I,
}

impl<O: OutputPin, I: InputPin> CoordinatePins for HalCoordinatePins<O, I> {
    type Error = PinError<O::Error, I::Error>;

    fn drive(&mut self, strobe: bool, data: u8, decimate: bool) -> Result<(), Self::Error> {
        // Data and decimation settle before CSTRB1 rises: the window logic latches the byte
        // on the strobe (four-phase handshake).
        for (bit, pin) in self.data.iter_mut().enumerate() {
            pin.set_state((data >> bit & 1 == 1).into()).map_err(PinError::Output)?;
        }
        self.decimate.set_state(decimate.into()).map_err(PinError::Output)?;
        self.strobe.set_state(strobe.into()).map_err(PinError::Output)
    }

    fn ready(&mut self) -> Result<bool, Self::Error> {
        self.ready.is_high().map_err(PinError::Input)
    }
}

/// Port 4 on embedded-hal pins: `data[0]` is bit 0.
pub struct HalPixelPins<I> {
    /// D0..D7.
    pub data: [I; 8],
    /// CSTRB4.
    pub strobe: I,
}

/// Why a pixel clock failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PixelPinError<E> {
    /// An input pin's error.
    Pin(E),
    /// The receiver refused the pixel.
    Receive(ReceiveError),
}

error_messages!(PixelPinError<E> {
    Pin(e) => "an input pin failed",
    Receive(e) => "the receiver refused the pixel",
});

impl<I: InputPin> HalPixelPins<I> {
    /// One pixel clock: samples CSTRB4 and, with it, the data lines into `rx`. True once the
    /// window is whole.
    pub fn poll(&mut self, rx: &mut PixelReceiver, buf: &mut [u8]) -> Result<bool, PixelPinError<I::Error>> {
        let strobe = self.strobe.is_high().map_err(PixelPinError::Pin)?;
        let mut data = 0u8;
        if strobe {
            for (bit, pin) in self.data.iter_mut().enumerate() {
                data |= u8::from(pin.is_high().map_err(PixelPinError::Pin)?) << bit;
            }
        }
        rx.poll(strobe, data, buf).map_err(PixelPinError::Receive)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ports::window::{coordinate_bytes, CoordinateWriter};
    use crate::types::{Decimation, WindowRequest};
    use core::cell::Cell;
    use core::convert::Infallible;
    use std::vec::Vec;

    /// A pin of a 16-bit port register: bits 0-7 data, 8 strobe, 9 decimate, 10 ready.
    struct Bit<'a>(&'a Cell<u16>, u8);
    impl embedded_hal::digital::ErrorType for Bit<'_> {
        type Error = Infallible;
    }
    impl OutputPin for Bit<'_> {
        fn set_low(&mut self) -> Result<(), Infallible> {
            self.0.set(self.0.get() & !(1 << self.1));
            Ok(())
        }
        fn set_high(&mut self) -> Result<(), Infallible> {
            self.0.set(self.0.get() | 1 << self.1);
            Ok(())
        }
    }
    impl InputPin for Bit<'_> {
        fn is_high(&mut self) -> Result<bool, Infallible> {
            Ok(self.0.get() >> self.1 & 1 == 1)
        }
        fn is_low(&mut self) -> Result<bool, Infallible> {
            Ok(self.0.get() >> self.1 & 1 == 0)
        }
    }

    #[test]
    fn the_writer_hands_each_byte_over_through_single_pins() {
        let reg = Cell::new(0u16);
        let mut pins = HalCoordinatePins {
            data: core::array::from_fn(|b| Bit(&reg, b as u8)),
            strobe: Bit(&reg, 8),
            decimate: Bit(&reg, 9),
            ready: Bit(&reg, 10),
        };
        let req = WindowRequest { x0: 200, y0: 31, width: 40, height: 40, decimation: Decimation::Quarter };
        let mut w = CoordinateWriter::new();
        w.write(&req).unwrap();
        // The window logic: CRDY1 follows CSTRB1 one poll later, taking the byte as it rises.
        let mut taken = Vec::new();
        for _ in 0..40 {
            w.poll(&mut pins).unwrap();
            let r = reg.get();
            let (strobe, ready) = (r >> 8 & 1 == 1, r >> 10 & 1 == 1);
            if strobe && !ready {
                taken.push(((r & 0xff) as u8, r >> 9 & 1 == 1));
            }
            reg.set(if strobe { r | 1 << 10 } else { r & !(1 << 10) });
        }
        let want: Vec<(u8, bool)> = coordinate_bytes(&req).unwrap().iter().map(|&b| (b, true)).collect();
        assert_eq!(taken, want);
        assert_eq!(w.sets_taken(), 1);
    }

    #[test]
    fn the_pixel_port_stores_strobed_bytes() {
        let reg = Cell::new(0u16);
        let mut pins = HalPixelPins { data: core::array::from_fn(|b| Bit(&reg, b as u8)), strobe: Bit(&reg, 8) };
        let req = WindowRequest { x0: 0, y0: 0, width: 2, height: 2, decimation: Decimation::Full };
        let mut rx = PixelReceiver::expect(&req);
        let mut buf = [0u8; 4];
        let clocks: [u16; 6] = [0x100 | 0xA5, 0x0FF, 0x100 | 0x01, 0x100 | 0x80, 0x000, 0x100 | 0x7E];
        let done: Vec<bool> = clocks.iter().map(|&c| { reg.set(c); pins.poll(&mut rx, &mut buf).unwrap() }).collect();
        assert_eq!(buf, [0xA5, 0x01, 0x80, 0x7E]);
        assert_eq!(done, [false, false, false, false, false, true]);
        reg.set(0x1FF);
        assert_eq!(pins.poll(&mut rx, &mut buf), Err(PixelPinError::Receive(ReceiveError::Unexpected)));
    }
}
