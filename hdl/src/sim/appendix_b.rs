//! The window acquisition of Appendix B, run in rust-hdl's `Simulation` (the thread-based
//! simulator, which also writes the VCD): a coordinate set written while FVAL is low, then one
//! frame delivered. Every clock's [`Flags`] are recorded, and the five sequences of the timing
//! diagrams (Figs. B1.1-B1.5) are located in the record for tests and drawings.
use super::camera::{CameraBus, RasterTiming, Window};
use super::driver::{queue_window, write_step, UnitOutputs};
use crate::coord_port::wide_coordinates;
use crate::window_unit::{Flags, WindowUnit};
use coopwin_firmware::ports::window::CoordinateWriter;
use rust_hdl::prelude::*;
use std::sync::{Arc, Mutex};

/// The five sequences of Appendix B.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sequence {
    /// B1.1: coordinates strobed in between frames; START, then WLEN.
    StartFlagSet,
    /// B1.2: FVAL rises; FVLH, STRBEN, the Y count reset, YMIN/YVAL.
    FrameValidRising,
    /// B1.3: LVAL rises on the window's first line; XMIN, XYVAL, the first CSTRB4.
    LineValidRising,
    /// B1.4: LVAL falls at the end of that line; XMAX, LVHL, the last CSTRB4 of the line.
    LineValidFalling,
    /// B1.5: the last line ends and FVAL falls; LVHL, FVHL, WLRST, STRBEN cleared.
    FrameValidFalling,
}

impl Sequence {
    /// All five, in the thesis's order.
    pub const ALL: [Sequence; 5] = [
        Sequence::StartFlagSet,
        Sequence::FrameValidRising,
        Sequence::LineValidRising,
        Sequence::LineValidFalling,
        Sequence::FrameValidFalling,
    ];

    /// The figure it corresponds to and its title.
    pub fn title(&self) -> &'static str {
        match self {
            Sequence::StartFlagSet => "Fig. B1.1 Start Flag Set",
            Sequence::FrameValidRising => "Fig. B1.2 Frame Valid Rising",
            Sequence::LineValidRising => "Fig. B1.3 Line Valid Rising",
            Sequence::LineValidFalling => "Fig. B1.4 Line Valid Falling",
            Sequence::FrameValidFalling => "Fig. B1.5 Frame Valid Falling",
        }
    }

    /// The clocks of `rec` the diagram spans, or `None` if the record lacks the sequence.
    pub fn span(&self, rec: &[Flags]) -> Option<std::ops::Range<usize>> {
        let rise = |f: fn(&Flags) -> bool, from: usize| {
            (from..rec.len()).find(|&t| f(&rec[t]) && (t == 0 || !f(&rec[t - 1])))
        };
        let fall = |f: fn(&Flags) -> bool, from: usize| {
            (from.max(1)..rec.len()).find(|&t| !f(&rec[t]) && f(&rec[t - 1]))
        };
        let around = |a: usize, b: usize| a.saturating_sub(3)..(b + 4).min(rec.len());
        match self {
            Sequence::StartFlagSet => {
                let s = rise(|f| f.coord_strobe, 0)?;
                Some(around(s, rise(|f| f.wlen, s)?))
            }
            Sequence::FrameValidRising => {
                let s = rise(|f| f.fval, 0)?;
                Some(around(s, rise(|f| f.yval, s)?))
            }
            Sequence::LineValidRising => {
                let first = rise(|f| f.pixel_strobe, 0)?;
                let l = (1..first)
                    .rev()
                    .find(|&t| rec[t].lval && !rec[t - 1].lval)?;
                Some(around(l, first + 2))
            }
            Sequence::LineValidFalling => {
                let first = rise(|f| f.pixel_strobe, 0)?;
                let last = fall(|f| f.pixel_strobe, first)?;
                Some(around(last.saturating_sub(4), last))
            }
            Sequence::FrameValidFalling => {
                let s = rise(|f| f.strben, 0)?;
                let end = fall(|f| f.fval, s)?;
                let last_line = (1..end).rev().find(|&t| !rec[t].lval && rec[t - 1].lval)?;
                Some(around(last_line, end + 2))
            }
        }
    }
}

