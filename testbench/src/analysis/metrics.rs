//! Tracking figures against ground truth, as the thesis defines them: RMS position error
//! (Figs. 2.9, 4.4-4.6), rate of loss-of-tracking (RLT, 3.4), and the lock-on, tracking and
//! recovery times of equations 2.1-2.3 (Table 2.3).
use crate::frames::groundtruth::Truth;
use crate::system::RunLog;

/// Errors beyond this many pixels count as lost (for RLT).
pub const LOST_PX: f64 = 3.0;

/// Oldest report, in frames, that still counts as a frame's position (the pipeline's
/// latency: a COOP decision waits for the partner's message).
pub const MAX_AGE: usize = 2;

/// The figures of one run.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Summary {
    /// Frames in the run.
    pub frames: usize,
    /// Frames with the tracked point inside the image.
    pub visible: usize,
    /// Position reports compared with the truth.
    pub reports: usize,
    /// RMS of the reports' position error, pixels.
    pub rms: f64,
    /// Mean error along x and y (signed), pixels.
    pub mean_x: f64,
    /// Mean error along y.
    pub mean_y: f64,
    /// Share of visible frames not tracked, or tracked more than [`LOST_PX`] off.
    pub rlt: f64,
    /// Eq. 2.1: from the target entering the field of view to the first report after it,
    /// seconds, averaged over every entry.
    pub lock_on: Option<f64>,
    /// Eq. 2.2: mean interval between consecutive reports while tracking, seconds.
    pub tracking: Option<f64>,
    /// Eq. 2.3: mean time from a loss (with the part in view) to the next report, seconds.
    pub recovery: Option<f64>,
}

/// Compares a run with the truth. The tracked point is a fixed point of the rigid part: when
/// the template's point was known before the run, its offset from the corner is known;
/// otherwise it is taken from the first report (the figures then measure jitter and drift,
/// not absolute position).
pub fn summarise(log: &RunLog, truth: &[Truth]) -> Summary {
    let period = log.frame_period;
    let offset = initial_offset(log, truth);
    let err = |frame: usize, x: f64, y: f64| -> Option<(f64, f64)> {
        let t = truth.get(frame)?;
        Some((x - t.corner.0 - offset.0, y - t.corner.1 - offset.1))
    };
    let errs: Vec<(f64, f64)> = log
        .reports
        .iter()
        .filter_map(|r| err(r.frame, f64::from(r.point.x), f64::from(r.point.y)))
        .collect();
    let n = errs.len().max(1) as f64;
    let rms = (errs.iter().map(|e| e.0 * e.0 + e.1 * e.1).sum::<f64>() / n).sqrt();
    let visible: Vec<usize> = (0..log.frames.len()).filter(|&k| truth.get(k).is_some_and(|t| t.visible)).collect();
    let lost = visible
        .iter()
        .filter(|&&k| {
            let r = &log.frames[k];
            match (r.point, r.measured_frame) {
                (Some((x, y)), Some(m)) => err(m, x, y).is_none_or(|e| e.0.hypot(e.1) > LOST_PX),
                _ => true,
            }
        })
        .count();
    let entries: Vec<f64> = (0..truth.len().min(log.frames.len()))
        .filter(|&k| truth[k].visible && (k == 0 || !truth[k - 1].visible))
        .map(|k| k as f64 * period)
        .collect();
    let locks: Vec<f64> =
        entries.iter().filter_map(|&e| log.reports.iter().find(|r| r.t >= e).map(|r| r.t - e)).collect();
    let gaps: Vec<f64> = log.reports.windows(2).map(|w| w[1].t - w[0].t).filter(|&g| g < 4.0 * period).collect();
    // Recovery from a loss inside the field of view: the part stays visible until tracked again
    // (a part leaving the image is a new lock-on, not a recovery).
    let seen = |t: f64| truth.get((t / period).max(0.0) as usize).is_some_and(|x| x.visible);
    let recoveries: Vec<f64> = log
        .losses
        .iter()
        .filter_map(|&l| {
            let r = log.reports.iter().find(|r| r.t > l)?;
            let steps = ((r.t - l) / period).ceil() as usize;
            (0..=steps).all(|i| seen(l + i as f64 * period)).then_some(r.t - l)
        })
        .collect();
    let mean = |v: &[f64]| (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64);
    Summary {
        frames: log.frames.len(),
        visible: visible.len(),
        reports: errs.len(),
        rms,
        mean_x: errs.iter().map(|e| e.0).sum::<f64>() / n,
        mean_y: errs.iter().map(|e| e.1).sum::<f64>() / n,
        rlt: if visible.is_empty() { 0.0 } else { lost as f64 / visible.len() as f64 },
        lock_on: mean(&locks),
        tracking: mean(&gaps),
        recovery: mean(&recoveries),
    }
}

/// Where the tracked point truly is in each frame: the part's corner plus the tracked
/// point's offset from it (see [`summarise`]).
pub fn true_points(log: &RunLog, truth: &[Truth]) -> Vec<(f64, f64)> {
    let o = initial_offset(log, truth);
    truth.iter().map(|t| (t.corner.0 + o.0, t.corner.1 + o.1)).collect()
}

/// The tracked point's offset from the part's corner (see [`summarise`]).
fn initial_offset(log: &RunLog, truth: &[Truth]) -> (f64, f64) {
    let known = log.reference.and_then(|(k, (x, y))| truth.get(k).map(|t| (x - t.corner.0, y - t.corner.1)));
    let first = || {
        let r = log.reports.first()?;
        let t = truth.get(r.frame)?;
        Some((f64::from(r.point.x) - t.corner.0, f64::from(r.point.y) - t.corner.1))
    };
    known.or_else(first).unwrap_or_default()
}
