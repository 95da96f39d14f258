//! The Foveal (Tracking) processor (thesis 2.3.2, 4.2): NCC or the corner detector at full
//! resolution around the tracked point; in COOP a master running NCC and a partner running
//! the corner detector on the same coordinates, the master's [`Policy`] choosing each frame.
use super::adapt::Adaptive;
use super::coop::guard::{dist, Guard, GuardParams, Measured};
use super::coop::Policy;
use super::messages::{Dest, Msg};
use super::params::Params;
use super::step::{placements, Fix, Mode, Outcome, Step, Work};
use super::template::Template;
use crate::kernels::corner::{CornerDetector, CornerParams, MAX_DIM};
use crate::kernels::matching::{best_match_full, best_match_pyramid, blocks_matching, score_at, Method};
use crate::kernels::refine::{LkTemplate, INTERIOR};
use crate::kernels::support::{best_match_on, Support};
use crate::kernels::view::WindowView;
use crate::kernels::warp::{MIN_INSIDE, MIN_IN_VIEW};
use crate::types::{Decimation, Point, Shape, Source, WindowRequest};

/// Lucas-Kanade's side of the template ([`LkTemplate`]), prepared once per template and
/// kept while it is; `over` says for which pixels (`Some(true)`: its support, `Some(false)`:
/// the whole template, `None`: not prepared).
struct LkCache<const P: usize> {
    over: Option<bool>,
    template: LkTemplate<P>,
}

impl<const P: usize> LkCache<P> {
    /// The template prepared over `support` (or all of it), as it is or prepared now.
    fn prepared(&mut self, tpl: &WindowView<'_>, support: Option<&Support>) -> &LkTemplate<P> {
        if self.over != Some(support.is_some()) {
            self.template.prepare(tpl, support);
            self.over = Some(support.is_some());
        }
        &self.template
    }
}

/// The columns and rows of a template past the frame's edges where the motion puts it, at
/// most half its side each (issue 38: a target leaving the view, still half in it, is matched
/// by its part inside, as OpenCV's trackers pad the frame's border; `leaves`'s target was
/// held to the frame's edge 3-15 px behind it for its last 10 visible frames).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Cut {
    left: usize,
    top: usize,
    right: usize,
    bottom: usize,
}

impl Cut {
    /// The cut of an `n`-pixel-square template whose top-left pixel the motion puts at
    /// `(x, y)` (frame coordinates) in a `w x h` frame.
    fn past_edges(x: f32, y: f32, n: usize, (w, h): (u16, u16)) -> Cut {
        // A pixel more than the overlap: the predicted placement is then not the search's
        // last, where the parabola has no neighbour beyond it (`leaves`'s match was held there
        // half a pixel off).
        let past = |by: f32| if by > 0.0 { libm::ceilf(by + 1.0).min((n / 2) as f32) as usize } else { 0 };
        let side = n as f32;
        Cut { left: past(-x), top: past(-y), right: past(x + side - f32::from(w)), bottom: past(y + side - f32::from(h)) }
    }

    /// The template's part inside the frame.
    fn of<'a>(&self, tpl: &WindowView<'a>) -> Option<WindowView<'a>> {
        tpl.sub(self.left, self.top, tpl.width().checked_sub(self.left + self.right)?, tpl.height().checked_sub(self.top + self.bottom)?)
    }
}

/// What NCC measured in a window: the tracked point and its score, and whether the best
/// placement lay on the window's edge (the target may be beyond it: the next window grows).
#[derive(Clone, Copy, Debug, PartialEq)]
struct NccFound {
    point: Point,
    score: f32,
    pinned: bool,
    /// The best placement (window pixels), where the template's blocks are scored; `None`
    /// where the template was cut at the frame's edge (its blocks are not all in view).
    placement: Option<(usize, usize)>,
    /// The parabola's placement (window pixels), where Lucas-Kanade starts.
    sub: (f32, f32),
}

impl NccFound {
    /// Whether the whole template was matched (not cut at the frame's edge).
    fn whole(&self) -> bool {
        self.placement.is_some()
    }

    /// The point refined by Lucas-Kanade from the parabola's placement (the parabola's own
    /// where it is refused). `lk` holds (or prepares) `tpl` over `support`.
    fn refine<const P: usize>(self, win: &WindowView<'_>, tpl: &Template, support: Option<&Support>, lk: &mut LkCache<P>) -> Self {
        let Some(tv) = tpl.view() else { return self };
        let (ox, oy) = win.origin();
        let Some((x, y)) = lk.prepared(&tv, support).refine(win, self.sub.0, self.sub.1) else { return self };
        NccFound { point: tpl.point_at(x + ox as f32, y + oy as f32), ..self }
    }
}

/// NCC tracking of `tpl` in `win`: the new point (the best placement, refined to sub-pixel
/// accuracy by Lucas-Kanade, [`crate::kernels::refine`], unless `adapting`: an adapting
/// track refines only where its first template does not align, [`Foveal::on_window_into`])
/// and its score, or `None` if the best score is under `ncc_min` (the target has left the
/// window, or no longer looks like the template). `lk` holds the template prepared for the
/// refinement; an `adapting` template is matched by zero-mean NCC ([`Params::correlation`]),
/// without its `cut` past the frame's edges (and then without its support).
#[inline(always)]
fn ncc_track<const P: usize>(win: &WindowView<'_>, tpl: &Template, support: Option<&Support>, cut: Cut, lk: &mut LkCache<P>, p: &Params, adapting: bool) -> (Option<NccFound>, Work) {
    let (method, acceptance) = p.correlation(adapting);
    let n = tpl.side();
    // The cost model counts the whole template: the support is a part of it, as is a cut one.
    let work = Work::Match { method, template: (n * n) as u32, placements: placements(win, n, 1) };
    let Some(tv) = tpl.view().and_then(|v| cut.of(&v)) else { return (None, work) };
    let support = support.filter(|_| cut == Cut::default());
    // The object's part of a corner template first; the whole template where that finds no
    // placement with the object's texture (a lamp's highlight across the support).
    let on_support = support.and_then(|s| Some((best_match_on(win, &tv, s).ok()?, s)));
    let (m, support) = match on_support {
        Some((m, s)) => (m, Some(s)),
        // An adapting track's window widens with the motion: its cost stays bounded.
        None => match if adapting { best_match_pyramid(method, win, &tv) } else { best_match_full(method, win, &tv) } {
            Ok(m) => (m, None),
            Err(_) => return (None, work),
        },
    };
    let score = m.score as f32;
    if score < acceptance {
        return (None, work);
    }
    let pinned = m.x == 0 || m.y == 0 || m.x + tv.width() >= win.width() || m.y + tv.height() >= win.height();
    let (left, top) = (cut.left as f32, cut.top as f32);
    let found = NccFound {
        point: tpl.point_at(m.frame_x - left, m.frame_y - top),
        score,
        pinned,
        placement: (cut == Cut::default()).then_some((m.x, m.y)),
        sub: (m.sub_x - left, m.sub_y - top),
    };
    (Some(if adapting { found } else { found.refine(win, tpl, support, lk) }), work)
}

/// The corner in `win`, or `None` when the detector finds none (also the COOP partner's,
/// [`super::partner`]).
pub(super) fn cd_track<const N: usize>(win: &WindowView<'_>, det: &mut CornerDetector<N>, p: &Params) -> (Option<Point>, Work) {
    let work = Work::Corner { pixels: (win.width() * win.height()) as u32 };
    let c = det.detect(win, &CornerParams::new(p.corner_threshold)).ok();
    (c.map(|c| Point { x: c.x, y: c.y }), work)
}

/// Farthest, in pixels, a COOP position may be from the window's NCC match for NCC's score
/// to stand as its confidence (the guard's agreement gate).
const VOUCH: f32 = 1.5;

/// Which algorithm a Foveal processor runs, and its role in COOP.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FovealKind {
    /// NCC alone (TPDF, MPDF; Table 4.1's NCC).
    Ncc,
    /// The corner detector alone (Table 4.1's CD).
    Cd,
    /// COOP master: NCC here, the corner detector on the partner
    /// ([`super::partner::CornerPartner`]); the confidence measure chooses (4.2-4.3).
    CoopMaster,
}

/// What an adapting track's model of the object says of a window's point (issue 38); once
/// the window is followed, what it said of the row (the chain the next window holds to).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Sighting {
    /// Not the object, as far as its model can tell (or the row was not vouched for).
    Unseen,
    /// The object: its first template vouches for the point ([`Foveal::first_vouches`]).
    Seen,
    /// The object as the chain last saw it: out of the chain, its first view aligns and the
    /// look kept from the last window its model vouched for matches ([`Foveal::recalls`]).
    /// Vouched for, and teaches the template as [`Sighting::Seen`] does; the look kept stays
    /// (the template that matched has learnt in doubt since).
    Recalled,
    /// The object partly covered: the window's whole match breaks the chain, but at least
    /// half its template still matches, block by block ([`Foveal::partly_covered`]). Vouched
    /// for; the window teaches the template nothing (the cover is not the object).
    PartlyCovered,
    /// The object coming back out from behind a cover: out of the chain (or still coming out),
    /// its first view aligns, if weakly, where the motion aimed the window
    /// ([`Foveal::reappears`]). Vouched for; the window teaches the template nothing (part of
    /// the view may still be the cover's).
    Reappearing,
}

/// Side of the grid of blocks a partly covered template is scored in
/// ([`Foveal::partly_covered`]): 8x8-pixel blocks for a 32x32 template, 5x5 for 20x20.
const COVER_GRID: usize = 4;

