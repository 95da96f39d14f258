//! A run's summary as text: what the run did and how fast ([`run_lines`]), the verdict
//! (tracked or lost), then the figures of eqs. 2.1-2.3 and RMS/RLT as a markdown table.
use super::ms;
use crate::analysis::metrics::Summary;
use crate::system::RunLog;
use std::fmt::Write as _;

/// Runs that lose more than this share of the visible frames read as lost.
pub const LOST_SHARE: f64 = 0.5;

/// One line that says first whether the run tracked or lost the target: the error figures
/// only cover the frames with a report, so they mean little for a lost run.
pub fn verdict(m: &Summary) -> String {
    let tracked = m.visible as f64 * (1.0 - m.rlt);
    let share = format!(
        "{tracked:.0} of {} frames with the target in view tracked ({:.0}% lost), {} position report(s)",
        m.visible,
        100.0 * m.rlt,
        m.reports
    );
    if m.reports == 0 {
        format!("LOST: {share}; no error figures")
    } else if m.rlt > LOST_SHARE {
        format!("LOST: {share}; the error figures cover those reports only")
    } else {
        format!("tracked: {share}")
    }
}

/// A markdown table of summaries, one row per labelled run.
pub fn summary_table(rows: &[(&str, Summary)]) -> String {
    let mut s = String::from(
        "| run | RMS error px | mean x, y px | RLT % | lock-on ms | tracking ms | recovery ms | reports |\n|---|---|---|---|---|---|---|---|\n",
    );
    for (name, m) in rows {
        let _ = writeln!(
            s,
            "| {name} | {} | {} | {:.1} | {} | {} | {} | {} |",
            if m.reports == 0 { "-".into() } else { format!("{:.3}", m.rms) },
            if m.reports == 0 { "-".into() } else { format!("{:+.2}, {:+.2}", m.mean_x, m.mean_y) },
            100.0 * m.rlt,
            ms(m.lock_on, 1),
            ms(m.tracking, 1),
            ms(m.recovery, 1),
            m.reports
        );
    }
    s
}

/// The lines `coopwin track` closes with for `log`: the HDL simulator's share (clocked units),
/// frames tracked and vouched for and the wall-clock rate against the simulated camera's, the lock-on, and
/// the log's losses and refusals. `secs` is the whole command's wall-clock time,
/// `tracking_secs` the run's; `first` the source's number of the run's frame 0.
pub fn run_lines(log: &RunLog, secs: f64, tracking_secs: f64, first: usize) -> Vec<String> {
    let mut lines = Vec::new();
    let secs = secs.max(1e-9);
    let tracked = log.frames.iter().filter(|r| r.point.is_some()).count();
    let vouched = log.frames.iter().filter(|r| r.vouched()).count();
    if log.hdl_clocks > 0 {
        lines.push(format!(
            "window units: {} pixel clocks, {:.2} M clocks/s over the run, about {:.0}% of the time in the HDL simulator",
            log.hdl_clocks,
            log.hdl_clocks as f64 / tracking_secs.max(1e-9) / 1e6,
            (100.0 * log.hdl_seconds / tracking_secs.max(1e-9)).min(100.0)
        ));
    }
    let n = log.frames.len();
    lines.push(format!(
        "{n} frames, {tracked} tracked, {vouched} vouched for (the CSV's ok 1: a robot may follow them), {} position reports; {:.0} frames/s wall-clock ({secs:.1} s on this machine); simulated: the camera, window units and processors in simulated time, at the source's {:.2} frames/s ({:.2} s of camera time)",
        log.reports.len(),
        n as f64 / secs,
        1.0 / log.frame_period,
        n as f64 * log.frame_period
    ));
    if let Some((k, (x, y))) = log.locked_on {
        lines.push(format!("locked on in frame {}: tracking the object's point at ({x:.1}, {y:.1}) there, the centre of the first motion seen", k + first));
    }
    if !(log.losses.is_empty() && log.watchdog.is_empty() && log.refused.is_empty()) {
        lines.push(format!(
            "log: {} losses of track, {} sets written again by the watchdog, {} requests refused",
            log.losses.len(),
            log.watchdog.len(),
            log.refused.len()
        ));
        for (_, clock, why) in log.refused.iter().take(3) {
            lines.push(format!("  refused on clock {clock}: {why}"));
        }
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::system::{FrameRecord, TrackState};
    use coopwin_firmware::processors::Mode;

    /// The closing line counts the frames a robot may follow as the CSV's `ok` does
    /// ([`FrameRecord::vouched`]); reference: three frames counted by hand.
    #[test]
    fn the_closing_line_counts_the_vouched_frames_apart_from_the_tracked() {
        let record = |frame: usize, measured: Option<usize>, state: TrackState| FrameRecord {
            frame,
            point: measured.map(|_| (10.0, 10.0)),
            measured_frame: measured,
            mode: Mode::Track,
            source: None,
            score: None,
            shape: None,
            box_shape: None,
            state,
            estimate: None,
        };
        // Vouched for; measured but not vouched for; vouched for but 3 frames old (MAX_AGE 2).
        let frames = vec![record(0, Some(0), TrackState::Tracking), record(1, Some(1), TrackState::Unconfirmed), record(4, Some(1), TrackState::Tracking)];
        let log = RunLog { frames, frame_period: 0.1, ..RunLog::default() };
        let line = &run_lines(&log, 1.0, 1.0, 0)[0];
        assert!(line.starts_with("3 frames, 3 tracked, 1 vouched for (the CSV's ok 1"), "{line}");
    }
}
