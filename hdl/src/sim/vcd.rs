//! rust-hdl's own VCD writer attached to a stepped unit or network ([`super::driver`]): the
//! waveforms the testbench writes (thesis Appendix B's timing, viewed in a waveform viewer);
//! and a flat VCD of one unit's thesis signals from its recorded flags, for `coopwin waves`.
use crate::window_unit::Flags;
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
struct Latch<T: Write> {
    inner: T,
    error: Rc<RefCell<Option<io::Error>>>,
}

impl<T: Write> Latch<T> {
    /// The writer, and the cell where its first error will be.
    fn new(inner: T) -> (Self, Rc<RefCell<Option<io::Error>>>) {
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

/// One traced signal of [`write_flags_vcd`]: its name in the thesis's spelling (lower case),
/// its width, whether it is an input (drawn changing at the falling edge before the rising edge
/// that samples it), and its value in a record.
struct Traced {
    name: &'static str,
    width: u32,
    input: bool,
    value: fn(&Flags) -> u32,
}

const TRACED: [Traced; 23] = {
    const fn bit(name: &'static str, input: bool, value: fn(&Flags) -> u32) -> Traced {
        Traced { name, width: 1, input, value }
    }
    [
        bit("fval", true, |f| f.fval as u32),
        bit("lval", true, |f| f.lval as u32),
        bit("coord_strobe", true, |f| f.coord_strobe as u32),
        bit("fvc", false, |f| f.fvc as u32),
        bit("lvc", false, |f| f.lvc as u32),
        bit("fvlh", false, |f| f.fvlh as u32),
        bit("fvhl", false, |f| f.fvhl as u32),
        bit("lvhl", false, |f| f.lvhl as u32),
        bit("coord_ready", false, |f| f.coord_ready as u32),
        bit("start", false, |f| f.start as u32),
        bit("wlen", false, |f| f.wlen as u32),
        bit("strben", false, |f| f.strben as u32),
        bit("wlrst", false, |f| f.wlrst as u32),
        Traced { name: "xcount", width: 16, input: false, value: |f| f.xcount },
        Traced { name: "ycount", width: 16, input: false, value: |f| f.ycount },
        bit("xmin", false, |f| f.xmin as u32),
        bit("xmax", false, |f| f.xmax as u32),
        bit("ymin", false, |f| f.ymin as u32),
        bit("ymax", false, |f| f.ymax as u32),
        bit("yval", false, |f| f.yval as u32),
        bit("xyval", false, |f| f.xyval as u32),
        bit("pixel_strobe", false, |f| f.pixel_strobe as u32),
        Traced { name: "pixel_out", width: 16, input: false, value: |f| f.pixel_out.into() },
    ]
};

/// Writes a unit's recorded flags (one record after each rising edge) as a VCD with one scope,
/// `window_unit`, and flat signal names: the pixel clock, the inputs changing half a clock
/// before the edge that samples them, and the thesis's registers and flags changing at the edge.
pub fn write_flags_vcd<W: Write>(mut out: W, rec: &[Flags], period_ps: u64) -> io::Result<()> {
    let code = |k: usize| char::from(b'"' + k as u8);
    writeln!(out, "$timescale 1ps $end\n$scope module window_unit $end")?;
    writeln!(out, "$var wire 1 ! clock $end")?;
    for (k, s) in TRACED.iter().enumerate() {
        writeln!(out, "$var wire {} {} {} $end", s.width, code(k), s.name)?;
    }
    writeln!(out, "$upscope $end\n$enddefinitions $end")?;
    let mut last: Vec<Option<u32>> = vec![None; TRACED.len()];
    let half = period_ps / 2;
    for (t, f) in rec.iter().enumerate() {
        let edge = (t as u64 + 1) * period_ps;
        // Falling edge: the inputs for the coming rising edge.
        writeln!(out, "#{}\n0!", edge - half)?;
        for phase_input in [true, false] {
            if !phase_input {
                writeln!(out, "#{edge}\n1!")?;
            }
            for (k, s) in TRACED.iter().enumerate().filter(|(_, s)| s.input == phase_input) {
                let v = (s.value)(f);
                if last[k] != Some(v) {
                    match s.width {
                        1 => writeln!(out, "{v}{}", code(k))?,
                        _ => writeln!(out, "b{v:b} {}", code(k))?,
                    }
                    last[k] = Some(v);
                }
            }
        }
    }
    out.flush()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reads the flat VCD back with a parser written here from the VCD format: one scope, the
    /// thesis's names, and every value in place, inputs half a clock before the edge.
    #[test]
    fn flat_vcd_holds_each_record_at_its_edge() {
        let rec: Vec<Flags> = (0..6u32)
            .map(|t| Flags { fval: t >= 1, lval: t % 2 == 0, fvc: t >= 2, xcount: t * 3, pixel_out: 700 + t as u16, pixel_strobe: t == 4, ..Flags::default() })
            .collect();
        let mut out = Vec::new();
        write_flags_vcd(&mut out, &rec, 100).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert_eq!(text.matches("$scope").count(), 1);
        let mut names = std::collections::HashMap::new();
        for l in text.lines().filter(|l| l.starts_with("$var")) {
            let f: Vec<&str> = l.split_whitespace().collect();
            names.insert(f[3].to_string(), f[4].to_string());
        }
        assert!(["clock", "fval", "fvc", "xcount", "pixel_out", "pixel_strobe", "strben"].iter().all(|n| names.values().any(|v| v == n)));
        // Replay the changes into a value table sampled at each timestamp.
        let (mut now, mut state) = (0u64, std::collections::HashMap::<String, u32>::new());
        let mut at = std::collections::BTreeMap::<u64, std::collections::HashMap<String, u32>>::new();
        for l in text.lines().skip_while(|l| !l.starts_with("$enddefinitions")).skip(1) {
            if let Some(t) = l.strip_prefix('#') {
                now = t.parse().unwrap();
            } else if let Some(rest) = l.strip_prefix('b') {
                let (v, code) = rest.split_once(' ').unwrap();
                state.insert(names[code].clone(), u32::from_str_radix(v, 2).unwrap());
            } else {
                let (v, code) = l.split_at(1);
                state.insert(names[code].clone(), v.parse().unwrap());
            }
            at.insert(now, state.clone());
        }
        for (t, f) in rec.iter().enumerate() {
            let edge = (t as u64 + 1) * 100;
            let (before, after) = (&at[&(edge - 50)], &at[&edge]);
            assert_eq!((before["clock"], after["clock"]), (0, 1));
            assert_eq!(before["fval"], f.fval as u32, "input set up before edge {t}");
            assert_eq!(before["lval"], f.lval as u32);
            assert_eq!(after["fvc"], f.fvc as u32);
            assert_eq!(after["xcount"], f.xcount);
            assert_eq!(after["pixel_out"], u32::from(f.pixel_out));
            assert_eq!(after["pixel_strobe"], f.pixel_strobe as u32);
        }
    }
}
