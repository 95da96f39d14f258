//! Guarded cooperation: the COOP decision made safe on real imagery (beyond the thesis's 4.3).
//!
//! The thesis's rule follows whichever source's last n positions lie closer to a straight
//! line. That measures smoothness, not correctness: the corner detector reports *a* corner
//! in the Foveal window, which is the tracked point only when the template was centred on
//! that corner, and its smooth track then wins and pulls the windows off the target.
//!
//! The guard lets the corner detector (CD) speak only when it measures the tracked point:
//!
//! 1. **Anchoring.** When the track starts and the detector finds a corner within `anchor`
//!    px of the start point, the tracked point *is* that corner (the template sits on it):
//!    the offset is set from that first window and CD is the anchored source. Its
//!    measurement is tied to the object's outline, while NCC on a corner template is
//!    mostly background and can stick to it as the object moves off.
//! 2. **Offset learning.** Otherwise, while NCC is trusted (score `>= trust`), the difference
//!    `d = p_ncc - p_cd` is the tracked point's offset from the detected corner. CD is
//!    enabled once `learn` consecutive frames give offsets within `learn_spread` px of their
//!    running mean (a texture detail that the detector takes for a corner now and then does
//!    not qualify), which then becomes the offset `o`; afterwards each agreeing frame refines it
//!    (`o += (d - o) / 8`). A CD candidate is `p_cd + o`.
//! 3. **Agreement.** NCC and the CD candidate agree when `|p_ncc - (p_cd + o)| <= gate`;
//!    then both measure the tracked point and are fused, each weighted by the inverse of its
//!    mean squared innovation (distance from the prediction, averaged with weight 1/10):
//!    the steadier source counts more, as in the thesis's SSE rule, but neither can take the
//!    track off the other. The source reported is the one with the larger weight. A learnt
//!    (not anchored) offset that disagrees `unlearn` times running while NCC is trusted
//!    means CD has locked onto another corner or slides along an edge: the offset is
//!    dropped and learnt again.
//! 4. **Choice on disagreement.** Trusted NCC wins. An anchored CD outvotes an untrusted
//!    NCC that has disagreed with it `persist` frames running (NCC sliding off the object,
//!    its score falling) while the corner stays within `jump` px of the prediction, if they
//!    parted gradually (by at most `4 gate / 3` in the first frame: a corner that jumps onto
//!    clutter parts at once); a single disagreement is more likely a detector outlier.
//!    Otherwise an untrusted NCC (appearance changed: a lamp, an occluder) and the CD
//!    candidate are judged by the prediction (the least-squares line through the last
//!    [`HISTORY`] positions followed, per axis): NCC counts within `gate` px of it, the
//!    corner within `gate / 2`, the nearer if both; otherwise neither is believed. An
//!    untrusted NCC match alone is followed within `reacquire` px of the prediction; with
//!    NCC under its acceptance score, the CD candidate carries the track alone only within
//!    `gate / 2` px of it: a step of `jump` at a time would let a corner creep onto clutter.
//! 5. **Coasting.** When neither source measures the point (an occluder passes over it), the
//!    track coasts for up to `coast` seconds: the next window is placed at the prediction and
//!    nothing is reported. An NCC match within `reacquire` px of the prediction resumes the
//!    track if it scores at least `resume` or the first template confirms it (an adapting
//!    track's `confirmed`); a corner alone resumes it within `gate / 2` px. After `coast`
//!    seconds the target is lost.
//!
//! Everything is `f32`/`f64` arithmetic on a few values: no allocation, no panic.

use crate::kernels::confidence::{ConfidencePolicy, SseCoop};
use crate::kernels::fmath::sqrtf;
use crate::processors::Params;
use crate::types::{Point, Source};

