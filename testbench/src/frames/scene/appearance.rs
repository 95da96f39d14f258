//! How the part's appearance changes over a run, beyond translation: it turns in the image
//! plane, scales (comes nearer and goes away), tilts out of plane, blurs with its motion,
//! passes under a sweeping shadow, and is covered for a stretch, to reappear elsewhere. These
//! make the evaluation sets of real use (issue 21): a tracker that only translates its template
//! loses such a part, however precise it is on rigid motion.
//!
//! Every change is smooth and periodic in time, so the truth of each frame is exact: the part
//! is the same photograph mapped through [`Pose`] about its centroid.
use std::f64::consts::TAU;

/// The appearance changes of a scene (all off by default: a rigid, sharp, evenly lit part).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Appearance {
    /// In-plane rotation about the centroid: `rotate_deg * sin(2 pi t / period)` degrees.
    pub rotate_deg: f64,
    /// Scale `scale^sin(2 pi t / period + 1)`: 1.25 sweeps 0.8-1.25x (1 or less: none).
    pub scale: f64,
    /// Out-of-plane tilt about the part's vertical axis, `tilt_deg * sin(...)` degrees: the part
    /// is foreshortened across by the cosine of the angle.
    pub tilt_deg: f64,
    /// Motion blur: each frame integrates the part's motion over the whole frame period (a
    /// shutter open all the time), so the blur is the displacement per frame.
    pub blur: bool,
    /// A soft shadow edge sweeping across the view twice per run: the light's gain goes from
    /// `1 - shadow` in the shadow to `1 + shadow * 0.75` in the highlight (0.4: gain 0.6-1.3).
    pub shadow: f64,
    /// The part is fully covered from this fraction of the run for `cover_frames` frames, and
    /// reappears displaced by `cover_jump` px (a second object passing in front, the part
    /// moved behind it).
    pub cover_at: Option<f64>,
    /// Frames the cover lasts.
    pub cover_frames: usize,
    /// Where the part reappears after the cover, relative to where it would have been.
    pub cover_jump: (f64, f64),
}

/// Periods, in runs: the rotation, scale and tilt oscillate at different rates so that all
/// combinations occur in a combined run.
const ROTATE_PERIODS: f64 = 2.0;
const SCALE_PERIODS: f64 = 1.5;
const TILT_PERIODS: f64 = 2.5;
/// Sub-frames a blurred frame integrates.
pub const BLUR_SAMPLES: usize = 9;
/// Width in pixels of the shadow's soft edge.
const SHADOW_EDGE: f64 = 10.0;

/// The part's pose at one moment: its linear map about the centroid (part coordinates to
/// frame coordinates), applied after the path's translation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// Row-major 2x2 matrix.
    pub m: [[f64; 2]; 2],
}

impl Pose {
    /// The identity: the rigid part.
    pub const RIGID: Pose = Pose { m: [[1.0, 0.0], [0.0, 1.0]] };

    /// `m * d`.
    pub fn apply(&self, d: (f64, f64)) -> (f64, f64) {
        (self.m[0][0] * d.0 + self.m[0][1] * d.1, self.m[1][0] * d.0 + self.m[1][1] * d.1)
    }

    /// `m^-1 * d` (the map is never singular: scales and cosines stay above 0.5).
    pub fn invert(&self, d: (f64, f64)) -> (f64, f64) {
        let [[a, b], [c, e]] = self.m;
        let det = a * e - b * c;
        ((e * d.0 - b * d.1) / det, (a * d.1 - c * d.0) / det)
    }

    /// The rotation angle in degrees and the mean scale (square root of the determinant).
    pub fn angle_scale(&self) -> (f64, f64) {
        let [[a, b], [c, e]] = self.m;
        (c.atan2(a).to_degrees(), (a * e - b * c).abs().sqrt())
    }
}

