//! rust-hdl's own VCD writer attached to a stepped unit or network ([`super::driver`]): the
//! waveforms the testbench writes (thesis Appendix B's timing, viewed in a waveform viewer).
use rust_hdl::core::vcd_probe::VCDProbe;
use rust_hdl::prelude::*;
use std::cell::RefCell;
use std::io::{self, Write};
use std::rc::Rc;

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

    pub(super) fn sample(&mut self, unit: &dyn Block, half: u64) {
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