/// Simulates `frames` acquisitions of `window` in rust-hdl's `Simulation`, on a
/// `WindowUnit<C, P>` of a `timing.width` x `timing.height` sensor showing `image` (row-major,
/// `P`-bit pixels). Each frame period starts at the vertical blanking, where the processor
/// writes the set (FVAL low, B1.1 step 1) with the firmware's `CoordinateWriter` for that
/// sensor (eight-byte sets above 256); then the frame streams past, and the run ends two lines
/// into the last blanking. Returns the flags after every rising edge
/// ([`super::vcd::write_flags_vcd`] writes them as a VCD).
pub fn simulate_acquisition<const C: usize, const P: usize>(
    timing: RasterTiming,
    window: Window,
    decimate: bool,
    frames: usize,
    image: Arc<Vec<u16>>,
) -> Result<Vec<Flags>, AcquisitionError> {
    let blank_start = timing.frame_clocks() - timing.v_blank_lines * timing.line_clocks();
    let tail = (blank_start + 2 * timing.line_clocks()).min(timing.frame_clocks());
    // (camera clock within its frame period, the processor writes the set on this clock)
    let mut clocks: Vec<(usize, bool)> = Vec::new();
    for _ in 0..frames {
        clocks.extend((blank_start..timing.frame_clocks()).map(|c| (c, c == blank_start)));
        clocks.extend((0..blank_start).map(|c| (c, false)));
    }
    clocks.extend((blank_start..tail).map(|c| (c, false)));
    let max_time = 125_000 * (clocks.len() as u64 + 16);
    let record = Arc::new(Mutex::new(Vec::with_capacity(clocks.len())));
    let out = record.clone();
    let mut uut = WindowUnit::<C, P>::new(timing.width, timing.height);
    uut.connect_all();
    let mut sim = Simulation::new();
    // 125 000 ps: the CA-D1's 8 MHz pixel clock, toggled every half period.
    sim.add_clock(62_500, |x: &mut Box<WindowUnit<C, P>>| {
        x.clock.next = !x.clock.val()
    });
    let wide = wide_coordinates(timing.width, timing.height);
    let sensor = (timing.width as u16, timing.height as u16);
    sim.add_testbench(move |mut sim: Sim<WindowUnit<C, P>>| {
        let mut x = sim.init()?;
        let mut writer = CoordinateWriter::for_sensor(sensor.0, sensor.1);
        for &(c, write) in &clocks {
            if write {
                queue_window(&mut writer, window, decimate, wide).map_err(|_| SimError::SimPanic)?;
            }
            drive(
                &mut x,
                timing.bus_at(c, |px, py| image[py * timing.width + px]),
            );
            // The firmware's four-phase writer: offers the next byte, drops the strobe once
            // it is taken.
            let bus = write_step(&mut writer, &UnitOutputs { coord_ready: x.coord_ready.val(), ..Default::default() });
            x.coord_strobe.next = bus.strobe;
            x.coord_data.next = u64::from(bus.data).into();
            x.decimate.next = bus.decimate;
            wait_clock_cycle!(sim, clock, x);
            out.lock().map_err(|_| SimError::SimPanic)?.push(x.flags());
        }
        sim.done(x)
    });
    sim.run(Box::new(uut), max_time)?;
    let rec = record.lock().map_err(|_| SimError::SimPanic)?.clone();
    Ok(rec)
}

/// Why an acquisition could not be simulated.
#[derive(Debug)]
pub enum AcquisitionError {
    /// rust-hdl's simulator stopped.
    Sim(SimError),
}

impl From<SimError> for AcquisitionError {
    fn from(e: SimError) -> Self {
        AcquisitionError::Sim(e)
    }
}

impl std::fmt::Display for AcquisitionError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            AcquisitionError::Sim(e) => write!(f, "rust-hdl simulation failed: {e:?}"),
        }
    }
}

impl std::error::Error for AcquisitionError {}

fn drive<const C: usize, const P: usize>(x: &mut WindowUnit<C, P>, cam: CameraBus) {
    x.fval.next = cam.fval;
    x.lval.next = cam.lval;
    x.pixel_valid.next = cam.pixel_valid;
    x.pixel.next = (cam.pixel as u64).into();
}
