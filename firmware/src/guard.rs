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
//!    enabled once `learn` consecutive frames give offsets within `gate` px of their running
//!    mean, which then becomes the offset `o`; afterwards each agreeing frame refines it
//!    (`o += (d - o) / 8`). A CD candidate is `p_cd + o`.
//! 3. **Agreement.** NCC and the CD candidate agree when `|p_ncc - (p_cd + o)| <= gate`;
//!    then both measure the tracked point and are fused, each weighted by the inverse of its
//!    mean squared innovation (distance from the prediction, averaged with weight 1/10):
//!    the steadier source counts more, as in the thesis's SSE rule, but neither can take the
//!    track off the other. The source reported is the one with the larger weight. A learnt (not anchored) offset that
//!    disagrees `unlearn` times running while NCC is trusted means CD has locked onto
//!    another corner or slides along an edge: the offset is dropped and learnt again.
//! 4. **Choice on disagreement.** An anchored CD wins while it stays within `jump` px of the
//!    prediction. Otherwise trusted NCC wins. An untrusted NCC (appearance changed: a lamp, an
//!    occluder) and a disagreeing CD candidate are judged by the constant-velocity
//!    prediction from the last two positions followed: the one nearer to it wins, and only
//!    within `jump` px of it. With NCC below its acceptance score, the CD candidate carries
//!    the track alone while it stays within `jump` px of the prediction.
//!
//! Everything is `f32`/`f64` arithmetic on a few values: no allocation, no panic.

use crate::confidence::Source;
use crate::types::Point;

/// Thresholds of the guard.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GuardParams {
    /// NCC score from which NCC is trusted outright and may teach CD its offset.
    pub trust: f32,
    /// Agreement radius in pixels between NCC and the CD candidate.
    pub gate: f32,
    /// Consecutive consistent offsets needed before CD is used.
    pub learn: u8,
    /// Consecutive disagreements under trusted NCC after which the offset is dropped.
    pub unlearn: u8,
    /// Largest distance in pixels from the prediction a candidate may be followed at.
    pub jump: f32,
    /// Largest distance in pixels from the start point to a corner that anchors CD.
    pub anchor: f32,
}

impl Default for GuardParams {
    fn default() -> Self {
        // trust: NCC of a 20x20 textured template under sensor noise stays above 0.99 while
        // the appearance holds; a lamp's highlight or a partial occluder takes it under.
        GuardParams { trust: 0.99, gate: 1.5, learn: 3, unlearn: 3, jump: 4.0, anchor: 3.0 }
    }
}

/// Weight of the newest squared innovation in each source's running mean.
const NOISE_WEIGHT: f32 = 0.1;

/// One Foveal window's two measurements.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Measured {
    /// NCC's tracked point and score, when its score reached the acceptance level.
    pub ncc: Option<(Point, f32)>,
    /// The corner detector's corner, when it found one.
    pub corner: Option<Point>,
}

/// The guard's state (see the module documentation).
#[derive(Clone, Debug, Default)]
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
    /// The last two positions followed, with their times, for the prediction.
    last: [Option<(f64, Point)>; 2],
    /// Mean squared innovation of NCC and of the CD candidate, while they agree.
    noise: [Option<f32>; 2],
}

impl Guard {
    /// A guard with `params`.
    pub fn new(params: GuardParams) -> Self {
        Guard { params, ..Guard::default() }
    }

    /// The learnt offset of the tracked point from the corner, once CD is enabled.
    pub fn offset(&self) -> Option<Point> {
        self.offset
    }

    /// Whether CD is anchored at the tracked point (the track started on a corner).
    pub fn anchored(&self) -> bool {
        self.anchored
    }

    /// A track starts at `p`: the motion is forgotten. The first track may anchor CD; later
    /// ones start from an approximate point and keep the offset (the template, and so the
    /// tracked point's place on the object, has not changed).
    pub fn begin(&mut self, p: Point) {
        self.last = [None, None];
        if self.offset.is_none() {
            self.start = Some(p);
        }
    }

