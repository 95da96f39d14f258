//! Direct-stepping drivers for long runs of the window logic (thesis 2.2.2, B1.1): inputs are
//! set, the clock toggled and the block settled with rust-hdl's `simulate`, with no threads.
//! rust-hdl's thread-based `Simulation` (kept for the Appendix B timing tests) runs this design
//! at thousands of clocks per second; stepping the block directly runs it at millions.
//!
//! The processor's side of the coordinate port is the firmware's own
//! [`CoordinateWriter`], one [`write_step`] a clock.
use super::camera::{CameraBus, Window};
use super::vcd::VcdTrace;
use crate::window_unit::WindowUnit;
use coopwin_firmware::ports::window::{bound_bytes, CoordinatePins, CoordinateWriter, WriteError};
use rust_hdl::prelude::*;
use std::io::Write;

/// The processor's side of one unit's coordinate port, as driven on one clock.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CoordBus {
    /// CSTRB1.
    pub strobe: bool,
    /// Port 1 data.
    pub data: u32,
    /// Decimation for the set being completed.
    pub decimate: bool,
}

/// A unit's outputs after a rising clock edge.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct UnitOutputs {
    /// CRDY1.
    pub coord_ready: bool,
    /// CSTRB4.
    pub pixel_strobe: bool,
    /// Port 4 data.
    pub pixel_out: u16,
    /// The last complete set was refused.
    pub coord_error: bool,
}

/// Settling iterations allowed per clock phase; the design settles in a handful.
const MAX_SETTLE: usize = 64;

/// rust-hdl's `simulate` loop (update every block until a pass changes nothing), returning
/// the passes it took: they are the cost of a clock.
fn settle<B: Block>(b: &mut B) -> usize {
    (1..=MAX_SETTLE)
        .find(|_| {
            b.update_all();
            !b.has_changed()
        })
        .unwrap_or(MAX_SETTLE)
}

/// A `WindowUnit` stepped one pixel clock at a time.
pub struct UnitDriver<const C: usize, const P: usize> {
    uut: WindowUnit<C, P>,
    passes: u64,
}

impl<const C: usize, const P: usize> Default for UnitDriver<C, P> {
    /// The unit of a 2^C x 2^C sensor.
    fn default() -> Self {
        Self::new(1 << C, 1 << C)
    }
}

impl<const C: usize, const P: usize> UnitDriver<C, P> {
    /// The unit of a `width` x `height` sensor at power-on.
    pub fn new(width: usize, height: usize) -> Self {
        let mut uut = WindowUnit::<C, P>::new(width, height);
        uut.connect_all();
        settle(&mut uut);
        Self { uut, passes: 0 }
    }

    /// The block, for reading its signals.
    pub fn unit(&self) -> &WindowUnit<C, P> {
        &self.uut
    }

    /// Settling passes over the block tree since power-on (both clock phases of every step).
    pub fn passes(&self) -> u64 {
        self.passes
    }

    /// Applies `cam` and `port` with the clock low, takes the rising edge, and returns the
    /// outputs as they are after that edge.
    pub fn step(&mut self, cam: CameraBus, port: CoordBus) -> UnitOutputs {
        self.step_reset(cam, port, false)
    }

    /// [`step`](Self::step) with the unit's synchronous `reset` input driven too.
    pub fn step_reset(&mut self, cam: CameraBus, port: CoordBus, reset: bool) -> UnitOutputs {
        set_inputs(&mut self.uut, cam, port);
        self.uut.reset.next = reset;
        self.uut.reset.update_all();
        self.passes += settle(&mut self.uut) as u64;
        self.rise()
    }

    fn rise(&mut self) -> UnitOutputs {
        set_clock(&mut self.uut, true);
        self.passes += settle(&mut self.uut) as u64;
        outputs(&self.uut)
    }
}

/// Drives a unit's inputs for the next clock, with its clock low.
///
/// The inputs take their new values at once rather than on the first settling pass (nothing
/// inside the block drives them), which saves that pass.
fn set_inputs<const C: usize, const P: usize>(u: &mut WindowUnit<C, P>, cam: CameraBus, port: CoordBus) {
    u.fval.next = cam.fval;
    u.lval.next = cam.lval;
    u.pixel_valid.next = cam.pixel_valid;
    u.pixel.next = (cam.pixel as u64).into();
    u.coord_strobe.next = port.strobe;
    u.coord_data.next = (port.data as u64).into();
    u.decimate.next = port.decimate;
    u.fval.update_all();
    u.lval.update_all();
    u.pixel_valid.update_all();
    u.pixel.update_all();
    u.coord_strobe.update_all();
    u.coord_data.update_all();
    u.decimate.update_all();
    set_clock(u, false);
}