/// What a Foveal processor is doing (a COOP master's coasting is its guard's,
/// [`Guard::coasting`]).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Phase {
    /// No track: waiting for a target (the Peripheral's location, or one given at start).
    Idle,
    /// Tracking; the last point followed.
    Tracking(Point),
    /// An adapting track the Peripheral handed over near the point: its first window, still
    /// to come, tries the first template too ([`Foveal::handed_over`]).
    HandedOver(Point),
    /// An adapting track holding a point its first view does not confirm (issue 38): the
    /// Peripheral looks for the object elsewhere meanwhile ([`Msg::Doubted`]), and a location
    /// it hands over is taken ([`Phase::Redirected`]).
    Doubted(Point),
    /// A doubted track the Peripheral found the object for elsewhere, at this point: the
    /// window in flight is followed, and unless it confirms the object, the next goes there
    /// (the window's outcome is then a re-detection, never a loss). Windows come in the order
    /// they were asked for: a restart at once would take the one in flight for the object's.
    Redirected(Point),
}

/// A Foveal (Tracking) processor, its corner detector sized for windows (and templates) up
/// to `N x N`, its Lucas-Kanade template for up to `P` used pixels ([`LkTemplate`]: `(n - 2)²`
/// for an `n x n` template; a larger template is tracked without the refinement).
pub struct Foveal<const N: usize = MAX_DIM, const P: usize = INTERIOR> {
    kind: FovealKind,
    template: Option<Template>,
    /// The object's part of a corner template ([`crate::kernels::support`]), when it is one.
    support: Option<Support>,
    lk: LkCache<P>,
    detector: CornerDetector<N>,
    phase: Phase,
    params: Params,
    coop: Policy,
    /// COOP master: own result of the current window (no corner yet), waiting for the
    /// partner's.
    own: Option<Measured>,
    partner: Option<Option<Point>>,
    /// With [`Params::adapt`]: the template's adaptation ([`super::adapt`]).
    adapt: Option<Adaptive<P>>,
    /// The last NCC placement sat on the window's edge: the next window is wider.
    pinned: bool,
    /// Adapting tracks: where the last window was aimed (the motion's prediction; a coasting
    /// window's, the coast's).
    aimed: Option<Point>,
    /// Adapting tracks: the largest recent distance between where a window was aimed and
    /// where the point was found, decaying by `miss_decay` a window: the motion's surprise.
    miss: f32,
    /// The object's shape as the last window's alignment measured it (adapting tracks).
    shape: Option<Shape>,
    /// Adapting tracks: what the object's model says of this window's point; once the window
    /// is followed, of its row.
    sighting: Sighting,
    /// Adapting tracks: windows in a row whose point the first template did not confirm.
    unconfirmed: u8,
    /// Adapting tracks: windows vouched for as the object coming back out since its model last
    /// vouched for a window otherwise.
    reappeared: u8,
    /// Adapting tracks: when a window was last vouched for, in seconds.
    vouched_at: Option<f64>,
    /// Adapting tracks: the template that matched the last window its model vouched for
    /// ([`Sighting::Seen`]), unless that was the first: a look of the object that learns
    /// nothing in doubt once it is kept ([`Foveal::vouched_look_matches`]).
    vouched_look: Option<Template>,
}

impl Foveal {
    /// A Foveal processor; a COOP master decides with guarded cooperation
    /// ([`Foveal::with_policy`] chooses another policy).
    pub fn new(kind: FovealKind, params: Params, template: Option<Template>) -> Self {
        let mut f = Self::sized(kind, params);
        if let Some(t) = template {
            f.set_template(t);
        }
        f
    }
}

impl<const N: usize, const P: usize> Foveal<N, P> {
    /// A processor as [`Foveal::new`] without a template yet ([`Foveal::set_template`]), with
    /// a detector for windows up to `N x N`. A struct literal of zeroed buffers and nothing
    /// else: the template is taken afterwards, in place, where the caller keeps the processor
    /// (the board's COOP pair builds it once, in a frame of its own, then never moves it).
    pub fn sized(kind: FovealKind, params: Params) -> Self {
        Foveal {
            kind,
            template: None,
            support: None,
            lk: LkCache { over: None, template: LkTemplate::sized() },
            detector: CornerDetector::sized(),
            phase: Phase::Idle,
            params,
            coop: Policy::Guarded(Guard::new(GuardParams::for_track(&params))),
            own: None,
            partner: None,
            adapt: None,
            pinned: false,
            aimed: None,
            miss: 0.0,
            shape: None,
            sighting: Sighting::Unseen,
            unconfirmed: 0,
            reappeared: 0,
            vouched_at: None,
            vouched_look: None,
        }
    }

    /// Takes `tpl` as the template, with its support when it is centred on a corner of an
    /// object given as a point (as the Watch's `Template` message does). Never inlined: its
    /// temporaries (the adaptation's first template prepared, 13 KB) stay off the stack of the
    /// frames that take messages.
    #[inline(never)]
    pub fn set_template(&mut self, tpl: Template) {
        let a = tpl.anchor();
        // A box around the object says an adapting template is all object, a corner at its
        // centre the object's own: vtest.avi's hoodie, whose support kept his template from
        // adapting, was lost in his second frame (issue 38, stop 49). The fixed template keeps
        // its support, which holds Megamind_bugy's candle (92 frames vouched for; 4 without).
        let whole = self.params.target_boxed && self.params.adapt;
        self.support = tpl.view().filter(|_| !whole).and_then(|v| {
            Support::of_template(&v, (a.x, a.y), &mut self.detector, &CornerParams::new(self.params.corner_threshold))
        });
        // Prepared now (outside the frames), over the support that NCC tries first.
        self.lk.over = None;
        if let Some(v) = tpl.view() {
            self.lk.prepared(&v, self.support.as_ref());
        }
        // A corner template's support is the object's part of it: the corner detector, not
        // the template, follows such an object's changes.
        let adapts = self.params.adapt && self.support.is_none() && matches!(self.kind, FovealKind::Ncc | FovealKind::CoopMaster);
        self.adapt = adapts.then(|| Adaptive::new(&tpl));
        self.template = Some(tpl);
        self.vouched_look = None;
    }

    /// Takes the adapted template `tpl` (one with no support) in place of the current one.
    /// Its Lucas-Kanade side is prepared when a window first needs it: where the first template
    /// aligns, none does.
    fn adopt(&mut self, tpl: Template) {
        self.lk.over = None;
        self.template = Some(tpl);
    }

    /// The same processor with another confidence policy (COOP master).
    pub fn with_policy(mut self, policy: Policy) -> Self {
        self.coop = policy;
        self
    }

    /// Starts tracking at `p` (the target given at start).
    pub fn start_at(&mut self, p: Point) -> Step {
        let mut step = Step::new(Work::None);
        self.start_at_into(p, &mut step);
        step
    }

    /// [`Foveal::start_at`], answered into `step` (cleared first), as
    /// [`Foveal::on_message_into`].
    pub fn start_at_into(&mut self, p: Point, step: &mut Step) {
        step.clear(Work::None);
        self.start(p, true, step);
    }

    /// Starts tracking at `p`: the tracked point itself when `exact`, otherwise the
    /// Peripheral's approximate location.
    fn start(&mut self, p: Point, exact: bool, step: &mut Step) {
        self.phase = if !exact && self.adapt.is_some() { Phase::HandedOver(p) } else { Phase::Tracking(p) };
        // A track (re)started is vouched for first by its model: coming out needs a track.
        (self.aimed, self.miss, self.unconfirmed, self.reappeared, self.sighting) = (None, 0.0, 0, self.params.track.rejoin_run, Sighting::Unseen);
        self.vouched_look = None;
        if !exact {
            step.outcome = Outcome::Redetected(p);
        }
        self.coop.begin(p, exact);
        // An adapting track resumed from the Peripheral's approximate location (25 %: +-2 px)
        // looks as widely as when its motion is unknown.
        let side = self.params.foveal + if self.adapt.is_some() && !exact { 2 * self.params.track.grow_margin } else { 0 };
        step.ask(Some(self.params.window(p, side, Decimation::Full)));
        if self.kind == FovealKind::CoopMaster {
            step.send(Dest::FovealCd, Msg::Follow(p));
        }
    }

    /// Whether a COOP master's track is coasting: tracking, but with no current position.
    pub fn coasting(&self) -> bool {
        matches!(&self.coop, Policy::Guarded(g) if g.coasting())
    }

    /// Whether it is tracking.
    pub fn mode(&self) -> Mode {
        match self.phase {
            Phase::Idle => Mode::Watch,
            Phase::Tracking(_) | Phase::HandedOver(_) | Phase::Doubted(_) | Phase::Redirected(_) => Mode::Track,
        }
    }

    /// A message arrived.
    pub fn on_message(&mut self, m: &Msg, t: f64) -> Step {
        let mut step = Step::new(Work::None);
        self.on_message_into(m, t, &mut step);
        step
    }

    /// [`Foveal::on_message`], answered into `step` (cleared first). A `Step` is over 4 KiB and
    /// each return by value copies it: a loop that keeps one (a board's) saves the copies.
    pub fn on_message_into(&mut self, m: &Msg, t: f64, step: &mut Step) {
        step.clear(Work::None);
        match m {
            Msg::Template(tpl) => self.set_template(tpl.clone()),
            // No location is taken by an adapting track after its motion prior has lapsed
            // (`prior_seconds`: for good, as `vouched_at` is kept).
            Msg::Approx(_) if self.adapt.is_some() && self.vouched_at.is_some_and(|v| t - v > self.params.track.prior_seconds) => {}
            // An adapting track that coasts restarts where the Peripheral found the target; one
            // its first view doubts, after the window in flight.
            Msg::Approx(p) => match self.phase {
                Phase::Idle => self.start(*p, false, step),
                _ if self.adapt.is_some() && self.coasting() => self.start(*p, false, step),
                Phase::Doubted(_) => self.phase = Phase::Redirected(*p),
                _ => {}
            },
            Msg::Follow(p) => {
                self.phase = Phase::Tracking(*p);
                step.ask(Some(self.params.foveal_window(*p)));
            }
            Msg::Result(r) if self.kind == FovealKind::CoopMaster => {
                self.partner = Some(*r);
                if self.decide(t, step) {
                    step.work = Work::Decision;
                }
            }
            _ => {}
        }
    }

