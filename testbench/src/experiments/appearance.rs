//! The appearance-change evaluation (issue 21): semi-synthetic sequences from the real
//! photographs in which the object turns, scales, tilts, blurs, passes under a shadow, or is
//! covered and reappears elsewhere ([`crate::frames::scene::appearance`]), tracked at 30
//! frames/s as real clips are, and scored as the real-image evaluation scores
//! ([`super::real_images::score`]) against the renderer's exact ground truth and OpenCV's
//! trackers (`scripts/opencv_real.py` on the same sequences).
use super::real_images::{chart_of, judge_frames, run_configured, score_log, score_table, simulate_configured, write_scores, Condition, Score, Tracked, OPENCV};
use super::ExperimentError;
use crate::analysis::metrics::auroc;
use crate::analysis::psr::{psr, Gray};
use crate::frames::prerendered::Prerendered;
use crate::frames::FrameSource;
use coopwin_firmware::processors::Params;
use std::fmt::Write as _;
use crate::frames::scene::{Appearance, PathKind, SceneConfig};
use crate::report::plot;
use crate::system::{CoopPolicy, Strategy};
use std::path::Path;

/// The conditions: one per appearance change, then all of them milder together. Each tracks
/// the object's centre on a swing at 30 frames/s (the part crosses the view in about 4 s).
pub fn conditions() -> Vec<Condition> {
    let base = SceneConfig { photo: true, noise: 2.0, frames: 300, fps: 30.0, seed: 21, path: PathKind::Swing, speed: 60.0, ..SceneConfig::default() };
    let look = |a: Appearance| SceneConfig { appearance: a, ..base.clone() };
    let none = Appearance::default();
    let sets = [
        ("centre-rotate", look(Appearance { rotate_deg: 30.0, ..none })),
        ("centre-scale", look(Appearance { scale: 1.25, ..none })),
        ("centre-tilt", look(Appearance { tilt_deg: 15.0, ..none })),
        ("centre-shadow", look(Appearance { shadow: 0.4, ..none })),
        // Mean speed 115 px/s: 6 px a frame mid-swing, blurred over 6 px.
        ("centre-blur", SceneConfig { speed: 115.0, ..look(Appearance { blur: true, ..none }) }),
        ("centre-cover", look(Appearance { cover_at: Some(0.4), cover_frames: 40, cover_jump: (0.0, -70.0), ..none })),
        (
            "centre-combined",
            SceneConfig {
                speed: 80.0,
                ..look(Appearance { rotate_deg: 20.0, scale: 1.15, tilt_deg: 10.0, shadow: 0.25, blur: true, ..none })
            },
        ),
    ];
    sets.into_iter().map(|(name, scene)| Condition { name: name.into(), scene, tracked: Tracked::Centre }).collect()
}

/// coopwin's trackers here: COOP with the template adapting (the default of `coopwin
/// track`), and COOP with the thesis's fixed template.
pub const OURS: [(&str, bool); 2] = [("COOP", true), ("COOP (fixed template)", false)];

/// One of [`OURS`] on a condition.
pub fn run(c: &Condition, frames: &mut crate::frames::prerendered::Prerendered, adapt: bool) -> Result<Score, crate::system::SimError> {
    run_configured(c, frames, Strategy::Coop, CoopPolicy::Guarded, adapt)
}

/// A frame whose row is over this many pixels from the truth is one the confidence should flag.
pub const BAD_PX: f64 = 2.0;

/// Placements on each side of a row's position over which the PSR baseline's surface is taken.
pub const PSR_RADIUS: usize = 8;

/// A run's visible frames as `(score, over BAD_PX)`, by `track`'s `confidence` and by the
/// PSR baseline: the first frame's template (the thesis's 20x20, cut at the true point) at the
/// row's position ([`crate::analysis::psr`]; -1 where the row has no position).
pub struct Judgement {
    /// By `track`'s `confidence`.
    pub confidence: Vec<(f64, bool)>,
    /// By the PSR baseline.
    pub psr: Vec<(f64, bool)>,
}

/// A run's [`Judgement`] (`log`, made from `frames` with the acceptance level `acceptance`).
pub fn judge(c: &Condition, log: &crate::system::RunLog, frames: &mut Prerendered, acceptance: f32) -> Judgement {
    let judged = judge_frames(c, log, &frames.truth, acceptance, BAD_PX);
    let side = usize::from(Params::default().template);
    let (width, height) = frames.size();
    let first = frames.truth.first().map(|t| c.tracked.of(t));
    let tpl = first.zip(frames.frame(0).ok()).and_then(|(p, f)| Gray { pixels: f, width, height }.patch_at(p, side));
    let psr = judged
        .iter()
        .map(|j| {
            let tpl = tpl.as_deref();
            let value = tpl.zip(j.at).zip(frames.frame(j.frame).ok()).and_then(|((t, at), f)| psr(&Gray { pixels: f, width, height }, t, side, at, PSR_RADIUS));
            (value.unwrap_or(-1.0), j.bad)
        })
        .collect();
    Judgement { confidence: judged.iter().map(|j| (j.confidence, j.bad)).collect(), psr }
}