    /// The position to follow for the window measured at time `t`, and its source.
    pub fn decide(&mut self, t: f64, m: Measured) -> Option<(Point, Source)> {
        if let Some(p0) = self.start.take() {
            if let Some(c) = m.corner.filter(|c| dist(*c, p0) <= self.params.anchor) {
                self.offset = Some(sub(p0, c));
                self.anchored = true;
            }
        }
        let trusted = m.ncc.filter(|(_, s)| *s >= self.params.trust).map(|(p, _)| p);
        if let (Some(n), Some(c), false) = (trusted, m.corner, self.anchored) {
            self.learn(sub(n, c));
        }
        let cd = match (m.corner, self.offset) {
            (Some(c), Some(o)) => Some(add(c, o)),
            _ => None,
        };
        let prediction = self.predict(t);
        let near = |p: Point| prediction.is_none_or(|q| dist(p, q) <= self.params.jump);
        let disagree = |n: Point, c: Point| dist(n, c) > self.params.gate;
        let chosen = match (trusted, m.ncc.map(|(p, _)| p), cd) {
            (_, Some(n), Some(c)) if self.anchored && disagree(n, c) => {
                if near(c) {
                    Some((c, Source::Cd))
                } else {
                    near(n).then_some((n, Source::Ncc))
                }
            }
            (_, Some(n), Some(c)) if !disagree(n, c) => Some(self.fuse(n, c, prediction)),
            (Some(n), _, _) => Some((n, Source::Ncc)),
            (None, Some(n), Some(c)) if disagree(n, c) => {
                let (nd, cdd) = match prediction {
                    Some(q) => (dist(n, q), dist(c, q)),
                    None => (0.0, 1.0),
                };
                if cdd < nd && near(c) {
                    Some((c, Source::Cd))
                } else {
                    near(n).then_some((n, Source::Ncc))
                }
            }
            (None, Some(n), _) => Some((n, Source::Ncc)),
            (None, None, Some(c)) => near(c).then_some((c, Source::Cd)),
            (None, None, None) => None,
        };
        if let Some((p, _)) = chosen {
            self.last = [Some((t, p)), self.last[0]];
        }
        chosen
    }

