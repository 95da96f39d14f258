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
#[cfg(test)]
use crate::types::Source;


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
        out.outcome = step.outcome;
        out.request = step.request;
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::processors::step::{Fix, Outcome};
    use crate::processors::testing::{cut, frame, params, square, TARGET};

    #[test]
    fn one_processor_watches_locates_tracks_and_falls_back() {
        let mut prev = [0u8; 64 * 64];
        let mut s = Spmf::new(params(), &mut prev, None);
        let full = square(0, 0, 64, Decimation::Full);
        let (blank, block) = (frame(None), frame(Some((30, 20))));
        assert_eq!((s.start(None).request, s.mode()), (Some(full), Mode::Watch));
        assert_eq!(s.on_window(&cut(&blank, &full), 0.0).request, Some(full));
        // Motion: the template goes to both sub-processors, the Peripheral window is next.
        let periph = square(24, 14, 16, Decimation::Quarter);
        let st = s.on_window(&cut(&block, &full), 0.04);
        assert_eq!((st.request, s.mode(), st.sends.len()), (Some(periph), Mode::Detect, 0));
        // Located: the Foveal window around the location.
        let fovea = square(24, 14, 16, Decimation::Full);
        let st = s.on_window(&cut(&block, &periph), 0.08);
        assert_eq!((st.request, s.mode(), st.outcome), (Some(fovea), Mode::Track, Outcome::Silent));
        let st = s.on_window(&cut(&block, &fovea), 0.12);
        let Some(&Fix { at: p, source, .. }) = st.outcome.fix() else { panic!("{:?}", st.outcome) };
        assert!((p.x - TARGET.x).abs() < 0.01 && (p.y - TARGET.y).abs() < 0.01 && source == Source::Ncc);
        assert_eq!((st.request, s.mode()), (Some(fovea), Mode::Track));
        // Lost: the Peripheral hands over where it last located the target, tracked again there.
        let st = s.on_window(&cut(&blank, &fovea), 0.16);
        assert_eq!((st.outcome, st.request, s.mode()), (Outcome::Lost(p), Some(fovea), Mode::Track));
        // Lost there too: Detection around it, then the larger window, then Watch.
        let st = s.on_window(&cut(&blank, &fovea), 0.20);
        assert_eq!((st.request, s.mode()), (Some(periph), Mode::Detect));
        let far = square(20, 10, 24, Decimation::Quarter);
        assert_eq!(s.on_window(&cut(&blank, &periph), 0.24).request, Some(far));
        let st = s.on_window(&cut(&blank, &far), 0.28);
        assert_eq!((st.request, s.mode()), (Some(full), Mode::Watch));
    }
}
