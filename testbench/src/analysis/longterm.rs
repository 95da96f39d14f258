//! Long-term scores (issue 38): a tracker judged by the rows it vouches for, as VOT-LT
//! (Lukezic et al., "Now you see me", 2018) and OxUvA (Valmadre et al., 2018) judge one.
//!
//! A row is *vouched* when it has `ok` 1; it is *right* when its point lies within
//! [`RIGHT_PX`] of the target's, or inside the target's labelled box (a hand label's box may
//! also stand where the target is hidden; a synthetic set's truth is a point, given only
//! while the target is visible). With the rows vouched at confidence at least `tau`:
//! - precision `Pr(tau)` = right rows / vouched rows (1 when none is vouched: nothing promised,
//!   nothing broken; VOT-LT's convention);
//! - recall `Re(tau)` = right rows / frames where the target is visible;
//! - `F(tau) = 2 Pr Re / (Pr + Re)`, and VOT-LT's F is its largest over `tau`;
//! - OxUvA's TPR is the recall at `tau = 0` (every `ok` 1 row), its TNR the share of frames
//!   where the target is hidden or gone whose row is not vouched.
//!
//! The confidences' AUROC separates right rows from wrong ones among every row (a row not
//! vouched has confidence -1, and is "wrong" for the AUROC when the target is visible).

use super::metrics::auroc;

/// Largest distance in pixels from the target's point at which a row is right (5 px, as in
/// the real-image evaluation and the criterion).
pub const RIGHT_PX: f64 = 5.0;

/// One frame's row, as the tracker's CSV gives it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Row {
    /// The row's `ok`.
    pub ok: bool,
    /// Its confidence, -1 without one (the AUROC and the F ignore it where the row is not
    /// `ok`; the reliability diagram counts every row with one).
    pub confidence: f64,
    /// Its point, when it has one.
    pub point: Option<(f64, f64)>,
}

/// The target in one frame, as the ground truth has it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Truth {
    /// Whether it can be seen: recall counts these frames, TNR the others.
    pub visible: bool,
    /// Where a row is right: the target's centre and the half-sides of its box (0 for a
    /// point); `None` where no row can be right (gone, or hidden with no box).
    pub on: Option<((f64, f64), (f64, f64))>,
}

impl Truth {
    /// A point target: right within [`RIGHT_PX`] of `point` while it is visible.
    pub fn point(point: Option<(f64, f64)>) -> Truth {
        Truth { visible: point.is_some(), on: point.map(|p| (p, (0.0, 0.0))) }
    }

    /// A labelled box `x, y, w, h` (pixel centres at integers: it covers columns x..x+w-1).
    pub fn labelled(visible: bool, bbox: Option<(f64, f64, f64, f64)>) -> Truth {
        let on = bbox.map(|(x, y, w, h)| ((x + (w - 1.0) / 2.0, y + (h - 1.0) / 2.0), ((w - 1.0) / 2.0, (h - 1.0) / 2.0)));
        Truth { visible, on }
    }

    /// Whether `row` is vouched and right.
    pub fn is_right(&self, row: &Row) -> bool {
        row.ok && self.is_on(row)
    }

    /// Whether `row`'s point, vouched for or not, is where a row is right.
    pub fn is_on(&self, row: &Row) -> bool {
        match (row.point, self.on) {
            (Some(p), Some((c, half))) => {
                let (dx, dy) = (p.0 - c.0, p.1 - c.1);
                (dx.abs() <= half.0 && dy.abs() <= half.1) || dx.hypot(dy) <= RIGHT_PX
            }
            _ => false,
        }
    }
}

