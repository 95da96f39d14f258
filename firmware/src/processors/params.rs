//! The processors' tuning (thesis Table 2.2's window sizes by default) and the placement of a
//! square window inside the frame.
use crate::kernels::matching::Method;
use crate::types::{Decimation, Point, WindowRequest};

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
    /// Beyond the thesis (issue 21): the Foveal template adapts to the object's appearance
    /// with drift correction ([`super::adapt`]) and its window is placed where the motion
    /// predicts the point. Off: the thesis's template cut once, windows on the last point.
    pub adapt: bool,
    /// The target was given as a box around the object (`track --target-box`): an adapting
    /// template, cut inside the box, is all object, and no corner support is cut from it
    /// ([`crate::kernels::support`], for a corner given as a point, whose template holds the
    /// background beyond its edges).
    pub target_boxed: bool,
    /// The Foveal's tuning for an adapting track.
    pub track: FovealParams,
    /// The Peripheral's tuning for an adapting track's re-detection.
    pub redetect: PeripheralParams,
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
            adapt: false,
            target_boxed: false,
            track: FovealParams::default(),
            redetect: PeripheralParams::default(),
        }
    }
}

/// The Foveal processor's tuning for an adapting track (issue 21's template that follows the
/// object's look, issue 38's verdict on it): its acceptance, its window, when a row is vouched
/// for, and when the track gives up. Each default says the measurement behind it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FovealParams {
    /// Zero-mean NCC from which an adapting template's match is accepted (default 0.4). The
    /// template is at most a few frames old, so a lower score means a changed look (a turn, a
    /// zoom, blur) more often than another object; zero-mean NCC, unlike the thesis's, scores a
    /// flat or unrelated patch near 0 however bright it is (a cut to another scene is not
    /// followed), and the guard's prediction gate keeps a match far from the motion out. The
    /// gap between wind-blown leaves of opencv-doc's `tree.avi` (15 frames/s, blocky MPEG)
    /// scores 0.42-0.6 frame to frame at the place CSRT puts it; 0.7 lost it in the third frame.
    pub accept: f32,
    /// NCC from which the thesis's fixed template's match, or an adapting template's while it
    /// is still the first, vouches for the point (default 0.99, issue 38): on the long-term
    /// sets (`coopwin experiment long-term`) right rows score 0.990 and more (the best VOT-LT
    /// thresholds lie at NCC 0.990-0.994), while look-alikes, a panel over the target and the
    /// background it is lost on score 0.97-0.99 (AUROC 0.99-1.00). The COOP guard trusts NCC
    /// from the same score ([`super::coop::guard::GuardParams::default`]).
    pub confirm_ncc: f32,
    /// The aligned first template's score from which it vouches for an adapting track's point
    /// (default 0.8, issue 38).
    pub confirm_align: f32,
    /// The current template's score from which an adapting track stays vouched for, window
    /// after window, where its first template does not align at all (default 0.9, the drift correction's own acceptance of the first template,
    /// [`super::adapt::CONFIRM`]). Measured on the long-term sets and clips: at 0.8 the chain
    /// carried the track onto the panel of `panel` (219 wrong rows; the match dips to 0.846 as
    /// the panel comes over); at 0.85 no row was wrong and the eye of Megamind.avi gained
    /// (recall 0.17 against 0.06), but the panel's dip missed the bar by 0.004; at 0.9 no row
    /// is wrong, and the hinge of `Megamind.avi` is vouched for on all its frames.
    pub hold_ncc: f32,
    /// The current template's score from which an adapting track stays vouched for, window
    /// after window, where its first template still aligns, if under
    /// [`FovealParams::confirm_align`] (default 0.8, stop 48): a view that changes from window
    /// to window, as a walking person's legs or an eye as the head turns, whose first view
    /// still corroborates the place; a panel the template learnt does not align at all, and
    /// holds only at [`FovealParams::hold_ncc`]. Measured on the long-term sets and clips: the
    /// crowd's recall 0.611 -> 0.704, Megamind's eyes 0.056 -> 0.169 and 0.050 -> 0.163,
    /// vtest's redcoat 0.047 -> 0.144, no row wrong; at 0.7 none either (crowd 0.724); at 0.6
    /// one on turned-front and on the crowd, three on vtest's jeans. Asking the first view to
    /// align at 0.65 rather than at all gave the eyes' gain back (0.063).
    pub hold_ncc_aligned: f32,
    /// The current template's score from which a track out of the chain (its last row not
    /// vouched for) is vouched for again where its first template aligns, if under
    /// [`FovealParams::confirm_align`] (default 0.9, stop 48). One window under the chain's
    /// bars used to leave a walking person unvouched until the first view aligned at 0.8
    /// again, which it rarely does. Measured on the long-term sets and clips: vtest's blond
    /// 0.004 -> 0.101, the redcoat 0.144 -> 0.159, no other figure moved and no row wrong;
    /// at 0.8 none wrong either (blond 0.115, redcoat 0.169), at 0.7 one on the stripes and the
    /// crowd's recall falls to 0.805, at 0.6 46 on the stripes (34 in a row).
    pub rejoin_ncc: f32,
    /// The current template's score from which a track whose row is not vouched for still
    /// learns the window's look (default 0.8, stop 48); under it the template stays the last
    /// one learnt, as item 1 of issue 38 asks: a look-alike or a cover coming over the object
    /// drops the match. Measured on the long-term sets and clips: the crowd's recall 0.704 ->
    /// 0.875 (ahead of the fixed template's 0.763), lookalike-front 0.957 -> 0.971,
    /// turned-front 0.954 -> 0.964, vtest's coat 0.127 -> 0.164, no row wrong; vtest's blond
    /// falls 0.071 -> 0.004 (in her tenth window the template matches at 0.7965 and the first
    /// view aligns at 0.796, just under both 0.8 bars: the chain breaks, and the template that
    /// stopped learning loses her before her first view aligns at 0.8 again). At 0.7 the crowd gains less (0.782); at 0.9 the redcoat loses a row; with no
    /// learning in doubt at all the redcoat falls 0.144 -> 0.072.
    pub learn_in_doubt: f32,
    /// The aligned first template's score from which a track out of the chain is vouched for
    /// again where the object comes back out from behind a cover, at the motion's prediction
    /// ([`FovealParams::rejoin_near`]; default 0.6, stop 53): there the current template,
    /// learnt before the cover came, matches at 0.48-0.68 and 1-5 of its 16 blocks at the
    /// chain's bar, while the first view aligns at 0.59-0.80 (lookalike-front, turned-front);
    /// the rows vouched for so are 0.07-0.53 px from the truth. A zero-mean NCC of 0.6 is about
    /// what a view 60 % the object's scores. Measured with `coopwin experiment long-term`,
    /// before the bound of [`FovealParams::rejoin_run`]: at 0.65 tree.avi's leaf gap gains one
    /// row (recall 0.033 against 0.467 at 0.6), at 0.55
    /// lookalike-front gets a wrong row where the target was under half in view, at 0.5
    /// turned-front too. Asked of a track still in the chain too (an object going under a
    /// cover), it vouched for such a row of the crowd, aligned at 0.645.
    pub rejoin_align: f32,
    /// Pixels from where the motion aimed the window within which a track out of the chain
    /// may be vouched for again by its first view aligned at [`FovealParams::rejoin_align`]
    /// (default 2, stop 53): the object coming out from behind a cover is where it was going.
    /// Measured on the long-term sets and clips, before the bound of
    /// [`FovealParams::rejoin_run`]: at 4 px two wrong rows on vtest's stripes; at 3 px none
    /// (and a little more recall: the gap 0.550 against 0.467 at 2 px, the redcoat 0.178
    /// against 0.163), so 2 keeps a margin.
    pub rejoin_near: f32,
    /// Windows a track may be vouched for as its object comes back out
    /// ([`FovealParams::rejoin_align`]) before its model vouches for one otherwise (its first
    /// view at `confirm_align`, the chain's bars or its blocks; default 4, stop 53): an object
    /// is out within a few windows, the long-term sets' within 2, and the rule is no second
    /// chain. A track (re)started has none until its model vouches for a window. Measured with `coopwin experiment long-term`: no other figure moves between 2 and
    /// 8 but tree.avi's leaf gap (its first view aligns at 0.5-0.8, never confirming), vouched
    /// for on 3 rows with 2, 15 with 4, 9 with 8, and 28 with no bound; with 2, vtest's blond
    /// loses a row.
    pub rejoin_run: u8,
    /// Share of an adapting template's blocks that must each still match, at `hold_ncc`, for a
    /// window whose whole match breaks the chain to be vouched for as the object partly
    /// covered (default 0.5, stop 50: at least half of it seen, as the long-term sets' truth
    /// calls a target visible). Measured with `coopwin experiment long-term`: `partial`'s
    /// recall 0.933 -> 1.000 (its 20 frames under the panel), lookalike-front 0.971 -> 0.979,
    /// turned-front 0.964 -> 0.971, the crowd 0.875 -> 0.895, Megamind_bugy's eye 0.163 ->
    /// 0.170, no row wrong and no other set's or clip's precision or recall moved; at 0.375 none wrong either
    /// (lookalike-front 0.982), nor at 0.5 with the blocks' bar at 0.8; at 0.375 with the bar
    /// at 0.8 one on lookalike-front, at 0.25 with 0.7 eight on four sets.
    pub cover_seen: f32,
    /// Zero-mean NCC from which the look the template had where its model last vouched for a
    /// window (`Foveal`'s `vouched_look`), matched where the current template matched best,
    /// vouches again for a window out of the chain whose first view aligns (default 0.7, stop
    /// 55). That look learns nothing in doubt, so what the current template has learnt since
    /// (a walking person's changing look, or a cover) is not in it. Measured with `coopwin
    /// experiment long-term`: vtest's redcoat 0.163 -> 0.269, the blond 0.111 -> 0.123, the
    /// red 0.069 -> 0.075, tree.avi's gap 0.250 -> 0.267, no row wrong, no other figure moved.
    /// In a first version (a recalled window could replace the look; docs/results.md): at
    /// 0.65 none wrong either, at 0.6 one on lookalike-front, whose recall fell; taking the
    /// look as the chain broke (the template the last vouched window taught) instead, a wrong
    /// row on vtest's coat at 0.7.
    pub vouched_look_ncc: f32,
    /// Windows in a row an adapting track may follow a point its first template does not
    /// confirm before it is taken to have gone astray and lost (default 8, issue 38): a
    /// look-alike that crossed in front, an occluder the template learnt. Measured on the
    /// long-term sets (recall of the `ok` 1 rows).
    pub unconfirmed_run: u8,
    /// Seconds after its last vouched window after which an adapting track takes no location
    /// the Peripheral hands over (default 3): the prior has lapsed, and the track stays absent.
    /// On vtest.avi (10 frames/s) the re-detections 8-27 s after the last vouched window were
    /// onto other people's clothing (78 wrong rows on the coat, 75 on the blond); the
    /// long-term sets' right ones came at most 72 frames (under 1 s of their camera's time)
    /// after it. The earring of Megamind.avi pays: recall 0.81 with no lapse, 0.70 with it.
    pub prior_seconds: f64,
    /// Extra pixels on each side of a coasting track's window, beyond the window's own +-2 px
    /// search (default 6): the prediction drifts while nothing is measured.
    pub coast_margin: u16,
    /// Extra pixels on each side of an adapting track's window after a match on the window's
    /// edge (the target moved further than the window's own search), or while its motion is
    /// not known (default 6: 6 px a frame is a brisk motion at 25-30 frames/s).
    pub grow_margin: u16,
    /// Most extra pixels on each side of an adapting track's window (default 14): a 32x32
    /// template's window stays within 64x64 (the largest the matcher and the corner detector
    /// take).
    pub max_margin: u16,
    /// Factor by which an adapting track's largest recent miss of the motion's prediction
    /// decays a window (default 0.8): a shake widens the next few windows, not all the later
    /// ones.
    pub miss_decay: f32,
}

