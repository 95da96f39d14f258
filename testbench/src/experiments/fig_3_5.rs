//! Figs. 3.5/3.6: the corner detector's location error (mean x, mean y, RMS) against the edge
//! threshold TH, on the part alone.
use super::{series, threshold_sweep, Context, ExperimentError};
use crate::report::plot::Chart;
use std::fmt::Write as _;

/// Runs the figure; returns its markdown.
pub fn reproduce(ctx: &mut Context) -> Result<String, ExperimentError> {
    let rows = threshold_sweep::sweep(ctx, false)?;
    let mut md = String::from("Corner detector in a 20x20 Foveal window, triangle path at 40 px/s, noise 2 (no clutter).\n\n| TH | mean x | mean y | RMS | thesis |\n|---|---|---|---|---|\n");
    for r in &rows {
        let thesis = if (30..=70).contains(&r.th) { "mean ~0.3, RMS ~0.5-1" } else { "worse" };
        let _ = writeln!(md, "| {} | {:+.2} | {:+.2} | {:.2} | {thesis} |", r.th, r.multi.mean_x, r.multi.mean_y, r.multi.rms);
    }
    ctx.write_chart(&Chart {
        title: "Figs. 3.5/3.6: corner location error vs edge threshold TH".into(),
        x_label: "TH".into(),
        y_label: "error (px)".into(),
        series: vec![
            series("mean x", rows.iter().map(|r| (r.x(), Some(r.multi.mean_x)))),
            series("mean y", rows.iter().map(|r| (r.x(), Some(r.multi.mean_y)))),
            series("RMS", rows.iter().map(|r| (r.x(), Some(r.multi.rms)))),
        ],
        y_range: None,
    })?;
    Ok(md)
}
