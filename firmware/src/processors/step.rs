//! What a processor answers to an event (thesis 2.3): the mode it is in, the kernel work it
//! did (for the processor cost model of 2.5) and a [`Step`] carrying the next window request,
//! the messages sent and what it says of the target's position.
use super::messages::{Dest, Msg};
use crate::kernels::view::WindowView;
use crate::types::{Point, Shape, Source, WindowRequest};
use crate::kernels::matching::Method;

/// The mode a strategy is in (thesis 2.3.1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Looking for motion.
    Watch,
    /// Locating the target approximately.
    Detect,
    /// Tracking with the Foveal window.
    Track,
}

/// A position a window measured: where, by which algorithm, and how well.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fix {
    /// The point.
    pub at: Point,
    /// The algorithm that measured it.
    pub source: Source,
    /// The NCC score of the window behind the point when NCC measured it (a confidence;
    /// `None` when the corner detector alone did).
    pub score: Option<f32>,
    /// The object's turn and scale, when an adapting track measured them.
    pub shape: Option<Shape>,
}

/// What a step says of the target's position: the verdict a robot follows (issue 38),
/// decided here, in the firmware, and nowhere else. Only [`Outcome::Measured`] vouches for a
/// position (`coopwin track`'s `ok` 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Outcome {
    /// Nothing new of the target's position.
    Silent,
    /// A position measured and confirmed to be the target's by its model (see `Foveal`'s
    /// `confirms`).
    Measured(Fix),
    /// A position measured that nothing confirms to be the target's: a look-alike, an
    /// occluder or a changed look may be under the window.
    Unconfirmed(Fix),
    /// Nothing believable measured: where the motion predicts the point, and the Foveal
    /// window looks next (COOP's coasting).
    Predicted(Point),
    /// The Peripheral found the target again near this point; the Foveal window has yet to
    /// measure it.
    Redetected(Point),
    /// The Foveal window gave the target up; the last position tracked.
    Lost(Point),
}

impl Outcome {
    /// The position a robot may follow: a measured one, vouched for. Only such positions go
    /// to the robot controller's link.
    pub fn vouched(&self) -> Option<&Fix> {
        match self {
            Outcome::Measured(f) => Some(f),
            _ => None,
        }
    }

    /// The position measured, vouched for or not.
    pub fn fix(&self) -> Option<&Fix> {
        match self {
            Outcome::Measured(f) | Outcome::Unconfirmed(f) => Some(f),
            _ => None,
        }
    }
}

/// Kernel work done for one event, for a processor cost model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Work {
    /// Nothing beyond bookkeeping.
    None,
    /// Image differencing over this many pixels.
    Motion {
        /// Pixels differenced.
        pixels: u32,
    },
    /// Template matching.
    Match {
        /// The measure.
        method: Method,
        /// Template pixels.
        template: u32,
        /// Placements tried.
        placements: u32,
    },
    /// The corner detector over a window of this many pixels.
    Corner {
        /// Window pixels.
        pixels: u32,
    },
    /// The COOP decision (two least-squares fits).
    Decision,
}

/// A processor's answer to an event.
#[derive(Clone, Debug, PartialEq)]
pub struct Step {
    /// Kernel work done.
    pub work: Work,
    /// The window to acquire next (applies from the next frame the window logic can arm).
    pub request: Option<WindowRequest>,
    /// Messages sent.
    pub sends: heapless::Vec<(Dest, Msg), 4>,
    /// What it says of the target's position (a measured one goes to the robot controller).
    pub outcome: Outcome,
}

// A step holds four messages, each as large as a template: over 4 KiB, so it is built in
// place rather than passed through builder calls by value (each a copy).
impl Step {
    /// An answer with `work` and nothing else: no request, message or report.
    #[inline]
    pub fn new(work: Work) -> Self {
        Step { work, request: None, sends: heapless::Vec::new(), outcome: Outcome::Silent }
    }
    /// Empties it for a new answer with `work` (as [`Step::new`], in place).
    #[inline]
    pub fn clear(&mut self, work: Work) {
        (self.work, self.request, self.outcome) = (work, None, Outcome::Silent);
        self.sends.clear();
    }
    #[inline(always)]
    pub(super) fn send(&mut self, d: Dest, m: Msg) -> &mut Self {
        // Four slots cover every processor's sends; a fifth is a bug, dropped rather than panic.
        let _ = self.sends.push((d, m));
        self
    }
    pub(super) fn ask(&mut self, r: Option<WindowRequest>) -> &mut Self {
        self.request = r;
        self
    }
}

/// Placements of an `n`-pixel-square template, subsampled by `step`, in `win`.
pub(super) fn placements(win: &WindowView<'_>, n: usize, step: usize) -> u32 {
    let s = step.max(1);
    let (w, h) = (win.width(), win.height());
    let t = n.div_ceil(s);
    (w.saturating_sub(t) + 1) as u32 * (h.saturating_sub(t) + 1) as u32
}
