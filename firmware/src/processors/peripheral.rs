//! The Peripheral (Detection) processor (thesis 2.3.2, Table 2.2): SSD of the decimated
//! template over a 25 % window to locate the target approximately, growing the window (40x40,
//! then 64x64) when it fails, and handing the location to the Foveal processor.
//!
//! With [`Params::adapt`] (issue 21) it re-detects a lost object anywhere in the view: it
//! matches by zero-mean NCC (blind to the light's gain and offset) both the first template
//! and the last one the Foveal track trusted (sent on a loss), and when the two growing
//! windows fail it sweeps the frame at 25 % in [`SWEEP_SIDE`] tiles, one a window, until the
//! object is found, instead of waiting for motion. Its wide windows (the 64x64 one, the tiles)
//! are searched by candidates ([`best_match_candidates`]) and get one look a frame, so that no
//! frame's work exceeds a fraction of the frame period (issue 22). Once the track has been
//! vouched for (issue 38), what it hands over must lie in a motion prior around where the
//! track was last vouched for (its motion there, [`PeripheralParams::prior_radius`]), and it
//! also searches while the track is doubted ([`Msg::Doubted`]).
use super::coop::guard::dist;
use super::messages::{Dest, Msg};
use super::params::{Params, PeripheralParams};
use super::step::{placements, Mode, Step, Work};
use super::template::Template;
use crate::kernels::matching::{best_match, best_match_candidates, Method, CANDIDATES_FROM};
use crate::kernels::view::WindowView;
use crate::types::{Decimation, Point, WindowRequest};


/// Side of the tiles an adapting Peripheral sweeps the frame with: the largest window it
/// matches at 25 % ([`crate::kernels::matching::MAX_PACKED_PIXELS`]: 64x64 samples).
pub const SWEEP_SIDE: u16 = 128;

/// The decimated template over a 25% window: the approximate target and how well it matched
/// (lower is better), or `None`. SSD as the thesis has it, or, for an adapting track, zero-mean
/// NCC from [`PeripheralParams::accept`].
fn locate(win: &WindowView<'_>, tpl: &Template, p: &Params) -> (Option<(Point, f32)>, Work) {
    let n = tpl.side();
    let method = if p.adapt { Method::Zncc } else { Method::Ssd };
    let Some(full) = tpl.view() else { return (None, Work::None) };
    let dt = full.decimated();
    let tn = (dt.width() * dt.height()) as u32;
    let work = Work::Match { method, template: tn, placements: placements(win, n, 2) };
    // An adapting track's windows reach a sweep's 128x128 tiles: their cost stays bounded.
    let searched = if p.adapt { best_match_candidates(win, &dt) } else { best_match(method, win, &dt) };
    let Ok(m) = searched else { return (None, work) };
    let (found, badness) = match method {
        Method::Zncc => (m.score as f32 >= p.redetect.accept, -(m.score as f32)),
        _ => {
            let per_pixel = m.score as f32 / tn.max(1) as f32;
            (per_pixel <= p.ssd_max, per_pixel)
        }
    };
    (found.then(|| (tpl.point_at(m.frame_x, m.frame_y), badness)), work)
}

/// Where an adapting Foveal track was last vouched for ([`Msg::Tracked`]), its motion, and
/// this processor's windows since (about one a frame).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Seen {
    at: Point,
    /// Pixels a window, between the last two vouched points.
    velocity: (f32, f32),
    windows: u16,
}

impl Seen {
    /// `at` vouched for, the motion measured from the last vouched point `before`.
    fn after(before: Option<Seen>, at: Point) -> Seen {
        let velocity = match before {
            Some(b) if b.windows > 0 => {
                let k = f32::from(b.windows);
                ((at.x - b.at.x) / k, (at.y - b.at.y) / k)
            }
            Some(b) => b.velocity,
            None => (0.0, 0.0),
        };
        Seen { at, velocity, windows: 0 }
    }

