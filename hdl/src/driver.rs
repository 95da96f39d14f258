//! Direct-stepping drivers for long runs: inputs are set, the clock toggled and the block
//! settled with rust-hdl's `simulate`, with no threads. rust-hdl's thread-based `Simulation`
//! (kept for the Appendix B timing tests) runs this design at thousands of clocks per second;
//! stepping the block directly runs it at millions.
//!
//! Also here: [`CoordWriter`], the processor's side of the four-phase coordinate handshake,
//! and [`VcdTrace`], rust-hdl's own VCD writer attached to a stepped unit.
use crate::camera::{CameraBus, Window};
use crate::window_unit::WindowUnit;
use rust_hdl::core::vcd_probe::VCDProbe;
use rust_hdl::prelude::*;
use std::cell::RefCell;
use std::collections::VecDeque;
use std::io::{self, Write};
use std::rc::Rc;

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
    pub pixel_out: u8,
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
pub struct UnitDriver<const W: usize> {
    uut: WindowUnit<W>,
    passes: u64,
}

impl<const W: usize> Default for UnitDriver<W> {
    fn default() -> Self {
        let mut uut = WindowUnit::<W>::default();
        uut.connect_all();
        settle(&mut uut);
        Self { uut, passes: 0 }
    }
}

impl<const W: usize> UnitDriver<W> {
    /// The block, for reading its signals.
    pub fn unit(&self) -> &WindowUnit<W> {
        &self.uut
    }

    /// Settling passes over the block tree since power-on (both clock phases of every step).
    pub fn passes(&self) -> u64 {
        self.passes
    }

    /// Applies `cam` and `port` with the clock low, takes the rising edge, and returns the
    /// outputs as they are after that edge.
    pub fn step(&mut self, cam: CameraBus, port: CoordBus) -> UnitOutputs {
        self.apply(cam, port);
        self.rise()
    }

