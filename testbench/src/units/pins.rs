//! The units' ports as `embedded-hal` pins, so the firmware's port drivers (`hal_pins`) drive
//! the simulated units with the same code as on the Cortex-M4 board (`firmware/board`).
use coopwin_firmware::ports::hal_pins::{HalCoordinatePins, HalPixelPins};
use coopwin_hdl::sim::driver::{CoordBus, UnitOutputs};
use core::cell::Cell;
use core::convert::Infallible;
use embedded_hal::digital::{InputPin, OutputPin};

/// One line of a unit's simulated coordinate bus as an `embedded-hal` output pin: the
/// firmware's writer drives the rust-hdl or Verilator unit through
/// [`HalCoordinatePins`], the same driver code as on the Cortex-M4 board (`firmware/board`).
pub(crate) struct BusPin<'a> {
    bus: &'a Cell<CoordBus>,
    line: BusLine,
}

/// Which line of the port a [`BusPin`] drives.
#[derive(Clone, Copy)]
enum BusLine {
    Data(u8),
    Strobe,
    Decimate,
}

impl embedded_hal::digital::ErrorType for BusPin<'_> {
    type Error = Infallible;
}

impl OutputPin for BusPin<'_> {
    fn set_low(&mut self) -> Result<(), Infallible> {
        self.set(false);
        Ok(())
    }
    fn set_high(&mut self) -> Result<(), Infallible> {
        self.set(true);
        Ok(())
    }
}

impl BusPin<'_> {
    fn set(&self, high: bool) {
        let mut b = self.bus.get();
        match self.line {
            BusLine::Data(bit) => b.data = (b.data & !(1 << bit)) | u32::from(high) << bit,
            BusLine::Strobe => b.strobe = high,
            BusLine::Decimate => b.decimate = high,
        }
        self.bus.set(b);
    }
}

/// A line the unit drove after the last clock edge (CRDY1, CSTRB4, a pixel bit), as an
/// `embedded-hal` input pin.
pub(crate) struct Level(bool);

impl embedded_hal::digital::ErrorType for Level {
    type Error = Infallible;
}

impl InputPin for Level {
    fn is_high(&mut self) -> Result<bool, Infallible> {
        Ok(self.0)
    }
    fn is_low(&mut self) -> Result<bool, Infallible> {
        Ok(!self.0)
    }
}

/// A unit's port 1 as pins: eight data lines, CSTRB1 and the decimation line on `bus`.
pub(crate) fn port_pins(bus: &Cell<CoordBus>, ready: bool) -> HalCoordinatePins<BusPin<'_>, Level> {
    HalCoordinatePins {
        data: std::array::from_fn(|bit| BusPin { bus, line: BusLine::Data(bit as u8) }),
        strobe: BusPin { bus, line: BusLine::Strobe },
        decimate: BusPin { bus, line: BusLine::Decimate },
        ready: Level(ready),
    }
}

/// A unit's port 4 as pins: the pixel lines and CSTRB4 as the unit drove them.
pub(crate) fn pixel_pins(out: &UnitOutputs) -> HalPixelPins<Level> {
    HalPixelPins { data: std::array::from_fn(|bit| Level(out.pixel_out >> bit & 1 == 1)), strobe: Level(out.pixel_strobe) }
}
