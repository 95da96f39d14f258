//! Template adaptation with drift correction (beyond the thesis, issue 21): the Foveal NCC
//! template follows an object that turns, scales, tilts, blurs or changes its lighting,
//! without drifting off the point it was cut at.
//!
//! The thesis keeps the template cut at lock-on, so NCC's score falls under the acceptance
//! level as soon as the object's appearance changes, and the track is lost. Updating the
//! template from every frame follows the appearance but lets each update's small error add
//! up (the template drifts). The rule here is Matthews, Ishikawa and Baker's strategy 3
//! ("The Template Update Problem", PAMI 2004), with translation as the warp:
//!
//! 1. Track with the current template `T_n`: the point `p_n` and its score `s_n`.
//! 2. Only when `s_n < `[`REFRESH`] (the appearance has changed measurably) is a new template
//!    proposed; while it holds, `T_n` is kept and nothing accumulates.
//! 3. Drift correction: the first template `T_1` is aligned in the same window, near `p_n`.
//!    Where it aligns under a similarity warp ([`Adaptive::align`]), `p_n` is already its
//!    point and only its translated score is measured there; otherwise it is searched (zero-mean
//!    NCC within [`RECLAIM_REACH`] px, then Lucas-Kanade from its best placement). When it
//!    still matches (score `>=` [`CONFIRM`]) and lands within [`DRIFT`] px of `p_n`, the new
//!    template is cut at `T_1`'s point `p*`, which carries no accumulated error.
//!    When `T_1` matches as well as at lock-on (score `>=` [`RECLAIM`]) `T_1` itself is taken
//!    back, wherever it lands: the object looks as it did, any drift is dropped, and a
//!    rigid object is tracked with its first template as the thesis tracks it.
//! 4. Otherwise (the object has turned too far for `T_1` to match) the new template is cut
//!    at `p_n`: drift can accumulate only while the object looks unlike its first view, and
//!    is removed as soon as it looks like it again.
//!
//! The proposal is taken only if the track then follows NCC's own measurement, and is vouched
//! for or still matches at [`super::params::FovealParams::learn_in_doubt`]
//! ([`Adaptive::take`]); otherwise it is discarded ([`Adaptive::discard`]).
use super::coop::guard::dist;
use super::template::Template;
use crate::kernels::matching::{best_match_near, score_at, Method};
use crate::kernels::refine::INTERIOR;
use crate::kernels::view::WindowView;
use crate::kernels::warp::{Pose, SimilarityTemplate};
use crate::types::Point;

/// Score against the current template under which a new template is proposed.
pub const REFRESH: f32 = 0.99;
/// Score of the first template from which its alignment corrects the drift.
pub const CONFIRM: f32 = 0.9;
/// Largest distance in pixels between the current template's point and the first template's
/// for the first to confirm it.
pub const DRIFT: f32 = 1.0;
/// Score of the first template aligned under a similarity warp from which its point is the
/// track's ([`Adaptive::align`]): lower than [`CONFIRM`], as the warp has taken out the turn and
/// scale that a translated template's score suffers from, and what is left (blur, tilt, light)
/// does not bias the aligned point as much as it lowers the score.
pub const ALIGN: f32 = 0.5;
/// Score from which the first template's point is taken at any distance up to
/// [`RECLAIM_REACH`]: the object looks as it did at lock-on again, and whatever the updates
/// accumulated is dropped.
pub const RECLAIM: f32 = 0.95;
/// Farthest, in pixels a side, from the current template's point that the first template is
/// searched (49 placements instead of the whole window's, which grows with the motion): the
/// drift that a turn away from the first view and back accumulates stays under it.
pub const RECLAIM_REACH: usize = 3;

/// What a window proposes as the next template.
// Without an allocator the template cannot be boxed, and the one proposal pending must have
// room for a cut anyway (nearly every proposal is one): a smaller `First` saves nothing.
#[allow(clippy::large_enum_variant)]
enum Proposal {
    /// The first template, taken back.
    First,
    /// A template cut from the window.
    Cut(Template),
}

