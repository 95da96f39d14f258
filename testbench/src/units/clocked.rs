//! The window units stepped clock by clock on the camera raster: the rust-hdl `WindowUnit`s, or
//! the exported `window_network` Verilog compiled with Verilator ([`UnitSimulator`]). Each unit
//! is written by the firmware's `window_ports::CoordinateWriter` over the four-phase handshake
//! and read from `pixel_strobe`/`pixel_out` by its `window_ports::PixelReceiver`, both through
//! `embedded-hal` pins ([`super::pins`]), as on the Cortex-M4 board.
//!
//! The units are built for the frames' geometry ([`Geometry`]): the writer sends eight-byte
//! sets when the frame is wider or taller than 256 (the firmware's `for_sensor`, the same rule
//! as the hardware's), and a unit of `pixel_bits` > 8 takes each 8-bit frame pixel scaled to
//! its top bits (`v << (pixel_bits - 8)`, as a wider sensor would see the scene) while the
//! processor's 8-bit port 4 is wired to the unit's top 8 pixel lines; so every width delivers
//! the pixels the behavioural model does.
use super::clocks::Clocks;
use super::pins::{pixel_pins, port_pins};
use super::{window_of, Delivered, RequestRefused, UnitError, UnitStats, WindowUnits};
use crate::frames::FrameSource;
use coopwin_firmware::types::{Decimation, WindowRequest};
use coopwin_firmware::ports::window::{bound_bytes, wide_coordinates, CoordinateSet, CoordinateWriter, PixelReceiver, WriteError};
use coopwin_hdl::sim::camera::CameraBus;
use coopwin_hdl::sim::driver::{network, CoordBus, SteppedNetwork, UnitOutputs};
use coopwin_hdl::sim::vcd::VcdTrace;
use coopwin_hdl::sim::verilator::{self, VerilatorNetwork};
use coopwin_hdl::verilog::Geometry;
use core::cell::Cell;
use std::collections::VecDeque;

/// The units' simulator: rust-hdl blocks, or the Verilator model of the exported Verilog.
pub enum UnitSimulator {
    /// One rust-hdl `WindowUnit` per processor, stepped directly (at the widths
    /// `coopwin_hdl::sim::driver::stepped_widths` picks for the geometry).
    RustHdl(Box<dyn SteppedNetwork>),
    /// `window_network` compiled with Verilator (4 units; unused ones idle).
    Verilator(VerilatorNetwork),
}

/// The window a unit is delivering: its frame, request, pixel buffer, and the firmware's
/// receiver storing the strobed pixels into it.
struct Acquisition {
    frame: usize,
    req: WindowRequest,
    pixels: Vec<u8>,
    receiver: PixelReceiver,
}

/// One unit's writer and what it is delivering.
struct ClockedUnit {
    /// The processor's writer: the firmware's, on simulated pins.
    writer: CoordinateWriter,
    last: UnitOutputs,
    /// Requests not yet handed to the writer: (clock, request).
    queued: VecDeque<(u64, WindowRequest)>,
    /// Requests handed to the writer, in order; sets complete in that order.
    written: VecDeque<WindowRequest>,
    /// Completed sets not yet armed: (completion clock, request).
    complete: Vec<(u64, WindowRequest)>,
    /// The set armed for the frame in progress.
    active: Option<Acquisition>,
    ready_rises: usize,
}

impl ClockedUnit {
    /// A unit of sensor `g` at power-on, with the firmware's writer for that sensor.
    fn new(g: &Geometry) -> Self {
        ClockedUnit {
            writer: CoordinateWriter::for_sensor(g.width as u16, g.height as u16),
            last: UnitOutputs::default(),
            queued: VecDeque::new(),
            written: VecDeque::new(),
            complete: Vec::new(),
            active: None,
            ready_rises: 0,
        }
    }
}

/// A VCD to write: where, and which frames.
pub struct Trace {
    /// The VCD's destination.
    pub out: Box<dyn std::io::Write>,
    /// Frames to record (each from the blanking before it).
    pub frames: std::ops::Range<usize>,
}

/// The VCD being recorded, and the clocks it covers.
struct Recording {
    vcd: VcdTrace<Box<dyn std::io::Write>>,
    /// Clocks the trace records: from the blanking before its first frame to the end of its
    /// last.
    span: std::ops::Range<u64>,
    /// Recording has begun (on the first quiet clock of the span).
    on: bool,
    /// FVAL rising of the first traced frame.
    first: u64,
}

