//! The Peripheral (Detection) processor (thesis 2.3.2, Table 2.2): SSD of the decimated
//! template over a 25 % window to locate the target approximately, growing the window (40x40,
//! then 64x64) when it fails, and handing the location to the Foveal processor.
use super::messages::{Dest, Msg};
use super::params::Params;
use super::step::{placements, Mode, Step, Work};
use super::template::Template;
use crate::kernels::matching::{best_match, Method};
use crate::kernels::view::WindowView;
use crate::types::{Decimation, Point};


/// SSD of the decimated template over a 25% window: the approximate target, or `None`.
fn ssd_locate(win: &WindowView<'_>, tpl: &Template, p: &Params) -> (Option<Point>, Work) {
    let n = tpl.side();
    let Some(full) = tpl.view() else { return (None, Work::None) };
    let dt = full.decimated();
    let tn = (dt.width() * dt.height()) as u32;
    let work = Work::Match { method: Method::Ssd, template: tn, placements: placements(win, n, 2) };
    let Ok(m) = best_match(Method::Ssd, win, &dt) else { return (None, work) };
    let per_pixel = m.score as f32 / tn.max(1) as f32;
    (
        (per_pixel <= p.ssd_max).then(|| tpl.point_at(m.frame_x, m.frame_y)),
        work,
    )
}

/// Peripheral processor states.
#[derive(Clone, Copy, Debug, PartialEq)]
enum State {
    /// Waiting for motion from a Watch processor.
    Idle,
    /// Locating the target around a point with window size index k (0: 40x40, 1: 64x64).
    Search { at: Point, k: usize },
    /// Located: following the target alongside the Foveal window.
    Follow { at: Point },
}

/// The Peripheral (Detection) processor: SSD at 25% resolution (2.3.2).
pub struct Peripheral {
    template: Option<Template>,
    state: State,
    params: Params,
    /// When set, it also tells the Foveal processor every location, not only on loss: the
    /// thesis's lock-on sequence L2 -> L3.
    foveal_waiting: bool,
}

impl Peripheral {
    /// A Peripheral processor, with the template if it is known in advance.
    pub fn new(params: Params, template: Option<Template>) -> Self {
        Peripheral { template, state: State::Idle, params, foveal_waiting: true }
    }

    /// Starts searching at `p` (used when the target is given).
    pub fn start_at(&mut self, p: Point) -> Step {
        self.state = State::Search { at: p, k: 0 };
        let mut step = Step::new(Work::None);
        step.ask(Some(self.params.window(p, self.params.peripheral[0], Decimation::Quarter)));
        step
    }

    /// Stops locating: back to waiting for motion (SPMF returning to its Watch mode).
    pub(super) fn reset(&mut self) {
        self.state = State::Idle;
    }

    /// The mode this processor is in.
    pub fn mode(&self) -> Mode {
        match self.state {
            State::Idle => Mode::Watch,
            _ => Mode::Detect,
        }
    }

    /// A message arrived.
    pub fn on_message(&mut self, m: &Msg) -> Step {
        let mut step = Step::new(Work::None);
        match (m, self.state) {
            (Msg::Template(t), _) => {
                self.template = Some(t.clone());
            }
            (Msg::Motion { xmin, xmax, ymin, ymax }, State::Idle) => {
                // The variable window of Table 2.2: the motion area with a template's margin.
                let at = Point { x: f32::from(*xmin + *xmax) / 2.0, y: f32::from(*ymin + *ymax) / 2.0 };
                let span = (*xmax - *xmin).max(*ymax - *ymin) + self.params.template;
                let side = span.clamp(self.params.peripheral[0], 128);
                self.state = State::Search { at, k: 0 };
                self.foveal_waiting = true;
                step.ask(Some(self.params.window(at, side, Decimation::Quarter)));
            }
            (Msg::Tracked(p), State::Follow { .. }) | (Msg::Tracked(p), State::Search { .. }) => {
                self.state = State::Follow { at: *p };
                self.foveal_waiting = false;
            }
            (Msg::Lost(p), State::Follow { at }) => {
                // Hand over the latest location at once (2.3.2); search again from there.
                self.foveal_waiting = true;
                self.state = State::Search { at: *p, k: 0 };
                step.send(Dest::Foveal, Msg::Approx(at));
            }
            (Msg::Lost(p), _) => {
                self.foveal_waiting = true;
                self.state = State::Search { at: *p, k: 0 };
                step.ask(Some(self.params.window(*p, self.params.peripheral[0], Decimation::Quarter)));
            }
            _ => {}
        }
        step
    }