/// Writes `appearance-confidence.csv` (`condition,tracker,frames,bad_frames,auroc,auroc_psr`,
/// and `all` for the frames of every condition together) and returns it as markdown: how well
/// `track`'s `confidence` column (with `ok` 0 as the lowest), and the PSR baseline, tell the
/// frames over [`BAD_PX`] from the rest, for each of [`OURS`].
fn confidence_table(dir: &Path, conds: &[Condition], judged: &[Vec<Judgement>]) -> Result<String, ExperimentError> {
    let area = |v: &[(f64, bool)]| auroc(v).map_or(String::new(), |a| format!("{a:.3}"));
    let mut csv = String::from("condition,tracker,frames,bad_frames,auroc,auroc_psr\n");
    let mut md = format!(
        "\nConfidence: the area under the ROC curve of `track`'s `confidence` (rows with `ok` 0 lowest) for telling the frames \
         whose row is over {BAD_PX} px from the truth (or has no position) from the rest, beside the same for the \
         peak-to-sidelobe ratio (PSR) of the first frame's template's zero-mean NCC surface at the row's position; `-` where \
         no frame is over.\n\n\
         | condition | tracker | frames | over {BAD_PX} px | AUROC confidence | AUROC PSR |\n|---|---|---|---|---|---|\n"
    );
    for (t, (tracker, _)) in OURS.iter().enumerate() {
        let pooled = |f: fn(&Judgement) -> &Vec<(f64, bool)>| -> Vec<(f64, bool)> { judged.iter().flat_map(|j| f(&j[t]).iter().copied()).collect() };
        let all = (pooled(|j| &j.confidence), pooled(|j| &j.psr));
        let rows = conds.iter().map(|c| c.name.as_str()).zip(judged.iter().map(|j| (j[t].confidence.clone(), j[t].psr.clone()))).chain([("all", all)]);
        for (name, (conf, psr)) in rows {
            let bad = conf.iter().filter(|f| f.1).count();
            let (a, p) = (area(&conf), area(&psr));
            let _ = writeln!(csv, "{name},{tracker},{},{bad},{a},{p}", conf.len());
            let dash = |s: String| if s.is_empty() { "-".to_string() } else { s };
            let _ = writeln!(md, "| {name} | {tracker} | {} | {bad} | {} | {} |", conf.len(), dash(a), dash(p));
        }
    }
    let path = dir.join("appearance-confidence.csv");
    std::fs::write(&path, csv).map_err(|source| ExperimentError::Io { action: "write", path, source })?;
    Ok(md)
}

/// The evaluation: writes `appearance.csv`, `appearance-confidence.csv`, a chart, and
/// returns the markdown.
pub fn evaluate(dir: &Path, progress: &mut dyn FnMut(&str)) -> Result<String, ExperimentError> {
    let conds = conditions();
    let labels: Vec<&str> = OURS.iter().map(|o| o.0).chain(OPENCV.iter().map(|o| o.0)).collect();
    // Each of OURS' frames judged, per condition.
    let mut judged: Vec<Vec<Judgement>> = Vec::new();
    let table = score_table(&conds, progress, &mut |c, frames| {
        let mut runs = Vec::new();
        let scores = OURS
            .iter()
            .map(|&(_, adapt)| {
                let log = simulate_configured(c, frames, Strategy::Coop, CoopPolicy::Guarded, adapt)?;
                let acceptance = Params::default().correlation(adapt).1;
                runs.push(judge(c, &log, frames, acceptance));
                Ok(score_log(c, &log, &frames.truth))
            })
            .collect();
        judged.push(runs);
        scores
    })?;
    let mut md = String::from(
        "## appearance (native profile)\n\nThe object turns (+-30 degrees), scales (0.8-1.25x), tilts out of plane (+-15 degrees), \
         passes under a sweeping shadow (gain 0.6-1.3), blurs with its motion (up to 6 px a frame), is covered for 40 frames and \
         reappears 70 px away, or all of these milder together; 300 frames at 30 frames/s, target given at the true centre of \
         frame 0. RMS error px / loss % (frames with no position or an error over 5 px), over the frames where the centre is \
         visible.\n\n",
    );
    md.push_str(&write_scores(dir, "appearance", &conds, &labels, &table)?);
    let chart = chart_of("Appearance changes: loss per condition (%)", "frames lost (%)", &conds, &labels, &table, &|s: &Score| Some(s.loss), Some((0.0, 100.0)));
    plot::write(&chart, dir, "appearance")?;
    md.push_str(&confidence_table(dir, &conds, &judged)?);
    md.push_str("\nFiles: `appearance.csv`, `appearance.svg`, `appearance.png`. OpenCV columns come from `fixtures/opencv/real/` (`scripts/opencv_real.py`).\n");
    Ok(md)
}
