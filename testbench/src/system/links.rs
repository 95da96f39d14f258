//! The processors' comm-port links (thesis 2.2, 20 Mbyte/s), and the time a run's events take
//! on the pixel clock.
use super::cost::CostModel;
use super::SimError;
use coopwin_firmware::ports::link::{FramedLink, Link};
use coopwin_firmware::processors::{Msg, Work};
use std::collections::VecDeque;

/// Seconds and clocks of a run: the cost model on the pixel clock.
#[derive(Clone, Copy, Debug)]
pub(super) struct Timing {
    pub(super) cost: CostModel,
    /// Pixel clock in Hz.
    pub(super) hz: f64,
    /// The blanking before frame 0, in clocks.
    pub(super) blank: u64,
}

impl Timing {
    /// Seconds from frame 0's FVAL rising to clock `c`, for reports.
    pub(super) fn seconds(&self, c: u64) -> f64 {
        (c as f64 - self.blank as f64) / self.hz
    }
    /// Clocks a processor is busy for `work`.
    pub(super) fn busy(&self, work: &Work) -> u64 {
        (self.cost.seconds(work) * self.hz).ceil() as u64
    }
    /// Clocks to carry a message of so many bytes.
    fn link(&self, bytes: usize) -> u64 {
        (self.cost.link_seconds(bytes) * self.hz).ceil() as u64
    }
}

/// The links, one per ordered pair of processors. Messages travel as bytes through the
/// firmware's `FramedLink`, first in first out: each takes the link time of its bytes, from
/// when it is sent or the one before it has arrived, whichever is later.
pub(super) struct Links {
    np: usize,
    pairs: Vec<(FramedLink<VecDeque<u8>>, u64)>,
    timing: Timing,
}

impl Links {
    /// Links between `np` processors.
    pub(super) fn new(np: usize, timing: Timing) -> Self {
        Links { np, pairs: (0..np * np).map(|_| (FramedLink::new(VecDeque::new()), 0)).collect(), timing }
    }

    /// Sends `m` from processor `from` to `to` at clock `at`; the clock it has arrived.
    pub(super) fn send(&mut self, from: usize, to: usize, m: &Msg, at: u64) -> Result<u64, SimError> {
        let (link, free) = self.pairs.get_mut(from * self.np + to).ok_or(SimError::NoLink)?;
        let before = link.io_mut().len();
        link.send(m).map_err(|error| SimError::Link { from, to, error })?;
        let bytes = link.io_mut().len() - before;
        *free = at.max(*free) + self.timing.link(bytes);
        Ok(*free)
    }

    /// The message at the head of the link from `from` to `to`.
    pub(super) fn receive(&mut self, from: usize, to: usize) -> Result<Msg, SimError> {
        let (link, _) = self.pairs.get_mut(from * self.np + to).ok_or(SimError::NoLink)?;
        link.receive().map_err(|error| SimError::Link { from, to, error })
    }
}
