//! The speed sweep behind Figs. 2.9 and 2.10: SPMF, TPDF and MPDF on the pendulum path at each
//! target speed, locking on from the Watch mode; one CSV row per run.
use super::setup::{pendulum, run_scene, watch_config, WATCH_STRATEGIES};
use super::{series, Context, ExperimentError};
use crate::analysis::metrics::Summary;
use crate::report::ms;
use crate::report::plot::Chart;
use crate::system::Strategy;
use std::fmt::Write as _;

/// Every strategy's runs, speed by speed.
pub struct SpeedSweep {
    /// The speeds, px/s.
    pub speeds: Vec<f64>,
    /// Per strategy, one summary per speed.
    pub runs: Vec<(Strategy, Vec<Summary>)>,
}

impl SpeedSweep {
    /// Runs the sweep and writes its CSV.
    pub fn sweep(ctx: &mut Context) -> Result<SpeedSweep, ExperimentError> {
        let speeds = ctx.speeds();
        let mut csv = String::from("speed,strategy,rms_px,rlt,lock_on_ms\n");
        let mut runs = Vec::new();
        for s in WATCH_STRATEGIES {
            let mut summaries = Vec::new();
            for &v in &speeds {
                ctx.say(&format!("{} {v} px/s", s.name()));
                let scene = pendulum(v, 2);
                let (_, m) = run_scene(&ctx.config(watch_config(s, ctx.profile, &scene)), scene)?;
                let _ = writeln!(csv, "{v},{},{:.3},{:.3},{}", s.name(), m.rms, m.rlt, ms(m.lock_on, 0));
                summaries.push(m);
            }
            runs.push((s, summaries));
        }
        ctx.write_csv(&csv)?;
        Ok(SpeedSweep { speeds, runs })
    }

    /// The markdown table: a line saying what the cells hold, then a row per speed.
    pub fn table(&self, what: &str, cell: impl Fn(&Summary) -> String) -> String {
        let mut md = String::new();
        let _ = writeln!(md, "Pendulum path, speeds {}-{} px/s. {what}.\n", self.speeds[0], self.speeds[self.speeds.len() - 1]);
        md.push_str("| speed px/s | SPMF | TPDF | MPDF |\n|---|---|---|---|\n");
        for (i, v) in self.speeds.iter().enumerate() {
            let cells: Vec<String> = self.runs.iter().map(|(_, m)| cell(&m[i])).collect();
            let _ = writeln!(md, "| {v} | {} | {} | {} |", cells[0], cells[1], cells[2]);
        }
        md
    }

    /// The chart of `y` against speed, a line per strategy.
    pub fn chart(&self, title: &str, y_label: &str, y: impl Fn(&Summary) -> Option<f64>) -> Chart {
        Chart {
            title: title.into(),
            x_label: "target speed (px/s)".into(),
            y_label: y_label.into(),
            series: self
                .runs
                .iter()
                .map(|(s, m)| series(&s.name().to_uppercase(), self.speeds.iter().zip(m).map(|(&v, m)| (v, y(m)))))
                .collect(),
            y_range: None,
        }
    }
}
