//! The thesis's experiments, reproduced on synthetic scenes with ground truth. Each writes a
//! CSV, a chart (SVG and PNG) and a markdown table that puts the thesis's numbers next to ours.
use crate::cost::CostModel;
use crate::metrics::{self, Summary};
use crate::plot::{self, Chart, Series};
use crate::scene::{PathKind, Scene, SceneConfig, Truth};
use crate::system::{self, CoopPolicy, FrameSource, HdlChoice, RunLog, Strategy, SystemConfig};
use coopwin_firmware::kernels::info::{corner_information, edge_information};
use coopwin_firmware::processors::Params;
use std::collections::VecDeque;
use std::fmt::Write as _;
use std::path::Path;

/// The experiments, by the name of the thesis's table or figure.
pub const NAMES: [&str; 7] = ["table-2.3", "fig-2.9", "fig-2.10", "fig-3.5", "fig-3.7", "fig-3.10", "table-4.1"];

/// A scene rendered on demand (deterministic), so runs need no files.
pub struct SceneFrames {
    scene: Scene,
    cache: VecDeque<(usize, Vec<u8>)>,
}

impl SceneFrames {
    /// Frames of `cfg`.
    pub fn new(cfg: SceneConfig) -> Self {
        SceneFrames { scene: Scene::new(cfg), cache: VecDeque::new() }
    }
    /// Ground truth of every frame.
    pub fn truth(&self) -> Vec<Truth> {
        (0..self.scene.config().frames).map(|k| self.scene.truth(k)).collect()
    }
}

impl FrameSource for SceneFrames {
    fn size(&self) -> (usize, usize) {
        (self.scene.config().width, self.scene.config().height)
    }
    fn len(&self) -> usize {
        self.scene.config().frames
    }
    fn frame(&mut self, k: usize) -> Result<&[u8], String> {
        if let Some(i) = self.cache.iter().position(|(j, _)| *j == k) {
            return Ok(&self.cache[i].1);
        }
        if self.cache.len() >= 4 {
            self.cache.pop_front();
        }
        self.cache.push_back((k, self.scene.render(k).0));
        Ok(&self.cache.back().ok_or("cache")?.1)
    }
}

/// A system configuration with the thesis's defaults.
pub fn system(strategy: Strategy, cost: CostModel, target: Option<(f64, f64)>) -> SystemConfig {
    SystemConfig {
        strategy,
        cost,
        params: Params::default(),
        coop_n: 4,
        target,
        model: None,
        pixel_clock_hz: coopwin_hdl::sim::camera::CA_D1_PIXEL_CLOCK_HZ,
        hdl: crate::system::HdlChoice::Model,
        policy: CoopPolicy::Guarded,
        corrupt_request: None,
        drop_window: None,
        jitter: None,
        write_phase: None,
    }
}

/// A system that must find the part with its Watch window(s), knowing only its template: a
/// model of the part cut at its corner (the part's centre is featureless) from the frame where
/// it is nearest the image centre.
pub fn watch_system(strategy: Strategy, cost: CostModel, scene: &SceneConfig) -> SystemConfig {
    let s = Scene::new(scene.clone());
    let best = (0..scene.frames)
        .map(|k| s.truth(k))
        .min_by(|a, b| {
            let d = |t: &Truth| (t.centre.0 - 128.0).hypot(t.centre.1 - 128.0);
            d(a).total_cmp(&d(b))
        });
    let mut cfg = system(strategy, cost, None);
    cfg.model = best.map(|t| (t.frame, t.corner));
    cfg
}

/// Runs `cfg` on `scene` and summarises it against the truth.
pub fn run_scene(cfg: &SystemConfig, scene: SceneConfig) -> Result<(RunLog, Summary), String> {
    let mut frames = SceneFrames::new(scene);
    let truth = frames.truth();
    let log = system::run(cfg, &mut frames, &mut |_| {})?;
    let s = metrics::summarise(&log, &truth);
    Ok((log, s))
}

/// The pendulum scene of Fig. 2.8 at `speed` px/s: long enough for several passes.
pub fn pendulum(speed: f64, seed: u64) -> SceneConfig {
    let frames = ((4.0 * 400.0 / speed.max(10.0)) * 114.0).clamp(300.0, 3000.0) as usize;
    SceneConfig { path: PathKind::Pendulum, speed, frames, noise: 1.0, seed, ..SceneConfig::default() }
}