    /// A Foveal window arrived, at time `t` seconds (for the confidence fits).
    pub fn on_window(&mut self, win: &WindowView<'_>, t: f64) -> Step {
        let mut step = Step::new(Work::None);
        self.on_window_into(win, t, &mut step);
        step
    }

    /// [`Foveal::on_window`], answered into `step` (cleared first), as
    /// [`Foveal::on_message_into`].
    pub fn on_window_into(&mut self, win: &WindowView<'_>, t: f64, step: &mut Step) {
        match self.kind {
            FovealKind::Cd => {
                let (found, work) = cd_track(win, &mut self.detector, &self.params);
                step.clear(work);
                self.follow(step, t, found, Source::Cd, None);
            }
            FovealKind::Ncc | FovealKind::CoopMaster => {
                // A track the Peripheral handed over tries its first template too (one call
                // site: the NCC master's 64 KiB has no room for a second inlined search).
                let handed = match self.phase {
                    Phase::HandedOver(p) => {
                        self.phase = Phase::Tracking(p);
                        true
                    }
                    _ => false,
                };
                let first = self.adapt.as_ref().map(Adaptive::first).filter(|f| handed && Some(*f) != self.template.as_ref());
                let (mut found, mut work, mut by_first) = (None, Work::None, false);
                for (k, tpl) in self.template.iter().chain(first).enumerate() {
                    let support = if k == 0 { self.support.as_ref() } else { None };
                    let cut = self.cut(tpl);
                    let (f, w) = ncc_track(win, tpl, support, cut, &mut self.lk, &self.params, self.adapt.is_some());
                    // The work of both searches (same template size: their placements add up).
                    match (&mut work, w) {
                        (Work::Match { placements, .. }, Work::Match { placements: more, .. }) => *placements += more,
                        (_, w) => work = w,
                    }
                    if let Some(f) = f.filter(|f| found.is_none_or(|b: NccFound| f.score > b.score)) {
                        (found, by_first) = (Some(f), k == 1);
                    }
                }
                step.clear(work);
                let found = if handed { self.handed_over(found, by_first) } else { found };
                // An adapting track's point is the first template's, aligned under a
                // similarity warp from the match where it aligns; where it does not, the
                // match refined by Lucas-Kanade, as a fixed template's.
                let aligned = self.adapt.as_mut().zip(found).and_then(|(a, f)| a.align(win, f.point, if f.whole() { MIN_INSIDE } else { MIN_IN_VIEW }));
                self.shape = aligned.map(|(_, pose, _)| Shape { scale: pose.scale(), angle_deg: pose.angle().to_degrees() });
                self.sighting = match found {
                    // A template the frame's edge cuts is vouched for by its first view's
                    // alignment alone: its match on half the template holds no chain.
                    _ if self.first_vouches(aligned.map(|(_, _, s)| s), found.filter(NccFound::whole).map(|f| f.score)) => Sighting::Seen,
                    Some(f) if self.in_doubt_breaks_the_chain(f.score) && f.placement.is_some_and(|at| self.partly_covered(win, at)) => Sighting::PartlyCovered,
                    Some(f) if f.whole() && aligned.is_some_and(|(p, _, s)| self.reappears(p, s)) => Sighting::Reappearing,
                    Some(f) if aligned.is_some() && f.placement.is_some_and(|at| self.recalls(win, at)) => Sighting::Recalled,
                    _ => Sighting::Unseen,
                };
                self.reappeared = match self.sighting {
                    Sighting::Seen | Sighting::PartlyCovered | Sighting::Recalled => 0,
                    Sighting::Reappearing => self.reappeared.saturating_add(1),
                    Sighting::Unseen => self.reappeared,
                };
                let found = match (found, aligned, self.template.as_ref()) {
                    (Some(f), Some((point, _, _)), _) => Some(NccFound { point, ..f }),
                    (Some(f), None, Some(tpl)) if self.adapt.is_some() => Some(f.refine(win, tpl, self.support.as_ref(), &mut self.lk)),
                    (f, _, _) => f,
                };
                self.pinned = found.is_some_and(|f| f.pinned);
                // A window that cannot teach the template proposes nothing: its search for the
                // first template pays for the partly covered check.
                let teaches = found.is_some_and(|f| self.teaches(f.score));
                match (self.adapt.as_mut(), found, self.template.as_ref()) {
                    (Some(a), Some(f), Some(tpl)) if teaches => {
                        a.matched(tpl, f.point, f.score);
                        a.propose(win, f.point, f.score, tpl.side(), aligned.is_some());
                    }
                    (Some(a), _, _) => a.discard(),
                    _ => {}
                }
                let own = found.map(|f| (f.point, f.score));
                if self.kind == FovealKind::CoopMaster {
                    self.own = Some(Measured { ncc: own, corner: None, confirmed: aligned.is_some() });
                    self.decide(t, step);
                } else {
                    self.follow(step, t, own.map(|(p, _)| p), Source::Ncc, own.map(|(_, s)| s));
                }
            }
        }
    }

    /// The first window of an adapting track the Peripheral handed over: `found`, the better
    /// of the current template's match and the first template's (`by_first`), from the bar
    /// the Peripheral's re-detection cleared ([`super::params::PeripheralParams::accept`]),
    /// the first template taken back where it won and cleared it. The current template is the look the track
    /// lost the object with: on the earring of `Megamind.avi` it scores 0.24-0.49 where the
    /// Peripheral hands the stud over, the first 0.78-0.96, and wrong places 0.44-0.72.
    fn handed_over(&mut self, found: Option<NccFound>, by_first: bool) -> Option<NccFound> {
        let found = found.filter(|f| f.score >= self.params.redetect.accept);
        // Refused, the track keeps the look it had (the Peripheral's last trusted one).
        if let Some(t) = self.adapt.as_mut().filter(|_| by_first && found.is_some()).map(Adaptive::back_to_first) {
            self.adopt(t);
        }
        found
    }

    /// COOP: once both results of a window are in, feed the confidence measure and follow
    /// the source it chooses, into `step` (filled in place: a `Step` is over 4 KiB, and each
    /// return by value is a copy); whether it decided.
    fn decide(&mut self, t: f64, step: &mut Step) -> bool {
        let (Some(own), Some(partner)) = (self.own, self.partner) else { return false };
        self.own = None;
        self.partner = None;
        let coasted = self.coasting();
        let chosen = self.coop.decide(t, Measured { corner: partner, ..own });
        if let Some(q) = chosen.is_none().then(|| self.coop.coast(t)).flatten() {
            // Nothing measured the point: look where it should be next.
            let side = self.params.foveal + 2 * self.params.track.coast_margin;
            if self.adapt.is_some() && !coasted {
                step.send(Dest::Peripheral, Msg::Coasting(q));
            }
            step.outcome = Outcome::Predicted(q);
            // The next window is placed at the coast's prediction (the request below), so the
            // object coming back out is judged against that aim ([`Foveal::reappears`]), not
            // the last one before the coast.
            if self.adapt.is_some() {
                self.aimed = Some(q);
            }
            self.sighting = Sighting::Unseen;
            if let Some(a) = self.adapt.as_mut() {
                a.discard();
            }
            step.ask(Some(self.params.window(q, side, Decimation::Full))).send(Dest::FovealCd, Msg::Follow(q));
            return true;
        }
        let (found, source) = (chosen.map(|c| c.0), chosen.map_or(Source::Ncc, |c| c.1));
        // NCC vouches for the point it measured, or one fused with it.
        let score = own.ncc.zip(found).filter(|((n, _), p)| dist(*n, *p) <= VOUCH).map(|((_, s), _)| s);
        self.follow(step, t, found, source, score);
        match (step.request, step.outcome) {
            (Some(req), Outcome::Measured(fix) | Outcome::Unconfirmed(fix)) => {
                // The partner looks where the master's window is centred.
                let centre = Point {
                    x: f32::from(req.x0) + (f32::from(req.width) - 1.0) / 2.0,
                    y: f32::from(req.y0) + (f32::from(req.height) - 1.0) / 2.0,
                };
                let at = if self.adapt.is_some() { centre } else { fix.at };
                step.send(Dest::FovealCd, Msg::Follow(at));
            }
            // The partner stops with the master; the Peripheral takes over.
            (_, Outcome::Lost(last)) => {
                step.send(Dest::FovealCd, Msg::Lost(last));
            }
            _ => {}
        }
        true
    }

