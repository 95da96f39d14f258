//! Where the system's windows come from: the window units on the camera bus, one per processor.
//!
//! - [`ModelBackend`]: the behavioural model of `hdl::WindowUnit`, computed per window (fast):
//!   a set written from clock `t` completes at `t + latency` (the handshake measured on the unit,
//!   `hdl::run::writer_timing`), arms the first frame whose FVAL rises at least 2 clocks later,
//!   one frame per set, the later of two pending sets winning; the window completes on the clock
//!   its last pixel is strobed (one clock after that pixel was on the bus).
//! - [`HdlBackend`]: the units themselves, stepped clock by clock on the camera raster, each
//!   written by the firmware's `window_ports::CoordinateWriter` over the four-phase handshake and
//!   read from `pixel_strobe`/`pixel_out` by its `window_ports::PixelReceiver`, both through
//!   `embedded-hal` pins (`hal_pins`, as on the Cortex-M4 board): the rust-hdl
//!   `WindowUnit`s, or the exported `window_network`
//!   Verilog compiled with Verilator ([`Bank`]).
//!
//! Clock 0 of a run is the start of the vertical blanking before frame 0; frame k's FVAL rises
//! on clock `blank + k * period`.
use crate::system::FrameSource;
use coopwin_firmware::types::{Decimation, WindowRequest};
use coopwin_hdl::sim::camera::{CameraBus, FrameRaster, Jitter, RasterTiming, Window};
use coopwin_firmware::ports::hal_pins::{HalCoordinatePins, HalPixelPins};
use coopwin_firmware::ports::window::{coordinate_bytes, CoordinateWriter, PixelReceiver};
use core::cell::Cell;
use core::convert::Infallible;
use embedded_hal::digital::{InputPin, OutputPin};
use coopwin_hdl::sim::driver::{CoordBus, NetworkDriver, UnitOutputs};
use coopwin_hdl::sim::vcd::VcdTrace;
use std::collections::VecDeque;

/// A window delivered to processor `p`.
#[derive(Clone, Debug, PartialEq)]
pub struct Delivered {
    /// The processor (and unit).
    pub p: usize,
    /// The frame it was cut from.
    pub frame: usize,
    /// The clock its last pixel was strobed.
    pub clock: u64,
    /// The request it answers.
    pub req: WindowRequest,
    /// Its pixels, packed row by row (decimated ones already dropped).
    pub pixels: Vec<u8>,
}

/// A source of windows for the system simulation.
pub trait WindowBackend {
    /// Processor `p` writes `req` from clock `at` on; a window the port cannot carry is refused
    /// (and nothing is written).
    fn request(&mut self, p: usize, req: WindowRequest, at: u64) -> Result<(), String>;
    /// The next window completed on or before clock `until` (earliest first, then by unit),
    /// or `None` once the units have run to `until` without completing one.
    fn next_window(&mut self, until: u64, frames: &mut dyn FrameSource) -> Result<Option<Delivered>, String>;
}

/// Raster geometry in run clocks: where each frame starts, and each frame's raster (with
/// jittered blanking when the run asks for it).
#[derive(Clone, Debug)]
pub struct Clocks {
    /// The camera's nominal raster.
    pub timing: RasterTiming,
    /// Frames in the run.
    pub frames: usize,
    /// Each frame's raster.
    rasters: Vec<FrameRaster>,
    /// Clock on which each frame's FVAL rises, and the end of the last frame.
    starts: Vec<u64>,
}

