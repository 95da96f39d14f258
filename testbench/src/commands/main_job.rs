//! The main job (`coopwin` with no arguments): COOP on the built-in default scene, the
//! thesis's cooperative-windowing experiment (4.4), next to NCC and CD alone.
use super::{output::OutFile, CliError};
use crate::experiments::setup::{run_scene, triangle};
use crate::frames::scene::{Scene, SceneConfig};
use crate::report::overlay::{OverlayKind, Painter};
use crate::analysis::metrics::true_points;
use crate::frames::scene::SceneFrames;
use crate::report::csv::{write_track_csv, CsvBox, FrameInfo};
use crate::report::plot::{self, Chart, Series};
use crate::report::{summary_table, verdict};
use crate::system::cost::CostModel;
use crate::system::{RunLog, Strategy, SystemConfig};
use coopwin_firmware::processors::Params;
use std::path::Path;

/// The built-in scene: the triangular path at 40 px/s under the lamp change of Fig. 4.2.
pub fn default_scene() -> SceneConfig {
    SceneConfig { lighting_ramp: true, ..triangle(40.0, 4) }
}

/// Runs COOP (and NCC, CD for comparison) on the default scene, prints the summary and
/// writes `out/` with the per-frame CSV, the summary, the error plot and COOP's overlay.
pub fn write_report(out: &Path) -> Result<(), CliError> {
    let scene = default_scene();
    let target = Scene::new(scene.clone()).truth(0).corner;
    println!(
        "coopwin: COOP on the built-in scene ({} frames, triangle path at {} px/s, lamp ramp), c40 timing",
        scene.frames, scene.speed
    );
    super::output::create_folder(out, "the report folder")?;
    let (coop_csv, summary_md) = (OutFile::check(&out.join("coop.csv"), "the report")?, OutFile::check(&out.join("summary.md"), "the report")?);
    let overlay = OutFile::check(&out.join("overlay.gif"), "the report")?;
    let mut rows = Vec::new();
    let mut logs = Vec::new();
    for (label, strategy) in [("COOP", Strategy::Coop), ("NCC (TPDF)", Strategy::Tpdf), ("CD (TPDF)", Strategy::TpdfCd)] {
        let started = std::time::Instant::now();
        let (log, m) = run_scene(&SystemConfig::thesis(strategy, CostModel::C40, Some(target)), scene.clone())?;
        let fps = log.frames.len() as f64 / started.elapsed().as_secs_f64().max(1e-9);
        rows.push((label, m, fps));
        logs.push((label, log));
    }
    let table = summary_table(&rows.iter().map(|(l, m, _)| (*l, *m)).collect::<Vec<_>>());
    for (label, m, _) in &rows {
        println!("{label}: {}", verdict(m));
    }
    println!("{table}");
    for (label, _, fps) in &rows {
        println!("{label}: {fps:.0} frames/s of simulation");
    }
    let truth = Scene::new(scene.clone()).all_truth();
    let err_series = |label: &str, log: &RunLog| Series {
        label: label.to_string(),
        points: log
            .reports
            .iter()
            .filter_map(|r| {
                let t = truth.get(r.frame)?;
                Some((r.frame as f64, Some((f64::from(r.point.x) - t.corner.0).hypot(f64::from(r.point.y) - t.corner.1))))
            })
            .collect(),
    };
    let chart = Chart {
        title: "Position error per update on the default scene".into(),
        x_label: "frame".into(),
        y_label: "error (px)".into(),
        series: logs.iter().map(|(l, log)| err_series(l, log)).collect(),
        y_range: None,
    };
    plot::write(&chart, out, "error")?;
    let shape = CsvBox { size: (20, 20), acceptance: Params::default().ncc_min };
    let mut csv = Vec::new();
    let info = FrameInfo { period: logs[0].1.frame_period, ..FrameInfo::default() };
    write_track_csv(&mut csv, &logs[0].1.frames, info, shape).map_err(|e| super::io_error("write", &coop_csv.path, e))?;
    coop_csv.write(&csv)?;
    summary_md.write(table.as_bytes())?;
    let coop = &logs[0].1;
    let points = true_points(coop, &truth);
    let painter = Painter::new(coop, Some(&points), shape.size);
    OverlayKind::Gif.write(overlay.stream()?, &mut SceneFrames::new(scene), painter, 1.0 / coop.frame_period)?.0.finish()?;
    println!("wrote {0}/coop.csv, {0}/summary.md, {0}/error.svg, {0}/error.png, {0}/overlay.gif", out.display());
    Ok(())
}