/// Thresholds of the guard.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GuardParams {
    /// NCC score from which NCC is trusted outright and may teach CD its offset.
    pub trust: f32,
    /// Agreement radius in pixels between NCC and the CD candidate.
    pub gate: f32,
    /// Consecutive consistent offsets needed before CD is used.
    pub learn: u8,
    /// Largest distance in pixels of a learnt offset from the running mean of the others.
    pub learn_spread: f32,
    /// Consecutive disagreements under trusted NCC after which the offset is dropped.
    pub unlearn: u8,
    /// Largest distance in pixels from the prediction a candidate may be followed at.
    pub jump: f32,
    /// Largest distance in pixels from the start point to a corner that anchors CD.
    pub anchor: f32,
    /// Consecutive disagreements after which an anchored CD outvotes NCC.
    pub persist: u8,
    /// Longest time in seconds a track may coast without a measurement before it is lost
    /// (in time, not windows: a coasting window can take a slow processor several frames).
    pub coast: f64,
    /// Largest distance in pixels from the prediction at which a coasting track resumes.
    pub reacquire: f32,
    /// Lowest NCC score at which a coasting track resumes on NCC's match (0: any accepted).
    pub resume: f32,
}

impl Default for GuardParams {
    fn default() -> Self {
        // trust: NCC of a 20x20 textured template under sensor noise stays above 0.99 while
        // the appearance holds; a lamp's highlight or a partial occluder takes it under.
        GuardParams { trust: 0.99, gate: 1.5, learn: 8, learn_spread: 0.5, unlearn: 3, jump: 4.0, anchor: 3.0, persist: 3, coast: 0.35, reacquire: 8.0, resume: 0.0 }
    }
}

impl GuardParams {
    /// For a track whose template adapts ([`crate::processors::Params::adapt`]): its
    /// zero-mean NCC scores an object that turns, scales or blurs under the 0.99 that the
    /// thesis's fixed template keeps on a rigid one, while each frame's point is checked by
    /// aligning the first template; from [`ADAPT_TRUST`] NCC is trusted, so a corner found
    /// elsewhere in the window does not make a fast object's track coast. A coasting track
    /// resumes on a trusted match, or on a weaker one the first template confirms
    /// ([`Measured::confirmed`]): its other weak matches (from the low acceptance of
    /// [`crate::processors::FovealParams::accept`]) followed a neck or a shoulder after a blink.
    pub fn adapting() -> Self {
        GuardParams { trust: ADAPT_TRUST, resume: ADAPT_TRUST, ..Self::default() }
    }

    /// The guard of a track with `params`: [`GuardParams::adapting`] where its template adapts,
    /// the thesis's fixed template's otherwise. Every guarded Foveal is paired here.
    pub fn for_track(params: &Params) -> Self {
        if params.adapt { Self::adapting() } else { Self::default() }
    }
}

/// The zero-mean NCC score from which an adapting track's NCC is trusted.
pub const ADAPT_TRUST: f32 = 0.85;

/// Positions in the prediction's least-squares fit.
pub const HISTORY: usize = 8;

/// Positions in the fit that places the next window ([`Guard::ahead`]).
const LEAD: usize = 3;

/// Weight of the newest squared innovation in each source's running mean.
const NOISE_WEIGHT: f32 = 0.1;

/// One Foveal window's two measurements.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Measured {
    /// NCC's tracked point and score, when its score reached the acceptance level.
    pub ncc: Option<(Point, f32)>,
    /// The corner detector's corner, when it found one.
    pub corner: Option<Point>,
    /// NCC's point is the first template's, aligned there under a similarity warp (an
    /// adapting track, [`crate::processors::adapt::Adaptive::align`]): the object's first
    /// view confirms the match, however low the current template's score.
    pub confirmed: bool,
}