/// Window units simulated clock by clock, rust-hdl or Verilator (see the module docs).
pub struct ClockedUnits {
    clocks: Clocks,
    /// The units' sensor: the frames' size and the unit's pixel width.
    geometry: Geometry,
    simulator: UnitSimulator,
    units: Vec<ClockedUnit>,
    ports: Vec<CoordBus>,
    outs: Vec<UnitOutputs>,
    clock: u64,
    /// The frame on the bus: its number and pixels.
    frame: Option<(usize, Vec<u8>)>,
    /// The clock the next frame's FVAL rises (when `frame` is replaced).
    next_frame_at: u64,
    done: VecDeque<Delivered>,
    recording: Option<Recording>,
    /// Per unit, the sets taken before the trace started (the audit starts after them).
    sets_before_trace: Vec<usize>,
    /// Pixel clocks stepped, for speed reports.
    clocks_stepped: u64,
    /// Wall time spent inside the simulator (sampled every 16th clock), for speed reports.
    sim_time: std::time::Duration,
}

impl ClockedUnits {
    /// `n` units of sensor `geometry` (the frames' size, see [`Self::geometry`]) at power-on in
    /// `simulator`; with `trace` (rust-hdl only), every unit's signals go into a VCD (scopes
    /// `uut$0`, `uut$1`, ...) for the frames in its range.
    pub fn new(clocks: Clocks, geometry: Geometry, n: usize, simulator: UnitSimulator, trace: Option<Trace>) -> Result<Self, UnitError> {
        if let UnitSimulator::Verilator(_) = simulator {
            if n > verilator::UNITS {
                return Err(UnitError::TooFewVerilatorUnits { have: verilator::UNITS, need: n });
            }
            if trace.is_some() {
                return Err(UnitError::VerilatorNotTraced);
            }
        }
        let recording = match (trace, &simulator) {
            (Some(t), UnitSimulator::RustHdl(net)) => {
                if t.frames.start >= t.frames.end || t.frames.end > clocks.frames {
                    return Err(UnitError::TraceFrames { frames: t.frames, run: clocks.frames });
                }
                // From inside the vertical blanking before the first frame (no window under
                // way), on a clock with no set half-written, so the units' state at the first
                // sample is just their pending set (which the VCD holds).
                let first = clocks.frame_start(t.frames.start);
                let span = first.saturating_sub(clocks.blank())..clocks.frame_start(t.frames.end);
                let vcd = VcdTrace::new(t.out, net.block(), coopwin_hdl::sim::vcd::VCD_CLOCK_PS);
                Some(Recording { vcd, span, on: false, first })
            }
            _ => None,
        };
        let next_frame_at = clocks.blank();
        Ok(ClockedUnits {
            clocks,
            geometry,
            simulator,
            units: (0..n).map(|_| ClockedUnit::new(&geometry)).collect(),
            ports: vec![CoordBus::default(); n],
            outs: vec![UnitOutputs::default(); n],
            clock: 0,
            frame: None,
            next_frame_at,
            done: VecDeque::new(),
            recording,
            sets_before_trace: vec![0; n],
            clocks_stepped: 0,
            sim_time: std::time::Duration::ZERO,
        })
    }

    /// The sensor of units for `clocks`' frames with `pixel_bits`-bit pixels (refused outside
    /// what `coopwin verilog` exports: 16 to 4096 pixels a side, 8 to 16 bits).
    pub fn geometry(clocks: &Clocks, pixel_bits: usize) -> Result<Geometry, UnitError> {
        let (w, h) = (clocks.timing.width, clocks.timing.height);
        Geometry::new(w, h, pixel_bits).map_err(|reason| UnitError::Geometry { width: w, height: h, reason })
    }

    /// `n` rust-hdl units of `pixel_bits`-bit pixels for `clocks`' frames.
    pub fn rust_hdl(clocks: Clocks, pixel_bits: usize, n: usize, trace: Option<Trace>) -> Result<Self, UnitError> {
        let g = Self::geometry(&clocks, pixel_bits)?;
        Self::new(clocks, g, n, UnitSimulator::RustHdl(network(n, &g)), trace)
    }

