//! The processors' tuning (thesis Table 2.2's window sizes by default) and the placement of a
//! square window inside the frame.
use crate::kernels::matching::Method;
use crate::types::{Decimation, Point, WindowRequest};

/// Extra pixels on each side of a coasting track's Foveal window, beyond the window's own
/// +-2 px search: the prediction drifts while nothing is measured.
pub const COAST_MARGIN: u16 = 6;

/// Extra pixels on each side of an adapting track's Foveal window after a match on the
/// window's edge (the target moved further than the window's own search), or while its
/// motion is not known: 6 px a frame is a brisk motion at 25-30 frames/s.
pub const GROW_MARGIN: u16 = 6;

/// Most extra pixels on each side of an adapting track's Foveal window: a 32x32 template's
/// window stays within 64x64 (the largest the matcher and the corner detector take).
pub const MAX_MARGIN: u16 = 14;

/// Factor by which an adapting track's largest recent miss of the motion's prediction
/// decays a window: a shake widens the next few windows, not all the later ones.
pub const MISS_DECAY: f32 = 0.8;


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
        }
    }
}

/// Zero-mean NCC acceptance of an adapting template ([`Params::adapt`]). The template is at
/// most a few frames old, so a lower score means a changed look (a turn, a zoom, blur) more
/// often than another object; zero-mean NCC, unlike the thesis's, scores a flat or unrelated
/// patch near 0 however bright it is (a cut to another scene is not followed), and the
/// guard's prediction gate keeps a match far from the motion out. 0.4: the gap between
/// wind-blown leaves of opencv-doc's `tree.avi` (15 frames/s, blocky MPEG) scores 0.42-0.6
/// frame to frame at the place CSRT puts it; 0.7 lost it in the third frame.
pub const ADAPT_NCC_MIN: f32 = 0.4;

/// Zero-mean NCC from which an adapting track's Peripheral re-detects the object anywhere in
/// its window: no motion gate checks the match there, so it is the acceptance of the first
/// lock-on, not [`ADAPT_NCC_MIN`] (at 0.5 it re-locked onto a cheek 60 px from the eye).
pub const REDETECT_MIN: f32 = 0.7;

/// The thesis's NCC from which a fixed template's match confirms the target (issue 38): on
/// the long-term sets (`coopwin experiment long-term`) its right rows score 0.990 and more
/// (the best VOT-LT thresholds lie at NCC 0.990-0.994), while look-alikes, a panel over the
/// target and the background it is lost on score 0.97-0.99 (AUROC 0.99-1.00). The COOP
/// guard trusts NCC from the same score ([`super::coop::guard::GuardParams::default`]).
pub const CONFIRM_NCC: f32 = 0.99;

/// The aligned first template's score from which it confirms an adapting track's point as the
/// target's (issue 38).
pub const CONFIRM_ALIGN: f32 = 0.8;

/// The current template's score from which an adapting track stays vouched for, window after
/// window, while its first template aligns under [`CONFIRM_ALIGN`] or not at all (issue 38):
/// the drift correction's own acceptance of the first template ([`super::adapt::CONFIRM`]).
/// Measured on the long-term sets and clips (`coopwin experiment long-term`): at 0.8 the
/// chain carried the track onto the panel of `panel` (219 wrong rows; the match dips to
/// 0.846 as the panel comes over); at 0.9 no row is wrong, and the hinge of `Megamind.avi`
/// is vouched for on all its frames.
pub const HOLD_NCC: f32 = super::adapt::CONFIRM;

/// Windows in a row an adapting track may follow a point its first template does not confirm
/// before it is taken to have gone astray and lost (issue 38): a look-alike that crossed in
/// front, an occluder the template learnt. Measured on the long-term sets
/// (`coopwin experiment long-term`, recall of the `ok` 1 rows).
pub const UNCONFIRMED_RUN: u8 = 8;

/// The motion prior of an adapting track's re-detection (issue 38, FuCoLoT's): the Peripheral
/// hands over a location only within this many pixels of where the track's last motion carries
/// its last vouched point, the radius growing by [`PRIOR_GROWTH`] a Peripheral window (about a
/// frame) up to [`PRIOR_MAX`]. Measured on the long-term sets (`coopwin experiment
/// long-term`): with no bound on the distance, leaves-identical's copy, which comes in 140 px
/// and more from where the target left the view, is vouched for on 63 rows; with it, none.
pub const PRIOR_RADIUS: f32 = 24.0;

/// Pixels a Peripheral window the motion prior's radius grows by ([`PRIOR_RADIUS`]): a target
/// that turns while it is hidden (the swing of lookalike-front and crowd, at most 1.5 px a
/// frame) stays inside it.
pub const PRIOR_GROWTH: f32 = 2.0;

/// The motion prior's largest radius ([`PRIOR_RADIUS`]): under leaves-identical's 140 px.
pub const PRIOR_MAX: f32 = 120.0;

/// Seconds after its last vouched window after which an adapting track takes no location the
/// Peripheral hands over: the prior has lapsed, and the track stays absent. On vtest.avi (10
/// frames/s) the re-detections 8-27 s after the last vouched window were onto other people's
/// clothing (78 wrong rows on the coat, 75 on the blond); the long-term sets' right ones came
/// at most 72 frames (under 1 s of their camera's time) after it. The earring of
/// Megamind.avi pays: recall 0.81 with no lapse, 0.70 with it.
pub const PRIOR_SECONDS: f64 = 3.0;

impl Params {
    /// These parameters with the template adapting ([`Params::adapt`]).
    pub fn adaptive(self) -> Params {
        Params { adapt: true, ..self }
    }

    /// The Foveal processor's correlation and its acceptance: the thesis's NCC from
    /// `ncc_min`, or zero-mean NCC from [`ADAPT_NCC_MIN`] for a template that adapts.
    pub fn correlation(&self, adapting: bool) -> (Method, f32) {
        if adapting {
            (Method::Zncc, ADAPT_NCC_MIN)
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