/// The guard's state (see the module documentation).
#[derive(Clone, Debug)]
pub struct Guard {
    params: GuardParams,
    offset: Option<Point>,
    /// The offset was set from a corner at the start point (see the module docs).
    anchored: bool,
    /// The start point, until the first window's corner has been compared with it.
    start: Option<Point>,
    learning: Point,
    learnt: u8,
    disagreements: u8,
    /// The last positions followed, with their times, newest first, for the prediction.
    history: [Option<(f64, Point)>; HISTORY],
    /// Windows coasted through since the last measurement.
    coasted: u8,
    /// When the last window was decided.
    last: Option<f64>,
    /// The time between the last two windows decided, which the next window's prediction
    /// looks ahead by (the last two positions' spacing spans a coast too); kept where a
    /// window's time is not a finite step on.
    interval: Option<f64>,
    /// Each source's last positions while they agree, for the thesis's SSE (4.3).
    lines: SseCoop,
    /// Running mean of each source's SSE (NCC, CD).
    jitter: [Option<f32>; 2],
    /// Consecutive frames in which both measured and disagreed.
    parted: u8,
    /// How far apart they were in the first of those frames.
    parted_by: f32,
}

impl Guard {
    /// A guard with `params`.
    pub fn new(params: GuardParams) -> Self {
        Guard {
            params,
            offset: None,
            anchored: false,
            start: None,
            learning: Point::default(),
            learnt: 0,
            disagreements: 0,
            history: [None; HISTORY],
            coasted: 0,
            last: None,
            interval: None,
            lines: SseCoop::thesis(),
            jitter: [None; 2],
            parted: 0,
            parted_by: 0.0,
        }
    }

    /// The learnt offset of the tracked point from the corner, once CD is enabled.
    pub fn offset(&self) -> Option<Point> {
        self.offset
    }

    /// Whether the track is coasting: its last window measured nothing believable.
    pub fn coasting(&self) -> bool {
        self.coasted > 0
    }

    /// Whether CD is anchored at the tracked point (the track started on a corner).
    pub fn anchored(&self) -> bool {
        self.anchored
    }

    /// A track starts at `p`: the motion is forgotten. A track started at the tracked point
    /// itself (`exact`) may anchor CD; one started from an approximate location keeps the
    /// offset (the template, and so the tracked point's place on the object, has not changed).
    pub fn begin(&mut self, p: Point, exact: bool) {
        self.history = [None; HISTORY];
        self.coasted = 0;
        self.last = None;
        self.interval = None;
        self.parted = 0;
        self.start = (exact && self.offset.is_none()).then_some(p);
    }