    /// `n` Verilator units (the exported network compiled at the geometry) of
    /// `pixel_bits`-bit pixels for `clocks`' frames.
    pub fn verilator(clocks: Clocks, pixel_bits: usize, n: usize) -> Result<Self, UnitError> {
        let g = Self::geometry(&clocks, pixel_bits)?;
        Self::new(clocks, g, n, UnitSimulator::Verilator(VerilatorNetwork::new(&g)?), None)
    }

    /// Bits a frame's 8-bit pixel is shifted up by on the bus (and the unit's output down by
    /// on port 4).
    fn pixel_shift(&self) -> u32 {
        self.geometry.pixel_bits as u32 - 8
    }

    /// One pixel clock: the frame on the bus, the writers, the simulator, the units' outputs.
    fn step(&mut self, frames: &mut dyn FrameSource) -> Result<(), UnitError> {
        let c = self.clock;
        if c >= self.next_frame_at {
            let k = self.clocks.frame_at(c);
            (self.frame, self.next_frame_at) = match k < self.clocks.frames {
                true => (Some((k, frames.frame(k)?.to_vec())), self.clocks.frame_start(k + 1)),
                false => (None, u64::MAX),
            };
        }
        let (mut bus, bus_frame) = self.clocks.bus(c, self.frame.as_ref().map(|(k, px)| (*k, px.as_slice())));
        bus.pixel <<= self.pixel_shift();
        let frame_rises = bus_frame.is_some() && Some(c) == bus_frame.map(|k| self.clocks.frame_start(k));
        self.drive_ports(c, frame_rises.then_some(bus_frame).flatten());
        // Every 16th step is timed (and counted 16 times): timing every clock would itself
        // cost a third of a Verilator step.
        let started = c.is_multiple_of(16).then(std::time::Instant::now);
        self.simulate(c, bus);
        if let Some(t) = started {
            self.sim_time += t.elapsed() * 16;
        }
        self.read_outputs(c)?;
        self.clock += 1;
        self.clocks_stepped += 1;
        Ok(())
    }

    /// The writers on clock `c`: queued requests handed over as they have room, the set armed
    /// when frame `rising`'s FVAL rises, one handshake step on each port.
    fn drive_ports(&mut self, c: u64, rising: Option<usize>) {
        for (u, port) in self.units.iter_mut().zip(self.ports.iter_mut()) {
            // Handed to the processor's writer as it has room (a full queue waits a clock).
            while let Some(&(at, req)) = u.queued.front() {
                if at > c || write_on_link(&mut u.writer, &req).is_err() {
                    break;
                }
                u.queued.pop_front();
                u.written.push_back(req);
            }
            if let Some(frame) = rising {
                // Which set the hardware arms: mirrored only to know the window's shape.
                let valid = |s: &(u64, WindowRequest)| s.0 + coopwin_hdl::ARM_MARGIN as u64 <= c && window_of(&s.1).is_valid();
                if let Some(idx) = u.complete.iter().rposition(valid) {
                    let req = u.complete[idx].1;
                    u.complete.drain(..=idx);
                    let (w, h) = req.delivered_size();
                    u.active = Some(Acquisition { frame, req, pixels: vec![0; w * h], receiver: PixelReceiver::expect(&req) });
                }
            }
            let bus = Cell::new(*port);
            let Ok(()) = u.writer.poll(&mut port_pins(&bus, u.last.coord_ready));
            *port = bus.get();
        }
    }

    /// The simulator's step on clock `c`, traced when the clock is in the VCD's span.
    fn simulate(&mut self, c: u64, bus: CameraBus) {
        match &mut self.simulator {
            UnitSimulator::RustHdl(net) => match &mut self.recording {
                Some(r) if r.span.contains(&c) => {
                    if !r.on {
                        // Quiet: no set part-taken, and CRDY1 low, so a set completed before
                        // is already in the set registers (CRDY1 falls two clocks after those
                        // load) and every later byte's CRDY1 rise is in the trace.
                        let quiet = self.units.iter().all(|u| u.ready_rises.is_multiple_of(u.writer.set_len()) && !u.last.coord_ready);
                        // Should no quiet clock come, the audit reports the half-written set.
                        r.on = quiet || c + 2 >= r.first;
                        for (before, u) in self.sets_before_trace.iter_mut().zip(&self.units) {
                            *before = u.ready_rises / u.writer.set_len();
                        }
                    }
                    match r.on {
                        true => net.step_traced(bus, &self.ports, &mut self.outs, &mut r.vcd),
                        false => {
                            r.vcd.skip();
                            net.step(bus, &self.ports, &mut self.outs)
                        }
                    }
                }
                Some(r) => {
                    r.vcd.skip();
                    net.step(bus, &self.ports, &mut self.outs)
                }
                None => net.step(bus, &self.ports, &mut self.outs),
            },
            UnitSimulator::Verilator(v) => v.step(bus, &self.ports, &mut self.outs),
        }
    }