impl Clocks {
    /// `frames` frames of `timing`, with `jitter`'s extra blanking if any.
    pub fn new(timing: RasterTiming, frames: usize, jitter: Option<Jitter>) -> Self {
        let rasters: Vec<FrameRaster> = (0..frames).map(|k| FrameRaster::new(timing, jitter, k)).collect();
        let blank = (timing.v_blank_lines * timing.line_clocks()) as u64;
        let starts = std::iter::once(blank)
            .chain(rasters.iter().scan(blank, |c, r| {
                *c += r.len() as u64;
                Some(*c)
            }))
            .collect();
        Clocks { timing, frames, rasters, starts }
    }
    /// Clocks a frame period (the mean, with jitter).
    pub fn period(&self) -> u64 {
        match self.frames {
            0 => self.timing.frame_clocks() as u64,
            n => (self.starts[n] - self.starts[0]) / n as u64,
        }
    }
    /// The blanking before frame 0.
    pub fn blank(&self) -> u64 {
        self.starts[0]
    }
    /// Clock on which frame k's FVAL rises (for k past the run, as if it went on unjittered).
    pub fn frame_start(&self, k: usize) -> u64 {
        match self.starts.get(k) {
            Some(&c) => c,
            None => self.starts[self.frames] + (k - self.frames) as u64 * self.timing.frame_clocks() as u64,
        }
    }
    /// The frame whose period holds clock `c` (0 before frame 0).
    pub fn frame_at(&self, c: u64) -> usize {
        let end = self.starts[self.frames];
        if c >= end {
            return self.frames + ((c - end) / self.timing.frame_clocks() as u64) as usize;
        }
        self.starts.partition_point(|&s| s <= c).saturating_sub(1)
    }
    /// The first frame whose FVAL rises on or after clock `c`.
    pub fn first_frame_from(&self, c: u64) -> usize {
        let end = self.starts[self.frames];
        if c > end {
            return self.frames + (c - end).div_ceil(self.timing.frame_clocks() as u64) as usize;
        }
        self.starts.partition_point(|&s| s < c)
    }
    /// The first clock at or after `c` that lies `phase` clocks after a frame's FVAL rising.
    pub fn next_phase(&self, c: u64, phase: u64) -> u64 {
        let k = self.frame_at(c);
        let t = self.frame_start(k) + phase;
        if t >= c {
            t
        } else {
            self.frame_start(k + 1) + phase
        }
    }
    /// The camera bus on run clock `c`, with frame `k`'s pixels when `c` falls in frame `k`'s
    /// period, and that frame.
    fn bus(&self, c: u64, frame: Option<(usize, &[u8])>) -> (CameraBus, Option<usize>) {
        let b = self.blank();
        if c < b {
            // The blanking lines of the frame before the run.
            let p = self.timing.frame_clocks() as u64;
            return (self.timing.bus_at((p - b + c) as usize, |_, _| 0), None);
        }
        let Some((k, pixels)) = frame else { return (CameraBus::default(), None) };
        let Some(raster) = self.rasters.get(k) else { return (CameraBus::default(), None) };
        let w = self.timing.width;
        let r = (c - self.frame_start(k)) as usize;
        (raster.bus_at(r, |x, y| pixels.get(y * w + x).copied().unwrap_or(0)), Some(k))
    }
    /// Clocks from frame k's FVAL rising to the clock the window's last pixel is strobed.
    fn last_strobe(&self, k: usize, req: &WindowRequest) -> u64 {
        let (w, h) = delivered_extent(req);
        let x = usize::from(req.x0) + w as usize - 1;
        let y = usize::from(req.y0) + h as usize - 1;
        // The unit strobes a pixel one clock after it is on the bus.
        self.rasters.get(k).map_or(0, |r| r.pixel_clock(x, y)) as u64 + 1
    }
}

/// Columns and rows spanned from the window's first to its last delivered pixel.
fn delivered_extent(req: &WindowRequest) -> (u64, u64) {
    let (w, h) = (u64::from(req.width), u64::from(req.height));
    match req.decimation {
        Decimation::Full => (w, h),
        // The last delivered pixel is the last one an even distance from xmin (and ymin).
        Decimation::Quarter => ((w - 1) / 2 * 2 + 1, (h - 1) / 2 * 2 + 1),
    }
}