    /// Follows `found` (measured by `source`, with NCC's `score` when NCC vouches for it) at
    /// time `t`: the next window, the Peripheral told, the outcome: the point, vouched for or
    /// not, or the loss. An adapting template takes the window's proposal when NCC measured
    /// the point followed and the window teaches it ([`Foveal::teaches`]).
    fn follow(&mut self, step: &mut Step, t: f64, found: Option<Point>, source: Source, score: Option<f32>) {
        let confirmed = self.confirms(score);
        // A COOP report the first template did not measure (the corner detector's) is no link
        // of the chain, though the template's own match vouched.
        if !confirmed {
            self.sighting = Sighting::Unseen;
        }
        // The look kept: the template that matched, where the model vouched for the window;
        // none where that was the first (its own view vouches for it).
        if confirmed && score.is_some() && self.sighting == Sighting::Seen {
            match self.adapt.as_ref().is_some_and(Adaptive::on_first) {
                true => self.vouched_look = None,
                false => self.vouched_look.clone_from(&self.template),
            }
        }
        let astray = self.astray(confirmed);
        let learns = score.is_some_and(|s| self.teaches(s));
        if let Some(a) = self.adapt.as_mut() {
            // A track that has gone astray starts again from the object's first view.
            let next = match (astray, learns) {
                (true, _) => Some(a.back_to_first()),
                (false, true) => a.take(),
                (false, false) => {
                    a.discard();
                    None
                }
            };
            if let Some(next) = next {
                self.adopt(next);
            }
        }
        match (found.filter(|_| !astray), self.phase) {
            (_, Phase::Redirected(to)) if !confirmed => self.start(to, false, step),
            (Some(p), _) => {
                // A fixed template's track is the thesis's: followed as tracked, vouched or not.
                let doubted = !confirmed && self.adapt.is_some();
                self.phase = if doubted { Phase::Doubted(p) } else { Phase::Tracking(p) };
                if let Some(a) = self.aimed {
                    self.miss = dist(p, a).max(self.miss * self.params.track.miss_decay);
                }
                step.ask(Some(self.next_window(p, t))).send(Dest::Peripheral, if doubted { Msg::Doubted(p) } else { Msg::Tracked(p) });
                let fix = Fix { at: p, source, score, shape: score.and(self.shape) };
                if confirmed && self.adapt.is_some() {
                    self.vouched_at = Some(t);
                }
                step.outcome = if confirmed { Outcome::Measured(fix) } else { Outcome::Unconfirmed(fix) };
            }
            (None, Phase::Tracking(last) | Phase::HandedOver(last) | Phase::Doubted(last)) => {
                self.phase = Phase::Idle;
                // The Peripheral re-detects with the last look the track trusted, too.
                if let (Some(_), Some(t)) = (&self.adapt, &self.template) {
                    step.send(Dest::Peripheral, Msg::Template(t.clone()));
                }
                step.send(Dest::Peripheral, Msg::Lost(last));
                step.outcome = Outcome::Lost(last);
            }
            // A redirected window without a point is unconfirmed: taken by the first arm.
            (None, Phase::Idle | Phase::Redirected(_)) => {}
        }
    }

    /// Whether an adapting track's first template vouches for this window's point (issue 38),
    /// from its aligned score `aligned` ([`Adaptive::align`]) and the current template's
    /// `matched` score: where it aligns with at least `confirm_align`; where the last window
    /// was vouched for and the current template still matches with at least `hold_ncc_aligned`
    /// where the first template aligns under `confirm_align` (a view that changes a little a
    /// window: a tilt under blur dips the aligned score to 0.52 for 29 windows on
    /// `centre-combined`; a walking person's legs, an eye as the head turns), or with at least
    /// `hold_ncc` where it does not align at all (the hinge of `Megamind.avi` turns until its
    /// first view no longer aligns, matched at 0.96-0.99 a window); out of the chain, where the
    /// first template aligns and the current one matches with at least `rejoin_ncc` (or, where
    /// the object comes back out from behind a cover, [`Foveal::reappears`]); and, where
    /// it cannot align (a pattern without a gradient across, the 1080p test's colour bars),
    /// where it is itself the current template and matches as the thesis's fixed template
    /// must (`confirm_ncc`). A cover breaks the chain: the panel of the long-term set `panel`
    /// dips the match to 0.85 as it comes over the target, and a panel the template learnt
    /// does not align at all.
    fn first_vouches(&self, aligned: Option<f32>, matched: Option<f32>) -> bool {
        let matched = matched.unwrap_or(0.0);
        let bars = &self.params.track;
        let chain = self.sighting != Sighting::Unseen;
        match aligned {
            Some(s) => s >= bars.confirm_align || matched >= if chain { bars.hold_ncc_aligned } else { bars.rejoin_ncc },
            None => (chain && matched >= bars.hold_ncc) || (self.adapt.as_ref().is_some_and(Adaptive::on_first) && matched >= bars.confirm_ncc),
        }
    }

    /// Whether a window whose template matched with `score` teaches the template its look: one
    /// vouched for whole, or one in doubt whose match still holds at `learn_in_doubt` (issue 38
    /// item 1: a look-alike or a cover coming over the object drops the match); never one of a
    /// partly covered object, or of one coming back out.
    fn teaches(&self, score: f32) -> bool {
        match self.sighting {
            Sighting::Seen | Sighting::Recalled => true,
            Sighting::PartlyCovered | Sighting::Reappearing => false,
            Sighting::Unseen => score >= self.params.track.learn_in_doubt,
        }
    }

    /// Whether the look kept from the last window the model vouched for ([`Sighting::Seen`],
    /// [`Foveal::vouched_look`]) matches at
    /// the placement `at` (window pixels) where the current template matched best, by zero-mean
    /// NCC at [`FovealParams::vouched_look_ncc`]: out of the chain, with the first view
    /// aligned, the object as the chain last saw it (issue 38 items 1 and 3). After the chain
    /// breaks the current template goes on learning in doubt (`learn_in_doubt`) and drifts
    /// from the object's look; the look kept does not: vtest's redcoat walks away with her first
    /// view aligning at 0.5-0.8 and is vouched for on 34 more frames, none wrong.
    ///
    /// [`FovealParams::vouched_look_ncc`]: super::params::FovealParams::vouched_look_ncc
    fn vouched_look_matches(&self, win: &WindowView<'_>, at: (usize, usize)) -> bool {
        let Some(look) = self.vouched_look.as_ref().and_then(Template::view) else { return false };
        score_at(Method::Zncc, win, &look, at).is_ok_and(|s| s as f32 >= self.params.track.vouched_look_ncc)
    }

    /// Whether a track out of the chain recalls its object as the chain last saw it
    /// ([`Sighting::Recalled`]): the look last vouched for matches at `at`
    /// ([`Foveal::vouched_look_matches`]). Not where the Peripheral redirected the track (its
    /// location is taken unless the first view vouches at the full bar, as for
    /// [`Foveal::reappears`]).
    fn recalls(&self, win: &WindowView<'_>, at: (usize, usize)) -> bool {
        self.sighting == Sighting::Unseen && !matches!(self.phase, Phase::Redirected(_)) && self.vouched_look_matches(win, at)
    }

    /// Whether an adapting window whose match scored `score` breaks the chain of vouched rows
    /// in doubt: the chain held (the last row vouched for, the object whole, recalled, partly
    /// covered or coming back out), and the match is under `learn_in_doubt`, so the window
    /// teaches the template nothing either way (where it reaches that bar the window learns in
    /// doubt, unvouched, as before; checking those too moved no figure).
    fn in_doubt_breaks_the_chain(&self, score: f32) -> bool {
        self.sighting != Sighting::Unseen && score < self.params.track.learn_in_doubt
    }

    /// Whether an adapting track's object is under the window's match partly covered (issue 38
    /// item 1): at least [`FovealParams::cover_seen`] of the current template's blocks (a
    /// [`COVER_GRID`]-square grid) each still match by zero-mean NCC at `hold_ncc`, the chain's
    /// own bar, at the placement `at` (window pixels) where the whole template matched best.
    /// Under a panel over a third of `partial`'s target the whole template matches at 0.46,
    /// while its 8 uncovered blocks score 0.94-0.99, those under the panel's edge 0.67-0.83
    /// and those covered -0.43-0.00.
    ///
    /// [`FovealParams::cover_seen`]: super::params::FovealParams::cover_seen
    fn partly_covered(&self, win: &WindowView<'_>, at: (usize, usize)) -> bool {
        let (Some(tv), Some(_)) = (self.template.as_ref().and_then(Template::view), &self.adapt) else { return false };
        let bars = &self.params.track;
        let (matching, _) = blocks_matching(win, &tv, at, COVER_GRID, bars.hold_ncc);
        f32::from(matching) >= bars.cover_seen * (COVER_GRID * COVER_GRID) as f32
    }

    /// Whether a track out of the chain, or seeing its object come back out, sees it come out
    /// from behind a cover (issue 38 item 1), at most [`FovealParams::rejoin_run`] windows
    /// since its model last vouched for one otherwise (a track (re)started, none before it has;
    /// a redirected one takes the Peripheral's location): its first view, matched whole, aligns at `p` with `aligned`, at least
    /// [`FovealParams::rejoin_align`], within [`FovealParams::rejoin_near`] of where the motion
    /// aimed the window. Coming out from behind lookalike-front's look-alike the target's first
    /// view aligns at 0.59-0.76, 0.07-0.53 px from the truth, while the template learnt before
    /// the cover matches at 0.48-0.68 and 1-5 of its 16 blocks (the chain's bars ask 0.9). It
    /// needs the COOP guard's motion, as the [`Cut`] does. An object going under a cover is
    /// judged by the chain's bars and its blocks, not so: these bars vouched for a row of the
    /// crowd whose target was under half in view. A template the frame's edge cuts is vouched
    /// for by its alignment at `confirm_align` alone, as before.
    ///
    /// [`FovealParams::rejoin_align`]: super::params::FovealParams::rejoin_align
    /// [`FovealParams::rejoin_near`]: super::params::FovealParams::rejoin_near
    /// [`FovealParams::rejoin_run`]: super::params::FovealParams::rejoin_run
    fn reappears(&self, p: Point, aligned: f32) -> bool {
        let bars = &self.params.track;
        let coming_out = matches!(self.sighting, Sighting::Unseen | Sighting::Reappearing) && self.reappeared < bars.rejoin_run;
        // The Peripheral's location, where a track was redirected, is taken unless the first
        // view vouches for the track's own point at the full bar.
        coming_out && !matches!(self.phase, Phase::Redirected(_)) && aligned >= bars.rejoin_align && self.aimed.is_some_and(|q| dist(p, q) <= bars.rejoin_near)
    }

