//! The COOP partner (thesis 4.2): the second Foveal processor of the cooperative pair, running
//! the corner detector on the coordinates its master sends and returning each window's corner.
//! It holds only its role's state (the detector, the point followed, the parameters): no
//! template, Lucas-Kanade cache or confidence policy, which are the master's
//! ([`super::Foveal`]).
use super::foveal::cd_track;
use super::messages::{Dest, Msg};
use super::params::Params;
use super::step::{Mode, Step, Work};
use crate::kernels::corner::{CornerDetector, MAX_DIM};
use crate::kernels::view::WindowView;
use crate::types::Point;

/// The COOP partner, its corner detector sized for windows up to `N x N` (the Foveal window
/// and a coasting track's wider one).
pub struct CornerPartner<const N: usize = MAX_DIM> {
    detector: CornerDetector<N>,
    /// The point the master last sent (`Follow`), until it loses the track.
    tracking: Option<Point>,
    params: Params,
}

impl CornerPartner {
    /// A partner with a detector for windows up to the largest side.
    pub fn new(params: Params) -> Self {
        Self::sized(params)
    }
}

impl<const N: usize> CornerPartner<N> {
    /// A partner with a detector for windows up to `N x N` (`N x N x 28` bytes): a struct
    /// literal of zeroed buffers, built once where its owner keeps it.
    pub fn sized(params: Params) -> Self {
        CornerPartner { detector: CornerDetector::sized(), tracking: None, params }
    }

    /// Whether it follows a track.
    pub fn mode(&self) -> Mode {
        if self.tracking.is_some() {
            Mode::Track
        } else {
            Mode::Watch
        }
    }

    /// A message from the master, answered into `step` (cleared first): `Follow` asks for the
    /// Foveal window there, `Lost` stops; it takes no other message.
    pub fn on_message_into(&mut self, m: &Msg, step: &mut Step) {
        step.clear(Work::None);
        match m {
            Msg::Follow(p) => {
                self.tracking = Some(*p);
                step.ask(Some(self.params.foveal_window(*p)));
            }
            Msg::Lost(_) => self.tracking = None,
            _ => {}
        }
    }

    /// [`CornerPartner::on_message_into`] into a new step.
    pub fn on_message(&mut self, m: &Msg) -> Step {
        let mut step = Step::new(Work::None);
        self.on_message_into(m, &mut step);
        step
    }

    /// A window arrived: its corner (or none) goes to the master, answered into `step`. Never
    /// inlined: the detector's locals are not added to the stack of a caller that also runs
    /// the master (a pair on one core).
    #[inline(never)]
    pub fn on_window_into(&mut self, win: &WindowView<'_>, step: &mut Step) {
        let (found, work) = cd_track(win, &mut self.detector, &self.params);
        step.clear(work);
        step.send(Dest::Foveal, Msg::Result(found));
    }

    /// [`CornerPartner::on_window_into`] into a new step.
    pub fn on_window(&mut self, win: &WindowView<'_>) -> Step {
        let mut step = Step::new(Work::None);
        self.on_window_into(win, &mut step);
        step
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernels::corner::CornerParams;
    use crate::processors::testing::{cut, frame, params, square, TARGET};
    use crate::types::Decimation;
    use crate::processors::step::Outcome;

    #[test]
    fn it_follows_its_master_and_returns_the_detectors_corner() {
        let mut partner = CornerPartner::<24>::sized(params());
        // Follow: the Foveal window (16 px) centred on the point, columns round(31.5 - 7.5).
        let win = square(24, 14, 16, Decimation::Full);
        let s = partner.on_message(&Msg::Follow(TARGET));
        assert_eq!((s.request, s.sends.len(), partner.mode()), (Some(win), 0, Mode::Track));
        // The window's corner, as the detector kernel itself finds it (the reference), goes
        // to the master; the partner reports nothing and asks for nothing.
        let block = frame(Some((30, 20)));
        let view = cut(&block, &win);
        let reference = CornerDetector::<24>::sized().detect(&view, &CornerParams::new(params().corner_threshold)).ok();
        let s = partner.on_window(&view);
        let expected = Msg::Result(reference.map(|c| Point { x: c.x, y: c.y }));
        assert_eq!(&s.sends[..], &[(Dest::Foveal, expected)][..]);
        assert_eq!((s.work, s.outcome, s.request), (Work::Corner { pixels: 256 }, Outcome::Silent, None));
        // Lost: it stops, answering nothing; a Result (the master's input) is not its own.
        let s = partner.on_message(&Msg::Lost(TARGET));
        assert_eq!((s.request, s.sends.len(), partner.mode()), (None, 0, Mode::Watch));
        assert_eq!(partner.on_message(&Msg::Result(None)).request, None);
    }

    #[test]
    fn it_holds_its_detector_and_little_else() {
        // No template, Lucas-Kanade cache or policy: the detector plus a point and the
        // parameters (under 256 bytes), against a COOP master's tens of kilobytes beyond it.
        let extra = core::mem::size_of::<CornerPartner<40>>() - core::mem::size_of::<CornerDetector<40>>();
        assert!(extra < 256, "{extra} bytes beside the detector");
    }
}