/// A tracker's long-term scores on one sequence.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LongTermScore {
    /// Frames.
    pub frames: usize,
    /// Frames where the target is visible.
    pub visible: usize,
    /// Rows vouched (`ok` 1).
    pub vouched: usize,
    /// Rows vouched and wrong: off the target by more than [`RIGHT_PX`], or while it is hidden
    /// or gone.
    pub wrong: usize,
    /// The longest run of consecutive frames vouched and wrong: how long a robot following
    /// the rows would follow something else.
    pub wrong_run: usize,
    /// Precision of every vouched row.
    pub precision: f64,
    /// OxUvA's TPR: the recall of every vouched row.
    pub recall: f64,
    /// OxUvA's TNR; `None` when the target is never absent.
    pub tnr: Option<f64>,
    /// VOT-LT's F: the largest F over the confidence thresholds.
    pub f: f64,
    /// The confidence threshold of that F.
    pub tau: f64,
    /// AUROC of the confidence, right rows against the others; `None` when all are one kind.
    pub auroc: Option<f64>,
    /// Frames where the target is visible and the row's position, measured and reported, is
    /// on it but has `ok` 0 (not vouched for, or vouched for more than the CSV's age rule
    /// allows before): the recall the verdict withholds.
    pub withheld: usize,
    /// Frames where the target is visible and the row has no measured position (the track
    /// coasting, lost or searching): the recall the tracking loses. The visible frames
    /// neither right, withheld nor unmeasured are those measured off the target.
    pub unmeasured: usize,
}

/// Scores `rows` against `truth` (one entry a frame; the shorter decides the frames).
pub fn score(rows: &[Row], truth: &[Truth]) -> LongTermScore {
    let n = rows.len().min(truth.len());
    let (rows, truth) = (&rows[..n], &truth[..n]);
    let right = |r: &Row, t: &Truth| t.is_right(r);
    let visible = truth.iter().filter(|t| t.visible).count();
    let vouched: Vec<(f64, bool, bool)> = rows.iter().zip(truth).filter(|(r, _)| r.ok).map(|(r, t)| (r.confidence, right(r, t), t.visible)).collect();
    let wrong = vouched.iter().filter(|v| !v.1).count();
    let wrong_run = rows
        .iter()
        .zip(truth)
        .scan(0usize, |run, (r, t)| {
            *run = if r.ok && !t.is_right(r) { *run + 1 } else { 0 };
            Some(*run)
        })
        .max()
        .unwrap_or(0);
    let pr_re = |tau: f64| {
        let (mut kept, mut good) = (0usize, 0usize);
        let mut recalled = 0usize;
        for &(c, ok, seen) in &vouched {
            if c >= tau {
                kept += 1;
                good += usize::from(ok);
                recalled += usize::from(ok && seen);
            }
        }
        let pr = if kept == 0 { 1.0 } else { good as f64 / kept as f64 };
        (pr, recalled as f64 / visible.max(1) as f64)
    };
    let f_of = |(pr, re): (f64, f64)| if pr + re > 0.0 { 2.0 * pr * re / (pr + re) } else { 0.0 };
    let mut taus: Vec<f64> = vouched.iter().map(|v| v.0).collect();
    taus.push(f64::NEG_INFINITY);
    let (f, tau) = taus.iter().map(|&t| (f_of(pr_re(t)), t)).fold((0.0, f64::NEG_INFINITY), |b, c| if c.0 > b.0 { c } else { b });
    let (precision, recall) = pr_re(f64::NEG_INFINITY);
    let absent: Vec<bool> = rows.iter().zip(truth).filter(|(_, t)| !t.visible).map(|(r, _)| !r.ok).collect();
    let tnr = (!absent.is_empty()).then(|| absent.iter().filter(|s| **s).count() as f64 / absent.len() as f64);
    let missed = || rows.iter().zip(truth).filter(|(r, t)| t.visible && !r.ok);
    let withheld = missed().filter(|(r, t)| r.confidence >= 0.0 && t.is_on(r)).count();
    let unmeasured = missed().filter(|(r, _)| r.confidence < 0.0).count();
    let judged: Vec<(f64, bool)> = rows.iter().zip(truth).map(|(r, t)| (if r.ok { r.confidence } else { -1.0 }, !right(r, t))).collect();
    LongTermScore {
        frames: n,
        visible,
        vouched: vouched.len(),
        wrong,
        wrong_run,
        precision,
        recall,
        tnr,
        f,
        tau: tau.max(0.0),
        auroc: auroc(&judged),
        withheld,
        unmeasured,
    }
}

