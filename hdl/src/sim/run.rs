//! A unit run end to end (thesis 2.2.2, B1.1): camera frames stream past while a processor
//! writes coordinate sets at chosen clocks; every clock's inputs and outputs are recorded, so
//! the same stimulus can be replayed in another simulator (Icarus Verilog, Verilator) and
//! compared clock for clock.
use super::camera::{CameraBus, RasterTiming, Window};
use super::driver::{queue_window, write_step, CoordBus, UnitDriver, UnitOutputs};
use crate::coord_port::{set_bytes, wide_coordinates};
use coopwin_firmware::ports::window::{CoordinateWriter, WriteError};

/// A coordinate set the processor starts writing on clock `at` of the run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Request {
    /// Clock (from the start of the run) at which the writer queues the set.
    pub at: usize,
    /// The window.
    pub window: Window,
    /// 25% resolution.
    pub decimate: bool,
}

/// A unit's inputs on one clock.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ClockInputs {
    /// The camera bus.
    pub cam: CameraBus,
    /// The processor's side of the coordinate port.
    pub port: CoordBus,
    /// The synchronous reset.
    pub reset: bool,
}

/// Every clock of a run.
#[derive(Clone, Debug, Default)]
pub struct Recording {
    /// Inputs applied before each rising edge.
    pub inputs: Vec<ClockInputs>,
    /// Outputs after each rising edge.
    pub outputs: Vec<UnitOutputs>,
    /// Clock on which each request's last byte was taken (its set completed).
    pub completed: Vec<usize>,
}

impl Recording {
    /// The delivered pixels, split by the frame period in which they were strobed.
    pub fn delivered_per_frame(&self, timing: &RasterTiming) -> Vec<Vec<u16>> {
        let period = timing.frame_clocks();
        let mut frames = vec![Vec::new(); self.outputs.len().div_ceil(period)];
        for (t, o) in self.outputs.iter().enumerate() {
            if o.pixel_strobe {
                frames[t / period].push(o.pixel_out);
            }
        }
        frames
    }
}

/// Streams `frames` (row-major, `timing.width` wide) through a fresh unit of a
/// `timing.width` x `timing.height` sensor, writing each request's coordinates from its clock
/// on (requests in order of `at`), and records the run.
pub fn run_unit<const C: usize, const P: usize>(
    timing: &RasterTiming,
    frames: &[Vec<u8>],
    requests: &[Request],
) -> Recording {
    let period = timing.frame_clocks();
    let buses = frames
        .iter()
        .flat_map(|frame| (0..period).map(move |c| timing.bus_at(c, |x, y| frame[y * timing.width + x])));
    run_bus::<C, P>((timing.width, timing.height), buses, requests, &[])
}

/// Streams a camera bus, one value a clock, through a fresh unit of a `sensor` = (width,
/// height) sensor, writing each request's coordinates from its clock on (requests in order of
/// `at`) and holding `reset` high on the clocks listed in `resets`; records the run.
pub fn run_bus<const C: usize, const P: usize>(
    sensor: (usize, usize),
    buses: impl IntoIterator<Item = CameraBus>,
    requests: &[Request],
    resets: &[usize],
) -> Recording {
    let wide = wide_coordinates(sensor.0, sensor.1);
    let mut unit = UnitDriver::<C, P>::new(sensor.0, sensor.1);
    let mut writer = CoordinateWriter::for_sensor(sensor.0 as u16, sensor.1 as u16);
    let mut rec = Recording::default();
    let mut pending = requests.iter().peekable();
    let mut last = UnitOutputs::default();
    for (t, cam) in buses.into_iter().enumerate() {
        // A set waits while the writer's queue is full: the writer takes no byte of it before
        // the sets ahead of it are out, so the bus is the same as with a longer queue.
        while let Some(r) = pending.peek().copied().filter(|r| r.at <= t) {
            match queue_window(&mut writer, r.window, r.decimate, wide) {
                Ok(()) => _ = pending.next(),
                Err(WriteError::QueueFull) => break,
                Err(WriteError::OutOfRange) => panic!("{:?}: a coordinate does not fit the port's bytes", r.window),
            }
        }
        let port = write_step(&mut writer, &last);
        let reset = resets.contains(&t);
        last = unit.step_reset(cam, port, reset);
        rec.inputs.push(ClockInputs { cam, port, reset });
        rec.outputs.push(last);
    }
    rec.completed = completion_clocks(&rec, set_bytes(sensor.0, sensor.1));
    rec
}

/// Clocks at whose rising edge a set's last byte was taken (CRDY1 rose for it).
fn completion_clocks(rec: &Recording, set_bytes: usize) -> Vec<usize> {
    let mut bytes = 0usize;
    let mut out = Vec::new();
    let mut ready_before = false;
    for (t, o) in rec.outputs.iter().enumerate() {
        if o.coord_ready && !ready_before {
            bytes += 1;
            if bytes.is_multiple_of(set_bytes) {
                out.push(t);
            }
        }
        ready_before = o.coord_ready;
    }
    out
}

/// The coordinate handshake's timing as the processor's [`CoordinateWriter`] sees it, measured on
/// the rust-hdl unit itself: `latency`, clocks from queueing a set (writer idle) to the clock
/// its fourth byte is taken; `repeat`, clocks between the completions of two sets queued
/// back to back. Behavioural models use these so they agree with the hardware clock for clock.
pub fn writer_timing() -> (usize, usize) {
    static T: std::sync::OnceLock<(usize, usize)> = std::sync::OnceLock::new();
    *T.get_or_init(|| {
        let t = RasterTiming { width: 8, height: 4, h_blank: 2, v_blank_lines: 40 };
        let w = Window { xmin: 1, xmax: 2, ymin: 1, ymax: 2 };
        let frame = vec![vec![0u8; 32]];
        let rec = run_unit::<{ crate::CA_D1_BITS }, { crate::CA_D1_PIXEL_BITS }>(
            &t,
            &frame,
            &[Request { at: 0, window: w, decimate: false }, Request { at: 0, window: w, decimate: false }],
        );
        match rec.completed[..] {
            [a, b, ..] => (a, b - a),
            _ => (usize::MAX, usize::MAX),
        }
    })
}