impl Appearance {
    /// The pose at `u`, the fraction of the run elapsed.
    pub fn pose(&self, u: f64) -> Pose {
        let wave = |periods: f64, phase: f64| (TAU * periods * u + phase).sin();
        let angle = self.rotate_deg.to_radians() * wave(ROTATE_PERIODS, 0.0);
        let s = if self.scale > 1.0 { self.scale.powf(wave(SCALE_PERIODS, 1.0)) } else { 1.0 };
        let squeeze = (self.tilt_deg.to_radians() * wave(TILT_PERIODS, 0.5)).cos();
        let (sin, cos) = angle.sin_cos();
        // R(angle) * diag(s * squeeze, s): the part foreshortened along its own x axis, scaled,
        // then turned.
        Pose { m: [[cos * s * squeeze, -sin * s], [sin * s * squeeze, cos * s]] }
    }

    /// The light's gain at column `x` of a `width`-wide frame at `u` (1 without a shadow).
    pub fn gain(&self, x: f64, width: f64, u: f64) -> f64 {
        if self.shadow <= 0.0 {
            return 1.0;
        }
        // The edge crosses the view left to right twice, starting and ending off it.
        let sweep = (2.0 * u).fract();
        let edge = -0.2 * width + 1.4 * width * sweep;
        let lit = 0.5 + 0.5 * ((x - edge) / SHADOW_EDGE).tanh();
        // Lit side behind the edge (left): highlight; ahead of it: shadow.
        1.0 - self.shadow + 1.75 * self.shadow * (1.0 - lit)
    }

    /// Whether frame `k` of `frames` is covered, and the displacement in force from then on.
    pub fn cover(&self, k: usize, frames: usize) -> (bool, (f64, f64)) {
        let Some(at) = self.cover_at else { return (false, (0.0, 0.0)) };
        let start = (at * frames as f64).round() as usize;
        let end = start + self.cover_frames;
        let jump = if k >= end { self.cover_jump } else { (0.0, 0.0) };
        ((start..end).contains(&k), jump)
    }

    /// Offsets in frame periods of the sub-frames frame `k` integrates, centred on its time.
    pub fn exposure(&self) -> impl Iterator<Item = f64> {
        let n = if self.blur { BLUR_SAMPLES } else { 1 };
        (0..n).map(move |j| if n == 1 { 0.0 } else { j as f64 / (n - 1) as f64 - 0.5 })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pose_sweeps_the_configured_ranges() {
        // Hand reference: the extremes are the amplitudes (rotation +-30 degrees, scale 0.8 to
        // 1.25, tilt cos 15 degrees = 0.966), sampled finely over one run.
        let a = Appearance { rotate_deg: 30.0, scale: 1.25, ..Appearance::default() };
        let (mut amin, mut amax, mut smin, mut smax) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for i in 0..=4000 {
            let (angle, s) = a.pose(i as f64 / 4000.0).angle_scale();
            (amin, amax, smin, smax) = (amin.min(angle), amax.max(angle), smin.min(s), smax.max(s));
        }
        assert!((amin + 30.0).abs() < 0.01 && (amax - 30.0).abs() < 0.01, "{amin} {amax}");
        assert!((smin - 0.8).abs() < 1e-3 && (smax - 1.25).abs() < 1e-3, "{smin} {smax}");
        let p = Pose { m: a.pose(0.3).m };
        let d = (3.0, -7.0);
        let back = p.invert(p.apply(d));
        assert!((back.0 - d.0).abs() < 1e-12 && (back.1 - d.1).abs() < 1e-12);
    }

    #[test]
    fn the_shadow_spans_gain_0_6_to_1_3() {
        let a = Appearance { shadow: 0.4, ..Appearance::default() };
        let g: Vec<f64> = (0..256).map(|x| a.gain(x as f64, 256.0, 0.25)).collect();
        let (lo, hi) = g.iter().fold((f64::MAX, f64::MIN), |(l, h), &v| (l.min(v), h.max(v)));
        assert!((lo - 0.6).abs() < 0.01 && (hi - 1.3).abs() < 0.01, "{lo} {hi}");
    }

    #[test]
    fn the_cover_lasts_its_frames_and_moves_the_part() {
        let a = Appearance { cover_at: Some(0.5), cover_frames: 40, cover_jump: (60.0, -30.0), ..Appearance::default() };
        let covered = (0..300).filter(|&k| a.cover(k, 300).0).count();
        assert_eq!(covered, 40);
        assert_eq!(a.cover(149, 300), (false, (0.0, 0.0)));
        assert_eq!(a.cover(190, 300), (false, (60.0, -30.0)));
    }
}
