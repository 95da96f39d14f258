//! Table 2.3: lock-on, tracking and recovery times of SPMF, TPDF and MPDF on the pendulum path
//! at 100 px/s, each locking on from the Watch mode.
use super::setup::{pendulum, run_scene, watch_config, WATCH_STRATEGIES};
use super::{series, Context, ExperimentError};
use crate::report::ms;
use crate::report::plot::Chart;
use std::fmt::Write as _;

/// The thesis's times in ms: (T_l, T_t, T_r) per strategy.
const THESIS: [(u32, u32, u32); 3] = [(320, 18, 112), (230, 18, 97), (80, 18, 97)];

/// Runs the table; returns its markdown.
pub fn reproduce(ctx: &mut Context) -> Result<String, ExperimentError> {
    let mut rows = Vec::new();
    let mut csv = String::from("strategy,lock_on_ms,tracking_ms,recovery_ms,rms_px,rlt\n");
    for s in WATCH_STRATEGIES {
        ctx.say(s.name());
        let (_, m) = run_scene(&ctx.config(watch_config(s, ctx.profile, &pendulum(100.0, 1))), pendulum(100.0, 1))?;
        let _ = writeln!(csv, "{},{},{},{},{:.3},{:.3}", s.name(), ms(m.lock_on, 0), ms(m.tracking, 0), ms(m.recovery, 0), m.rms, m.rlt);
        rows.push((s, m));
    }
    ctx.write_csv(&csv)?;
    let mut md = String::from("Pendulum path at 100 px/s, lock-on from Watch mode (no target given).\n\n| strategy | T_l thesis | T_l ours | T_t thesis | T_t ours | T_r thesis | T_r ours |\n|---|---|---|---|---|---|---|\n");
    for ((s, m), (tl, tt, tr)) in rows.iter().zip(THESIS) {
        let _ = writeln!(md, "| {} | {tl} | {} | {tt} | {} | {tr} | {} |", s.name().to_uppercase(), ms(m.lock_on, 0), ms(m.tracking, 0), ms(m.recovery, 0));
    }
    let in_ms = |v: Option<f64>| v.map(|v| v * 1e3);
    let chart = Chart {
        title: "Table 2.3: lock-on, tracking and recovery times (ms)".into(),
        x_label: "strategy (1 SPMF, 2 TPDF, 3 MPDF)".into(),
        y_label: "ms".into(),
        series: vec![
            series("lock-on", rows.iter().enumerate().map(|(i, (_, m))| (i as f64 + 1.0, in_ms(m.lock_on)))),
            series("tracking", rows.iter().enumerate().map(|(i, (_, m))| (i as f64 + 1.0, in_ms(m.tracking)))),
            series("recovery", rows.iter().enumerate().map(|(i, (_, m))| (i as f64 + 1.0, in_ms(m.recovery)))),
        ],
        y_range: None,
    };
    ctx.write_chart(&chart)?;
    Ok(md)
}
