//! The single processor of SPMF (thesis 2.3.1): Watch, Detection and Tracking modes in turn.
use super::foveal::{Foveal, FovealKind};
use super::messages::Msg;
use super::params::Params;
use super::peripheral::Peripheral;
use super::step::{Mode, Step, Work};
use super::template::Template;
use super::watch::Watch;
use crate::kernels::view::WindowView;
use crate::types::{Decimation, Point, WindowRequest};


/// The single processor of SPMF (2.3.1): Watch, Detection and Tracking modes in turn, one
/// window a frame, the sub-processors talking to each other without a link.
pub struct Spmf<'b> {
    watch: Watch<'b>,
    peripheral: Peripheral,
    foveal: Foveal,
    mode: Mode,
}

impl<'b> Spmf<'b> {
    /// SPMF over the whole frame; `prev` stores the last Watch window.
    pub fn new(params: Params, prev: &'b mut [u8], template: Option<Template>) -> Self {
        let full = WindowRequest { x0: 0, y0: 0, width: params.frame_w, height: params.frame_h, decimation: Decimation::Full };
        Spmf {
            watch: Watch::new(full, prev, params, template.is_some()),
            peripheral: Peripheral::new(params, template.clone()),
            foveal: Foveal::new(FovealKind::Ncc, params, template),
            mode: Mode::Watch,
        }
    }

    /// The first request: Watch, or straight to Tracking at a given target.
    pub fn start(&mut self, target: Option<Point>) -> Step {
        match target {
            Some(p) => {
                self.mode = Mode::Track;
                self.foveal.start_at(p)
            }
            None => self.watch.start(),
        }
    }

    /// The mode it is in.
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// The window of the current mode arrived. The sub-processors' messages are handed over
    /// at once; the mode follows the window finally requested.
    pub fn on_window(&mut self, win: &WindowView<'_>, t: f64) -> Step {
        let step = match self.mode {
            Mode::Watch => self.watch.on_window(win),
            Mode::Detect => self.peripheral.on_window(win),
            Mode::Track => self.foveal.on_window(win, t),
        };
        let mut out = Step::new(step.work);
        out.report = step.report;
        out.request = step.request;
        out.lost = step.lost;
        let mut mode = self.mode;
        let mut queue: heapless::Deque<Msg, 8> = heapless::Deque::new();
        for (_, m) in step.sends {
            let _ = queue.push_back(m);
        }
        while let Some(m) = queue.pop_front() {
            let (inner, inner_mode) = match &m {
                Msg::Template(_) => {
                    let _ = self.foveal.on_message(&m, t);
                    (self.peripheral.on_message(&m), None)
                }
                Msg::Motion { .. } | Msg::Lost(_) => (self.peripheral.on_message(&m), Some(Mode::Detect)),
                Msg::Approx(_) => (self.foveal.on_message(&m, t), Some(Mode::Track)),
                _ => (Step::new(Work::None), None),
            };
            if let (Some(r), Some(im)) = (inner.request, inner_mode) {
                out.request = Some(r);
                mode = im;
            }
            for (_, m2) in inner.sends {
                let _ = queue.push_back(m2);
            }
        }
        if out.request.is_none() {
            // Nothing to locate or track: back to watching the whole frame.
            mode = Mode::Watch;
            self.peripheral.reset();
            out.request = self.watch.start().request;
        }
        self.mode = mode;
        out
    }
}
