//! The window processors of the thesis's windowing strategies (2.3, 2.5, 4.2) as event-driven
//! state machines: each is handed the pixels of the window it asked for, or a message from
//! another processor, and answers with a [`Step`]: the kernel work it did (for a cost model),
//! the window it wants next, the messages it sends and the position it reports.
//!
//! - [`Watch`]: image differencing over a whole frame or a strip (2.4), reporting motion;
//! - [`Peripheral`]: SSD at 25% resolution to locate the target approximately, growing its
//!   window (40x40, then 64x64) when it fails (Detection mode, Table 2.2);
//! - [`Foveal`]: NCC (or the corner detector) at full resolution for accurate tracking; in
//!   COOP a second Foveal window runs the other algorithm on the same coordinates and the
//!   least-squares confidence measure picks the result each frame (4.3);
//! - [`Spmf`]: the single processor that runs Watch, Detection and Tracking in turn (2.3.1).
//!
//! The hardware is reached only through the [`Step`]s: the caller (a board's main loop, or the
//! testbench's simulation) turns requests into coordinate writes
//! ([`crate::window_ports::CoordinateWriter`]) and messages into link traffic
//! ([`crate::ports::FramedLink`]); the testbench does both through these same types.
use crate::confidence::{ConfidencePolicy, KalmanCoop, SseCoop, Source};
use crate::corner::{CornerDetector, CornerParams};
use crate::guard::{Guard, GuardParams, Measured};
use crate::matching::{best_match, Method};
use crate::motion::detect_motion;
use crate::refine::{refine_translation, refine_translation_on};
use crate::support::{best_match_on, Support};
use crate::ports::{Decimation, WindowRequest};
use crate::view::WindowView;

/// Largest template side.
pub const MAX_TEMPLATE: usize = 32;

/// Extra pixels on each side of a coasting track's Foveal window, beyond the window's own
/// +-2 px search: the prediction drifts while nothing is measured.
pub const COAST_MARGIN: u16 = 6;

pub use crate::types::Point;

/// What produced a tracked position.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Algo {
    /// Normalised cross-correlation (Foveal).
    Ncc,
    /// Corner detector (Foveal).
    Cd,
    /// SSD at 25% resolution (Peripheral).
    Ssd,
}

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

/// A message between processors (thesis 2.3.2: "exchanging coordinates").
// The template variant is large by nature (its pixels travel with it, as on the C40 link);
// it is sent once per lock-on, so the enum's size costs nothing that matters.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq)]
pub enum Msg {
    /// Watch -> Peripheral: the bounding box of the motion area, inclusive.
    Motion {
        /// Left column.
        xmin: u16,
        /// Right column.
        xmax: u16,
        /// Top row.
        ymin: u16,
        /// Bottom row.
        ymax: u16,
    },
    /// Peripheral -> Foveal: the target is approximately here.
    Approx(Point),
    /// Foveal -> Peripheral: tracked position.
    Tracked(Point),
    /// Foveal -> Peripheral: the target was lost near here.
    Lost(Point),
    /// Watch -> others: the template acquired at lock-on.
    Template(Template),
    /// Cooperative Foveal -> master: this frame's result of the second algorithm.
    Result(Option<Point>),
    /// Cooperative master -> second Foveal: acquire the next window around here.
    Follow(Point),
}


/// Where a message goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dest {
    /// The Peripheral processor.
    Peripheral,
    /// The (master) Foveal processor.
    Foveal,
    /// The second cooperative Foveal processor.
    FovealCd,
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
    pub report: Option<(Point, Algo)>,
    /// Tracking was lost on this step; the last position tracked.
    pub lost: Option<Point>,
}

impl Step {
    fn new(work: Work) -> Self {
        Step { work, request: None, sends: heapless::Vec::new(), report: None, lost: None }
    }
    fn send(mut self, d: Dest, m: Msg) -> Self {
        // Four slots cover every processor's sends; a fifth is a bug, dropped rather than panic.
        let _ = self.sends.push((d, m));
        self
    }
    fn ask(mut self, r: Option<WindowRequest>) -> Self {
        self.request = r;
        self
    }
}