/// The first template, prepared for alignment for up to `P` used pixels (as its tracker's
/// [`crate::kernels::refine::LkTemplate`]: `(n - 2)²` for an `n x n` template), and the
/// template proposed by the last window.
pub struct Adaptive<const P: usize = INTERIOR> {
    first: Template,
    first_sim: SimilarityTemplate<P>,
    pending: Option<Proposal>,
    /// The current template is the first one: set when a proposal is taken, not when it is
    /// made (a proposal may be discarded).
    on_first: bool,
    /// The first template's turn and scale in the last window it aligned in (`(a, b)` of
    /// its [`Pose`]): the next alignment starts from them.
    shape: (f32, f32),
    /// This window's translation match of the current template when that is the first
    /// ([`Adaptive::matched`]): the first template's own, which [`Adaptive::propose`] then
    /// need not search for again.
    first_match: Option<(Point, f32)>,
}

impl<const P: usize> Adaptive<P> {
    /// Adaptation anchored on `first` (the template cut at lock-on).
    pub fn new(first: &Template) -> Self {
        let mut first_sim = SimilarityTemplate::sized();
        if let Some(v) = first.view() {
            first_sim.prepare(&v);
        }
        Adaptive { first: first.clone(), first_sim, pending: None, on_first: true, shape: (1.0, 0.0), first_match: None }
    }

    /// The first template.
    pub fn first(&self) -> &Template {
        &self.first
    }

    /// Whether the current template is the first.
    pub fn on_first(&self) -> bool {
        self.on_first
    }

    /// The first template, to track with again (a re-detected object): nothing proposed.
    pub fn back_to_first(&mut self) -> Template {
        (self.pending, self.on_first) = (None, true);
        self.first.clone()
    }

    /// The point the current template measured `at` in `win`, refined by aligning the first
    /// template there under a similarity warp ([`crate::kernels::warp`]), and the first
    /// template's pose (frame coordinates) and its score; `None` when it does not align with a score of
    /// at least [`ALIGN`] (the object no longer looks like a turned and scaled first view), or
    /// with fewer than `min_inside` of its pixels in `win` ([`SimilarityTemplate::align`]).
    ///
    /// The first template carries no accumulated error, and the warp follows a turn or a
    /// scale that biases a translated template's match: where it aligns, its point is the
    /// drift-free one.
    pub fn align(&mut self, win: &WindowView<'_>, at: Point, min_inside: f32) -> Option<(Point, Pose, f32)> {
        let n = self.first.side() as f32;
        let c = (n - 1.0) / 2.0;
        let (ox, oy) = (win.origin().0 as f32, win.origin().1 as f32);
        // The tracked point's offset from the template's centre, and the centre it puts at `at`.
        let (du, dv) = (self.first.anchor().x - c, self.first.anchor().y - c);
        let (a, b) = self.shape;
        let start = Pose { x: at.x - ox - (a * du - b * dv), y: at.y - oy - (b * du + a * dv), a, b };
        let found = self.first_sim.align(win, start, min_inside).filter(|f| f.score >= ALIGN)?;
        self.shape = (found.pose.a, found.pose.b);
        let (x, y) = found.pose.map(du, dv);
        let pose = Pose { x: found.pose.x + ox, y: found.pose.y + oy, ..found.pose };
        Some((Point { x: x + ox, y: y + oy }, pose, found.score))
    }

    /// The current template `tpl` matched at `point` (the first template's aligned point, or
    /// the match refined by Lucas-Kanade where it did not align) with `score` (translated) in
    /// this window: when `tpl` is the first template, that is the first template's match,
    /// kept for [`Adaptive::propose`].
    pub fn matched(&mut self, tpl: &Template, point: Point, score: f32) {
        self.first_match = (*tpl == self.first).then_some((point, score));
    }