    /// The position to follow for the window measured at time `t`, and its source.
    pub fn decide(&mut self, t: f64, m: Measured) -> Option<(Point, Source)> {
        self.interval = self.last.map(|l| t - l).filter(|d| d.is_finite() && *d > 0.0).or(self.interval);
        self.last = Some(t);
        if let Some(p0) = self.start.take() {
            if let Some(c) = m.corner.filter(|c| dist(*c, p0) <= self.params.anchor) {
                self.offset = Some(sub(p0, c));
                self.anchored = true;
            }
        }
        // A coasting track has lost its look: a weak match is as likely something else, unless
        // the first template aligns on it (on the real clips the first view scores 0.58-0.76 at
        // the current template's point where the track resumes rightly, at most 0.13 on a
        // neck or a cheek).
        let m = Measured { ncc: m.ncc.filter(|(_, s)| self.coasted == 0 || *s >= self.params.resume || m.confirmed), ..m };
        let trusted = m.ncc.filter(|(_, s)| *s >= self.params.trust).map(|(p, _)| p);
        if let (Some(n), Some(c), false) = (trusted, m.corner, self.anchored) {
            self.learn(sub(n, c));
        }
        let cd = match (m.corner, self.offset) {
            (Some(c), Some(o)) => Some(add(c, o)),
            _ => None,
        };
        let prediction = self.predict(t);
        let within = |p: Point, r: f32| prediction.is_none_or(|q| dist(p, q) <= r);
        // A lone corner must sit close to the prediction: a step of `jump` at a time would let
        // it creep onto clutter. A lone template match is evidence of the target's identity and
        // may be up to `reacquire` px off (after an occlusion, the prediction has drifted).
        let disagree = |n: Point, c: Point| dist(n, c) > self.params.gate;
        self.parted = match (m.ncc, cd) {
            (Some((n, _)), Some(c)) if disagree(n, c) => {
                if self.parted == 0 {
                    self.parted_by = dist(n, c);
                }
                self.parted.saturating_add(1)
            }
            _ => 0,
        };
        // NCC sliding off the object parts from the corner gradually; a corner that jumps onto
        // clutter parts at once.
        let gradual = self.parted_by <= self.params.gate * 4.0 / 3.0;
        let persistent = self.anchored && gradual && self.parted >= self.params.persist;
        let chosen = match (trusted, m.ncc.map(|(p, _)| p), cd) {
            (None, Some(n), Some(c)) if persistent => {
                if within(c, self.params.jump) {
                    Some((c, Source::Cd))
                } else {
                    within(n, self.params.jump).then_some((n, Source::Ncc))
                }
            }
            (_, Some(n), Some(c)) if !disagree(n, c) => Some(self.fuse(t, n, c)),
            (Some(n), _, _) => Some((n, Source::Ncc)),
            // Two untrusted measurements that disagree: the one the motion bears out (NCC within
            // `gate`, a corner within `gate / 2` of the prediction; the nearer if both), else
            // neither, and the track coasts.
            (None, Some(n), Some(c)) => {
                let off = |p: Point| prediction.map_or(0.0, |q| dist(p, q));
                match (off(n) <= self.params.gate, off(c) <= self.params.gate / 2.0) {
                    (true, true) if off(c) < off(n) => Some((c, Source::Cd)),
                    (true, _) => Some((n, Source::Ncc)),
                    (false, true) => Some((c, Source::Cd)),
                    (false, false) => None,
                }
            }
            (None, Some(n), None) => within(n, self.params.reacquire).then_some((n, Source::Ncc)),
            (None, None, Some(c)) => within(c, self.params.gate / 2.0).then_some((c, Source::Cd)),
            (None, None, None) => None,
        };
        if let Some((p, _)) = chosen {
            remember(&mut self.history, t, p);
            self.coasted = 0;
        }
        chosen
    }

    /// After a window with no position at time `t`: where to look next (the prediction one
    /// window interval ahead), or `None` when the track has coasted `coast` seconds or has
    /// no motion to go by, and is lost.
    pub fn coast(&mut self, t: f64) -> Option<Point> {
        let (Some((t1, _)), Some(dt)) = (self.history[0], self.window_interval()) else { return None };
        if t - t1 > self.params.coast {
            return None;
        }
        self.coasted = self.coasted.saturating_add(1);
        self.predict(t + dt)
    }

    /// Where the followed point should be one window interval (the time between the last
    /// two windows) after `t`, from the positions followed; `None` before there are two.
    pub fn ahead(&self, t: f64) -> Option<Point> {
        // The last few positions only: a target that speeds up is followed, not lagged.
        self.window_interval().and_then(|dt| line_at(&self.history[..LEAD], t + dt))
    }

    /// The window interval, once two positions followed at different times give the motion.
    fn window_interval(&self) -> Option<f64> {
        let (Some((t1, _)), Some((t0, _))) = (self.history[0], self.history[1]) else { return None };
        (t1 > t0).then_some(self.interval).flatten()
    }

    /// Inverse-variance fusion of two agreeing measurements (see the module docs).
    fn fuse(&mut self, t: f64, n: Point, c: Point) -> (Point, Source) {
        for (k, (src, p)) in [(Source::Ncc, n), (Source::Cd, c)].into_iter().enumerate() {
            // A non-finite sample is refused and leaves the history as it was.
            let _ = self.lines.push(src, t, f64::from(p.x), f64::from(p.y));
            if let Some(fit) = self.lines.fit(src) {
                let e = fit.sse as f32;
                self.jitter[k] = Some(self.jitter[k].map_or(e, |v| v + NOISE_WEIGHT * (e - v)));
            }
        }
        let (wn, wc) = match self.jitter {
            [Some(a), Some(b)] => (1.0 / a.max(1e-6), 1.0 / b.max(1e-6)),
            _ => (1.0, 1.0),
        };
        let k = wc / (wn + wc);
        let p = Point { x: n.x + k * (c.x - n.x), y: n.y + k * (c.y - n.y) };
        (p, if wc > wn { Source::Cd } else { Source::Ncc })
    }

