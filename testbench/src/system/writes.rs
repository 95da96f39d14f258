//! Coordinate writes from the processors to their window units: the write phase and the
//! corrupted request of the fault campaign, the refusals, and the main loop's watchdog, which
//! writes a request again when it brought no window for three frame periods (thesis 2.5).
use super::config::SystemConfig;
use crate::units::clocks::Clocks;
use crate::units::{RequestRefused, WindowUnits};
use coopwin_firmware::types::WindowRequest;

/// The coordinate writes of a run and what each processor waits for.
pub(super) struct CoordinateWrites<'c> {
    /// Fault injection: the index of the request to corrupt.
    corrupt: Option<usize>,
    /// Fault injection: every write held to this clock of a frame.
    write_phase: Option<u64>,
    clocks: &'c Clocks,
    /// The request each processor waits on, and since when.
    awaiting: Vec<Option<(WindowRequest, u64)>>,
    /// Every request written: (processor, clock, request as the unit received it).
    pub(super) written: Vec<(usize, u64, WindowRequest)>,
    /// Requests the port refused: (processor, clock, why).
    pub(super) refused: Vec<(usize, u64, RequestRefused)>,
}

impl<'c> CoordinateWrites<'c> {
    /// No writes yet, for `np` processors.
    pub(super) fn new(cfg: &SystemConfig, clocks: &'c Clocks, np: usize) -> Self {
        CoordinateWrites {
            corrupt: cfg.corrupt_request,
            write_phase: cfg.write_phase,
            clocks,
            awaiting: vec![None; np],
            written: Vec::new(),
            refused: Vec::new(),
        }
    }

    /// Processor `p` asks for `req` on clock `at`; the fault campaign may corrupt it on its
    /// way into an invalid set (a one-column window).
    pub(super) fn request(&mut self, p: usize, req: WindowRequest, at: u64, units: &mut dyn WindowUnits) {
        let sent = if self.corrupt == Some(self.written.len()) { WindowRequest { width: 1, ..req } } else { req };
        self.write(p, req, sent, at, units);
    }

    /// Processor `p`'s request `req`, arriving as `sent`, is written to its unit from clock `at`
    /// (held to the write phase, if any) and logged, and `p` waits for its window (the
    /// watchdog writes it again if none comes). A request the port refuses is logged in
    /// `refused`. Returns the clock of the write.
    fn write(&mut self, p: usize, req: WindowRequest, sent: WindowRequest, at: u64, units: &mut dyn WindowUnits) -> u64 {
        let written = self.write_phase.map_or(at, |phase| self.clocks.next_phase(at, phase));
        match units.request(p, sent, written) {
            Ok(()) => self.written.push((p, written, sent)),
            Err(why) => self.refused.push((p, written, why)),
        }
        self.awaiting[p] = Some((req, written));
        written
    }

    /// Processor `p` has its window.
    pub(super) fn delivered(&mut self, p: usize) {
        self.awaiting[p] = None;
    }

    /// The watchdog at frame `k`'s start (clock `c`): a request that brought no window in
    /// three frame periods is written again. Returns the rewrites: (processor, clock).
    pub(super) fn watchdog(&mut self, k: usize, c: u64, units: &mut dyn WindowUnits) -> Vec<(usize, u64)> {
        let mut rewrites = Vec::new();
        for p in 0..self.awaiting.len() {
            if let Some((req, since)) = self.awaiting[p] {
                if k >= 3 && since < self.clocks.frame_start(k - 3) {
                    rewrites.push((p, self.write(p, req, req, c, units)));
                }
            }
        }
        rewrites
    }
}
