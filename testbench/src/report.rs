//! Text, CSV and SVG renderings of tracking results.
use crate::metrics::Summary;
use std::fmt::Write as _;

fn ms(v: Option<f64>) -> String {
    v.map(|s| format!("{:.1}", s * 1e3)).unwrap_or_else(|| "-".into())
}

/// A markdown table of summaries, one row per labelled run.
pub fn summary_table(rows: &[(&str, Summary)]) -> String {
    let mut s = String::from(
        "| run | RMS error px | mean x, y px | RLT % | lock-on ms | tracking ms | recovery ms | reports |\n|---|---|---|---|---|---|---|---|\n",
    );
    for (name, m) in rows {
        let _ = writeln!(
            s,
            "| {name} | {:.3} | {:+.2}, {:+.2} | {:.1} | {} | {} | {} | {} |",
            m.rms,
            m.mean_x,
            m.mean_y,
            100.0 * m.rlt,
            ms(m.lock_on),
            ms(m.tracking),
            ms(m.recovery),
            m.reports
        );
    }
    s
}
