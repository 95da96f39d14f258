//! Fig. 2.9: RMS position error against target speed on the pendulum path, for SPMF, TPDF and
//! MPDF (a run that loses the target half the time or more has no error point).
use super::speed_sweep::SpeedSweep;
use super::{Context, ExperimentError};
use crate::analysis::metrics::Summary;

/// The RMS error of a run that kept the target.
fn tracked_rms(m: &Summary) -> Option<f64> {
    (m.rlt < 0.5).then_some(m.rms)
}

/// Runs the figure; returns its markdown.
pub fn reproduce(ctx: &mut Context) -> Result<String, ExperimentError> {
    let sweep = SpeedSweep::sweep(ctx)?;
    let mut md = sweep.table("RMS error (px); empty where RLT >= 50%", |m| match tracked_rms(m) {
        Some(y) => format!("{y:.2} (RLT {:.0}%)", 100.0 * m.rlt),
        None => format!("lost (RLT {:.0}%)", 100.0 * m.rlt),
    });
    md.push_str("\nThesis (Fig. 2.9): TPDF and MPDF about 0.25 px RMS up to 80 px/s and hold the target to 100 px/s; SPMF loses it beyond 80 px/s.\n");
    ctx.write_chart(&sweep.chart("Fig. 2.9: RMS position error vs target speed", "RMS error (px)", tracked_rms))?;
    Ok(md)
}