/// Tuning shared by the processors (thesis Table 2.2 sizes by default).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    /// Frame width.
    pub frame_w: u16,
    /// Frame height.
    pub frame_h: u16,
    /// Template side N (20 in 2.6).
    pub template: u16,
    /// Foveal window side (24).
    pub foveal: u16,
    /// Peripheral window sides in Tracking and the two Detection steps (40, 64).
    pub peripheral: [u16; 2],
    /// Image differencing threshold.
    pub motion_threshold: u8,
    /// Moving pixels needed to report motion.
    pub motion_min_pixels: u32,
    /// Lowest NCC accepted as the target.
    pub ncc_min: f32,
    /// Highest mean squared difference per pixel accepted by the Peripheral SSD.
    pub ssd_max: f32,
    /// Corner detector edge threshold TH.
    pub corner_threshold: u16,
}

impl Default for Params {
    fn default() -> Self {
        Params {
            frame_w: 256,
            frame_h: 256,
            template: 20,
            foveal: 24,
            peripheral: [40, 64],
            motion_threshold: 25,
            motion_min_pixels: 12,
            ncc_min: 0.97,
            ssd_max: 900.0,
            corner_threshold: 50,
        }
    }
}

impl Params {
    /// A `side`x`side` window centred on `p`, moved inside the frame.
    pub fn window(&self, p: Point, side: u16, decimation: Decimation) -> WindowRequest {
        let side = side.min(self.frame_w).min(self.frame_h).max(2);
        let place = |c: f32, len: u16| {
            let start = libm::roundf(c - (f32::from(side) - 1.0) / 2.0);
            start.clamp(0.0, f32::from(len - side)) as u16
        };
        WindowRequest { x0: place(p.x, self.frame_w), y0: place(p.y, self.frame_h), width: side, height: side, decimation }
    }

    fn foveal_window(&self, p: Point) -> WindowRequest {
        self.window(p, self.foveal, Decimation::Full)
    }
}

/// The target template: an N x N block and the offset of the tracked point from its
/// top-left pixel (N/2 - 0.5 when the point was the block's centre).
#[derive(Clone, Debug, PartialEq)]
pub struct Template {
    px: [u8; MAX_TEMPLATE * MAX_TEMPLATE],
    n: usize,
    anchor: Point,
}

impl Template {
    /// The N x N block of `frame` whose centre is nearest `p`, or `None` if it does not fit
    /// in the view or N is 0 or over [`MAX_TEMPLATE`].
    pub fn capture(frame: &WindowView<'_>, p: Point, n: usize) -> Option<Template> {
        if n == 0 || n > MAX_TEMPLATE {
            return None;
        }
        let half = (n as f32 - 1.0) / 2.0;
        let (ox, oy) = frame.origin();
        let x0 = libm::roundf(p.x - half - ox as f32);
        let y0 = libm::roundf(p.y - half - oy as f32);
        if x0 < 0.0 || y0 < 0.0 {
            return None;
        }
        let sub = frame.sub(x0 as usize, y0 as usize, n, n)?;
        let mut px = [0u8; MAX_TEMPLATE * MAX_TEMPLATE];
        for y in 0..n {
            for (x, v) in sub.row_iter(y).enumerate() {
                if let Some(slot) = px.get_mut(y * n + x) {
                    *slot = v;
                }
            }
        }
        let top_left = Point { x: x0 + ox as f32, y: y0 + oy as f32 };
        Some(Template { px, n, anchor: Point { x: p.x - top_left.x, y: p.y - top_left.y } })
    }