/// One tenth of a reliability diagram: its rows, how many of them are right (vouched for or
/// not, [`Truth::is_on`]) and the sum of their confidences.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Bin {
    /// Rows with a confidence in this tenth.
    pub rows: usize,
    /// Those whose point is the target's.
    pub right: usize,
    /// Their confidences, summed.
    pub confidence: f64,
}

/// A reliability diagram's bins: every row with a confidence (vouched for or not) by tenth of
/// the confidence; a calibrated confidence has each bin's share of right rows equal to its mean.
pub fn reliability(rows: &[Row], truth: &[Truth]) -> [Bin; 10] {
    let mut bins = [Bin::default(); 10];
    for (r, t) in rows.iter().zip(truth).filter(|(r, _)| r.confidence >= 0.0) {
        let b = &mut bins[((r.confidence.min(1.0) * 10.0) as usize).min(9)];
        b.rows += 1;
        b.right += usize::from(t.is_on(r));
        b.confidence += r.confidence;
    }
    bins
}

/// Adds `more`'s rows into `bins`.
pub fn pool(bins: &mut [Bin; 10], more: &[Bin; 10]) {
    for (b, m) in bins.iter_mut().zip(more) {
        (b.rows, b.right, b.confidence) = (b.rows + m.rows, b.right + m.right, b.confidence + m.confidence);
    }
}