    /// Inverse-variance fusion of two agreeing measurements (see the module docs).
    fn fuse(&mut self, n: Point, c: Point, prediction: Option<Point>) -> (Point, Source) {
        if let Some(q) = prediction {
            for (slot, p) in self.noise.iter_mut().zip([n, c]) {
                let e = dist(p, q) * dist(p, q);
                *slot = Some(slot.map_or(e, |v| v + NOISE_WEIGHT * (e - v)));
            }
        }
        let (wn, wc) = match self.noise {
            [Some(a), Some(b)] if a > 0.0 && b > 0.0 => (1.0 / a, 1.0 / b),
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
            None if self.learnt > 0 && dist(d, self.learning) <= gate => {
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

    /// Constant-velocity extrapolation of the last two positions to time `t`.
    fn predict(&self, t: f64) -> Option<Point> {
        match self.last {
            [Some((t1, p1)), Some((t0, p0))] if t1 > t0 => {
                let k = ((t - t1) / (t1 - t0)) as f32;
                Some(Point { x: p1.x + k * (p1.x - p0.x), y: p1.y + k * (p1.y - p0.y) })
            }
            [Some((_, p1)), _] => Some(p1),
            _ => None,
        }
    }
}

fn add(a: Point, b: Point) -> Point {
    Point { x: a.x + b.x, y: a.y + b.y }
}

fn sub(a: Point, b: Point) -> Point {
    Point { x: a.x - b.x, y: a.y - b.y }
}

fn dist(a: Point, b: Point) -> f32 {
    libm::hypotf(a.x - b.x, a.y - b.y)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f32, y: f32) -> Point {
        Point { x, y }
    }

    fn both(n: Point, score: f32, c: Point) -> Measured {
        Measured { ncc: Some((n, score)), corner: Some(c) }
    }

    #[test]
    fn cd_is_not_followed_before_its_offset_is_learnt() {
        // The template's point sits 10 px right of the corner: a raw corner is 10 px off.
        let mut g = Guard::new(GuardParams::default());
        g.decide(0.0, Measured { ncc: Some((p(50.0, 50.0), 0.999)), corner: None });
        let got = g.decide(0.01, Measured { ncc: None, corner: Some(p(40.0, 50.0)) });
        assert_eq!(got, None, "no offset yet: CD alone is not the tracked point");
    }

    #[test]
    fn offset_is_learnt_then_cd_carries_the_track_through_an_ncc_dropout() {
        let mut g = Guard::new(GuardParams::default());
        g.decide(0.0, Measured { ncc: Some((p(50.0, 50.0), 0.999)), corner: None });
        // Moving 1 px a frame right; the corner is (-10, +2) from the tracked point.
        for k in 1..=5 {
            let x = 50.0 + k as f32;
            let got = g.decide(0.01 * k as f64, both(p(x, 50.0), 0.995, p(x - 10.0, 52.0)));
            assert_eq!(got, Some((p(x, 50.0), Source::Ncc)));
        }
        let o = g.offset().expect("learnt after 3 consistent frames");
        assert!((o.x - 10.0).abs() < 1e-4 && (o.y + 2.0).abs() < 1e-4, "{o:?}");
        // NCC drops out (occluder): the CD candidate, corner + offset, is followed.
        let got = g.decide(0.06, Measured { ncc: None, corner: Some(p(46.0, 52.0)) });
        assert_eq!(got, Some((p(56.0, 50.0), Source::Cd)));
    }

    #[test]
    fn a_corner_far_from_the_prediction_is_refused() {
        let mut g = Guard::new(GuardParams::default());
        g.decide(0.0, Measured { ncc: Some((p(50.0, 50.0), 0.999)), corner: None });
        for k in 1..=4 {
            g.decide(0.01 * k as f64, both(p(50.0, 50.0), 0.995, p(40.0, 50.0)));
        }
        // CD jumps to another corner 8 px away while NCC is out: no position rather than a wrong one.
        assert_eq!(g.decide(0.05, Measured { ncc: None, corner: Some(p(48.0, 50.0)) }), None);
    }

    #[test]
    fn an_untrusted_ncc_that_slides_loses_to_an_agreeing_cd() {
        let mut g = Guard::new(GuardParams::default());
        g.decide(0.0, Measured { ncc: Some((p(50.0, 50.0), 0.999)), corner: None });
        for k in 1..=4 {
            g.decide(0.01 * k as f64, both(p(50.0, 50.0), 0.995, p(40.0, 50.0)));
        }
        // A highlight drags NCC 3 px (score 0.975, accepted but not trusted); CD stays put.
        let got = g.decide(0.05, both(p(53.0, 50.0), 0.975, p(40.0, 50.0)));
        assert_eq!(got, Some((p(50.0, 50.0), Source::Cd)));
    }

    #[test]
    fn a_corner_that_keeps_disagreeing_is_unlearnt() {
        let mut g = Guard::new(GuardParams::default());
        g.decide(0.0, Measured { ncc: Some((p(50.0, 50.0), 0.999)), corner: None });
        for k in 1..=4 {
            g.decide(0.01 * k as f64, both(p(50.0, 50.0), 0.995, p(40.0, 50.0)));
        }
        assert!(g.offset().is_some());
        // The detector now finds a texture corner 5 px away, three frames running.
        for k in 5..=7 {
            let got = g.decide(0.01 * k as f64, both(p(50.0, 50.0), 0.995, p(45.0, 50.0)));
            assert_eq!(got, Some((p(50.0, 50.0), Source::Ncc)), "trusted NCC wins");
        }
        assert_eq!(g.offset(), None);
    }

    #[test]
    fn a_corner_at_the_start_point_anchors_cd_and_outvotes_a_stuck_ncc() {
        let mut g = Guard::new(GuardParams::default());
        g.begin(p(50.0, 50.0));
        // First window: the detector's corner is 0.4 px from the start point.
        let got = g.decide(0.0, both(p(50.0, 50.0), 1.0, p(50.4, 50.0)));
        assert_eq!(got, Some((p(50.0, 50.0), Source::Ncc)));
        assert!(g.anchored());
        // The object moves 1 px a frame; NCC sticks to the background at (50, 50) with a high
        // score. Once they part by more than the gate, the anchored corner is followed.
        let mut last = None;
        for k in 1..=4 {
            let x = 50.0 + k as f32;
            last = g.decide(0.01 * k as f64, both(p(50.0, 50.0), 0.998, p(x + 0.4, 50.0)));
        }
        assert_eq!(last, Some((p(54.0, 50.0), Source::Cd)));
    }

    #[test]
    fn a_corner_away_from_the_start_point_does_not_anchor() {
        let mut g = Guard::new(GuardParams::default());
        g.begin(p(50.0, 50.0));
        g.decide(0.0, both(p(50.0, 50.0), 1.0, p(40.0, 50.0)));
        assert!(!g.anchored());
        assert_eq!(g.offset(), None, "one frame is not enough to learn an offset");
    }

    #[test]
    fn agreeing_sources_are_fused_by_their_steadiness() {
        let mut g = Guard::new(GuardParams::default());
        g.decide(0.0, Measured { ncc: Some((p(50.0, 50.0), 0.999)), corner: None });
        // A static target; NCC jitters by +-0.4 px, CD (offset learnt from NCC) by +-0.1 px.
        for k in 1..=40 {
            let s = if k % 2 == 0 { 1.0 } else { -1.0 };
            g.decide(0.01 * k as f64, both(p(50.0 + 0.4 * s, 50.0), 0.995, p(40.0 - 0.1 * s, 50.0)));
        }
        // Learnt offset ~10 px. Hand calculation for the next frame: innovations about 0.4 and
        // 0.1 px, so the weights are ~1/0.16 and ~1/0.01 and CD's share k ~ 0.94.
        let (q, src) = g.decide(0.41, both(p(50.4, 50.0), 0.995, p(39.9, 50.0))).expect("agreeing");
        assert_eq!(src, Source::Cd);
        assert!((q.x - 50.0).abs() < 0.1, "fused {q:?} nearer CD's 49.9.. than NCC's 50.4");
    }

    #[test]
    fn prediction_extrapolates_constant_velocity() {
        let mut g = Guard::new(GuardParams::default());
        g.decide(0.0, Measured { ncc: Some((p(0.0, 0.0), 0.999)), corner: None });
        g.decide(1.0, Measured { ncc: Some((p(2.0, 1.0), 0.999)), corner: None });
        // Hand calculation: (2, 1) + (2, 1) * (3 - 1) / (1 - 0) = (6, 3).
        assert_eq!(g.predict(3.0), Some(p(6.0, 3.0)));
    }
}
