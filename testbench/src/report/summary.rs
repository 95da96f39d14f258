//! A run's summary as text: the verdict first (tracked or lost), then the figures of
//! eqs. 2.1-2.3 and RMS/RLT as a markdown table.
use super::ms;
use crate::analysis::metrics::Summary;
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