    /// The template's pixels as a view.
    pub fn view(&self) -> Option<WindowView<'_>> {
        WindowView::packed(self.px.get(..self.n * self.n)?, self.n, self.n).ok()
    }

    /// Side N.
    pub fn side(&self) -> usize {
        self.n
    }

    /// The N x N pixels, row by row.
    pub fn pixels(&self) -> &[u8] {
        self.px.get(..self.n * self.n).unwrap_or(&[])
    }

    /// Offset of the tracked point from the top-left pixel.
    pub fn anchor(&self) -> Point {
        self.anchor
    }

    /// A template from its side, anchor and N x N pixels (as a link carries it), or `None`
    /// if N is 0 or over [`MAX_TEMPLATE`] or the pixels are not N x N.
    pub fn from_parts(n: usize, anchor: Point, pixels: &[u8]) -> Option<Template> {
        if n == 0 || n > MAX_TEMPLATE || pixels.len() != n * n {
            return None;
        }
        let mut px = [0u8; MAX_TEMPLATE * MAX_TEMPLATE];
        px[..n * n].copy_from_slice(pixels);
        Some(Template { px, n, anchor })
    }

    /// The tracked point for a template placed with its top-left at `(x, y)`.
    fn point_at(&self, x: f32, y: f32) -> Point {
        Point { x: x + self.anchor.x, y: y + self.anchor.y }
    }
}

fn placements(win: &WindowView<'_>, n: usize, step: usize) -> u32 {
    let s = step.max(1);
    let (w, h) = (win.width(), win.height());
    let t = n.div_ceil(s);
    (w.saturating_sub(t) + 1) as u32 * (h.saturating_sub(t) + 1) as u32
}

/// NCC tracking of `tpl` in `win`: the new point (the best placement, refined to sub-pixel
/// accuracy by [`refine_translation`]) and its score, or `None` if the best score is under
/// `ncc_min` (the target has left the window, or no longer looks like the template).
fn ncc_track(win: &WindowView<'_>, tpl: &Template, support: Option<&Support>, p: &Params) -> (Option<(Point, f32)>, Work) {
    let n = tpl.side();
    // The cost model counts the whole template: the support is a part of it.
    let work = Work::Match { method: Method::Ncc, template: (n * n) as u32, placements: placements(win, n, 1) };
    let Some(tv) = tpl.view() else { return (None, work) };
    // The object's part of a corner template first; the whole template where that finds no
    // placement with the object's texture (a lamp's highlight across the support).
    let on_support = support.and_then(|s| Some((best_match_on(win, &tv, s).ok()?, s)));
    let (m, support) = match on_support {
        Some((m, s)) => (m, Some(s)),
        None => match best_match(Method::Ncc, win, &tv) {
            Ok(m) => (m, None),
            Err(_) => return (None, work),
        },
    };
    let score = m.score as f32;
    if score < p.ncc_min {
        return (None, work);
    }
    // Lucas-Kanade from the parabola's placement; the parabola's own when it is refused.
    let (ox, oy) = win.origin();
    let refined = match support {
        Some(s) => refine_translation_on(win, &tv, s, m.sub_x, m.sub_y),
        None => refine_translation(win, &tv, m.sub_x, m.sub_y),
    };
    let (x, y) = refined.map_or((m.frame_x, m.frame_y), |(x, y)| (x + ox as f32, y + oy as f32));
    (Some((tpl.point_at(x, y), score)), work)
}

/// The corner in `win`, or `None` when the detector finds none.
fn cd_track(win: &WindowView<'_>, det: &mut CornerDetector, p: &Params) -> (Option<Point>, Work) {
    let work = Work::Corner { pixels: (win.width() * win.height()) as u32 };
    let c = det.detect(win, &CornerParams::new(p.corner_threshold)).ok();
    (c.map(|c| Point { x: c.x, y: c.y }), work)
}

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

/// A Watch processor: differences consecutive acquisitions of its region (the whole frame,
/// or one of MPDF's strips) and reports the motion area. Without a template yet, it captures
/// one at the centre of the first motion it sees and sends it to the others.
pub struct Watch<'b> {
    region: WindowRequest,
    prev: &'b mut [u8],
    have_prev: bool,
    template_sent: bool,
    params: Params,
}

impl<'b> Watch<'b> {
    /// A Watch processor over `region`; `prev` stores the last acquisition (at least the
    /// region's pixel count). `template_known`: the template was given, don't capture one.
    pub fn new(region: WindowRequest, prev: &'b mut [u8], params: Params, template_known: bool) -> Self {
        Watch { region, prev, have_prev: false, template_sent: template_known, params }
    }