/// The window unit's coordinates for a request.
pub fn window_of(req: &WindowRequest) -> Window {
    Window {
        xmin: u32::from(req.x0),
        xmax: u32::from(req.x0) + u32::from(req.width) - 1,
        ymin: u32::from(req.y0),
        ymax: u32::from(req.y0) + u32::from(req.height) - 1,
    }
}

fn crop(req: &WindowRequest, frame: &[u8], width: usize) -> Vec<u8> {
    window_of(req).crop(frame, width, req.decimation == Decimation::Quarter)
}

/// A unit's sets as the model tracks them.
#[derive(Clone, Debug, Default)]
struct UnitSets {
    /// Completion clock of the last set written (the writer's pacing).
    last_complete: Option<u64>,
    /// Sets written but not yet armed: (completion clock, request), latest last.
    pending: Vec<(u64, WindowRequest)>,
}

/// The behavioural window unit model (see the module docs).
pub struct ModelBackend {
    clocks: Clocks,
    units: Vec<UnitSets>,
    latency: u64,
    repeat: u64,
}

impl ModelBackend {
    /// `n` units on the raster.
    pub fn new(clocks: Clocks, n: usize) -> Self {
        let (latency, repeat) = coopwin_hdl::sim::run::writer_timing();
        ModelBackend { clocks, units: vec![UnitSets::default(); n], latency: latency as u64, repeat: repeat as u64 }
    }

    /// The window a unit's pending sets give: (frame, completion clock, request).
    fn armed(&self, u: &UnitSets) -> Option<(usize, u64, WindowRequest, usize)> {
        let first = u.pending.first()?;
        // The first frame whose FVAL rises `ARM_MARGIN` clocks after the first pending set completes.
        let k = self.clocks.first_frame_from(first.0 + coopwin_hdl::ARM_MARGIN as u64);
        let start = self.clocks.frame_start(k);
        // Of the sets complete by then, the latest wins.
        let idx = u.pending.iter().rposition(|s| s.0 + coopwin_hdl::ARM_MARGIN as u64 <= start)?;
        let req = u.pending[idx].1;
        (k < self.clocks.frames).then(|| (k, start + self.clocks.last_strobe(k, &req), req, idx))
    }
}

impl WindowBackend for ModelBackend {
    fn request(&mut self, p: usize, req: WindowRequest, at: u64) -> Result<(), String> {
        if req.width == 0 || req.height == 0 {
            return Err(format!("processor {p}: the empty window {req:?} cannot be written"));
        }
        let (latency, repeat) = (self.latency, self.repeat);
        if let Some(u) = self.units.get_mut(p) {
            // Back-to-back sets queue in the writer, one every `repeat` clocks.
            let done = match u.last_complete {
                Some(prev) if at + latency < prev + repeat => prev + repeat,
                _ => at + latency,
            };
            u.last_complete = Some(done);
            // The unit refuses an invalid set: it arms nothing and cancels nothing.
            if window_of(&req).is_valid() {
                u.pending.push((done, req));
            }
        }
        Ok(())
    }

    fn next_window(&mut self, until: u64, frames: &mut dyn FrameSource) -> Result<Option<Delivered>, String> {
        let best = (0..self.units.len())
            .filter_map(|p| self.armed(&self.units[p]).map(|a| (a.1, p, a)))
            .filter(|(c, _, _)| *c <= until)
            .min_by_key(|(c, p, _)| (*c, *p));
        let Some((clock, p, (frame, _, req, idx))) = best else { return Ok(None) };
        self.units[p].pending.drain(..=idx);
        let width = frames.size().0;
        let pixels = crop(&req, frames.frame(frame)?, width);
        Ok(Some(Delivered { p, frame, clock, req, pixels }))
    }
}

/// The units themselves: rust-hdl blocks, or the Verilator model of the exported Verilog.
pub enum Bank {
    /// One rust-hdl `WindowUnit` per processor, stepped directly.
    RustHdl(NetworkDriver<{ coopwin_hdl::CA_D1_BITS }>),
    /// `window_network` compiled with Verilator (4 units; unused ones idle).
    Verilator(crate::verilator::VerilatorNetwork),
}