    /// Whether the point followed, with NCC's `score` where NCC vouches for it, is the
    /// target's (issue 38): an adapting track's where its first template vouches for the
    /// template's match in this window ([`Foveal::first_vouches`]), or, out of the chain, the
    /// first view aligns and the look last vouched for matches ([`Foveal::recalls`]), or
    /// enough of the template
    /// does where the object is partly covered ([`Foveal::partly_covered`]), or it comes back
    /// out from behind a cover ([`Foveal::reappears`]), and that match is the point followed;
    /// a fixed template's where NCC scores at least `confirm_ncc`. The corner detector alone
    /// has no model of the target: the thesis's CD tracker is vouched for as the thesis does,
    /// a COOP report of the corner alone is not.
    fn confirms(&self, score: Option<f32>) -> bool {
        match (self.kind, &self.adapt) {
            (FovealKind::Cd, _) => true,
            (_, Some(_)) => score.is_some() && self.sighting != Sighting::Unseen,
            (_, None) => score.is_some_and(|s| s >= self.params.track.confirm_ncc),
        }
    }

    /// Whether an adapting track has gone astray: more than `unconfirmed_run` windows not
    /// `confirmed` since it was last confirmed, counting those where the first
    /// template aligns without confirming (something like the target, but not it: a
    /// look-alike that passed in front, an occluder it learnt); it is then lost, and the
    /// Peripheral re-detects the object by its first view. A window where the first template
    /// does not align at all (the object looks unlike its first view) neither counts nor
    /// clears the run: the track holds, vouched for only while the chain holds
    /// ([`Foveal::first_vouches`]; opencv-doc's hinge and eye: 70 and 26 measured rows
    /// against 40 and 17 when every unconfirmed window counts).
    fn astray(&mut self, confirmed: bool) -> bool {
        if self.adapt.is_none() {
            return false;
        }
        self.unconfirmed = match confirmed {
            true => 0,
            false if self.shape.is_some() => self.unconfirmed.saturating_add(1),
            false => self.unconfirmed,
        };
        self.unconfirmed > self.params.track.unconfirmed_run
    }

    /// What of `tpl` an adapting track matches in the window aimed where the motion puts the
    /// point ([`Cut`]): all of it, unless the motion puts it past the frame's edges.
    fn cut(&self, tpl: &Template) -> Cut {
        match self.aimed.filter(|_| self.adapt.is_some()) {
            Some(q) => Cut::past_edges(q.x - tpl.anchor().x, q.y - tpl.anchor().y, tpl.side(), (self.params.frame_w, self.params.frame_h)),
            None => Cut::default(),
        }
    }

