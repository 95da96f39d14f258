//! A unit run end to end: camera frames stream past while a processor writes coordinate sets
//! at chosen clocks; every clock's inputs and outputs are recorded, so the same stimulus can be
//! replayed in another simulator (Icarus Verilog, Verilator) and compared clock for clock.
use crate::camera::{CameraBus, RasterTiming, Window};
use crate::driver::{CoordBus, CoordWriter, UnitDriver, UnitOutputs};

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

/// Every clock of a run.
#[derive(Clone, Debug, Default)]
pub struct Recording {
    /// Inputs applied before each rising edge.
    pub inputs: Vec<(CameraBus, CoordBus)>,
    /// Outputs after each rising edge.
    pub outputs: Vec<UnitOutputs>,
    /// Clock on which each request's fourth byte was taken (its set completed).
    pub completed: Vec<usize>,
}

impl Recording {
    /// The delivered pixels, split by the frame period in which they were strobed.
    pub fn delivered_per_frame(&self, timing: &RasterTiming) -> Vec<Vec<u8>> {
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

/// Streams `frames` (row-major, `timing.width` wide) through a fresh W-bit unit, writing each
/// request's coordinates from its clock on (requests in order of `at`), and records the run.
pub fn run_unit<const W: usize>(
    timing: &RasterTiming,
    frames: &[Vec<u8>],
    requests: &[Request],
) -> Recording {
    let mut unit = UnitDriver::<W>::default();
    let mut writer = CoordWriter::default();
    let mut rec = Recording::default();
    let mut pending = requests.iter().peekable();
    let mut last = UnitOutputs::default();
    let period = timing.frame_clocks();
    for (f, frame) in frames.iter().enumerate() {
        for c in 0..period {
            let t = f * period + c;
            while let Some(r) = pending.next_if(|r| r.at <= t) {
                writer.write(r.window, r.decimate);
            }
            let cam = timing.bus_at(c, |x, y| frame[y * timing.width + x]);
            let port = writer.next(&last);
            last = unit.step(cam, port);
            rec.inputs.push((cam, port));
            rec.outputs.push(last);
        }
    }
    rec.completed = completion_clocks(&rec);
    rec
}

/// Clocks at whose rising edge a set's fourth byte was taken (CRDY1 rose for it).
fn completion_clocks(rec: &Recording) -> Vec<usize> {
    let mut bytes = 0usize;
    let mut out = Vec::new();
    let mut ready_before = false;
    for (t, o) in rec.outputs.iter().enumerate() {
        if o.coord_ready && !ready_before {
            bytes += 1;
            if bytes % 4 == 0 {
                out.push(t);
            }
        }
        ready_before = o.coord_ready;
    }
    out
}