    /// The current template measured `at` with `score` in `win`: proposes the next template
    /// (see the module documentation), replacing any earlier proposal. `aligned`: `at` is the
    /// first template's own point, aligned there under a similarity warp ([`Adaptive::align`]),
    /// so only its translated score is measured (one placement), not its point.
    pub fn propose(&mut self, win: &WindowView<'_>, at: Point, score: f32, n: usize, aligned: bool) {
        self.pending = None;
        let first_match = self.first_match.take();
        if score >= REFRESH {
            return;
        }
        let first = if aligned {
            first_match.map(|(_, s)| s).or_else(|| self.first_score(win, at)).map(|s| (at, s))
        } else {
            first_match.or_else(|| self.first_point(win, at))
        };
        let first = first.filter(|&(_, s)| s >= CONFIRM);
        let cut_at = match first {
            // The object looks as it did at lock-on: the first template itself, unchanged.
            Some((_, s)) if s >= RECLAIM => {
                if !self.on_first {
                    self.pending = Some(Proposal::First);
                }
                return;
            }
            Some((p, _)) if dist(p, at) <= DRIFT => p,
            _ => at,
        };
        self.pending = Template::capture(win, cut_at, n).map(Proposal::Cut);
    }

    /// The placement of the first template in `win` that puts its anchor nearest `at`.
    fn placement_at(&self, win: &WindowView<'_>, at: Point) -> (usize, usize) {
        let (ox, oy) = win.origin();
        let placement = |p: f32, o: u32, anchor: f32| libm::roundf(p - o as f32 - anchor).max(0.0) as usize;
        (placement(at.x, ox, self.first.anchor().x), placement(at.y, oy, self.first.anchor().y))
    }

    /// The first template's translated (zero-mean NCC) score at its placement nearest `at`
    /// (the last one where `at` lies beyond it).
    fn first_score(&self, win: &WindowView<'_>, at: Point) -> Option<f32> {
        let tv = self.first.view()?;
        let (x, y) = self.placement_at(win, at);
        let last = |w: usize, t: usize| w.checked_sub(t);
        let p = (x.min(last(win.width(), tv.width())?), y.min(last(win.height(), tv.height())?));
        score_at(Method::Zncc, win, &tv, p).ok().map(|s| s as f32)
    }

    /// The first template's point in `win` and its score, when it still matches (score `>=`
    /// [`CONFIRM`]) within [`RECLAIM_REACH`] px of `at` (where the current template put the
    /// point: a drift of more would have been reclaimed before).
    fn first_point(&self, win: &WindowView<'_>, at: Point) -> Option<(Point, f32)> {
        let tv = self.first.view()?;
        let (ox, oy) = win.origin();
        let p = self.placement_at(win, at);
        let m = best_match_near(Method::Zncc, win, &tv, p, p, RECLAIM_REACH).ok()?;
        let score = m.score as f32;
        if score < CONFIRM {
            return None;
        }
        let (x, y) = self.first_sim.lk().refine(win, m.sub_x, m.sub_y).map_or((m.frame_x, m.frame_y), |(x, y)| (x + ox as f32, y + oy as f32));
        Some((self.first.point_at(x, y), score))
    }

    /// The proposed template, if the last window proposed one, as the current template from
    /// now on (taken: proposed once).
    pub fn take(&mut self) -> Option<Template> {
        let (template, on_first) = match self.pending.take()? {
            Proposal::First => (self.first.clone(), true),
            Proposal::Cut(t) => (t, false),
        };
        self.on_first = on_first;
        Some(template)
    }