    /// A Peripheral window arrived.
    pub fn on_window(&mut self, win: &WindowView<'_>) -> Step {
        let Some(tpl) = &self.template else {
            self.state = State::Idle;
            return Step::new(Work::None);
        };
        let (found, work) = ssd_locate(win, tpl, &self.params);
        let mut step = Step::new(work);
        let side = |k: usize| self.params.peripheral[k.min(1)];
        match (found, self.state) {
            (Some(p), _) => {
                let was_waiting = self.foveal_waiting;
                self.state = State::Follow { at: p };
                step.ask(Some(self.params.window(p, side(0), Decimation::Quarter)));
                if was_waiting {
                    self.foveal_waiting = false;
                    step.send(Dest::Foveal, Msg::Approx(p));
                }
            }
            (None, State::Follow { at }) => {
                self.state = State::Search { at, k: 0 };
                step.ask(Some(self.params.window(at, side(0), Decimation::Quarter)));
            }
            (None, State::Search { at, k }) if k < 1 => {
                self.state = State::Search { at, k: k + 1 };
                step.ask(Some(self.params.window(at, side(k + 1), Decimation::Quarter)));
            }
            (None, _) => {
                // Both Detection sizes failed: back to waiting for the Watch processor.
                self.state = State::Idle;
            }
        }
        step
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::processors::testing::{cut, frame, params, square, template, TARGET};

    #[test]
    fn motion_locks_on_hands_the_location_over_and_the_window_grows_when_lost() {
        let mut p = Peripheral::new(params(), Some(template()));
        assert_eq!(p.mode(), Mode::Watch);
        // Motion 4 px wide: 3 + the 8 px template = 11, raised to the 16 px window, centred on
        // (31.5, 21.5): columns 24..=39, rows 14..=29 at 25 %.
        let s = p.on_message(&Msg::Motion { xmin: 30, xmax: 33, ymin: 20, ymax: 23 });
        let near = square(24, 14, 16, Decimation::Quarter);
        assert_eq!((s.request, s.sends.len(), p.mode()), (Some(near), 0, Mode::Detect));
        // The decimated template (4x4) sits at decimated placement (2, 2) of the 8x8 window,
        // its SSD 0 and its neighbours' equal: the block's centre exactly.
        let block = frame(Some((30, 20)));
        let s = p.on_window(&cut(&block, &near));
        assert_eq!(s.work, Work::Match { method: Method::Ssd, template: 16, placements: 25 });
        assert_eq!(&s.sends[..], &[(Dest::Foveal, Msg::Approx(TARGET))][..]);
        assert_eq!(s.request, Some(near));
        // Found again: the Foveal processor already has it.
        assert!(p.on_window(&cut(&block, &near)).sends.is_empty());
        // Gone: 4 bright samples of 16 differ by 150, 5625 per pixel > 900. The same window,
        // then the larger one (24 px: columns 20..=43), then back to waiting for motion.
        let blank = frame(None);
        assert_eq!(p.on_window(&cut(&blank, &near)).request, Some(near));
        let far = square(20, 10, 24, Decimation::Quarter);
        assert_eq!(p.on_window(&cut(&blank, &near)).request, Some(far));
        let s = p.on_window(&cut(&blank, &far));
        assert_eq!((s.request, s.sends.len(), p.mode()), (None, 0, Mode::Watch));
        // A loss reported while waiting: search around it (round(40 - 7.5) = 33).
        let s = p.on_message(&Msg::Lost(Point { x: 40.0, y: 40.0 }));
        assert_eq!(s.request, Some(square(33, 33, 16, Decimation::Quarter)));
    }

    #[test]
    fn a_foveal_loss_while_following_hands_the_latest_location_over_at_once() {
        let mut p = Peripheral::new(params(), Some(template()));
        let s = p.start_at(TARGET);
        let near = square(24, 14, 16, Decimation::Quarter);
        assert_eq!(s.request, Some(near));
        p.on_window(&cut(&frame(Some((30, 20))), &near));
        let s = p.on_message(&Msg::Lost(Point { x: 40.0, y: 40.0 }));
        assert_eq!((&s.sends[..], s.request), (&[(Dest::Foveal, Msg::Approx(TARGET))][..], None));
    }
}
