//! The behavioural model of `hdl::WindowUnit`, computed per window (fast): a set written from
//! clock `t` completes at `t + latency` (the handshake measured on the unit,
//! `hdl::run::writer_timing`), arms the first frame whose FVAL rises at least 2 clocks later,
//! one frame per set, the later of two pending sets winning; the window completes on the clock
//! its last pixel is strobed (one clock after that pixel was on the bus).
use super::clocks::Clocks;
use super::{window_of, Delivered, RequestRefused, UnitError, WindowUnits};
use crate::frames::FrameSource;
use coopwin_firmware::types::{Decimation, WindowRequest};

/// A unit's sets as the model tracks them.
#[derive(Clone, Debug, Default)]
struct UnitSets {
    /// Completion clock of the last set written (the writer's pacing).
    last_complete: Option<u64>,
    /// Sets written but not yet armed: (completion clock, request), latest last.
    pending: Vec<(u64, WindowRequest)>,
}

/// A window a unit's pending sets arm.
struct Armed {
    frame: usize,
    /// The clock the window's last pixel is strobed.
    clock: u64,
    req: WindowRequest,
    /// Index of the armed set in the pending list.
    index: usize,
}

/// The behavioural window units (see the module docs).
pub struct BehaviouralUnits {
    clocks: Clocks,
    units: Vec<UnitSets>,
    latency: u64,
    repeat: u64,
}

impl BehaviouralUnits {
    /// `n` units on the raster.
    pub fn new(clocks: Clocks, n: usize) -> Self {
        let (latency, repeat) = coopwin_hdl::sim::run::writer_timing();
        BehaviouralUnits { clocks, units: vec![UnitSets::default(); n], latency: latency as u64, repeat: repeat as u64 }
    }

    /// The window a unit's pending sets give.
    fn armed(&self, u: &UnitSets) -> Option<Armed> {
        let first = u.pending.first()?;
        // The first frame whose FVAL rises `ARM_MARGIN` clocks after the first pending set completes.
        let k = self.clocks.first_frame_from(first.0 + coopwin_hdl::ARM_MARGIN as u64);
        let start = self.clocks.frame_start(k);
        // Of the sets complete by then, the latest wins.
        let index = u.pending.iter().rposition(|s| s.0 + coopwin_hdl::ARM_MARGIN as u64 <= start)?;
        let req = u.pending[index].1;
        (k < self.clocks.frames).then(|| Armed { frame: k, clock: start + self.clocks.last_strobe(k, &req), req, index })
    }
}

impl WindowUnits for BehaviouralUnits {
    fn request(&mut self, unit: usize, req: WindowRequest, at: u64) -> Result<(), RequestRefused> {
        if req.width == 0 || req.height == 0 {
            return Err(RequestRefused::Empty { unit, req });
        }
        let (latency, repeat) = (self.latency, self.repeat);
        if let Some(u) = self.units.get_mut(unit) {
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

    fn next_window(&mut self, until: u64, frames: &mut dyn FrameSource) -> Result<Option<Delivered>, UnitError> {
        let best = (0..self.units.len())
            .filter_map(|unit| self.armed(&self.units[unit]).map(|a| (unit, a)))
            .filter(|(_, a)| a.clock <= until)
            .min_by_key(|(unit, a)| (a.clock, *unit));
        let Some((unit, Armed { frame, clock, req, index })) = best else { return Ok(None) };
        self.units[unit].pending.drain(..=index);
        let width = frames.size().0;
        let pixels = window_of(&req).crop(frames.frame(frame)?, width, req.decimation == Decimation::Quarter);
        Ok(Some(Delivered { unit, frame, clock, req, pixels }))
    }
}