    /// The first request.
    pub fn start(&self) -> Step {
        Step::new(Work::None).ask(Some(self.region))
    }

    /// A Watch window arrived.
    pub fn on_window(&mut self, win: &WindowView<'_>) -> Step {
        let pixels = (win.width() * win.height()) as u32;
        let mut step = Step::new(Work::Motion { pixels }).ask(Some(self.region));
        let Some(prev_buf) = self.prev.get(..pixels as usize) else { return step };
        if self.have_prev {
            let (ox, oy) = win.origin();
            let prev = WindowView::new(prev_buf, win.width(), win.height(), win.width(), ox, oy);
            if let Ok(prev) = prev {
                if let Ok(Some(area)) = detect_motion(&prev, win, self.params.motion_threshold) {
                    if area.count >= self.params.motion_min_pixels {
                        step = self.report(step, win, area);
                    }
                }
            }
        }
        if win.pack_into(self.prev).is_some() {
            self.have_prev = true;
        }
        step
    }

    fn report(&mut self, step: Step, win: &WindowView<'_>, a: crate::motion::MotionArea) -> Step {
        let c = Point { x: (a.xmin + a.xmax) as f32 / 2.0, y: (a.ymin + a.ymax) as f32 / 2.0 };
        let mut step = step;
        if !self.template_sent {
            if let Some(t) = Template::capture(win, c, self.params.template as usize) {
                self.template_sent = true;
                step = step.send(Dest::Peripheral, Msg::Template(t.clone())).send(Dest::Foveal, Msg::Template(t));
            }
        }
        step.send(
            Dest::Peripheral,
            Msg::Motion { xmin: a.xmin as u16, xmax: a.xmax as u16, ymin: a.ymin as u16, ymax: a.ymax as u16 },
        )
    }
}

/// Peripheral processor states.
#[derive(Clone, Copy, Debug, PartialEq)]
enum PState {
    /// Waiting for motion from a Watch processor.
    Idle,
    /// Locating the target around a point with window size index k (0: 40x40, 1: 64x64);
    /// `motion` marks the variable window sized from a motion area.
    Search { at: Point, k: usize },
    /// Located: following the target alongside the Foveal window.
    Follow { at: Point },
}

/// The Peripheral (Detection) processor: SSD at 25% resolution (2.3.2).
pub struct Peripheral {
    template: Option<Template>,
    state: PState,
    params: Params,
    /// When set, it also tells the Foveal processor every location, not only on loss: the
    /// thesis's lock-on sequence L2 -> L3.
    foveal_waiting: bool,
}

impl Peripheral {
    /// A Peripheral processor, with the template if it is known in advance.
    pub fn new(params: Params, template: Option<Template>) -> Self {
        Peripheral { template, state: PState::Idle, params, foveal_waiting: true }
    }

    /// Starts searching at `p` (used when the target is given).
    pub fn start_at(&mut self, p: Point) -> Step {
        self.state = PState::Search { at: p, k: 0 };
        Step::new(Work::None).ask(Some(self.params.window(p, self.params.peripheral[0], Decimation::Quarter)))
    }

    /// The mode this processor is in.
    pub fn mode(&self) -> Mode {
        match self.state {
            PState::Idle => Mode::Watch,
            _ => Mode::Detect,
        }
    }