    /// Whether `p` lies in the motion prior (FuCoLoT's): within `prior`'s radius, growing a
    /// window up to its largest ([`PeripheralParams`]), of where the motion carries the point.
    fn admits(&self, p: Point, prior: &PeripheralParams) -> bool {
        let k = f32::from(self.windows);
        let centre = Point { x: self.at.x + self.velocity.0 * k, y: self.at.y + self.velocity.1 * k };
        dist(p, centre) <= (prior.prior_radius + prior.prior_growth * k).min(prior.prior_max)
    }
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
    /// Adapting tracks: both sizes failed; sweeping the frame, tile `tile` next.
    Sweep { tile: u16 },
}

/// The Peripheral (Detection) processor: SSD at 25% resolution (2.3.2).
pub struct Peripheral {
    template: Option<Template>,
    /// Adapting tracks: the last template the Foveal track trusted, sent on its loss.
    recent: Option<Template>,
    state: State,
    params: Params,
    /// When set, it also tells the Foveal processor every location, not only on loss: the
    /// thesis's lock-on sequence L2 -> L3.
    foveal_waiting: bool,
    /// The window last asked for: a wide one is asked again for its second look.
    asked: Option<WindowRequest>,
    /// The window in hand is a wide one's repeat, for its second look (the first template).
    second_look: bool,
    /// Adapting tracks: where the Foveal track was last vouched for: the motion prior of what
    /// it hands over ([`Peripheral::may_hand_over`]).
    seen: Option<Seen>,
    /// Adapting tracks: the point a doubted Foveal track holds ([`Msg::Doubted`]).
    held: Option<Point>,
}

impl Peripheral {
    /// A Peripheral processor, with the template if it is known in advance.
    pub fn new(params: Params, template: Option<Template>) -> Self {
        Peripheral { template, recent: None, state: State::Idle, params, foveal_waiting: true, asked: None, second_look: false, seen: None, held: None }
    }