/// One line of a unit's simulated coordinate bus as an `embedded-hal` output pin: the
/// firmware's writer drives the rust-hdl or Verilator unit through
/// [`HalCoordinatePins`], the same driver code as on the Cortex-M4 board (`firmware/board`).
struct BusPin<'a> {
    bus: &'a Cell<CoordBus>,
    line: BusLine,
}

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
struct Level(bool);

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
fn port_pins(bus: &Cell<CoordBus>, ready: bool) -> HalCoordinatePins<BusPin<'_>, Level> {
    HalCoordinatePins {
        data: std::array::from_fn(|bit| BusPin { bus, line: BusLine::Data(bit as u8) }),
        strobe: BusPin { bus, line: BusLine::Strobe },
        decimate: BusPin { bus, line: BusLine::Decimate },
        ready: Level(ready),
    }
}

/// One unit's writer and what it is delivering.
struct HdlUnit {
    /// The processor's writer: the firmware's, on simulated pins.
    writer: CoordinateWriter,
    last: UnitOutputs,
    /// Requests not yet handed to the writer: (clock, request).
    queued: VecDeque<(u64, WindowRequest)>,
    /// Requests handed to the writer, in order; sets complete in that order.
    written: VecDeque<WindowRequest>,
    /// Completed sets not yet armed: (completion clock, request).
    complete: Vec<(u64, WindowRequest)>,
    /// The set armed for the frame in progress: its frame, request, pixel buffer, and the
    /// firmware's receiver storing the strobed pixels into it.
    active: Option<(usize, WindowRequest, Vec<u8>, PixelReceiver)>,
    ready_rises: usize,
}

/// A VCD to write: where, and which frames.
pub struct Trace {
    /// The VCD's destination.
    pub out: Box<dyn std::io::Write>,
    /// Frames to record (each from the blanking before it).
    pub frames: std::ops::Range<usize>,
}

/// Window units simulated clock by clock, rust-hdl or Verilator (see the module docs).
pub struct HdlBackend {
    clocks: Clocks,
    bank: Bank,
    units: Vec<HdlUnit>,
    ports: Vec<CoordBus>,
    outs: Vec<UnitOutputs>,
    clock: u64,
    /// The frame on the bus: its number and pixels.
    frame: Option<(usize, Vec<u8>)>,
    /// The clock the next frame's FVAL rises (when `frame` is replaced).
    next_frame_at: u64,
    done: VecDeque<Delivered>,
    trace: Option<VcdTrace<Box<dyn std::io::Write>>>,
    /// Clocks the trace records: from the blanking before its first frame to the end of its
    /// last.
    trace_span: std::ops::Range<u64>,
    /// Recording has begun (on the first quiet clock of the span).
    trace_on: bool,
    /// FVAL rising of the first traced frame.
    trace_first: u64,
    /// Per unit, the sets taken before the trace started (the audit starts after them).
    pub sets_before_trace: Vec<usize>,
    /// Pixel clocks stepped, for speed reports.
    pub clocks_stepped: u64,
    /// Wall time spent inside the simulator (the bank's steps, sampled every 16th clock), for
    /// speed reports.
    pub sim_time: std::time::Duration,
}