    /// A message arrived.
    pub fn on_message(&mut self, m: &Msg) -> Step {
        let idle = Step::new(Work::None);
        match (m, self.state) {
            (Msg::Template(t), _) => {
                self.template = Some(t.clone());
                idle
            }
            (Msg::Motion { xmin, xmax, ymin, ymax }, PState::Idle) => {
                // The variable window of Table 2.2: the motion area with a template's margin.
                let at = Point { x: f32::from(*xmin + *xmax) / 2.0, y: f32::from(*ymin + *ymax) / 2.0 };
                let span = (*xmax - *xmin).max(*ymax - *ymin) + self.params.template;
                let side = span.clamp(self.params.peripheral[0], 128);
                self.state = PState::Search { at, k: 0 };
                self.foveal_waiting = true;
                idle.ask(Some(self.params.window(at, side, Decimation::Quarter)))
            }
            (Msg::Tracked(p), PState::Follow { .. }) | (Msg::Tracked(p), PState::Search { .. }) => {
                self.state = PState::Follow { at: *p };
                self.foveal_waiting = false;
                idle
            }
            (Msg::Lost(p), PState::Follow { at }) => {
                // Hand over the latest location at once (2.3.2); search again from there.
                self.foveal_waiting = true;
                self.state = PState::Search { at: *p, k: 0 };
                idle.send(Dest::Foveal, Msg::Approx(at))
            }
            (Msg::Lost(p), _) => {
                self.foveal_waiting = true;
                self.state = PState::Search { at: *p, k: 0 };
                idle.ask(Some(self.params.window(*p, self.params.peripheral[0], Decimation::Quarter)))
            }
            _ => idle,
        }
    }

    /// A Peripheral window arrived.
    pub fn on_window(&mut self, win: &WindowView<'_>) -> Step {
        let Some(tpl) = &self.template else {
            self.state = PState::Idle;
            return Step::new(Work::None);
        };
        let (found, work) = ssd_locate(win, tpl, &self.params);
        let step = Step::new(work);
        let side = |k: usize| self.params.peripheral[k.min(1)];
        match (found, self.state) {
            (Some(p), _) => {
                let was_waiting = self.foveal_waiting;
                self.state = PState::Follow { at: p };
                let step = step.ask(Some(self.params.window(p, side(0), Decimation::Quarter)));
                if was_waiting {
                    self.foveal_waiting = false;
                    step.send(Dest::Foveal, Msg::Approx(p))
                } else {
                    step
                }
            }
            (None, PState::Follow { at }) => {
                self.state = PState::Search { at, k: 0 };
                step.ask(Some(self.params.window(at, side(0), Decimation::Quarter)))
            }
            (None, PState::Search { at, k }) if k < 1 => {
                self.state = PState::Search { at, k: k + 1 };
                step.ask(Some(self.params.window(at, side(k + 1), Decimation::Quarter)))
            }
            (None, _) => {
                // Both Detection sizes failed: back to waiting for the Watch processor.
                self.state = PState::Idle;
                step
            }
        }
    }
}

/// Which algorithm a Foveal processor runs, and its role in COOP.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FovealKind {
    /// NCC alone (TPDF, MPDF; Table 4.1's NCC).
    Ncc,
    /// The corner detector alone (Table 4.1's CD).
    Cd,
    /// COOP master: NCC here, the corner detector on the partner; the confidence measure
    /// chooses (4.2-4.3).
    CoopMaster,
    /// COOP partner: the corner detector on the master's coordinates.
    CoopPartner,
}

/// The COOP master's decision: guarded cooperation (the default), the thesis's
/// least-squares SSE (4.3), or the Kalman filter it proposes as future work (5.2).
#[derive(Clone, Debug)]
// No allocator to box the guard into: each policy lives inline in its processor.
#[allow(clippy::large_enum_variant)]
pub enum Policy {
    /// CD only where it measures the tracked point ([`crate::guard`]).
    Guarded(Guard),
    /// Lower SSE about the least-squares line of the last n positions wins.
    Sse(SseCoop),
    /// Lower smoothed Kalman innovation wins.
    Kalman(KalmanCoop),
}