/// The triangular path of Fig. 3.4 (300 frames, the thesis's 300-point path).
pub fn triangle(speed: f64, seed: u64) -> SceneConfig {
    SceneConfig { path: PathKind::Triangle, speed, frames: 300, noise: 1.0, seed, ..SceneConfig::default() }
}

fn corner0(scene: &SceneConfig) -> (f64, f64) {
    Scene::new(scene.clone()).truth(0).corner
}

fn ms(v: Option<f64>) -> String {
    v.map(|s| format!("{:.0}", s * 1e3)).unwrap_or_else(|| "-".into())
}

/// What an experiment wrote: its markdown section.
pub struct Outcome {
    /// Markdown: the table next to the thesis's, and the files written.
    pub markdown: String,
}

fn write_csv(dir: &Path, name: &str, text: &str) -> Result<(), String> {
    let p = dir.join(format!("{name}.csv"));
    std::fs::write(&p, text).map_err(|e| format!("cannot write {}: {e}", p.display()))
}

/// Runs experiment `name` (one of [`NAMES`]) with `profile`, writing into `dir`.
pub fn run(
    name: &str,
    dir: &Path,
    profile: CostModel,
    hdl: HdlChoice,
    progress: &mut dyn FnMut(&str),
) -> Result<Outcome, String> {
    let hw = |mut c: SystemConfig| {
        c.hdl = hdl;
        c
    };
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let strategies = [Strategy::Spmf, Strategy::Tpdf, Strategy::Mpdf];
    // The thesis's range; with our kernels' speed every update fits a frame, so go further
    // to find where each strategy loses the target.
    let speeds: Vec<f64> = if profile.name == "native" {
        (1..=8).map(|k| 40.0 * f64::from(k)).collect()
    } else {
        (1..=8).map(|k| 20.0 * f64::from(k)).collect()
    };
    let thresholds: Vec<u16> = (1..=10).map(|k| k * 10).collect();
    let hdl_name = if hdl == HdlChoice::RustHdl { ", rust-hdl window units" } else { "" };
    let mut md = format!("## {name} ({} profile{hdl_name})\n\n", profile.name);
    match name {
        "table-2.3" => {
            let mut rows = Vec::new();
            let mut csv = String::from("strategy,lock_on_ms,tracking_ms,recovery_ms,rms_px,rlt\n");
            for s in strategies {
                progress(s.name());
                let (_, m) = run_scene(&hw(watch_system(s, profile, &pendulum(100.0, 1))), pendulum(100.0, 1))?;
                let _ = writeln!(csv, "{},{},{},{},{:.3},{:.3}", s.name(), ms(m.lock_on), ms(m.tracking), ms(m.recovery), m.rms, m.rlt);
                rows.push((s, m));
            }
            write_csv(dir, name, &csv)?;
            let thesis = [(320, 18, 112), (230, 18, 97), (80, 18, 97)];
            md.push_str("Pendulum path at 100 px/s, lock-on from Watch mode (no target given).\n\n| strategy | T_l thesis | T_l ours | T_t thesis | T_t ours | T_r thesis | T_r ours |\n|---|---|---|---|---|---|---|\n");
            for ((s, m), (tl, tt, tr)) in rows.iter().zip(thesis) {
                let _ = writeln!(md, "| {} | {tl} | {} | {tt} | {} | {tr} | {} |", s.name().to_uppercase(), ms(m.lock_on), ms(m.tracking), ms(m.recovery));
            }
            let chart = Chart {
                title: "Table 2.3: lock-on, tracking and recovery times (ms)".into(),
                x_label: "strategy (1 SPMF, 2 TPDF, 3 MPDF)".into(),
                y_label: "ms".into(),
                series: vec![
                    series("lock-on", rows.iter().enumerate().map(|(i, (_, m))| (i as f64 + 1.0, m.lock_on.map(|v| v * 1e3)))),
                    series("tracking", rows.iter().enumerate().map(|(i, (_, m))| (i as f64 + 1.0, m.tracking.map(|v| v * 1e3)))),
                    series("recovery", rows.iter().enumerate().map(|(i, (_, m))| (i as f64 + 1.0, m.recovery.map(|v| v * 1e3)))),
                ],
                y_range: None,
            };
            plot::write(&chart, dir, name)?;
        }
        "fig-2.9" | "fig-2.10" => {
            let lock = name == "fig-2.10";
            let mut csv = String::from("speed,strategy,rms_px,rlt,lock_on_ms\n");
            let mut series_v = Vec::new();
            for s in strategies {
                let mut pts = Vec::new();
                for &v in &speeds {
                    progress(&format!("{} {v} px/s", s.name()));
                    let scene = pendulum(v, 2);
                    let (_, m) = run_scene(&hw(watch_system(s, profile, &scene)), scene)?;
                    let _ = writeln!(csv, "{v},{},{:.3},{:.3},{}", s.name(), m.rms, m.rlt, ms(m.lock_on));
                    let tracked = m.rlt < 0.5;
                    pts.push((v, if lock { m.lock_on.map(|x| x * 1e3) } else { tracked.then_some(m.rms) }, m));
                }
                series_v.push((s, pts));
            }
            write_csv(dir, name, &csv)?;
            let what = if lock { "lock-on time (ms)" } else { "RMS error (px); empty where RLT >= 50%" };
            let _ = writeln!(md, "Pendulum path, speeds {}-{} px/s. {what}.\n", speeds[0], speeds[speeds.len() - 1]);
            md.push_str("| speed px/s | SPMF | TPDF | MPDF |\n|---|---|---|---|\n");
            for (i, v) in speeds.iter().enumerate() {
                let cell = |k: usize| -> String {
                    let (_, y, m) = &series_v[k].1[i];
                    match (lock, y) {
                        (true, _) => ms(m.lock_on),
                        (false, Some(y)) => format!("{y:.2} (RLT {:.0}%)", 100.0 * m.rlt),
                        (false, None) => format!("lost (RLT {:.0}%)", 100.0 * m.rlt),
                    }
                };
                let _ = writeln!(md, "| {v} | {} | {} | {} |", cell(0), cell(1), cell(2));
            }
            md.push_str(if lock {
                "\nThesis (Fig. 2.10): MPDF locks on fastest, then TPDF, then SPMF (Table 2.3: 80, 230, 320 ms).\n"
            } else {
                "\nThesis (Fig. 2.9): TPDF and MPDF about 0.25 px RMS up to 80 px/s and hold the target to 100 px/s; SPMF loses it beyond 80 px/s.\n"
            });
            let chart = Chart {
                title: if lock { "Fig. 2.10: lock-on time vs target speed".into() } else { "Fig. 2.9: RMS position error vs target speed".into() },
                x_label: "target speed (px/s)".into(),
                y_label: if lock { "lock-on time (ms)".into() } else { "RMS error (px)".into() },
                series: series_v.iter().map(|(s, pts)| series(&s.name().to_uppercase(), pts.iter().map(|p| (p.0, p.1)))).collect(),
                y_range: None,
            };
            plot::write(&chart, dir, name)?;
        }
        "fig-3.5" | "fig-3.7" | "fig-3.10" => {
            let mut csv = String::from("threshold,mean_x,mean_y,rms,rlt_multi,rlt_single,edge_pixels,i_edge,i_cd\n");
            let mut rows = Vec::new();
            for &th in &thresholds {
                progress(&format!("TH {th}"));
                // Figs. 3.5/3.6/3.10 on the part alone; Fig. 3.7 (loss of tracking) with clutter.
                let scene = SceneConfig { clutter: name == "fig-3.7", noise: 2.0, ..triangle(40.0, 3) };
                let target = Some(corner0(&scene));
                let mut cfg = hw(system(Strategy::TpdfCd, profile, target));
                cfg.params.corner_threshold = th;
                cfg.params.foveal = 20;
                let (_, multi) = run_scene(&cfg, scene.clone())?;
                cfg.strategy = Strategy::SingleCd;
                let (_, single) = run_scene(&cfg, scene.clone())?;
                let (edges, total) = edge_count(&scene, th);
                let i_edge = edge_information(edges, total);
                let i_cd = corner_information(multi.rms).unwrap_or(0.0);
                let _ = writeln!(csv, "{th},{:.3},{:.3},{:.3},{:.3},{:.3},{edges},{i_edge:.1},{i_cd:.3}", multi.mean_x, multi.mean_y, multi.rms, multi.rlt, single.rlt);
                rows.push((th, multi, single, edges, i_edge, i_cd));
            }
            write_csv(dir, name, &csv)?;
            let th = |r: &(u16, Summary, Summary, u32, f64, f64)| f64::from(r.0);
            let chart = match name {
                "fig-3.5" => {
                    md.push_str("Corner detector in a 20x20 Foveal window, triangle path at 40 px/s, noise 2 (no clutter).\n\n| TH | mean x | mean y | RMS | thesis |\n|---|---|---|---|---|\n");
                    for r in &rows {
                        let _ = writeln!(md, "| {} | {:+.2} | {:+.2} | {:.2} | {} |", r.0, r.1.mean_x, r.1.mean_y, r.1.rms, if (30..=70).contains(&r.0) { "mean ~0.3, RMS ~0.5-1" } else { "worse" });
                    }
                    Chart {
                        title: "Figs. 3.5/3.6: corner location error vs edge threshold TH".into(),
                        x_label: "TH".into(),
                        y_label: "error (px)".into(),
                        series: vec![
                            series("mean x", rows.iter().map(|r| (th(r), Some(r.1.mean_x)))),
                            series("mean y", rows.iter().map(|r| (th(r), Some(r.1.mean_y)))),
                            series("RMS", rows.iter().map(|r| (th(r), Some(r.1.rms)))),
                        ],
                        y_range: None,
                    }
                }
                "fig-3.7" => {
                    md.push_str("Triangle path at 40 px/s with clutter and noise 2. Rate of loss of tracking (RLT) of the corner detector: with the Watch and Peripheral windows to recover (multi-window) and the Foveal window alone (single).\n\n| TH | RLT multi % | RLT single % |\n|---|---|---|\n");
                    for r in &rows {
                        let _ = writeln!(md, "| {} | {:.1} | {:.1} |", r.0, 100.0 * r.1.rlt, 100.0 * r.2.rlt);
                    }
                    md.push_str("\nThesis (Fig. 3.7): the multi-window strategy loses the target less often than a single window.\n");
                    Chart {
                        title: "Fig. 3.7: RLT, multi-window (1) vs single window (2)".into(),
                        x_label: "TH".into(),
                        y_label: "RLT (%)".into(),
                        series: vec![
                            series("multi-window", rows.iter().map(|r| (th(r), Some(100.0 * r.1.rlt)))),
                            series("single window", rows.iter().map(|r| (th(r), Some(100.0 * r.2.rlt)))),
                        ],
                        y_range: None,
                    }
                }
                _ => {
                    md.push_str("Edge-pixel information I = -log2 P (Fig. 3.8) and the proposed I_cd = 1/CLERR (Fig. 3.10) against TH.\n\n| TH | edge pixels | I bits | I_cd |\n|---|---|---|---|\n");
                    for r in &rows {
                        let _ = writeln!(md, "| {} | {} | {:.0} | {:.2} |", r.0, r.3, r.4, r.5);
                    }
                    md.push_str("\nThesis (3.4.1): I grows with the number of edge pixels, while I_cd peaks at the threshold with the lowest corner error (30 < TH < 70).\n");
                    Chart {
                        title: "Fig. 3.10: I_cd = 1/CLERR vs TH".into(),
                        x_label: "TH".into(),
                        y_label: "I_cd (1/px)".into(),
                        series: vec![series("I_cd", rows.iter().map(|r| (th(r), Some(r.5))))],
                        y_range: None,
                    }
                }
            };
            plot::write(&chart, dir, name)?;
        }
        "table-4.1" => {
            let scene = SceneConfig { lighting_ramp: true, ..triangle(40.0, 4) };
            let target = Some(corner0(&scene));
            let mut runs: Vec<(String, Summary, RunLog)> = Vec::new();
            let rows = [
                ("NCC", Strategy::Tpdf, 4, CoopPolicy::Sse),
                ("CD", Strategy::TpdfCd, 4, CoopPolicy::Sse),
                ("COOP n=3", Strategy::Coop, 3, CoopPolicy::Sse),
                ("COOP n=4", Strategy::Coop, 4, CoopPolicy::Sse),
                ("COOP n=5", Strategy::Coop, 5, CoopPolicy::Sse),
                ("COOP Kalman (5.2)", Strategy::Coop, 4, CoopPolicy::Kalman),
                ("COOP guarded", Strategy::Coop, 4, CoopPolicy::Guarded),
            ];
            for (label, strategy, n, policy) in rows {
                progress(label);
                let mut cfg = hw(system(strategy, profile, target));
                cfg.coop_n = n;
                cfg.policy = policy;
                let (log, m) = run_scene(&cfg, scene.clone())?;
                runs.push((label.to_string(), m, log));
            }
            let thesis = ["0.63", "0.97", "0.61", "0.59", "0.60", "-", "-"];
            md.push_str("Triangle path at 40 px/s, the lamp brightening the scene ~25% over the middle third (Fig. 4.2).\n\n| method | RMS thesis px | RMS ours px | RLT ours % |\n|---|---|---|---|\n");
            let mut csv = String::from("method,rms,rlt,mean_x,mean_y\n");
            for ((label, m, _), t) in runs.iter().zip(thesis) {
                let _ = writeln!(md, "| {label} | {t} | {:.2} | {:.1} |", m.rms, 100.0 * m.rlt);
                let _ = writeln!(csv, "{label},{:.3},{:.3},{:.3},{:.3}", m.rms, m.rlt, m.mean_x, m.mean_y);
            }
            write_csv(dir, name, &csv)?;
            // Fig. 4.3/4.6: which source COOP (n=4) followed, frame by frame.
            let coop = &runs[3].2;
            let chart = Chart {
                title: "Fig. 4.3: source followed by COOP (n=4): 1 = NCC, 2 = CD".into(),
                x_label: "frame".into(),
                y_label: "source".into(),
                series: vec![series(
                    "COOP",
                    coop.frames.iter().map(|r| {
                        (r.frame as f64, r.source.map(|a| if a == coopwin_firmware::types::Source::Cd { 2.0 } else { 1.0 }))
                    }),
                )],
                y_range: Some((0.5, 2.5)),
            };
            plot::write(&chart, dir, name)?;
            md.push_str("\nThesis: COOP (0.59 px at n = 4) below both NCC (0.63) and CD (0.97); COOP follows CD where the lamp makes the windows ~25% brighter than the template.\n");
        }
        other => return Err(format!("unknown experiment '{other}'; expected one of {} or all", NAMES.join(", "))),
    }
    let _ = writeln!(md, "\nFiles: `{name}.csv`, `{name}.svg`, `{name}.png`.\n");
    let p = dir.join(format!("{name}.md"));
    std::fs::write(&p, &md).map_err(|e| format!("cannot write {}: {e}", p.display()))?;
    Ok(Outcome { markdown: md })
}

fn series(label: &str, pts: impl Iterator<Item = (f64, Option<f64>)>) -> Series {
    Series { label: label.to_string(), points: pts.collect() }
}

/// Edge pixels (Sobel magnitude over TH) in the 20x20 window at the corner of frame 0.
fn edge_count(scene: &SceneConfig, th: u16) -> (u32, u32) {
    let s = Scene::new(scene.clone());
    let (img, t) = s.render(0);
    let (w, _) = (scene.width, scene.height);
    let (cx, cy) = (t.corner.0.round() as usize, t.corner.1.round() as usize);
    let (x0, y0) = (cx.saturating_sub(10), cy.saturating_sub(10));
    let view = coopwin_firmware::kernels::view::WindowView::packed(&img, w, scene.height)
        .ok()
        .and_then(|v| v.sub(x0, y0, 20, 20));
    let Some(view) = view else { return (0, 400) };
    let mut n = 0;
    for y in 1..19 {
        for x in 1..19 {
            if let Some((gx, gy)) = coopwin_firmware::kernels::corner::sobel_at(&view, x, y) {
                if f64::from(gx).hypot(f64::from(gy)) > f64::from(th) {
                    n += 1;
                }
            }
        }
    }
    (n, 18 * 18)
}