impl HdlBackend {
    /// `n` units at power-on in `bank`; with `trace` (rust-hdl only), every unit's signals go
    /// into a VCD (scopes `uut$0`, `uut$1`, ...) for the frames in its range.
    pub fn new(clocks: Clocks, n: usize, bank: Bank, trace: Option<Trace>) -> Result<Self, String> {
        if let Bank::Verilator(_) = bank {
            if n > crate::verilator::UNITS {
                return Err(format!("the Verilator network has {} units, the strategy needs {n}", crate::verilator::UNITS));
            }
            if trace.is_some() {
                return Err("--vcd records the rust-hdl units (--hdl rust-hdl)".into());
            }
        }
        let units: Vec<HdlUnit> = (0..n)
            .map(|_| HdlUnit {
                writer: CoordinateWriter::new(),
                last: UnitOutputs::default(),
                queued: VecDeque::new(),
                written: VecDeque::new(),
                complete: Vec::new(),
                active: None,
                ready_rises: 0,
            })
            .collect();
        let (mut trace_span, mut trace_first) = (0..0, 0);
        let blank = clocks.blank();
        let trace = match (trace, &bank) {
            (Some(t), Bank::RustHdl(net)) => {
                if t.frames.start >= t.frames.end || t.frames.end > clocks.frames {
                    return Err(format!(
                        "VCD frames {}..{}: the run has frames 0..{}",
                        t.frames.start, t.frames.end, clocks.frames
                    ));
                }
                // From inside the vertical blanking before the first frame (no window under
                // way), on a clock with no set half-written, so the units' state at the first
                // sample is just their pending set (which the VCD holds).
                trace_first = clocks.frame_start(t.frames.start);
                trace_span = trace_first.saturating_sub(clocks.blank())..clocks.frame_start(t.frames.end);
                Some(VcdTrace::new(t.out, net.block(), coopwin_hdl::sim::vcd::VCD_CLOCK_PS))
            }
            _ => None,
        };
        Ok(HdlBackend {
            clocks,
            bank,
            units,
            ports: vec![CoordBus::default(); n],
            outs: vec![UnitOutputs::default(); n],
            clock: 0,
            frame: None,
            next_frame_at: blank,
            done: VecDeque::new(),
            trace,
            trace_span,
            trace_on: false,
            trace_first,
            sets_before_trace: vec![0; n],
            clocks_stepped: 0,
            sim_time: std::time::Duration::ZERO,
        })
    }

    /// `n` rust-hdl units.
    pub fn rust_hdl(clocks: Clocks, n: usize, trace: Option<Trace>) -> Result<Self, String> {
        Self::new(clocks, n, Bank::RustHdl(NetworkDriver::new(n)), trace)
    }

    /// Flushes the VCD, if any.
    pub fn finish(&mut self) -> Result<(), String> {
        match self.trace.take() {
            Some(t) => t.finish().map_err(|e| format!("cannot write the VCD: {e}")),
            None => Ok(()),
        }
    }