    /// The Foveal window after following `p` at `t`: with [`Params::adapt`], centred where
    /// the motion puts the point at the next window, widened on each side by half the
    /// predicted step, or by `grow_margin` after a match on the window's edge or before the
    /// motion is known; otherwise the thesis's, centred on `p`.
    fn next_window(&mut self, p: Point, t: f64) -> WindowRequest {
        if self.adapt.is_none() {
            return self.params.foveal_window(p);
        }
        // Without a prediction yet (the track's first window) the motion is unknown too. A
        // fast target also accelerates by more: half its step a window is added, or the
        // prediction's recent miss where that is larger (a hand-held camera's shake, a low
        // frame rate).
        let ahead = self.coop.ahead(t);
        self.aimed = ahead;
        let extra = match ahead {
            Some(q) if !self.pinned => (dist(p, q) / 2.0).max(self.miss),
            _ => self.miss.max(f32::from(self.params.track.grow_margin)),
        };
        let extra = (libm::ceilf(extra) as u16).min(self.params.track.max_margin);
        self.params.window(ahead.unwrap_or(p), self.params.foveal + 2 * extra, Decimation::Full)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernels::matching::Method;
    use crate::processors::partner::CornerPartner;
    use crate::processors::params::FovealParams;
    use crate::processors::testing::{cut, frame, params, square, template, texture, SIDE, TARGET};

    fn near(p: Point, q: Point) -> bool {
        (p.x - q.x).abs() < 0.01 && (p.y - q.y).abs() < 0.01
    }

    /// The position `s` measured; a test's failure where it measured none.
    fn fix(s: &Step) -> Fix {
        *s.outcome.fix().unwrap_or_else(|| panic!("no position measured: {:?}", s.outcome))
    }

    #[test]
    fn ncc_tracks_the_block_and_loses_it_when_it_goes() {
        let mut f = Foveal::new(FovealKind::Ncc, params(), Some(template()));
        let s = f.start_at(TARGET);
        let win = square(24, 14, 16, Decimation::Full);
        assert_eq!((s.request, s.sends.len(), f.mode()), (Some(win), 0, Mode::Track));
        // The template (8x8) placed at its own pixels: NCC 1, the point where it started.
        let s = f.on_window(&cut(&frame(Some((30, 20))), &win), 0.0);
        assert_eq!(s.work, Work::Match { method: Method::Ncc, template: 64, placements: 81 });
        let Fix { at: p, source, score, .. } = fix(&s);
        assert!(near(p, TARGET) && source == Source::Ncc, "{p:?}");
        assert!(score.is_some_and(|v| v > 0.999_99), "the report carries NCC's score: {score:?}");
        assert_eq!(&s.sends[..], &[(Dest::Peripheral, Msg::Tracked(p))][..]);
        assert_eq!(s.request, Some(win));
        // The block moves by (2, 1): so does the point, and the window follows
        // (round(33.5 - 7.5) = 26, round(22.5 - 7.5) = 15).
        let s = f.on_window(&cut(&frame(Some((32, 21))), &win), 0.04);
        let p = fix(&s).at;
        assert!(near(p, Point { x: 33.5, y: 22.5 }), "{p:?}");
        assert_eq!(s.request, Some(square(26, 15, 16, Decimation::Full)));
        // A flat window: NCC 5600 / sqrt(760000 * 64) = 0.80 < 0.97, lost where it last was.
        let s = f.on_window(&cut(&frame(None), &win), 0.08);
        assert_eq!((s.outcome, s.request), (Outcome::Lost(p), None));
        assert_eq!(&s.sends[..], &[(Dest::Peripheral, Msg::Lost(p))][..]);
        assert_eq!(f.mode(), Mode::Watch);
    }

    #[test]
    fn an_adapting_window_widens_by_the_motions_surprise() {
        // The block moves 2 px a window (40 ms) for four windows, then 5: the fifth window,
        // aimed where the motion predicted (x 39.5), finds the point 3 px further (42.5). The
        // next window adds that miss on each side (16 + 2 x 3 = 22 px), where half the
        // predicted step alone (about 1.5 px, rounded up to 2) would give 20.
        // The motion is the COOP guard's: a master, its partner finding no corner.
        let mut f = Foveal::new(FovealKind::CoopMaster, params().adaptive(), Some(template()));
        let mut req = f.start_at(TARGET).request.unwrap();
        let mut last = None;
        for (k, x) in [30, 32, 34, 36, 41].into_iter().enumerate() {
            let t = 0.04 * k as f64;
            f.on_window(&cut(&frame(Some((x, 20))), &req), t);
            let s = f.on_message(&Msg::Result(None), t);
            let p = fix(&s).at;
            assert!(near(p, Point { x: TARGET.x + (x - 30) as f32, y: TARGET.y }), "window {k}: {p:?}");
            req = s.request.unwrap();
            last = Some(p);
        }
        assert!((f.miss - 3.0).abs() < 0.01, "{}", f.miss);
        let ahead = f.coop.ahead(0.16).unwrap();
        assert!(libm::ceilf(dist(last.unwrap(), ahead) / 2.0) < 3.0, "{ahead:?}");
        assert_eq!(req.width, 16 + 2 * 3);
    }

    #[test]
    fn an_adapting_track_resumed_from_an_approximate_location_looks_wider() {
        // The Peripheral's location is good to its 25 % grid: the thesis's window is the
        // template plus 4 px (16 px, columns round(31.5 - 7.5) = 24..); an adapting track adds
        // `grow_margin` a side: 28 px from round(31.5 - 13.5) = 18, rows from round(21.5 - 13.5) = 8.
        let thesis = Foveal::new(FovealKind::Ncc, params(), Some(template())).on_message(&Msg::Approx(TARGET), 0.0);
        assert_eq!(thesis.request, Some(square(24, 14, 16, Decimation::Full)));
        let mut adapting = Foveal::new(FovealKind::Ncc, params().adaptive(), Some(template()));
        assert!(adapting.adapt.is_some(), "a whole template (no corner support) adapts");
        let s = adapting.on_message(&Msg::Approx(TARGET), 0.0);
        assert_eq!(s.request, Some(square(18, 8, 16 + 2 * FovealParams::default().grow_margin, Decimation::Full)));
    }

    #[test]
    fn a_corner_template_keeps_its_support_unless_a_box_gives_the_object() {
        // A 20x20 template centred on the corner of a textured quadrant (columns 30.., rows
        // 20..) over a flat background. Given as a point, it is matched over the corner's
        // support, fixed or not, and does not adapt; given inside a box around the object,
        // an adapting one is matched whole and adapts, a fixed one keeps its support.
        let mut f = std::vec![40u8; SIDE * SIDE];
        for y in 20..SIDE {
            for x in 30..SIDE {
                f[y * SIDE + x] = (120 + ((x - 30) * 7 + (y - 20) * 13) % 50) as u8;
            }
        }
        let corner = Template::capture(&WindowView::packed(&f, SIDE, SIDE).unwrap(), Point { x: 30.5, y: 20.5 }, 20).unwrap();
        let p20 = Params { template: 20, foveal: 24, ..params() };
        for (p, supported, adapts) in [
            (p20, true, false),
            (p20.adaptive(), true, false),
            (Params { target_boxed: true, ..p20 }, true, false),
            (Params { target_boxed: true, ..p20.adaptive() }, false, true),
        ] {
            let tracker = Foveal::new(FovealKind::Ncc, p, Some(corner.clone()));
            assert_eq!((tracker.support.is_some(), tracker.adapt.is_some()), (supported, adapts), "{p:?}");
        }
    }

    #[test]
    fn a_handed_over_track_takes_back_the_first_template_and_needs_the_redetection_bar() {
        // The track had adapted to a look with two more bright pixels (its current template);
        // the block shows again as it was cut: handed over, the first template (score 1) wins
        // over the current one and is taken back.
        let mut changed = frame(Some((30, 20)));
        (changed[21 * 64 + 29], changed[22 * 64 + 34]) = (200, 200);
        let look = Template::capture(&WindowView::packed(&changed, 64, 64).unwrap(), TARGET, 8).unwrap();
        let handed = |look: &Template| {
            let mut f = Foveal::new(FovealKind::Ncc, params().adaptive(), Some(template()));
            f.adopt(look.clone());
            let req = f.on_message(&Msg::Approx(TARGET), 0.0).request.unwrap();
            (f, req)
        };
        let (mut f, req) = handed(&look);
        let s = f.on_window(&cut(&frame(Some((30, 20))), &req), 0.0);
        // Both searches are charged: twice the 21x21 placements of an 8x8 template in 28x28.
        assert_eq!(s.work, Work::Match { method: Method::Zncc, template: 64, placements: 2 * 21 * 21 });
        let p = fix(&s).at;
        assert!(near(p, TARGET), "{p:?}");
        assert!(f.template == Some(template()), "the first template is taken back");
        // A 2x2 block where the Peripheral pointed: zero-mean NCC 192 / sqrt(768 x 240) = 0.447
        // for either template (hand calculation), over the 0.4 a running track accepts but under
        // the 0.7 of a re-detection: refused, the track lost again.
        let mut small = frame(None);
        for y in 21..23 {
            small[y * 64 + 31..y * 64 + 33].fill(200);
        }
        let (mut f, req) = handed(&template());
        let s = f.on_window(&cut(&small, &req), 0.0);
        assert_eq!(s.outcome, Outcome::Lost(TARGET));
        // Refused, a track keeps the look it had, even where the first template scored higher.
        let (mut f, req) = handed(&look);
        assert!(f.on_window(&cut(&small, &req), 0.0).outcome.fix().is_none());
        assert!(f.template == Some(look.clone()), "the adapted look is kept");
        // The same window in a running track is accepted.
        let mut running = Foveal::new(FovealKind::Ncc, params().adaptive(), Some(template()));
        let req = running.start_at(TARGET).request.unwrap();
        let s = running.on_window(&cut(&small, &req), 0.0);
        assert!(fix(&s).score.is_some_and(|v| (v - 0.447).abs() < 0.001), "{:?}", s.outcome);
    }

    #[test]
    fn a_coasting_adapting_master_asks_the_peripheral_once_and_restarts_where_it_finds_the_target() {
        let mut master = Foveal::new(FovealKind::CoopMaster, params().adaptive(), Some(template()));
        let mut req = master.start_at(TARGET).request.unwrap();
        // Two positions: a motion to coast with.
        for t in [0.0, 0.01] {
            master.on_window(&cut(&frame(Some((30, 20))), &req), t);
            let s = master.on_message(&Msg::Result(None), t);
            assert!(s.outcome.fix().is_some());
            req = s.request.unwrap();
        }
        // The block is gone: nothing measured, the track coasts, predicting the point; the
        // Peripheral is told where the track expects it, on the first such window only.
        let (mut told, mut predicted) = ([None; 2], [None; 2]);
        for (k, t) in [0.02, 0.03].into_iter().enumerate() {
            master.on_window(&cut(&frame(None), &req), t);
            let s = master.on_message(&Msg::Result(None), t);
            let Outcome::Predicted(q) = s.outcome else { panic!("window {k}: {:?}", s.outcome) };
            assert!(master.coasting());
            told[k] = s.sends.iter().find_map(|(d, m)| match m {
                Msg::Coasting(q) if *d == Dest::Peripheral => Some(*q),
                _ => None,
            });
            predicted[k] = Some(q);
            req = s.request.unwrap();
        }
        assert!(told[0].is_some() && told == [predicted[0], None], "{told:?}");
        // The Peripheral finds the block elsewhere: the track restarts there, as a handed-over
        // one (the wider window, the partner told), no longer coasting.
        let found = Point { x: 41.5, y: 31.5 };
        let s = master.on_message(&Msg::Approx(found), 0.04);
        assert_eq!(s.request, Some(master.params.window(found, 16 + 2 * master.params.track.grow_margin, Decimation::Full)));
        assert_eq!(&s.sends[..], &[(Dest::FovealCd, Msg::Follow(found))][..]);
        assert!(!master.coasting() && s.outcome == Outcome::Redetected(found));
    }

    #[test]
    fn the_coop_master_decides_once_both_results_of_a_window_are_in() {
        let mut master = Foveal::new(FovealKind::CoopMaster, params(), Some(template()));
        let mut partner = CornerPartner::new(params());
        let win = square(24, 14, 16, Decimation::Full);
        let s = master.start_at(TARGET);
        assert_eq!(&s.sends[..], &[(Dest::FovealCd, Msg::Follow(TARGET))][..]);
        assert_eq!(partner.on_message(&Msg::Follow(TARGET)).request, Some(win));
        let block = frame(Some((30, 20)));
        // The partner answers with its corner, whatever it is; it reports nothing itself.
        let s = partner.on_window(&cut(&block, &win));
        assert!(matches!(&s.sends[..], [(Dest::Foveal, Msg::Result(_))]) && s.outcome == Outcome::Silent);
        // The master's own NCC waits for the partner's result.
        let s = master.on_window(&cut(&block, &win), 0.0);
        assert_eq!((s.outcome, s.request, s.sends.len()), (Outcome::Silent, None, 0));
        // No corner: trusted NCC (score 1 >= 0.99) is followed, and the partner told to follow.
        let s = master.on_message(&Msg::Result(None), 0.0);
        let Fix { at: p, source, score, .. } = fix(&s);
        assert!(near(p, TARGET) && source == Source::Ncc, "{p:?}");
        assert!(score.is_some_and(|v| v > 0.999_99), "NCC vouches for its own point: {score:?}");
        assert_eq!(s.work, Work::Decision);
        assert_eq!(&s.sends[..], &[(Dest::Peripheral, Msg::Tracked(p)), (Dest::FovealCd, Msg::Follow(p))][..]);
    }

    #[test]
    fn a_doubted_track_asks_for_a_search_and_takes_a_hand_over_after_the_window_in_flight() {
        let mut f = Foveal::new(FovealKind::Ncc, params().adaptive(), Some(template()));
        let req = f.start_at(TARGET).request.unwrap();
        assert!(f.on_window(&cut(&frame(Some((30, 20))), &req), 0.0).outcome.vouched().is_some());
        // A point the first template does not vouch for (the corner detector's alone): followed,
        // unvouched, and the Peripheral told to look elsewhere rather than that it is tracked.
        let held = Point { x: 33.5, y: 21.5 };
        let mut step = Step::new(Work::None);
        f.follow(&mut step, 0.04, Some(held), Source::Cd, None);
        assert!(matches!(step.outcome, Outcome::Unconfirmed(fix) if fix.at == held));
        assert_eq!(&step.sends[..], &[(Dest::Peripheral, Msg::Doubted(held))][..]);
        let in_flight = step.request.unwrap();
        // The Peripheral finds the object at (11.5, 41.5): nothing is asked yet, as the window
        // in flight comes first; it shows nothing, and the next window is around the location,
        // as a re-detection's (`grow_margin` a side: columns round(11.5 - 13.5) -> 0).
        let to = Point { x: 11.5, y: 41.5 };
        let s = f.on_message(&Msg::Approx(to), 0.05);
        assert_eq!((s.request, f.phase), (None, Phase::Redirected(to)));
        let s = f.on_window(&cut(&frame(None), &in_flight), 0.08);
        assert_eq!((s.outcome, s.request), (Outcome::Redetected(to), Some(square(0, 28, 16 + 2 * FovealParams::default().grow_margin, Decimation::Full))));
    }

    #[test]
    fn a_window_that_confirms_the_object_keeps_the_track_where_it_is() {
        let mut f = Foveal::new(FovealKind::Ncc, params().adaptive(), Some(template()));
        let req = f.start_at(TARGET).request.unwrap();
        f.on_window(&cut(&frame(Some((30, 20))), &req), 0.0);
        let mut step = Step::new(Work::None);
        f.follow(&mut step, 0.04, Some(TARGET), Source::Cd, None);
        f.on_message(&Msg::Approx(Point { x: 11.5, y: 41.5 }), 0.05);
        // The window in flight shows the object as it was cut: vouched for, and the hand-over
        // dropped.
        let s = f.on_window(&cut(&frame(Some((30, 20))), &step.request.unwrap()), 0.08);
        assert!(s.outcome.vouched().is_some_and(|fix| near(fix.at, TARGET)), "{:?}", s.outcome);
        assert!(matches!(f.phase, Phase::Tracking(p) if near(p, TARGET)));
    }

    #[test]
    fn a_vouched_track_stays_vouched_while_its_template_matches_at_the_hold_bar() {
        let mut f = Foveal::new(FovealKind::Ncc, params().adaptive(), Some(template()));
        let req = f.start_at(TARGET).request.unwrap();
        assert!(f.on_window(&cut(&frame(Some((30, 20))), &req), 0.0).outcome.vouched().is_some());
        // The first view no longer aligns: held from `hold_ncc` (under `confirm_ncc`, from
        // which the first template alone vouches for itself).
        let bars = f.params.track;
        assert!(f.first_vouches(None, Some(bars.hold_ncc)));
        assert!(!f.first_vouches(None, Some(bars.hold_ncc - 0.01)), "a dip under the bar breaks the chain");
        // Where it still aligns (from `ALIGN`, under `confirm_align`), from `hold_ncc_aligned`.
        for aligned in [crate::processors::adapt::ALIGN, bars.confirm_align - 0.01] {
            assert!(f.first_vouches(Some(aligned), Some(bars.hold_ncc_aligned)), "{aligned}");
            assert!(!f.first_vouches(Some(aligned), Some(bars.hold_ncc_aligned - 0.01)), "{aligned}: under both bars");
        }
        // A window followed unvouched (the corner detector's point, no NCC score) is no link.
        let mut step = Step::new(Work::None);
        f.follow(&mut step, 0.04, Some(TARGET), Source::Cd, None);
        assert!(matches!(step.outcome, Outcome::Unconfirmed(_)));
        // Out of the chain, a first view that aligns (under `confirm_align`) and a match at
        // `rejoin_ncc` vouch again; the chain's own bar does not.
        let weak = bars.confirm_align - 0.01;
        assert!(f.first_vouches(Some(weak), Some(bars.rejoin_ncc)));
        assert!(!f.first_vouches(Some(weak), Some(bars.rejoin_ncc - 0.01)) && !f.first_vouches(Some(weak), Some(bars.hold_ncc_aligned)));
        // A first view that does not align vouches for nothing out of the chain (but for the
        // first template itself at `confirm_ncc`); one that aligns at `confirm_align`, whatever
        // the match.
        assert!(!f.first_vouches(None, Some(0.95)));
        assert!(f.first_vouches(Some(bars.confirm_align), None));
    }

    #[test]
    fn a_track_in_doubt_learns_only_from_a_window_whose_match_holds() {
        // The block grown to 4x8: a look its first view does not confirm, so the window
        // proposes a template cut from it.
        let mut grown = frame(Some((30, 20)));
        for y in 24..28 {
            grown[y * SIDE + 30..y * SIDE + 34].fill(200);
        }
        let bar = FovealParams::default().learn_in_doubt;
        // (vouched for, match, learns): a vouched row learns whatever its match.
        for (vouched, score, learns) in [(false, bar, true), (false, bar - 0.01, false), (true, bar - 0.01, true)] {
            let mut f = Foveal::new(FovealKind::Ncc, params().adaptive(), Some(template()));
            let req = f.start_at(TARGET).request.unwrap();
            f.adapt.as_mut().unwrap().propose(&cut(&grown, &req), TARGET, score, 8, false);
            f.sighting = if vouched { Sighting::Seen } else { Sighting::Unseen };
            let before = f.template.clone();
            let mut step = Step::new(Work::None);
            f.follow(&mut step, 0.04, Some(TARGET), Source::Ncc, Some(score));
            assert_eq!(step.outcome.vouched().is_some(), vouched, "{:?}", step.outcome);
            assert_eq!(f.template != before, learns, "match {score}: learns {learns}");
            // A template refused leaves the track on its first one, as it says.
            assert_eq!(f.adapt.as_ref().unwrap().on_first(), !learns);
        }
    }

    #[test]
    fn a_partly_covered_object_is_vouched_for_while_half_its_blocks_match_and_teaches_nothing() {
        // A 16x16 template of random texture at the frame's centre; covers of other random
        // texture over its left 6 and 10 columns (of 16): the 4x4 grid of 4x4 blocks keeps
        // its two right block columns (8 of 16 blocks, half) and one (4).
        let mut px = 0x2545_f491u32;
        let scene = texture(&mut px, SIDE * SIDE, 60);
        let cover = texture(&mut px, SIDE * SIDE, 60);
        let covered = |cols: usize| {
            let mut f = scene.clone();
            for y in 24..40 {
                f[y * SIDE + 24..y * SIDE + 24 + cols].copy_from_slice(&cover[y * SIDE + 24..y * SIDE + 24 + cols]);
            }
            f
        };
        let at = Point { x: 31.5, y: 31.5 };
        let tpl = Template::capture(&WindowView::packed(&scene, SIDE, SIDE).unwrap(), at, 16).unwrap();
        let p = Params { template: 16, foveal: 24, ..params() }.adaptive();
        let mut f = Foveal::new(FovealKind::Ncc, p, Some(tpl.clone()));
        let mut req = f.start_at(at).request.unwrap();
        let mut run = |f: &mut Foveal, img: &[u8], t: f64| {
            let s = f.on_window(&cut(img, &req), t);
            req = s.request.unwrap_or(req);
            s.outcome
        };
        assert!(run(&mut f, &scene, 0.0).vouched().is_some(), "uncovered");
        // A third covered: the whole match breaks the chain, half the blocks hold it. The point
        // is the object's (within half a pixel: the cover pulls the first view's alignment,
        // here by 0.29 px), and the template learns nothing from the cover.
        let third = covered(6);
        let out = run(&mut f, &third, 0.04);
        assert_eq!(f.sighting, Sighting::PartlyCovered);
        assert!(out.vouched().is_some_and(|fix| dist(fix.at, at) < 0.5), "{out:?}");
        assert!(f.template == Some(tpl.clone()) && f.adapt.as_ref().is_some_and(Adaptive::on_first));
        // Still a third covered: the chain holds, window after window.
        assert!(run(&mut f, &third, 0.08).vouched().is_some());
        // Covered further, a quarter of the blocks left: not vouched for.
        let out = run(&mut f, &covered(10), 0.12);
        assert!(out.vouched().is_none() && f.sighting == Sighting::Unseen, "{out:?}");
        // Out of the chain, a third covered is not vouched for: it only holds a chain.
        assert!(run(&mut f, &third, 0.16).vouched().is_none());
    }

    #[test]
    fn out_of_the_chain_the_look_last_vouched_for_vouches_again_where_the_first_view_aligns() {
        // A 16x16 object of random texture at the centre of the 64x64 frame, tracked by NCC
        // alone (no motion: nothing is vouched for as coming out). Its look has changed: other
        // texture over its left 6 columns of 16, so its first view aligns under
        // `confirm_align` (a hand calculation: ZNCC of a view 10/16 the object's, about 0.6).
        // The current template is that look with its right 3 columns learnt from something
        // else (13/16 the look: about 0.8, under `rejoin_ncc`).
        let mut px = 0x2545_f491u32;
        let scene = texture(&mut px, SIDE * SIDE, 60);
        let other = texture(&mut px, SIDE * SIDE, 60);
        let over = |img: &[u8], cols: core::ops::Range<usize>| {
            let mut f = img.to_vec();
            for y in 24..40 {
                f[y * SIDE + 24 + cols.start..y * SIDE + 24 + cols.end].copy_from_slice(&other[y * SIDE + 24 + cols.start..y * SIDE + 24 + cols.end]);
            }
            f
        };
        let at = Point { x: 31.5, y: 31.5 };
        let view = |img: &[u8]| Template::capture(&WindowView::packed(img, SIDE, SIDE).unwrap(), at, 16).unwrap();
        let looks = over(&scene, 0..6);
        let (first, look, drifted) = (view(&scene), view(&looks), view(&over(&looks, 13..16)));
        let p = Params { template: 16, foveal: 24, ..params() }.adaptive();
        // (the look kept, the Peripheral's location in flight, vouched for).
        for (kept, redirected, vouched) in [(None, false, false), (Some(view(&other)), false, false), (Some(look.clone()), true, false), (Some(look.clone()), false, true)] {
            let mut f = Foveal::new(FovealKind::Ncc, p, Some(first.clone()));
            let req = f.start_at(at).request.unwrap();
            f.adopt(drifted.clone());
            f.vouched_look = kept.clone();
            if redirected {
                f.phase = Phase::Redirected(Point { x: 10.0, y: 10.0 });
            }
            let out = f.on_window(&cut(&looks, &req), 0.04).outcome;
            assert_eq!(out.vouched().is_some(), vouched, "{out:?}");
            assert!(out.fix().is_some_and(|fix| dist(fix.at, at) < 0.5) || redirected, "{out:?}");
            // The window the look recalled does not replace it with the template learnt in
            // doubt; a track restarted where the Peripheral found the object keeps none.
            assert_eq!((f.sighting == Sighting::Recalled, &f.vouched_look), (vouched, if redirected { &None } else { &kept }));
        }
        // The look kept is the template that matched a window the model vouched for: not the
        // first (its own view vouches for it), then the one that window taught the track.
        let mut f = Foveal::new(FovealKind::Ncc, p, Some(first.clone()));
        let req = f.start_at(at).request.unwrap();
        f.vouched_look = Some(view(&other));
        let vouched_window = |f: &mut Foveal| {
            f.sighting = Sighting::Seen;
            f.follow(&mut Step::new(Work::None), 0.04, Some(at), Source::Ncc, Some(0.95));
        };
        f.adapt.as_mut().unwrap().propose(&cut(&looks, &req), at, 0.95, 16, false);
        vouched_window(&mut f);
        let learnt = f.template.clone();
        assert!(f.vouched_look.is_none() && learnt.as_ref().is_some_and(|t| t != f.adapt.as_ref().unwrap().first()));
        vouched_window(&mut f);
        assert_eq!(f.vouched_look, learnt);
        // A window not vouched for keeps it, whatever template matched.
        f.adopt(view(&other));
        f.adapt.as_mut().unwrap().propose(&cut(&scene, &req), at, 0.95, 16, false);
        f.sighting = Sighting::Unseen;
        f.follow(&mut Step::new(Work::None), 0.08, Some(at), Source::Ncc, Some(0.95));
        assert_eq!(f.vouched_look, learnt);
        // An object coming out where the motion aimed the window (here from an alignment of
        // 0.5) is judged so first: vouched for, teaching nothing, the look kept as it was.
        let coming_out = Params { track: FovealParams { rejoin_align: 0.5, ..p.track }, ..p };
        let mut f = Foveal::new(FovealKind::Ncc, coming_out, Some(first));
        let req = f.start_at(at).request.unwrap();
        f.adopt(drifted.clone());
        (f.vouched_look, f.aimed, f.reappeared) = (Some(look.clone()), Some(at), 0);
        let out = f.on_window(&cut(&looks, &req), 0.04).outcome;
        assert!(out.vouched().is_some() && f.sighting == Sighting::Reappearing, "{out:?}");
        assert!(f.template == Some(drifted) && f.vouched_look == Some(look));
    }

    #[test]
    fn a_target_leaving_the_view_is_vouched_for_while_half_its_template_is_in_it() {
        // A 24x24 patch of random texture on flat grey moves 3 px a window (40 ms) out of the
        // 64x64 frame, through each of its sides, tracked from its centre (31.5, 31.5) with a
        // 16x16 template. The template fits the frame up to window 8 (7.5 px from the edge);
        // in windows 9 and 10, 13 and 10 of its 16 columns (or rows) are in view, in window 11
        // 7, under half. The motion is the COOP guard's: a master, its partner finding no corner.
        let patch = texture(&mut 0x2545_f491, 24 * 24, 40);
        let scene = |(left, top): (isize, isize)| {
            let mut f = std::vec![100u8; SIDE * SIDE];
            for (y, row) in patch.chunks(24).enumerate() {
                for (x, &v) in row.iter().enumerate() {
                    let (fx, fy) = (usize::try_from(left + x as isize), usize::try_from(top + y as isize));
                    if let (Ok(fx @ 0..SIDE), Ok(fy @ 0..SIDE)) = (fx, fy) {
                        f[fy * SIDE + fx] = v;
                    }
                }
            }
            f
        };
        let at = Point { x: 31.5, y: 31.5 };
        let tpl = Template::capture(&WindowView::packed(&scene((20, 20)), SIDE, SIDE).unwrap(), at, 16).unwrap();
        for (dx, dy) in [(3, 0), (-3, 0), (0, 3), (0, -3)] {
            let mut f = Foveal::new(FovealKind::CoopMaster, Params { template: 16, foveal: 24, ..params() }.adaptive(), Some(tpl.clone()));
            let mut req = f.start_at(at).request.unwrap();
            for k in 0..=11 {
                let t = 0.04 * k as f64;
                f.on_window(&cut(&scene((20 + dx * k, 20 + dy * k)), &req), t);
                let s = f.on_message(&Msg::Result(None), t);
                let truth = Point { x: at.x + (dx * k) as f32, y: at.y + (dy * k) as f32 };
                match s.outcome.vouched() {
                    // Exact copies of the patch: the point to a tenth of a pixel.
                    Some(fix) if k <= 10 => assert!(dist(fix.at, truth) < 0.1, "({dx}, {dy}), window {k}: {fix:?}"),
                    None if k == 11 => {}
                    _ => panic!("({dx}, {dy}), window {k}: {:?}", s.outcome),
                }
                req = s.request.unwrap_or(req);
            }
        }
    }

    #[test]
    fn an_object_coming_out_from_behind_a_cover_is_vouched_for_where_the_motion_aimed() {
        // A 16x16 template of random texture moving 1 px a window (40 ms) to the right, tracked
        // by a COOP master (its partner finding no corner: the motion is the guard's). A cover
        // of other random texture hides it for 4 windows (the guard coasts on), then lies over
        // its left 6 columns of 16 as it comes out: the template learnt before the cover
        // matches there, if weakly, and its first view aligns, under `confirm_align` (a hand
        // calculation: ZNCC of a view 10/16 the object's, about 0.6 where the cover is as
        // varied as the object).
        let mut px = 0x2545_f491u32;
        let object = texture(&mut px, 16 * 16, 60);
        let cover = texture(&mut px, SIDE * SIDE, 60);
        // The object with its top-left pixel at (left, 24), its left `covered` columns under
        // the cover (all 16: hidden).
        let scene = |left: usize, covered: usize| {
            let mut f = std::vec![100u8; SIDE * SIDE];
            for y in 0..16 {
                let row = (24 + y) * SIDE + left;
                f[row..row + 16].copy_from_slice(&object[y * 16..y * 16 + 16]);
                f[row..row + covered].copy_from_slice(&cover[row..row + covered]);
            }
            f
        };
        // The object at (left, 24) with every third column of it under the cover: two thirds
        // of it seen, in each of its blocks (none matches at the chain's 0.9).
        let striped = |left: usize| {
            let mut f = scene(left, 0);
            for y in 24..40 {
                for x in (left..left + 16).step_by(3) {
                    f[y * SIDE + x] = cover[y * SIDE + x];
                }
            }
            f
        };
        let at = Point { x: 27.5, y: 31.5 };
        let tpl = Template::capture(&WindowView::packed(&scene(20, 0), SIDE, SIDE).unwrap(), at, 16).unwrap();
        // Where it comes out, 8 windows on, where the motion aims the window.
        let aimed = Point { x: 35.5, y: 31.5 };
        // The row of the window that shows the object coming out `moved` px right of where the
        // motion aims, and whether each of the next 8 windows, the object striped, is vouched.
        let coming_out = |track: FovealParams, moved: usize| {
            let p = Params { template: 16, foveal: 24, track, ..params() }.adaptive();
            let mut f = Foveal::new(FovealKind::CoopMaster, p, Some(tpl.clone()));
            let mut req = f.start_at(at).request.unwrap();
            let mut run = |f: &mut Foveal, img: &[u8], t: f64| {
                f.on_window(&cut(img, &req), t);
                let s = f.on_message(&Msg::Result(None), t);
                req = s.request.unwrap_or(req);
                s.outcome
            };
            for k in 0..4 {
                assert!(run(&mut f, &scene(20 + k, 0), 0.04 * k as f64).vouched().is_some(), "window {k}");
            }
            for k in 4..8 {
                assert!(matches!(run(&mut f, &scene(20 + k, 16), 0.04 * k as f64), Outcome::Predicted(_)), "window {k}");
            }
            let out = run(&mut f, &scene(28 + moved, 6), 0.32);
            let (sighting, kept) = (f.sighting, f.template == Some(tpl.clone()));
            let next: std::vec::Vec<bool> = (9..17).map(|k| run(&mut f, &striped(20 + k + moved), 0.04 * k as f64).vouched().is_some()).collect();
            (out, sighting, kept, next)
        };
        // Where the motion aims: vouched for, to a quarter of a pixel (the cover pulls the
        // alignment, here by 0.16 px), and the template learns nothing from the part of the
        // view that is the cover's. Were the window still aimed where the track went under
        // (4 px back) it would not be: each coasting window is aimed at the coast's prediction.
        let (out, sighting, kept, next) = coming_out(FovealParams::default(), 0);
        assert!(out.vouched().is_some_and(|fix| dist(fix.at, aimed) < 0.25), "{out:?}");
        assert!(sighting == Sighting::Reappearing && kept);
        // Seen no better in the windows after, it is vouched for in `rejoin_run` (4) windows in
        // all, then no more until its model vouches for it otherwise: an object is out within a
        // few windows. Before stop 54 the guard aimed the first after as far ahead as the
        // coast's span (40.8 with the object at 36.5), and it was refused.
        assert_eq!(next, [true, true, true, false, false, false, false, false]);
        // Without the rule (no aligned score reaches 1.1), the same window is not vouched for:
        // the chain's bars, asked of the whole template, refuse it.
        let (out, ..) = coming_out(FovealParams { rejoin_align: 1.1, ..FovealParams::default() }, 0);
        assert!(out.vouched().is_none() && out.fix().is_some(), "{out:?}");
        // Come out 4 px from where the motion aimed (2 px the most): measured, not vouched for.
        let (out, ..) = coming_out(FovealParams::default(), 4);
        assert!(out.vouched().is_none() && out.fix().is_some_and(|fix| dist(fix.at, Point { x: aimed.x + 4.0, ..aimed }) < 0.5), "{out:?}");
    }

    #[test]
    fn no_hand_over_is_taken_once_the_motion_prior_has_lapsed() {
        let lost = |track: FovealParams, t: f64| {
            let mut f = Foveal::new(FovealKind::Ncc, Params { track, ..params().adaptive() }, Some(template()));
            let req = f.start_at(TARGET).request.unwrap();
            f.on_window(&cut(&frame(Some((30, 20))), &req), 0.0);
            f.on_window(&cut(&frame(None), &req), 0.04);
            assert_eq!(f.mode(), Mode::Watch, "lost");
            f.on_message(&Msg::Approx(TARGET), t).request
        };
        // Vouched for last at 0 s: a location `prior_seconds` (3 s by default) later is still
        // taken, not one after; 1 s where that is the lapse.
        let default = FovealParams::default();
        assert!(lost(default, 3.0).is_some());
        assert_eq!(lost(default, 3.01), None);
        let brief = FovealParams { prior_seconds: 1.0, ..default };
        assert!(lost(brief, 1.0).is_some());
        assert_eq!(lost(brief, 1.01), None);
    }
}