    fn learn(&mut self, d: Point) {
        let gate = self.params.gate;
        match self.offset {
            Some(o) if dist(d, o) <= gate => {
                self.disagreements = 0;
                self.offset = Some(Point { x: o.x + (d.x - o.x) / 8.0, y: o.y + (d.y - o.y) / 8.0 });
            }
            Some(_) => {
                self.disagreements = self.disagreements.saturating_add(1);
                if self.disagreements >= self.params.unlearn {
                    self.offset = None;
                    self.disagreements = 0;
                    self.learnt = 0;
                }
            }
            None if self.learnt > 0 && dist(d, self.learning) <= self.params.learn_spread => {
                self.learnt = self.learnt.saturating_add(1);
                let k = f32::from(self.learnt);
                self.learning = Point { x: self.learning.x + (d.x - self.learning.x) / k, y: self.learning.y + (d.y - self.learning.y) / k };
                if self.learnt >= self.params.learn {
                    self.offset = Some(self.learning);
                }
            }
            None => {
                self.learning = d;
                self.learnt = 1;
            }
        }
    }

    /// The least-squares line through the positions followed, evaluated at `t`.
    fn predict(&self, t: f64) -> Option<Point> {
        line_at(&self.history, t)
    }
}

/// The least-squares line through timed positions (per axis, against time), newest first,
/// evaluated at `t`; the one position when there is only one. In `f32` (the positions' own
/// precision; `f64` is software on the Cortex-M4F), with times taken from the newest, which
/// keeps them small, and positions about their mean.
fn line_at(history: &[Option<(f64, Point)>], t: f64) -> Option<Point> {
    let (t_new, p_new) = (*history.first()?)?;
    let mut pts = [(0.0f32, Point { x: 0.0, y: 0.0 }); HISTORY];
    let mut n = 0;
    for (d, &(ti, p)) in pts.iter_mut().zip(history.iter().flatten()) {
        *d = ((ti - t_new) as f32, p);
        n += 1;
    }
    let pts = pts.get(..n)?;
    if n < 2 {
        return Some(p_new);
    }
    let nf = n as f32;
    let mean = |f: &dyn Fn(&(f32, Point)) -> f32| pts.iter().map(f).sum::<f32>() / nf;
    let (mt, mx, my) = (mean(&|q| q.0), mean(&|q| q.1.x), mean(&|q| q.1.y));
    let (mut stt, mut stx, mut sty) = (0.0f32, 0.0f32, 0.0f32);
    for &(ti, p) in pts {
        let dt = ti - mt;
        stt += dt * dt;
        stx += dt * (p.x - mx);
        sty += dt * (p.y - my);
    }
    if stt <= 0.0 {
        return Some(p_new);
    }
    let dt = (t - t_new) as f32 - mt;
    let p = Point { x: mx + stx / stt * dt, y: my + sty / stt * dt };
    (p.x.is_finite() && p.y.is_finite()).then_some(p)
}

/// Records `p` at `t` as the newest entry of `history`.
fn remember(history: &mut [Option<(f64, Point)>; HISTORY], t: f64, p: Point) {
    history.rotate_right(1);
    history[0] = Some((t, p));
}

fn add(a: Point, b: Point) -> Point {
    Point { x: a.x + b.x, y: a.y + b.y }
}

fn sub(a: Point, b: Point) -> Point {
    Point { x: a.x - b.x, y: a.y - b.y }
}

/// `|a - b|` in `f32` on the FPU (`libm::hypotf` works in soft-float `f64`): positions are
/// pixels, far from overflow.
pub(crate) fn dist(a: Point, b: Point) -> f32 {
    let (dx, dy) = (a.x - b.x, a.y - b.y);
    sqrtf(dx * dx + dy * dy)
}

#[cfg(test)]
mod tests;