    /// Forgets the proposal: the track did not follow its measurement.
    pub fn discard(&mut self) {
        self.pending = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::processors::testing::{cut, frame, square, template, TARGET};
    use crate::types::Decimation;

    /// The block with two pixels of 200 beside it, point-symmetric about the target.
    fn changed_look() -> std::vec::Vec<u8> {
        let mut changed = frame(Some((30, 20)));
        changed[21 * 64 + 29] = 200;
        changed[22 * 64 + 34] = 200;
        changed
    }

    #[test]
    fn a_perfect_match_proposes_nothing_and_a_changed_one_is_cut_where_the_first_template_lands() {
        let mut a = Adaptive::<INTERIOR>::new(&template());
        let win = square(24, 14, 16, Decimation::Full);
        // Score 1 >= REFRESH: the template is kept.
        a.propose(&cut(&frame(Some((30, 20))), &win), TARGET, 1.0, 8, false);
        assert!(a.take().is_none());
        // The look changed: two pixels of 200 beside the block, point-symmetric about the
        // target, so the first template still lands exactly on it, with zero-mean NCC 0.923
        // (hand calculation: numpy over the 8x8 patches), between CONFIRM and RECLAIM. The
        // current point is 0.6 px off: the cut is put back at the target (drift corrected).
        let changed = changed_look();
        let off = Point { x: TARGET.x + 0.6, y: TARGET.y };
        a.propose(&cut(&changed, &win), off, 0.95, 8, false);
        let t = a.take().expect("a proposal");
        let expected = Template::capture(&cut(&changed, &win), TARGET, 8).unwrap();
        assert_eq!(t.pixels(), expected.pixels());
        assert!((t.anchor().x - template().anchor().x).abs() < 1e-3, "{:?}", t.anchor());
        // Proposed once.
        assert!(a.take().is_none());
    }

    #[test]
    fn where_the_first_template_lands_too_far_away_the_cut_is_at_the_current_point() {
        let mut a = Adaptive::<INTERIOR>::new(&template());
        let win = square(24, 14, 16, Decimation::Full);
        // The block moved by (3, 2) and a bright pixel changed its look: the first template
        // matches 3.6 px from the point given, over DRIFT, with NCC under RECLAIM, so it
        // does not confirm the point and the cut is where the point is.
        let mut moved = frame(Some((33, 22)));
        moved[27 * 64 + 36] = 255;
        let at = Point { x: TARGET.x + 0.4, y: TARGET.y - 0.2 };
        a.propose(&cut(&moved, &win), at, 0.9, 8, false);
        let t = a.take().expect("a proposal");
        assert_eq!(Some(t), Template::capture(&cut(&moved, &win), at, 8));
        // Unchanged but moved, the block matches the first template exactly (NCC 1 >=
        // RECLAIM): the first template is taken back 3.6 px away (within RECLAIM_REACH);
        // once, as it is then the template in use.
        let moved = frame(Some((33, 22)));
        a.propose(&cut(&moved, &win), at, 0.9, 8, false);
        assert_eq!(a.take(), Some(template()));
        a.propose(&cut(&moved, &win), at, 0.9, 8, false);
        assert_eq!(a.take(), None);
    }

    #[test]
    fn an_aligned_point_is_cut_where_it_is_and_only_the_first_templates_score_is_measured() {
        let mut a = Adaptive::<INTERIOR>::new(&template());
        let win = square(24, 14, 16, Decimation::Full);
        // The changed look of the first test: at the placement nearest the aligned point the
        // first template scores 0.923 (hand calculation, numpy), between CONFIRM and RECLAIM.
        // The aligned point is the drift-free one: the cut is there, 0.3 px off the target,
        // not at a point searched again (the unaligned path would cut at the target).
        let changed = changed_look();
        let at = Point { x: TARGET.x + 0.3, y: TARGET.y };
        a.propose(&cut(&changed, &win), at, 0.95, 8, true);
        assert_eq!(a.take(), Template::capture(&cut(&changed, &win), at, 8));
        // The unchanged block scores 1 >= RECLAIM there: the first template is taken back.
        a.propose(&cut(&frame(Some((30, 20))), &win), at, 0.95, 8, true);
        assert_eq!(a.take(), Some(template()));
    }
}