fn set_clock<const C: usize, const P: usize>(u: &mut WindowUnit<C, P>, level: bool) {
    u.clock.next = level.into();
    u.clock.update_all();
}

fn outputs<const C: usize, const P: usize>(u: &WindowUnit<C, P>) -> UnitOutputs {
    UnitOutputs {
        coord_ready: u.coord_ready.val(),
        pixel_strobe: u.pixel_strobe.val(),
        pixel_out: u.pixel_out.val().index() as u16,
        coord_error: u.coord_error.val(),
    }
}

/// Units on one camera bus, each with its own coordinate port (the thesis's network of
/// windowing units, 2.2.2: "additional windowing units operate independently and in parallel"),
/// settled together as one rust-hdl block tree so one VCD can hold them all (`uut$k`).
pub struct NetworkDriver<const C: usize, const P: usize> {
    units: Vec<WindowUnit<C, P>>,
}

impl<const C: usize, const P: usize> NetworkDriver<C, P> {
    /// `n` units of a 2^C x 2^C sensor at power-on.
    pub fn new(n: usize) -> Self {
        Self::for_sensor(n, 1 << C, 1 << C)
    }

    /// `n` units of a `width` x `height` sensor (each at most 2^C) at power-on.
    pub fn for_sensor(n: usize, width: usize, height: usize) -> Self {
        let mut units: Vec<WindowUnit<C, P>> = (0..n).map(|_| WindowUnit::new(width, height)).collect();
        units.connect_all();
        settle(&mut units);
        Self { units }
    }

    /// Number of units.
    pub fn len(&self) -> usize {
        self.units.len()
    }

    /// True when the network has no unit.
    pub fn is_empty(&self) -> bool {
        self.units.is_empty()
    }

    /// One clock: the shared camera bus, unit k's port from `ports[k]`, outputs into `out[k]`.
    pub fn step(&mut self, cam: CameraBus, ports: &[CoordBus], out: &mut [UnitOutputs]) {
        self.apply(cam, ports);
        self.rise(out);
    }

    /// Like [`step`](Self::step), recording both clock phases of every unit into `trace`.
    pub fn step_traced<T: Write>(
        &mut self,
        cam: CameraBus,
        ports: &[CoordBus],
        out: &mut [UnitOutputs],
        trace: &mut VcdTrace<T>,
    ) {
        self.apply(cam, ports);
        trace.sample(&self.units, 0);
        self.rise(out);
        trace.sample(&self.units, 1);
    }

    fn apply(&mut self, cam: CameraBus, ports: &[CoordBus]) {
        for (u, p) in self.units.iter_mut().zip(ports) {
            set_inputs(u, cam, *p);
        }
        settle(&mut self.units);
    }

    fn rise(&mut self, out: &mut [UnitOutputs]) {
        for u in self.units.iter_mut() {
            set_clock(u, true);
        }
        settle(&mut self.units);
        for (o, u) in out.iter_mut().zip(&self.units) {
            *o = outputs(u);
        }
    }

    /// The units, traced as `uut$0`, `uut$1`, ...
    pub fn block(&self) -> &Vec<WindowUnit<C, P>> {
        &self.units
    }
}

/// A network of stepped units of any counter and pixel width, as the testbench steps it (the
/// widths chosen from the sensor by [`network`]).
pub trait SteppedNetwork {
    /// One clock: see [`NetworkDriver::step`].
    fn step(&mut self, cam: CameraBus, ports: &[CoordBus], out: &mut [UnitOutputs]);
    /// One clock, recorded: see [`NetworkDriver::step_traced`].
    fn step_traced(&mut self, cam: CameraBus, ports: &[CoordBus], out: &mut [UnitOutputs], trace: &mut VcdTrace<Box<dyn Write>>);
    /// The units, for a VCD header (`uut$0`, `uut$1`, ...).
    fn block(&self) -> &dyn Block;
}