/// The expected calibration error: the rows' mean distance between a bin's mean confidence and
/// its share of right rows, `sum |right_b - confidence_b| / rows` (Naeini et al., 2015);
/// `None` without rows.
pub fn calibration_error(bins: &[Bin; 10]) -> Option<f64> {
    let rows: usize = bins.iter().map(|b| b.rows).sum();
    (rows > 0).then(|| bins.iter().map(|b| (b.right as f64 - b.confidence).abs()).sum::<f64>() / rows as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(ok: bool, confidence: f64, x: f64) -> Row {
        Row { ok, confidence, point: Some((x, 0.0)) }
    }

    #[test]
    fn the_visible_frames_missed_are_told_apart() {
        // Hand count: the target at x 0 in all six frames. Rows: vouched and right; measured
        // on it, not vouched (twice); measured 6 px off, not vouched; no measured position
        // (a prediction: confidence -1, twice).
        let truth = [Truth::point(Some((0.0, 0.0))); 6];
        let rows = [row(true, 0.9, 0.0), row(false, 0.6, 1.0), row(false, 0.6, 0.0), row(false, 0.6, 6.0), row(false, -1.0, 0.0), row(false, -1.0, 9.0)];
        let s = score(&rows, &truth);
        assert_eq!((s.withheld, s.unmeasured), (2, 2));
        assert!((s.recall - 1.0 / 6.0).abs() < 1e-12);
    }

    #[test]
    fn scores_match_a_hand_count() {
        // Five frames: target at x 0 in frames 0-2, absent in 3-4.
        // Rows: right (0.9), wrong by 6 px (0.8), not vouched, vouched while absent (0.3),
        // silent while absent.
        let at = Truth::point(Some((0.0, 0.0)));
        let truth = [at, at, at, Truth::point(None), Truth::point(None)];
        let rows = [row(true, 0.9, 1.0), row(true, 0.8, 6.0), row(false, 0.0, 0.0), row(true, 0.3, 0.0), row(false, 0.0, 0.0)];
        let s = score(&rows, &truth);
        assert_eq!((s.frames, s.visible, s.vouched, s.wrong), (5, 3, 3, 2));
        // Wrong rows 1 and 3 are apart (row 2 is silent): the longest wrong run is one frame.
        assert_eq!(s.wrong_run, 1);
        // Every vouched row: precision 1/3, recall 1/3; TNR 1/2.
        assert!((s.precision - 1.0 / 3.0).abs() < 1e-12 && (s.recall - 1.0 / 3.0).abs() < 1e-12);
        assert_eq!(s.tnr, Some(0.5));
        // From tau 0.9: precision 1, recall 1/3, F = 2 (1/3) / (4/3) = 0.5, the best.
        assert!((s.f - 0.5).abs() < 1e-12 && s.tau == 0.9, "{s:?}");
        // AUROC: the one right row (0.9) above the four others (0.8, -1, 0.3, -1): 1.
        assert_eq!(s.auroc, Some(1.0));
    }

    #[test]
    fn silence_is_precise_but_recalls_nothing() {
        let truth = [Truth::point(Some((0.0, 0.0))), Truth::point(None)];
        let s = score(&[row(false, 0.0, 0.0), row(false, 0.0, 0.0)], &truth);
        assert_eq!((s.precision, s.recall, s.f, s.tnr), (1.0, 0.0, 0.0, Some(1.0)));
    }

    #[test]
    fn reliability_bins_every_row_with_a_confidence_by_tenths() {
        let truth = [Truth::point(Some((0.0, 0.0))); 5];
        // Right at 0.95, wrong by 9 px at 0.91, right unvouched at 0.2 and at 0.0, and a row
        // without a confidence (-1), which no bin takes.
        let rows = [row(true, 0.95, 0.0), row(true, 0.91, 9.0), row(false, 0.2, 0.0), row(false, 0.0, 0.0), row(false, -1.0, 0.0)];
        let bins = reliability(&rows, &truth);
        assert_eq!((bins[9].rows, bins[9].right, bins[2].rows, bins[2].right, bins[0].rows, bins[5].rows), (2, 1, 1, 1, 1, 0));
        assert!((bins[9].confidence - 1.86).abs() < 1e-12);
        // By hand: |1 - 1.86| + |1 - 0.2| + |1 - 0| = 2.66 over 4 rows.
        assert!((calibration_error(&bins).unwrap() - 2.66 / 4.0).abs() < 1e-12);
        let mut twice = bins;
        pool(&mut twice, &bins);
        assert_eq!((twice[9].rows, twice[2].right), (4, 2));
        assert_eq!(calibration_error(&[Bin::default(); 10]), None);
    }

    #[test]
    fn a_labelled_box_takes_rows_inside_it_and_near_its_centre() {
        // Box 10,20,11x31: centre (15, 35), half-sides 5 and 15 (columns 10-20, rows 20-50).
        let hidden = Truth::labelled(false, Some((10.0, 20.0, 11.0, 31.0)));
        let at = |x, y| Row { ok: true, confidence: 1.0, point: Some((x, y)) };
        assert!(hidden.is_right(&at(20.0, 50.0)) && hidden.is_right(&at(10.0, 20.0)));
        assert!(!hidden.is_right(&at(20.5, 35.0)) && !hidden.is_right(&at(15.0, 50.5)));
        // Outside the box's side but within 5 px of the centre: a narrow box still takes it.
        let narrow = Truth::labelled(true, Some((15.0, 20.0, 1.0, 31.0)));
        assert!(narrow.is_right(&at(19.0, 35.0)) && !narrow.is_right(&at(20.5, 35.0)));
        // A hidden frame's right row counts for precision, not for recall, and breaks TNR.
        let s = score(&[at(15.0, 35.0)], &[hidden]);
        assert_eq!((s.precision, s.recall, s.tnr, s.wrong), (1.0, 0.0, Some(0.0), 0));
        // Two wrong rows in a row, then a right one: a run of 2.
        let s = score(&[at(40.0, 35.0), at(40.0, 35.0), at(15.0, 35.0)], &[hidden; 3]);
        assert_eq!((s.wrong, s.wrong_run), (2, 2));
        // Gone: no box, no right row.
        assert!(!Truth::labelled(false, None).is_right(&at(15.0, 35.0)));
    }
}