impl Policy {
    /// The position to follow for one window's NCC result (point, score) and corner.
    fn decide(&mut self, t: f64, ncc: Option<(Point, f32)>, corner: Option<Point>) -> Option<(Point, Algo)> {
        let smooth: &mut dyn ConfidencePolicy = match self {
            Policy::Guarded(g) => {
                return g.decide(t, Measured { ncc, corner }).map(|(p, s)| (p, Algo::from(s)));
            }
            Policy::Sse(p) => p,
            Policy::Kalman(p) => p,
        };
        let own = ncc.map(|(p, _)| p);
        // A rejected (non-finite) sample leaves that source's history as it was.
        if let Some(p) = own {
            let _ = smooth.push(Source::Ncc, t, f64::from(p.x), f64::from(p.y));
        }
        if let Some(p) = corner {
            let _ = smooth.push(Source::Cd, t, f64::from(p.x), f64::from(p.y));
        }
        match (smooth.choose(), own, corner) {
            (Source::Ncc, Some(p), _) | (Source::Cd, Some(p), None) => Some((p, Algo::Ncc)),
            (Source::Cd, _, Some(p)) | (Source::Ncc, None, Some(p)) => Some((p, Algo::Cd)),
            _ => None,
        }
    }

    /// After a window with no position: where a coasting track looks next (see
    /// [`Guard::coast`]); the thesis's policies do not coast.
    fn coast(&mut self, t: f64) -> Option<Point> {
        match self {
            Policy::Guarded(g) => g.coast(t),
            Policy::Sse(_) | Policy::Kalman(_) => None,
        }
    }

    /// A track starts at `p` (see [`Guard::begin`]).
    fn begin(&mut self, p: Point, exact: bool) {
        if let Policy::Guarded(g) = self {
            g.begin(p, exact);
        }
    }
}

impl From<Source> for Algo {
    fn from(s: Source) -> Self {
        match s {
            Source::Ncc => Algo::Ncc,
            Source::Cd => Algo::Cd,
        }
    }
}

/// A Foveal (Tracking) processor.
pub struct Foveal {
    kind: FovealKind,
    template: Option<Template>,
    /// The object's part of a corner template ([`crate::support`]), when it is one.
    support: Option<Support>,
    detector: CornerDetector,
    tracking: Option<Point>,
    params: Params,
    coop: Policy,
    /// COOP master: own result of the current window, waiting for the partner's.
    own: Option<Option<(Point, f32)>>,
    partner: Option<Option<Point>>,
}

impl Foveal {
    /// A Foveal processor; a COOP master decides with guarded cooperation
    /// ([`Foveal::with_policy`] chooses another policy).
    pub fn new(kind: FovealKind, params: Params, template: Option<Template>) -> Self {
        let mut f = Foveal {
            kind,
            template: None,
            support: None,
            detector: CornerDetector::default(),
            tracking: None,
            params,
            coop: Policy::Guarded(Guard::new(GuardParams::default())),
            own: None,
            partner: None,
        };
        if let Some(t) = template {
            f.set_template(t);
        }
        f
    }

    /// Takes `tpl` as the template, with its support when it is centred on a corner.
    fn set_template(&mut self, tpl: Template) {
        let a = tpl.anchor();
        self.support = tpl.view().and_then(|v| {
            Support::of_template(&v, (a.x, a.y), &mut self.detector, &CornerParams::new(self.params.corner_threshold))
        });
        self.template = Some(tpl);
    }

    /// The same processor with another confidence policy (COOP master).
    pub fn with_policy(mut self, policy: Policy) -> Self {
        self.coop = policy;
        self
    }

    /// Starts tracking at `p` (the target given at start).
    pub fn start_at(&mut self, p: Point) -> Step {
        self.start(p, true)
    }

    /// Starts tracking at `p`: the tracked point itself when `exact`, otherwise the
    /// Peripheral's approximate location.
    fn start(&mut self, p: Point, exact: bool) -> Step {
        self.tracking = Some(p);
        self.coop.begin(p, exact);
        let step = Step::new(Work::None).ask(Some(self.params.foveal_window(p)));
        if self.kind == FovealKind::CoopMaster {
            step.send(Dest::FovealCd, Msg::Follow(p))
        } else {
            step
        }
    }

    /// Whether a COOP master's track is coasting: tracking, but with no current position.
    pub fn coasting(&self) -> bool {
        matches!(&self.coop, Policy::Guarded(g) if g.coasting())
    }