    fn step(&mut self, frames: &mut dyn FrameSource) -> Result<(), String> {
        let c = self.clock;
        if c >= self.next_frame_at {
            let k = self.clocks.frame_at(c);
            (self.frame, self.next_frame_at) = match k < self.clocks.frames {
                true => (Some((k, frames.frame(k)?.to_vec())), self.clocks.frame_start(k + 1)),
                false => (None, u64::MAX),
            };
        }
        let (bus, bus_frame) = self.clocks.bus(c, self.frame.as_ref().map(|(k, px)| (*k, px.as_slice())));
        let frame_rises = bus_frame.is_some() && Some(c) == bus_frame.map(|k| self.clocks.frame_start(k));
        for (u, port) in self.units.iter_mut().zip(self.ports.iter_mut()) {
            // Handed to the processor's writer as it has room (a full queue waits a clock).
            while let Some(&(at, req)) = u.queued.front() {
                if at > c || u.writer.write(&req).is_err() {
                    break;
                }
                u.queued.pop_front();
                u.written.push_back(req);
            }
            if frame_rises {
                // Which set the hardware arms: mirrored only to know the window's shape.
                let valid = |s: &(u64, WindowRequest)| s.0 + coopwin_hdl::ARM_MARGIN as u64 <= c && window_of(&s.1).is_valid();
                if let Some(idx) = u.complete.iter().rposition(valid) {
                    let req = u.complete[idx].1;
                    u.complete.drain(..=idx);
                    let (w, h) = req.delivered_size();
                    u.active = bus_frame.map(|k| (k, req, vec![0; w * h], PixelReceiver::expect(&req)));
                }
            }
            let bus = Cell::new(*port);
            let Ok(()) = u.writer.poll(&mut port_pins(&bus, u.last.coord_ready));
            *port = bus.get();
        }
        // Every 16th step is timed (and counted 16 times): timing every clock would itself
        // cost a third of a Verilator step.
        let started = c.is_multiple_of(16).then(std::time::Instant::now);
        match &mut self.bank {
            Bank::RustHdl(net) => match &mut self.trace {
                Some(t) if self.trace_span.contains(&c) => {
                    if !self.trace_on {
                        // Quiet: no set part-taken, and CRDY1 low, so a set completed before
                        // is already in the set registers (CRDY1 falls two clocks after those
                        // load) and every later byte's CRDY1 rise is in the trace.
                        let quiet = self.units.iter().all(|u| u.ready_rises % 4 == 0 && !u.last.coord_ready);
                        // Should no quiet clock come, the audit reports the half-written set.
                        self.trace_on = quiet || c + 2 >= self.trace_first;
                        for (before, u) in self.sets_before_trace.iter_mut().zip(&self.units) {
                            *before = u.ready_rises / 4;
                        }
                    }
                    match self.trace_on {
                        true => net.step_traced(bus, &self.ports, &mut self.outs, t),
                        false => {
                            t.skip();
                            net.step(bus, &self.ports, &mut self.outs)
                        }
                    }
                }
                Some(t) => {
                    t.skip();
                    net.step(bus, &self.ports, &mut self.outs)
                }
                None => net.step(bus, &self.ports, &mut self.outs),
            },
            Bank::Verilator(v) => v.step(bus, &self.ports, &mut self.outs),
        }
        if let Some(t) = started {
            self.sim_time += t.elapsed() * 16;
        }
        for (p, (u, out)) in self.units.iter_mut().zip(self.outs.iter().copied()).enumerate() {
            if out.coord_ready && !u.last.coord_ready {
                u.ready_rises += 1;
                if u.ready_rises % 4 == 0 {
                    if let Some(req) = u.written.pop_front() {
                        u.complete.push((c, req));
                    }
                }
            }
            u.last = out;
            if out.pixel_strobe {
                let Some((k, req, px, rx)) = &mut u.active else {
                    return Err(format!("unit {p} strobed a pixel on clock {c} with no window armed"));
                };
                // Port 4 through embedded-hal input pins, as on the board.
                let mut pins = HalPixelPins {
                    data: std::array::from_fn(|bit| Level(out.pixel_out >> bit & 1 == 1)),
                    strobe: Level(out.pixel_strobe),
                };
                if pins.poll(rx, px).map_err(|e| format!("unit {p}, clock {c}: {e:?}"))? {
                    self.done.push_back(Delivered { p, frame: *k, clock: c, req: *req, pixels: std::mem::take(px) });
                    u.active = None;
                }
            }
        }
        self.clock += 1;
        self.clocks_stepped += 1;
        Ok(())
    }
}

impl WindowBackend for HdlBackend {
    fn request(&mut self, p: usize, req: WindowRequest, at: u64) -> Result<(), String> {
        coordinate_bytes(&req).map_err(|e| format!("processor {p}: window {req:?} cannot be written: {e}"))?;
        if let Some(u) = self.units.get_mut(p) {
            u.queued.push_back((at, req));
        }
        Ok(())
    }

    fn next_window(&mut self, until: u64, frames: &mut dyn FrameSource) -> Result<Option<Delivered>, String> {
        // Nothing is delivered after the last frame period.
        let end = self.clocks.frame_start(self.clocks.frames);
        while self.done.is_empty() && self.clock <= until.min(end) {
            self.step(frames)?;
        }
        Ok(self.done.pop_front())
    }
}
