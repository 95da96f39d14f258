//! Fig. 2.10: lock-on time against target speed on the pendulum path, for SPMF, TPDF and MPDF.
use super::speed_sweep::SpeedSweep;
use super::{Context, ExperimentError};
use crate::report::ms;

/// Runs the figure; returns its markdown.
pub fn reproduce(ctx: &mut Context) -> Result<String, ExperimentError> {
    let sweep = SpeedSweep::sweep(ctx)?;
    let mut md = sweep.table("lock-on time (ms)", |m| ms(m.lock_on, 0));
    md.push_str("\nThesis (Fig. 2.10): MPDF locks on fastest, then TPDF, then SPMF (Table 2.3: 80, 230, 320 ms).\n");
    ctx.write_chart(&sweep.chart("Fig. 2.10: lock-on time vs target speed", "lock-on time (ms)", |m| m.lock_on.map(|x| x * 1e3)))?;
    Ok(md)
}