    /// Whether it is tracking.
    pub fn mode(&self) -> Mode {
        if self.tracking.is_some() {
            Mode::Track
        } else {
            Mode::Watch
        }
    }

    /// A message arrived.
    pub fn on_message(&mut self, m: &Msg, t: f64) -> Step {
        match m {
            Msg::Template(tpl) => {
                self.set_template(tpl.clone());
                Step::new(Work::None)
            }
            Msg::Approx(p) if self.tracking.is_none() => self.start(*p, false),
            Msg::Follow(p) => {
                self.tracking = Some(*p);
                Step::new(Work::None).ask(Some(self.params.foveal_window(*p)))
            }
            Msg::Result(r) if self.kind == FovealKind::CoopMaster => {
                self.partner = Some(*r);
                self.decide(t)
            }
            Msg::Lost(_) if self.kind == FovealKind::CoopPartner => {
                self.tracking = None;
                Step::new(Work::None)
            }
            _ => Step::new(Work::None),
        }
    }

    /// A Foveal window arrived, at time `t` seconds (for the confidence fits).
    pub fn on_window(&mut self, win: &WindowView<'_>, t: f64) -> Step {
        match self.kind {
            FovealKind::Cd | FovealKind::CoopPartner => {
                let (found, work) = cd_track(win, &mut self.detector, &self.params);
                let step = Step::new(work);
                if self.kind == FovealKind::CoopPartner {
                    step.send(Dest::Foveal, Msg::Result(found))
                } else {
                    self.follow(step, found, Algo::Cd)
                }
            }
            FovealKind::Ncc | FovealKind::CoopMaster => {
                let (found, work) = match &self.template {
                    Some(tpl) => ncc_track(win, tpl, self.support.as_ref(), &self.params),
                    None => (None, Work::None),
                };
                if self.kind == FovealKind::CoopMaster {
                    self.own = Some(found);
                    let mut s = self.decide(t);
                    s.work = work;
                    s
                } else {
                    self.follow(Step::new(work), found.map(|(p, _)| p), Algo::Ncc)
                }
            }
        }
    }

    /// COOP: once both results of a window are in, feed the confidence measure and follow
    /// the source it chooses.
    fn decide(&mut self, t: f64) -> Step {
        let (Some(own), Some(partner)) = (self.own, self.partner) else { return Step::new(Work::None) };
        self.own = None;
        self.partner = None;
        let chosen = self.coop.decide(t, own, partner);
        if let Some(q) = chosen.is_none().then(|| self.coop.coast(t)).flatten() {
            // Nothing measured the point: look where it should be next, report nothing.
            let side = self.params.foveal + 2 * COAST_MARGIN;
            return Step::new(Work::Decision)
                .ask(Some(self.params.window(q, side, Decimation::Full)))
                .send(Dest::FovealCd, Msg::Follow(q));
        }
        let (found, algo) = (chosen.map(|c| c.0), chosen.map_or(Algo::Ncc, |c| c.1));
        let step = self.follow(Step::new(Work::Decision), found, algo);
        match (step.request, found, step.lost) {
            (Some(_), Some(p), _) => step.send(Dest::FovealCd, Msg::Follow(p)),
            // The partner stops with the master; the Peripheral takes over.
            (_, _, Some(last)) => step.send(Dest::FovealCd, Msg::Lost(last)),
            _ => step,
        }
    }

    fn follow(&mut self, step: Step, found: Option<Point>, algo: Algo) -> Step {
        match (found, self.tracking) {
            (Some(p), _) => {
                self.tracking = Some(p);
                let mut s = step.ask(Some(self.params.foveal_window(p))).send(Dest::Peripheral, Msg::Tracked(p));
                s.report = Some((p, algo));
                s
            }
            (None, Some(last)) => {
                self.tracking = None;
                let mut s = step.send(Dest::Peripheral, Msg::Lost(last));
                s.lost = Some(last);
                s
            }
            (None, None) => step,
        }
    }
}

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
            self.peripheral.state = PState::Idle;
            out.request = self.watch.start().request;
        }
        self.mode = mode;
        out
    }
}