impl<const C: usize, const P: usize> SteppedNetwork for NetworkDriver<C, P> {
    fn step(&mut self, cam: CameraBus, ports: &[CoordBus], out: &mut [UnitOutputs]) {
        NetworkDriver::step(self, cam, ports, out)
    }
    fn step_traced(&mut self, cam: CameraBus, ports: &[CoordBus], out: &mut [UnitOutputs], trace: &mut VcdTrace<Box<dyn Write>>) {
        NetworkDriver::step_traced(self, cam, ports, out, trace)
    }
    fn block(&self) -> &dyn Block {
        &self.units
    }
}

/// Something done with a unit of chosen counter width `C` and pixel width `P` (a generic
/// closure): the one place [`with_widths`] turns a sensor's geometry into the const widths.
pub trait WidthsVisitor {
    /// What it gives.
    type Out;
    /// Does it with `WindowUnit<C, P>`.
    fn visit<const C: usize, const P: usize>(self) -> Self::Out;
}

/// The rust-hdl widths that carry geometry `g`: counters of 8 bits up to 256x256 and 12 bits
/// beyond (to 4096, the exported module's limit); pixels of 8, 10, 12 or 16 bits, the least
/// that holds `g.pixel_bits`. (The exported Verilog takes the exact widths as parameters; the
/// rust-hdl blocks are const-generic, so a few are instantiated.)
pub fn stepped_widths(g: &crate::verilog::Geometry) -> (usize, usize) {
    let c = if g.counter_bits() <= 8 { 8 } else { 12 };
    let p = [8, 10, 12, 16].into_iter().find(|&p| p >= g.pixel_bits).unwrap_or(16);
    (c, p)
}

/// Runs `v` with the unit widths [`stepped_widths`] picks for `g`.
pub fn with_widths<V: WidthsVisitor>(g: &crate::verilog::Geometry, v: V) -> V::Out {
    match stepped_widths(g) {
        (8, 8) => v.visit::<8, 8>(),
        (8, 10) => v.visit::<8, 10>(),
        (8, 12) => v.visit::<8, 12>(),
        (8, _) => v.visit::<8, 16>(),
        (_, 8) => v.visit::<12, 8>(),
        (_, 10) => v.visit::<12, 10>(),
        (_, 12) => v.visit::<12, 12>(),
        _ => v.visit::<12, 16>(),
    }
}

/// `n` units of sensor `g` at power-on, at the widths [`stepped_widths`] picks.
pub fn network(n: usize, g: &crate::verilog::Geometry) -> Box<dyn SteppedNetwork> {
    struct Make(usize, usize, usize);
    impl WidthsVisitor for Make {
        type Out = Box<dyn SteppedNetwork>;
        fn visit<const C: usize, const P: usize>(self) -> Self::Out {
            Box::new(NetworkDriver::<C, P>::for_sensor(self.0, self.1, self.2))
        }
    }
    with_widths(g, Make(n, g.width, g.height))
}

/// A unit's coordinate port as the firmware's writer sees its pins: CRDY1 as the unit drove it
/// after the last edge, and the bus the writer drives for the next clock.
struct BusPins<'a> {
    ready: bool,
    bus: &'a mut CoordBus,
}

impl CoordinatePins for BusPins<'_> {
    type Error = core::convert::Infallible;

    fn drive(&mut self, strobe: bool, data: u8, decimate: bool) -> Result<(), Self::Error> {
        *self.bus = CoordBus {
            strobe,
            data: data.into(),
            decimate,
        };
        Ok(())
    }

    fn ready(&mut self) -> Result<bool, Self::Error> {
        Ok(self.ready)
    }
}

/// One clock of the processor's side of the coordinate handshake (thesis B1.1 step 1), run by
/// the firmware's [`CoordinateWriter`]: given the unit's outputs after the last edge, what the
/// processor drives on the next clock.
pub fn write_step(writer: &mut CoordinateWriter, last: &UnitOutputs) -> CoordBus {
    let mut bus = CoordBus::default();
    let Ok(()) = writer.poll(&mut BusPins {
        ready: last.coord_ready,
        bus: &mut bus,
    });
    bus
}

/// Queues `w`'s bytes (xmin, xmax, ymin, ymax; two bytes each, high first, when `wide`) on
/// `writer` as they are, valid or not: [`WriteError::OutOfRange`] when a coordinate does not
/// fit its bytes, [`WriteError::QueueFull`] when the writer has no room for the set.
pub fn queue_window(
    writer: &mut CoordinateWriter,
    w: Window,
    decimate: bool,
    wide: bool,
) -> Result<(), WriteError> {
    writer.write_bytes(&bound_bytes(w.bytes(), wide)?, decimate)
}