    fn apply(&mut self, cam: CameraBus, port: CoordBus) {
        set_inputs(&mut self.uut, cam, port);
        self.passes += settle(&mut self.uut) as u64;
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
fn set_inputs<const W: usize>(u: &mut WindowUnit<W>, cam: CameraBus, port: CoordBus) {
    u.fval.next = cam.fval;
    u.lval.next = cam.lval;
    u.pixel.next = (cam.pixel as u64).into();
    u.coord_strobe.next = port.strobe;
    u.coord_data.next = (port.data as u64).into();
    u.decimate.next = port.decimate;
    u.fval.update_all();
    u.lval.update_all();
    u.pixel.update_all();
    u.coord_strobe.update_all();
    u.coord_data.update_all();
    u.decimate.update_all();
    set_clock(u, false);
}

fn set_clock<const W: usize>(u: &mut WindowUnit<W>, level: bool) {
    u.clock.next = level.into();
    u.clock.update_all();
}

fn outputs<const W: usize>(u: &WindowUnit<W>) -> UnitOutputs {
    UnitOutputs {
        coord_ready: u.coord_ready.val(),
        pixel_strobe: u.pixel_strobe.val(),
        pixel_out: u.pixel_out.val().index() as u8,
        coord_error: u.coord_error.val(),
    }
}

/// Units on one camera bus, each with its own coordinate port (the thesis's network of
/// windowing units, 2.2.2: "additional windowing units operate independently and in parallel"),
/// settled together as one rust-hdl block tree so one VCD can hold them all (`uut$k`).
pub struct NetworkDriver<const W: usize> {
    units: Vec<WindowUnit<W>>,
}

impl<const W: usize> NetworkDriver<W> {
    /// `n` units at power-on.
    pub fn new(n: usize) -> Self {
        let mut units: Vec<WindowUnit<W>> = (0..n).map(|_| WindowUnit::default()).collect();
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
    pub fn block(&self) -> &Vec<WindowUnit<W>> {
        &self.units
    }
}

/// The processor's side of the coordinate handshake (thesis B1.1 step 1): a queue of coordinate
/// sets written byte by byte, each byte held with CSTRB1 high until CRDY1 answers, then
/// released until CRDY1 falls (four-phase).
#[derive(Clone, Debug, Default)]
pub struct CoordWriter {
    queue: VecDeque<(u32, bool)>,
    bus: CoordBus,
    sets_done: usize,
    bytes_done: usize,
}

impl CoordWriter {
    /// Queues the four bytes of `w` (xmin, xmax, ymin, ymax), decimated or not.
    pub fn write(&mut self, w: Window, decimate: bool) {
        self.queue
            .extend(w.bytes().into_iter().map(|b| (b, decimate)));
    }

    /// True while bytes are queued or a handshake is under way.
    pub fn busy(&self) -> bool {
        !self.queue.is_empty() || self.bus.strobe
    }

    /// Complete sets whose fourth byte has been taken.
    pub fn sets_done(&self) -> usize {
        self.sets_done
    }

    /// What to drive on the next clock, given the unit's outputs after the last edge.
    pub fn next(&mut self, last: &UnitOutputs) -> CoordBus {
        if self.bus.strobe && last.coord_ready {
            self.bus.strobe = false;
            self.bytes_done += 1;
            if self.bytes_done.is_multiple_of(4) {
                self.sets_done += 1;
            }
        } else if !self.bus.strobe && !last.coord_ready {
            if let Some((data, decimate)) = self.queue.pop_front() {
                self.bus = CoordBus {
                    strobe: true,
                    data,
                    decimate,
                };
            }
        }
        self.bus
    }
}

/// Picoseconds per pixel clock in the VCDs the testbench writes (8 MHz).
pub const VCD_CLOCK_PS: u64 = 125_000;

/// rust-hdl's VCD writer on a stepped unit. Write errors do not stop the simulation: the first
/// one is kept and returned by [`finish`](Self::finish).
pub struct VcdTrace<T: Write> {
    probe: Option<VCDProbe<Latch<T>>>,
    error: Rc<RefCell<Option<io::Error>>>,
    period_ps: u64,
    clocks: u64,
}

impl<T: Write> VcdTrace<T> {
    /// A trace of `block`'s signals (a unit's `unit()`, or a network's `block()`) into `out`,
    /// one pixel clock every `period_ps` picoseconds.
    pub fn new(out: T, block: &dyn Block, period_ps: u64) -> Self {
        let (latch, error) = Latch::new(out);
        let probe = write_vcd_header(latch, block);
        Self {
            probe: Some(probe),
            error,
            period_ps,
            clocks: 0,
        }
    }

    fn sample(&mut self, unit: &dyn Block, half: u64) {
        if let Some(mut probe) = self.probe.take() {
            let t = self.clocks * self.period_ps + half * self.period_ps / 2;
            // Errors land in the latch, so this result carries nothing new.
            let _ = probe.timestamp(t);
            self.probe = Some(write_vcd_change(probe, unit));
        }
        self.clocks += half;
    }

    /// A clock not recorded (outside the traced span); later timestamps stay run clocks.
    pub fn skip(&mut self) {
        self.clocks += 1;
    }

    /// Flushes the trace; the first write error, if any.
    pub fn finish(mut self) -> io::Result<()> {
        drop(self.probe.take());
        match self.error.borrow_mut().take() {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }
}

/// A writer that never fails: rust-hdl's VCD writer unwraps every write, so errors are held
/// here instead and reported when the trace finishes.
pub(crate) struct Latch<T: Write> {
    inner: T,
    error: Rc<RefCell<Option<io::Error>>>,
}

impl<T: Write> Latch<T> {
    /// The writer, and the cell where its first error will be.
    pub(crate) fn new(inner: T) -> (Self, Rc<RefCell<Option<io::Error>>>) {
        let error = Rc::new(RefCell::new(None));
        (
            Latch {
                inner,
                error: error.clone(),
            },
            error,
        )
    }

    fn keep(&self, r: io::Result<()>) {
        let mut slot = self.error.borrow_mut();
        if let (Err(e), None) = (r, slot.as_ref()) {
            *slot = Some(e);
        }
    }
}

impl<T: Write> Write for Latch<T> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        if self.error.borrow().is_none() {
            let r = self.inner.write_all(buf);
            self.keep(r);
        }
        Ok(buf.len())
    }

    fn flush(&mut self) -> io::Result<()> {
        let r = self.inner.flush();
        self.keep(r);
        Ok(())
    }
}

impl<T: Write> Drop for Latch<T> {
    fn drop(&mut self) {
        let r = self.inner.flush();
        self.keep(r);
    }
}
