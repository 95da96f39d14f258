//! Tracking figures against ground truth, as the thesis defines them: RMS position error
//! (Figs. 2.9, 4.4-4.6), rate of loss-of-tracking (RLT, 3.4), and the lock-on, tracking and
//! recovery times of equations 2.1-2.3 (Table 2.3).
use crate::frames::groundtruth::Truth;
use crate::system::RunLog;

/// Errors beyond this many pixels count as lost (for RLT).
pub const LOST_PX: f64 = 3.0;

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

/// Compares a run with the truth. The tracked point is a fixed point of the part (an `Anchor`):
/// when the template's point was known before the run, its place on the part is known;
/// otherwise it is taken from the first report (the figures then measure jitter and drift,
/// not absolute position).
pub fn summarise(log: &RunLog, truth: &[Truth]) -> Summary {
    let period = log.frame_period;
    let anchor = Anchor::of_run(log, truth);
    let err = |frame: usize, x: f64, y: f64| -> Option<(f64, f64)> {
        let p = anchor.point(truth.get(frame)?);
        Some((x - p.0, y - p.1))
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

/// Where the tracked point truly is in each frame (see [`summarise`]).
pub fn true_points(log: &RunLog, truth: &[Truth]) -> Vec<(f64, f64)> {
    let anchor = Anchor::of_run(log, truth);
    truth.iter().map(|t| anchor.point(t)).collect()
}

/// The tracked point's place on the part: its offset from the part's corner or from its
/// centre, whichever the point is nearer. On a rigid part every point keeps its offset; on a
/// part that turns or scales (`coopwin scene --set centre-rotate`), only these two points
/// are the truth's, so a point near one of them is taken as it.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Anchor {
    centre: bool,
    offset: (f64, f64),
}

impl Anchor {
    /// The point `(x, y)` in frame `k`: the run's reference point when known before the
    /// run, otherwise its first report.
    fn of_run(log: &RunLog, truth: &[Truth]) -> Anchor {
        let at = |k: usize, (x, y): (f64, f64)| {
            let t = truth.get(k)?;
            let centre = (x - t.centre.0).hypot(y - t.centre.1) < (x - t.corner.0).hypot(y - t.corner.1);
            let p = if centre { t.centre } else { t.corner };
            Some(Anchor { centre, offset: (x - p.0, y - p.1) })
        };
        let first = || log.reports.first().and_then(|r| at(r.frame, (f64::from(r.point.x), f64::from(r.point.y))));
        log.reference.and_then(|(k, p)| at(k, p)).or_else(first).unwrap_or(Anchor { centre: false, offset: (0.0, 0.0) })
    }

    /// Where it truly is in `t`'s frame.
    fn point(&self, t: &Truth) -> (f64, f64) {
        let p = if self.centre { t.centre } else { t.corner };
        (p.0 + self.offset.0, p.1 + self.offset.1)
    }
}

/// The area under the ROC curve of `confidence` as a detector of good frames: the chance
/// that a frame drawn from the good ones (`bad == false`) has a higher confidence than one
/// drawn from the bad ones, ties counting half (the Mann-Whitney statistic). 1 separates
/// them perfectly, 0.5 is a coin. `None` without a frame of each kind.
pub fn auroc(frames: &[(f64, bool)]) -> Option<f64> {
    let mut sorted: Vec<(f64, bool)> = frames.to_vec();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
    let bad = sorted.iter().filter(|f| f.1).count();
    let good = sorted.len() - bad;
    if bad == 0 || good == 0 {
        return None;
    }
    // Walk the confidences upward, one group of equal values at a time: each good frame beats
    // the bad frames below its group and ties with half of those in it.
    let (mut below_bad, mut wins, mut i) = (0usize, 0.0, 0);
    while i < sorted.len() {
        let j = i + sorted[i..].iter().take_while(|f| f.0 == sorted[i].0).count();
        let group_bad = sorted[i..j].iter().filter(|f| f.1).count();
        let group_good = (j - i) - group_bad;
        wins += group_good as f64 * (below_bad as f64 + group_bad as f64 / 2.0);
        below_bad += group_bad;
        i = j;
    }
    Some(wins / (good as f64 * bad as f64))
}

#[cfg(test)]
mod tests {
    use super::auroc;

    #[test]
    fn auroc_counts_the_pairs_a_confidence_orders_right() {
        // By hand: good 0.9, 0.8, 0.5 against bad 0.6, 0.1: of the 6 pairs the good frame is
        // above in all but (0.5, 0.6): 5/6.
        let frames = [(0.9, false), (0.6, true), (0.8, false), (0.1, true), (0.5, false)];
        assert!((auroc(&frames).unwrap() - 5.0 / 6.0).abs() < 1e-12);
        // A tie counts half: good 0.6 and 0.2 against bad 0.6: (0.5 + 0) / 2.
        assert_eq!(auroc(&[(0.6, false), (0.6, true), (0.2, false)]), Some(0.25));
        assert_eq!(auroc(&[(0.6, false), (0.2, false)]), None);
    }
}