impl Default for FovealParams {
    fn default() -> Self {
        FovealParams {
            accept: 0.4,
            confirm_ncc: 0.99,
            confirm_align: 0.8,
            hold_ncc: super::adapt::CONFIRM,
            hold_ncc_aligned: 0.8,
            rejoin_ncc: 0.9,
            rejoin_align: 0.6,
            rejoin_near: 2.0,
            rejoin_run: 4,
            learn_in_doubt: 0.8,
            cover_seen: 0.5,
            vouched_look_ncc: 0.7,
            unconfirmed_run: 8,
            prior_seconds: 3.0,
            coast_margin: 6,
            grow_margin: 6,
            max_margin: 14,
            miss_decay: 0.8,
        }
    }
}

/// The Peripheral processor's tuning for an adapting track's re-detection (issue 38): what it
/// takes for the object, and the motion prior (FuCoLoT's) a location must lie in to be handed
/// over. Each default says the measurement behind it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PeripheralParams {
    /// Zero-mean NCC from which the Peripheral re-detects the object anywhere in its window
    /// (default 0.7): no motion gate checks the match there, so it is the acceptance of the
    /// first lock-on, not [`FovealParams::accept`] (at 0.5 it re-locked onto a cheek 60 px from
    /// the eye).
    pub accept: f32,
    /// Pixels around where the track's last motion carries its last vouched point within which
    /// a location is handed over (default 24). With no bound on the distance, leaves-identical's
    /// copy, which comes in 140 px and more from where the target left the view, is vouched
    /// for on 63 rows (`coopwin experiment long-term`); with it, none.
    pub prior_radius: f32,
    /// Pixels a Peripheral window (about a frame) the prior's radius grows by (default 2): a
    /// target that turns while it is hidden (the swing of lookalike-front and crowd, at most
    /// 1.5 px a frame) stays inside it.
    pub prior_growth: f32,
    /// The prior's largest radius (default 120): under leaves-identical's 140 px.
    pub prior_max: f32,
}

