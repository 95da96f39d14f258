//! Fig. 3.7: the corner detector's rate of loss of tracking against the edge threshold TH,
//! with the Watch and Peripheral windows to recover (multi-window) and alone, beside clutter.
use super::{series, threshold_sweep, Context, ExperimentError};
use crate::report::plot::Chart;
use std::fmt::Write as _;

/// Runs the figure; returns its markdown.
pub fn reproduce(ctx: &mut Context) -> Result<String, ExperimentError> {
    let rows = threshold_sweep::sweep(ctx, true)?;
    let mut md = String::from("Triangle path at 40 px/s with clutter and noise 2. Rate of loss of tracking (RLT) of the corner detector: with the Watch and Peripheral windows to recover (multi-window) and the Foveal window alone (single).\n\n| TH | RLT multi % | RLT single % |\n|---|---|---|\n");
    for r in &rows {
        let _ = writeln!(md, "| {} | {:.1} | {:.1} |", r.th, 100.0 * r.multi.rlt, 100.0 * r.single.rlt);
    }
    md.push_str("\nThesis (Fig. 3.7): the multi-window strategy loses the target less often than a single window.\n");
    ctx.write_chart(&Chart {
        title: "Fig. 3.7: RLT, multi-window (1) vs single window (2)".into(),
        x_label: "TH".into(),
        y_label: "RLT (%)".into(),
        series: vec![
            series("multi-window", rows.iter().map(|r| (r.x(), Some(100.0 * r.multi.rlt)))),
            series("single window", rows.iter().map(|r| (r.x(), Some(100.0 * r.single.rlt)))),
        ],
        y_range: None,
    })?;
    Ok(md)
}
