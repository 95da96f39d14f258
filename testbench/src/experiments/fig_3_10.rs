//! Figs. 3.8/3.10: the information of the edge pixels, I = -log2 P, and the proposed
//! I_cd = 1/CLERR against the edge threshold TH.
use super::{series, threshold_sweep, Context, ExperimentError};
use crate::report::plot::Chart;
use std::fmt::Write as _;

/// Runs the figure; returns its markdown.
pub fn reproduce(ctx: &mut Context) -> Result<String, ExperimentError> {
    let rows = threshold_sweep::sweep(ctx, false)?;
    let mut md = String::from("Edge-pixel information I = -log2 P (Fig. 3.8) and the proposed I_cd = 1/CLERR (Fig. 3.10) against TH.\n\n| TH | edge pixels | I bits | I_cd |\n|---|---|---|---|\n");
    for r in &rows {
        let _ = writeln!(md, "| {} | {} | {:.0} | {:.2} |", r.th, r.edges, r.i_edge, r.i_cd);
    }
    md.push_str("\nThesis (3.4.1): I grows with the number of edge pixels, while I_cd peaks at the threshold with the lowest corner error (30 < TH < 70).\n");
    ctx.write_chart(&Chart {
        title: "Fig. 3.10: I_cd = 1/CLERR vs TH".into(),
        x_label: "TH".into(),
        y_label: "I_cd (1/px)".into(),
        series: vec![series("I_cd", rows.iter().map(|r| (r.x(), Some(r.i_cd))))],
        y_range: None,
    })?;
    Ok(md)
}