impl Default for PeripheralParams {
    fn default() -> Self {
        PeripheralParams { accept: 0.7, prior_radius: 24.0, prior_growth: 2.0, prior_max: 120.0 }
    }
}

impl Params {
    /// The thesis's parameters for an `n`x`n` template searched `search` pixels a side: the
    /// Foveal window is `n + 2 search` (`track`'s `--template` and `--search`). The
    /// Peripheral's windows stay Table 2.2's whatever `n`: scaled with a 32x32 template (to 64
    /// and 102) they moved no figure of `coopwin experiment long-term` by more than a row
    /// (stop 49).
    pub fn sized(n: u16, search: u16) -> Params {
        Params { template: n, foveal: n + 2 * search, ..Params::default() }
    }

    /// These parameters with the template adapting ([`Params::adapt`]).
    pub fn adaptive(self) -> Params {
        Params { adapt: true, ..self }
    }

    /// The Foveal processor's correlation and its acceptance: the thesis's NCC from
    /// `ncc_min`, or zero-mean NCC from [`FovealParams::accept`] for a template that adapts.
    pub fn correlation(&self, adapting: bool) -> (Method, f32) {
        if adapting {
            (Method::Zncc, self.track.accept)
        } else {
            (Method::Ncc, self.ncc_min)
        }
    }

    /// A `side`x`side` window centred on `p`, moved inside the frame.
    pub fn window(&self, p: Point, side: u16, decimation: Decimation) -> WindowRequest {
        let side = side.min(self.frame_w).min(self.frame_h).max(2);
        let place = |c: f32, len: u16| {
            let start = libm::roundf(c - (f32::from(side) - 1.0) / 2.0);
            start.clamp(0.0, f32::from(len - side)) as u16
        };
        WindowRequest { x0: place(p.x, self.frame_w), y0: place(p.y, self.frame_h), width: side, height: side, decimation }
    }

    pub(super) fn foveal_window(&self, p: Point) -> WindowRequest {
        self.window(p, self.foveal, Decimation::Full)
    }
}