    /// The units' outputs after clock `c`: completed sets (the CRDY1 rise of each set's last byte, the fourth or the eighth) and strobed
    /// pixels, a window delivered once whole.
    fn read_outputs(&mut self, c: u64) -> Result<(), UnitError> {
        let shift = self.pixel_shift();
        for (unit, (u, out)) in self.units.iter_mut().zip(self.outs.iter().copied()).enumerate() {
            if out.coord_ready && !u.last.coord_ready {
                u.ready_rises += 1;
                if u.ready_rises.is_multiple_of(u.writer.set_len()) {
                    if let Some(req) = u.written.pop_front() {
                        u.complete.push((c, req));
                    }
                }
            }
            u.last = out;
            if out.pixel_strobe {
                let Some(a) = &mut u.active else {
                    return Err(UnitError::StrobeWithoutWindow { unit, clock: c });
                };
                // Port 4 through embedded-hal input pins, as on the board: the unit's top 8
                // pixel lines.
                let whole = pixel_pins(&UnitOutputs { pixel_out: out.pixel_out >> shift, ..out })
                    .poll(&mut a.receiver, &mut a.pixels)
                    .map_err(|error| UnitError::Receive { unit, clock: c, error })?;
                if whole {
                    let pixels = std::mem::take(&mut a.pixels);
                    self.done.push_back(Delivered { unit, frame: a.frame, clock: c, req: a.req, pixels });
                    u.active = None;
                }
            }
        }
        Ok(())
    }
}

impl WindowUnits for ClockedUnits {
    fn request(&mut self, unit: usize, req: WindowRequest, at: u64) -> Result<(), RequestRefused> {
        let wide = wide_coordinates(self.geometry.width, self.geometry.height);
        link_set(&req, wide).map_err(|reason| RequestRefused::Unwritable { unit, req, reason })?;
        if let Some(u) = self.units.get_mut(unit) {
            u.queued.push_back((at, req));
        }
        Ok(())
    }

    fn next_window(&mut self, until: u64, frames: &mut dyn FrameSource) -> Result<Option<Delivered>, UnitError> {
        // Nothing is delivered after the last frame period.
        let end = self.clocks.frame_start(self.clocks.frames);
        while self.done.is_empty() && self.clock <= until.min(end) {
            self.step(frames)?;
        }
        Ok(self.done.pop_front())
    }

    /// Flushes the VCD, if any.
    fn finish(&mut self) -> Result<UnitStats, UnitError> {
        if let Some(r) = self.recording.take() {
            r.vcd.finish().map_err(UnitError::Vcd)?;
        }
        Ok(UnitStats {
            clocks: self.clocks_stepped,
            seconds: self.sim_time.as_secs_f64(),
            sets_before_trace: self.sets_before_trace.clone(),
        })
    }
}

/// The bytes of `req`'s bounds as the link carries them, valid or not (a set corrupted on its
/// way, such as the fault campaign's one-column window, reaches the unit, which refuses it).
fn link_set(req: &WindowRequest, wide: bool) -> Result<CoordinateSet, WriteError> {
    if req.width == 0 || req.height == 0 {
        return Err(WriteError::OutOfRange);
    }
    let last = |start: u16, len: u16| (u32::from(start) + u32::from(len)).saturating_sub(1);
    bound_bytes([req.x0.into(), last(req.x0, req.width), req.y0.into(), last(req.y0, req.height)], wide)
}

/// Queues `req` on the writer: through the firmware's own check, or, for a set the firmware
/// would refuse (a request corrupted on the link), as its raw bounds for the unit to judge.
fn write_on_link(writer: &mut CoordinateWriter, req: &WindowRequest) -> Result<(), WriteError> {
    match writer.write(req) {
        Err(WriteError::OutOfRange) => writer.write_bytes(&link_set(req, writer.set_len() == 8)?, req.decimation == Decimation::Quarter),
        done => done,
    }
}
