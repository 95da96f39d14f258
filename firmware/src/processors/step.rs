//! What a processor answers to an event (thesis 2.3): the mode it is in, the kernel work it
//! did (for the processor cost model of 2.5) and a [`Step`] carrying the next window request,
//! the messages sent and the position reported.
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

/// Whether a position report is the target's, as far as the processor can tell (issue 38):
/// a robot follows only a confirmed one (`coopwin track`'s `ok`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Identity {
    /// The target's model confirms the point (see `Foveal`'s `identity`).
    Confirmed,
    /// Tracked, but nothing confirms that the point is the target's: a look-alike, an
    /// occluder or a changed look may be under the window.
    Unconfirmed,
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
    /// A position to report to the robot controller.
    pub report: Option<(Point, Source)>,
    /// Whether `report` is confirmed to be the target's.
    pub identity: Identity,
    /// The NCC score of the window behind `report` when NCC measured the reported point (a
    /// confidence; `None` when the corner detector alone did).
    pub score: Option<f32>,
    /// The object's turn and scale behind `report`, when an adapting track measured them.
    pub shape: Option<Shape>,
    /// Tracking was lost on this step; the last position tracked.
    pub lost: Option<Point>,
}

// A step holds four messages, each as large as a template: over 4 KiB, so it is built in
// place rather than passed through builder calls by value (each a copy).
impl Step {
    /// An answer with `work` and nothing else: no request, message or report.
    #[inline]
    pub fn new(work: Work) -> Self {
        Step { work, request: None, sends: heapless::Vec::new(), report: None, identity: Identity::Unconfirmed, score: None, shape: None, lost: None }
    }
    /// Empties it for a new answer with `work` (as [`Step::new`], in place).
    #[inline]
    pub fn clear(&mut self, work: Work) {
        (self.work, self.request, self.report, self.score, self.shape, self.lost) = (work, None, None, None, None, None);
        self.identity = Identity::Unconfirmed;
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
