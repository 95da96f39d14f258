//! Table 4.1 (and Figs. 4.3/4.6): NCC, the corner detector and COOP (n = 3, 4, 5; the Kalman
//! policy of 5.2; guarded cooperation) on the triangle path under the lamp change of Fig. 4.2,
//! and which source COOP followed frame by frame.
use super::setup::{corner0, run_scene, triangle};
use super::{series, Context, ExperimentError};
use crate::analysis::metrics::Summary;
use crate::frames::scene::SceneConfig;
use crate::report::plot::Chart;
use crate::system::{CoopPolicy, RunLog, Strategy, SystemConfig};
use coopwin_firmware::types::Source;
use std::fmt::Write as _;

/// The methods compared: label, strategy, COOP's n and policy.
const METHODS: [(&str, Strategy, usize, CoopPolicy); 7] = [
    ("NCC", Strategy::Tpdf, 4, CoopPolicy::Sse),
    ("CD", Strategy::TpdfCd, 4, CoopPolicy::Sse),
    ("COOP n=3", Strategy::Coop, 3, CoopPolicy::Sse),
    ("COOP n=4", Strategy::Coop, 4, CoopPolicy::Sse),
    ("COOP n=5", Strategy::Coop, 5, CoopPolicy::Sse),
    ("COOP Kalman (5.2)", Strategy::Coop, 4, CoopPolicy::Kalman),
    ("COOP guarded", Strategy::Coop, 4, CoopPolicy::Guarded),
];

/// The thesis's RMS errors in px, per method.
const THESIS: [&str; 7] = ["0.63", "0.97", "0.61", "0.59", "0.60", "-", "-"];

/// Runs the table; returns its markdown.
pub fn reproduce(ctx: &mut Context) -> Result<String, ExperimentError> {
    let scene = SceneConfig { lighting_ramp: true, ..triangle(40.0, 4) };
    let target = Some(corner0(&scene));
    let mut runs: Vec<(String, Summary, RunLog)> = Vec::new();
    for (label, strategy, n, policy) in METHODS {
        ctx.say(label);
        let mut cfg = ctx.config(SystemConfig::thesis(strategy, ctx.profile, target));
        cfg.coop_n = n;
        cfg.policy = policy;
        let (log, m) = run_scene(&cfg, scene.clone())?;
        runs.push((label.to_string(), m, log));
    }
    let mut md = String::from("Triangle path at 40 px/s, the lamp brightening the scene ~25% over the middle third (Fig. 4.2).\n\n| method | RMS thesis px | RMS ours px | RLT ours % |\n|---|---|---|---|\n");
    let mut csv = String::from("method,rms,rlt,mean_x,mean_y\n");
    for ((label, m, _), t) in runs.iter().zip(THESIS) {
        let _ = writeln!(md, "| {label} | {t} | {:.2} | {:.1} |", m.rms, 100.0 * m.rlt);
        let _ = writeln!(csv, "{label},{:.3},{:.3},{:.3},{:.3}", m.rms, m.rlt, m.mean_x, m.mean_y);
    }
    ctx.write_csv(&csv)?;
    // Fig. 4.3/4.6: which source COOP (n=4) followed, frame by frame.
    let coop = &runs[3].2;
    ctx.write_chart(&Chart {
        title: "Fig. 4.3: source followed by COOP (n=4): 1 = NCC, 2 = CD".into(),
        x_label: "frame".into(),
        y_label: "source".into(),
        series: vec![series("COOP", coop.frames.iter().map(|r| (r.frame as f64, r.source.map(|a| if a == Source::Cd { 2.0 } else { 1.0 }))))],
        y_range: Some((0.5, 2.5)),
    })?;
    md.push_str("\nThesis: COOP (0.59 px at n = 4) below both NCC (0.63) and CD (0.97); COOP follows CD where the lamp makes the windows ~25% brighter than the template.\n");
    Ok(md)
}