    /// Starts searching at `p` (used when the target is given).
    pub fn start_at(&mut self, p: Point) -> Step {
        self.state = State::Search { at: p, k: 0 };
        let mut step = Step::new(Work::None);
        self.ask(&mut step, self.params.window(p, self.params.peripheral[0], Decimation::Quarter));
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
            // A template from an adapting Foveal track while it runs: its last trusted look.
            (Msg::Template(t), State::Follow { .. } | State::Search { .. } | State::Sweep { .. }) if self.params.adapt && self.template.is_some() => {
                self.recent = Some(t.clone());
            }
            (Msg::Template(t), _) => {
                self.template = Some(t.clone());
                self.recent = None;
            }
            // Motion seen while sweeping is where to look first.
            (Msg::Motion { xmin, xmax, ymin, ymax }, State::Idle | State::Sweep { .. }) => {
                // The variable window of Table 2.2: the motion area with a template's margin.
                let at = Point { x: f32::from(*xmin + *xmax) / 2.0, y: f32::from(*ymin + *ymax) / 2.0 };
                // Once an adapting track has been vouched for, motion where nothing may be handed
                // over (outside the motion prior, or the doubted point itself) is another
                // object's: the sweep goes on (in crowd, a look-alike walking away drew the
                // Peripheral's every window for 20 frames).
                if self.seen.is_some() && !self.may_hand_over(at) {
                    return step;
                }
                let span = (*xmax - *xmin).max(*ymax - *ymin) + self.params.template;
                let side = span.clamp(self.params.peripheral[0], 128);
                self.state = State::Search { at, k: 0 };
                self.foveal_waiting = true;
                self.ask(&mut step, self.params.window(at, side, Decimation::Quarter));
            }
            // The Foveal track begins to coast (an onset of fast motion, an occluder): the
            // larger window around its prediction, and what it finds is handed over.
            (Msg::Coasting(p), State::Follow { .. } | State::Search { .. } | State::Sweep { .. }) => {
                self.foveal_waiting = true;
                // A coasting track holds no point.
                self.held = None;
                self.search_wide(&mut step, *p);
            }
            (Msg::Tracked(p), State::Follow { .. } | State::Search { .. } | State::Sweep { .. }) => {
                self.state = State::Follow { at: *p };
                self.foveal_waiting = false;
                if self.params.adapt {
                    (self.seen, self.held) = (Some(Seen::after(self.seen, *p)), None);
                }
            }
            // The Foveal track holds a point its first view does not confirm: look for the
            // object where it was last vouched for (the larger window, then the sweep), and
            // hand over what is found elsewhere.
            (Msg::Doubted(p), state) => {
                self.held = Some(*p);
                self.foveal_waiting = true;
                if let State::Follow { .. } = state {
                    self.search_wide(&mut step, self.seen.map_or(*p, |s| s.at));
                }
            }
            (Msg::Lost(p), state) => {
                // A lost track holds no point.
                (self.foveal_waiting, self.held) = (true, None);
                match state {
                    // Hand over the latest location at once (2.3.2); search again from there.
                    State::Follow { at } if self.may_hand_over(at) => {
                        self.state = State::Search { at: *p, k: 0 };
                        step.send(Dest::Foveal, Msg::Approx(at));
                    }
                    _ => {
                        self.state = State::Search { at: *p, k: 0 };
                        self.ask(&mut step, self.params.window(*p, self.params.peripheral[0], Decimation::Quarter));
                    }
                }
            }
            _ => {}
        }
        step
    }

    /// Whether location `p` may be handed over to the Foveal track (issue 38): for an adapting
    /// track, within the motion prior from where the track was last vouched for
    /// ([`Seen::admits`]), and more than half a template from the point a doubted track holds
    /// (that one it has).
    fn may_hand_over(&self, p: Point) -> bool {
        let elsewhere = |h: Point| dist(p, h) > f32::from(self.params.template) / 2.0;
        !self.params.adapt || (self.seen.is_none_or(|s| s.admits(p, &self.params.redetect)) && self.held.is_none_or(elsewhere))
    }

    /// Searches around `at` from the larger of the two windows.
    fn search_wide(&mut self, step: &mut Step, at: Point) {
        self.state = State::Search { at, k: 1 };
        self.ask(step, self.params.window(at, self.params.peripheral[1], Decimation::Quarter));
    }

    /// Asks for window `r` (its first look, if it is wide).
    fn ask(&mut self, step: &mut Step, r: WindowRequest) {
        self.asked = Some(r);
        self.second_look = false;
        step.ask(Some(r));
    }

    /// The tiles of the sweep: a grid of [`SWEEP_SIDE`] windows over the frame, overlapping
    /// by a template so that an object on a seam is whole in one; (columns, rows, stride, side).
    fn tiles(&self) -> (u16, u16, u16, u16) {
        let p = &self.params;
        let side = SWEEP_SIDE.min(p.frame_w).min(p.frame_h);
        let stride = side.saturating_sub(p.template).max(1);
        let count = |len: u16| len.saturating_sub(side).div_ceil(stride) + 1;
        (count(p.frame_w), count(p.frame_h), stride, side)
    }

    /// Tile `k`'s window, counting row by row.
    fn tile_window(&self, k: u16) -> WindowRequest {
        let (cols, _, stride, side) = self.tiles();
        let centre = |i: u16| f32::from(i * stride) + (f32::from(side) - 1.0) / 2.0;
        self.params.window(Point { x: centre(k % cols), y: centre(k / cols) }, side, Decimation::Quarter)
    }

    /// The tile holding `p` (nearest its centre), where a sweep starts.
    fn tile_of(&self, p: Point) -> u16 {
        let (cols, rows, stride, _) = self.tiles();
        let index = |v: f32, n: u16| ((libm::floorf(v / f32::from(stride)).max(0.0)) as u16).min(n - 1);
        index(p.y, rows) * cols + index(p.x, cols)
    }

    /// A Peripheral window arrived.
    pub fn on_window(&mut self, win: &WindowView<'_>) -> Step {
        let Some(tpl) = &self.template else {
            self.state = State::Idle;
            return Step::new(Work::None);
        };
        if let Some(s) = self.seen.as_mut() {
            s.windows = s.windows.saturating_add(1);
        }
        // The better of the first and the last trusted look, and the work of both; but a wide
        // window (a sweep's tile, 64x64) gets one look a frame, so that a frame's work stays
        // bounded: the last trusted look first, then the same window again for the first.
        let wide = self.params.adapt && placements(win, tpl.side(), 2) as usize > CANDIDATES_FROM;
        let (looks, again) = match (&self.recent, wide, self.second_look) {
            (Some(recent), true, false) => ([Some(recent), None], true),
            (Some(_), true, true) => ([Some(tpl), None], false),
            (recent, ..) => ([Some(tpl), recent.as_ref()], false),
        };
        let (mut found, mut work) = (None, Work::None);
        for look in looks.into_iter().flatten() {
            let (other, w) = locate(win, look, &self.params);
            if other.is_some_and(|o| found.is_none_or(|f: (Point, f32)| o.1 < f.1)) {
                found = other;
            }
            work = match (work, w) {
                (Work::Match { method, template, placements }, Work::Match { placements: more, .. }) => Work::Match { method, template, placements: placements + more },
                (Work::None, w) => w,
                (w, _) => w,
            };
        }
        // Only what may be handed over counts as found while the Foveal track waits for it.
        let found = found.map(|f| f.0).filter(|p| !self.foveal_waiting || self.may_hand_over(*p));
        let mut step = Step::new(work);
        if let (None, true, Some(same)) = (found, again, self.asked) {
            self.second_look = true;
            step.ask(Some(same));
            return step;
        }
        let side = |k: usize| self.params.peripheral[k.min(1)];
        match (found, self.state) {
            (Some(p), _) => {
                let was_waiting = self.foveal_waiting;
                self.state = State::Follow { at: p };
                self.ask(&mut step, self.params.window(p, side(0), Decimation::Quarter));
                if was_waiting {
                    self.foveal_waiting = false;
                    step.send(Dest::Foveal, Msg::Approx(p));
                }
            }
            (None, State::Follow { at }) => {
                self.state = State::Search { at, k: 0 };
                self.ask(&mut step, self.params.window(at, side(0), Decimation::Quarter));
            }
            (None, State::Search { at, k }) if k < 1 => {
                self.state = State::Search { at, k: k + 1 };
                self.ask(&mut step, self.params.window(at, side(k + 1), Decimation::Quarter));
            }
            (None, State::Search { at, .. }) if self.params.adapt => {
                let tile = self.tile_of(at);
                self.state = State::Sweep { tile: tile + 1 };
                self.ask(&mut step, self.tile_window(tile));
            }
            (None, State::Sweep { tile }) => {
                let (cols, rows, ..) = self.tiles();
                let tile = tile % (cols * rows);
                self.state = State::Sweep { tile: tile + 1 };
                self.ask(&mut step, self.tile_window(tile));
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
    use crate::processors::testing::{cut, frame, params, square, template, SIDE, TARGET};

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
    fn an_adapting_search_sweeps_the_frame_until_it_finds_the_object_anywhere() {
        let mut p = Peripheral::new(params().adaptive(), Some(template()));
        // Lost at the target: the two windows around it (as the thesis's) find nothing...
        let near = square(24, 14, 16, Decimation::Quarter);
        assert_eq!(p.on_message(&Msg::Lost(TARGET)).request, Some(near));
        let blank = frame(None);
        let far = square(20, 10, 24, Decimation::Quarter);
        assert_eq!(p.on_window(&cut(&blank, &near)).request, Some(far));
        // ...then the sweep, where the thesis's waits for motion: on a 64x64 frame a single
        // tile, the whole frame, asked for again and again.
        let whole = square(0, 0, 64, Decimation::Quarter);
        assert_eq!(p.on_window(&cut(&blank, &far)).request, Some(whole));
        let s = p.on_window(&cut(&blank, &whole));
        assert_eq!((s.request, p.mode()), (Some(whole), Mode::Detect));
        // The block reappears far away, top-left (50, 44): at 25 % its 2x2 samples match the
        // decimated template's (zero-mean NCC 1) at placement (48, 42), the point 3.5 px in.
        let s = p.on_window(&cut(&frame(Some((50, 44))), &whole));
        assert_eq!(&s.sends[..], &[(Dest::Foveal, Msg::Approx(Point { x: 51.5, y: 45.5 }))][..]);
    }

    #[test]
    fn a_wide_window_gets_one_look_a_frame_the_last_trusted_first() {
        let mut p = Peripheral::new(params().adaptive(), Some(template()));
        // The last trusted look, a light block's negative (a dark block on light): it finds
        // nothing where the first look finds the block (zero-mean NCC -1 against 1).
        let negative: std::vec::Vec<u8> = frame(Some((30, 20))).iter().map(|&v| 250 - v).collect();
        let recent = Template::capture(&WindowView::packed(&negative, SIDE, SIDE).unwrap(), TARGET, 8).unwrap();
        let near = square(24, 14, 16, Decimation::Quarter);
        p.on_message(&Msg::Lost(TARGET));
        p.on_message(&Msg::Template(recent));
        // The two sizes (25 and 81 placements of the 4x4 samples at 25 %) take both looks at once.
        let (blank, far, whole) = (frame(None), square(20, 10, 24, Decimation::Quarter), square(0, 0, 64, Decimation::Quarter));
        let looks = |placements| Work::Match { method: Method::Zncc, template: 16, placements };
        let s = p.on_window(&cut(&blank, &near));
        assert_eq!((s.request, s.work), (Some(far), looks(2 * 25)));
        assert_eq!(p.on_window(&cut(&blank, &far)).request, Some(whole));
        // The sweep's tile (29x29 = 841 placements) is wide: the last trusted look alone, which
        // misses the block, then the same tile again for the first look, which finds it.
        let block = frame(Some((50, 44)));
        let s = p.on_window(&cut(&block, &whole));
        assert_eq!((s.request, s.sends.len(), s.work), (Some(whole), 0, looks(841)));
        let s = p.on_window(&cut(&block, &whole));
        assert_eq!((&s.sends[..], s.work), (&[(Dest::Foveal, Msg::Approx(Point { x: 51.5, y: 45.5 }))][..], looks(841)));
    }

    #[test]
    fn a_coasting_track_gets_the_larger_window_around_its_prediction_and_what_it_finds() {
        let mut p = Peripheral::new(params().adaptive(), Some(template()));
        let near = square(24, 14, 16, Decimation::Quarter);
        p.start_at(TARGET);
        p.on_window(&cut(&frame(Some((30, 20))), &near));
        assert!(p.on_message(&Msg::Tracked(TARGET)).request.is_none());
        // The Foveal track coasts, expecting the target at (39, 35): the larger (24 px) window
        // there, columns round(39 - 11.5) = 28.., rows round(35 - 11.5) = 24..
        let s = p.on_message(&Msg::Coasting(Point { x: 39.0, y: 35.0 }));
        let around = square(28, 24, 24, Decimation::Quarter);
        assert_eq!((s.request, p.mode()), (Some(around), Mode::Detect));
        // The block, moved to (36, 30), is found there and handed over (its point 1.5 px in).
        let s = p.on_window(&cut(&frame(Some((36, 30))), &around));
        assert_eq!(&s.sends[..], &[(Dest::Foveal, Msg::Approx(Point { x: 37.5, y: 31.5 }))][..]);
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

    /// An adapting Peripheral that has found the block and been told the Foveal track vouches
    /// for it, and its 16 px window around the block.
    fn following_a_vouched_track() -> (Peripheral, WindowRequest) {
        let mut p = Peripheral::new(params().adaptive(), Some(template()));
        let near = square(24, 14, 16, Decimation::Quarter);
        p.start_at(TARGET);
        p.on_window(&cut(&frame(Some((30, 20))), &near));
        p.on_message(&Msg::Tracked(TARGET));
        (p, near)
    }

    #[test]
    fn a_doubted_track_gets_a_search_and_only_what_the_motion_prior_admits_elsewhere() {
        let (mut p, _) = following_a_vouched_track();
        // The Foveal track holds the block's place but doubts it: the larger window where the
        // track was last vouched for (24 px: columns round(31.5 - 11.5) = 20..).
        let s = p.on_message(&Msg::Doubted(TARGET));
        let around = square(20, 10, 24, Decimation::Quarter);
        assert_eq!((s.request, p.mode()), (Some(around), Mode::Detect));
        // The block there is the held point: not handed back; the sweep follows.
        let whole = square(0, 0, 64, Decimation::Quarter);
        let s = p.on_window(&cut(&frame(Some((30, 20))), &around));
        assert_eq!((s.request, s.sends.len()), (Some(whole), 0));
        // The block at (50, 44), its point (51.5, 45.5) 31.2 px from the last vouched one: the
        // prior's radius is 24 + 2 px a window since (`prior_radius`, `prior_growth`), 28 and 30 at
        // the 2nd and 3rd windows (refused), 32 at the 4th (handed over).
        let far = frame(Some((50, 44)));
        for _ in 0..2 {
            assert!(p.on_window(&cut(&far, &whole)).sends.is_empty());
        }
        let s = p.on_window(&cut(&far, &whole));
        assert_eq!(&s.sends[..], &[(Dest::Foveal, Msg::Approx(Point { x: 51.5, y: 45.5 }))][..]);
    }

    #[test]
    fn the_motion_prior_carries_the_last_vouched_point_at_its_velocity() {
        let at = |x, y| Point { x, y };
        // Vouched at (10, 10), then 4 windows later at (18, 14): (2, 1) px a window.
        let mut first = Seen::after(None, at(10.0, 10.0));
        assert_eq!(first.velocity, (0.0, 0.0));
        first.windows = 4;
        let mut seen = Seen::after(Some(first), at(18.0, 14.0));
        assert_eq!((seen.velocity, seen.windows), ((2.0, 1.0), 0));
        // 10 windows on, by hand: the centre (18 + 20, 14 + 10) = (38, 24), the radius
        // 24 + 2 * 10 = 44 (the default `prior_radius`, `prior_growth`).
        let prior = PeripheralParams::default();
        seen.windows = 10;
        assert!(seen.admits(at(82.0, 24.0), &prior) && !seen.admits(at(82.5, 24.0), &prior));
        // 27 px behind the last vouched point, against the motion: 45 px from the centre.
        assert!(!seen.admits(at(-7.0, 24.0), &prior));
        // 60 windows on: the radius stops at `prior_max` (120), not 144; at 50 where that is
        // the largest.
        seen.windows = 60;
        let centre = at(18.0 + 120.0, 14.0 + 60.0);
        assert!(seen.admits(at(centre.x, centre.y + 120.0), &prior) && !seen.admits(at(centre.x, centre.y + 121.0), &prior));
        let narrow = PeripheralParams { prior_max: 50.0, ..prior };
        assert!(seen.admits(at(centre.x, centre.y + 50.0), &narrow) && !seen.admits(at(centre.x, centre.y + 51.0), &narrow));
        // A point vouched for in the same window as the last one (a hand-over's jump) keeps
        // the measured velocity rather than dividing by no time.
        seen.windows = 0;
        assert_eq!(Seen::after(Some(seen), at(100.0, 100.0)).velocity, (2.0, 1.0));
    }

    #[test]
    fn motion_outside_a_lost_tracks_motion_prior_does_not_stop_the_sweep() {
        let (mut p, near) = following_a_vouched_track();
        p.on_message(&Msg::Lost(TARGET));
        let blank = frame(None);
        p.on_window(&cut(&blank, &near));
        let whole = square(0, 0, 64, Decimation::Quarter);
        assert_eq!(p.on_window(&cut(&blank, &square(20, 10, 24, Decimation::Quarter))).request, Some(whole));
        // Two windows since the last vouched point: the prior's radius is 28 px. Motion centred
        // on (61.5, 61.5), 50 px away, is another object's; at (31.5, 21.5) it is where to look.
        assert_eq!(p.on_message(&Msg::Motion { xmin: 60, xmax: 63, ymin: 60, ymax: 63 }).request, None);
        assert!(matches!(p.state, State::Sweep { .. }));
        assert_eq!(p.on_message(&Msg::Motion { xmin: 30, xmax: 33, ymin: 20, ymax: 23 }).request, Some(near));
    }

    #[test]
    fn a_lost_track_holds_no_point_and_gets_it_back_where_it_was_doubted() {
        let (mut p, near) = following_a_vouched_track();
        p.on_message(&Msg::Doubted(TARGET));
        // Lost there (the object turned, then hid): the block reappearing in place is handed
        // over, where a doubted track's own point would not be.
        assert_eq!(p.on_message(&Msg::Lost(TARGET)).request, Some(near));
        let s = p.on_window(&cut(&frame(Some((30, 20))), &near));
        assert_eq!(&s.sends[..], &[(Dest::Foveal, Msg::Approx(TARGET))][..]);
    }
}
