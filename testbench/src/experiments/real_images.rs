//! The real-image evaluation: semi-synthetic sequences made from real photographs (a textured
//! object from one photo moving over another in exact sub-pixel translation, see
//! [`crate::frames::scene`]), tracked by coopwin's strategies and compared with OpenCV's
//! trackers, whose results are stored as fixtures by `scripts/opencv_real.py`.
//!
//! Every tracker is scored the same way over the frames where the target is visible: the
//! error is the distance from the reported point to the true point of the frame the report
//! measured; RMS is over the frames with a position; loss counts the frames with no position
//! or an error above [`LOSS_PX`]. A report older than [`MAX_AGE`] frames (a track coasting
//! or waiting to recover) is no position: a stale point is not a measurement of this frame.
use super::ExperimentError;
use crate::frames::groundtruth::Truth;
use crate::frames::prerendered::Prerendered;
use crate::frames::scene::{PathKind, SceneConfig};
use crate::report::csv;
use crate::report::plot::{self, Chart, Series};
use crate::system::cost::CostModel;
use crate::system::{self, CoopPolicy, RunLog, SimError, Strategy, SystemConfig};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Error beyond which a frame counts as lost (5 px, as in the OpenCV script).
pub const LOSS_PX: f64 = 5.0;

use crate::system::MAX_AGE;

/// Which point of the object is tracked.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tracked {
    /// The centre of the object: the template lies wholly on its textured surface.
    Centre,
    /// The object's corner: the template holds the object and the background.
    Corner,
}

impl Tracked {
    /// Where the tracked point truly is in `t`'s frame.
    pub fn of(self, t: &Truth) -> (f64, f64) {
        match self {
            Tracked::Centre => t.centre,
            Tracked::Corner => t.corner,
        }
    }
}

/// One condition of the evaluation.
#[derive(Clone, Debug)]
pub struct Condition {
    /// Name, also the sequence folder's and the fixtures' (`centre-...` or `corner-...`).
    pub name: String,
    /// The scene.
    pub scene: SceneConfig,
    /// The point tracked.
    pub tracked: Tracked,
}

impl Condition {
    /// The condition's frames, rendered once and tracked by every tracker.
    pub fn render(&self) -> Prerendered {
        Prerendered::new(&self.scene)
    }
}

/// The conditions: the object's centre on a swing at mean speeds 20-120 px/s, and its corner on
/// the triangle at 60 px/s plain, under the lamp, beside clutter and behind an occluder.
pub fn conditions() -> Vec<Condition> {
    let base = SceneConfig { photo: true, noise: 2.0, frames: 300, seed: 11, ..SceneConfig::default() };
    let mut v: Vec<Condition> = [20.0, 40.0, 80.0, 120.0]
        .iter()
        .map(|&speed| Condition {
            name: format!("centre-swing-{speed}"),
            scene: SceneConfig { path: PathKind::Swing, speed, ..base.clone() },
            tracked: Tracked::Centre,
        })
        .collect();
    let tri = SceneConfig { path: PathKind::Triangle, speed: 60.0, ..base };
    for (name, scene) in [
        ("corner-plain", tri.clone()),
        ("corner-lamp", SceneConfig { lighting_ramp: true, ..tri.clone() }),
        ("corner-clutter", SceneConfig { clutter: true, ..tri.clone() }),
        ("corner-occluder", SceneConfig { occlusion: true, ..tri.clone() }),
    ] {
        v.push(Condition { name: name.into(), scene, tracked: Tracked::Corner });
    }
    v
}

/// coopwin's trackers in the evaluation: label, strategy and COOP policy.
pub const OURS: [(&str, Strategy, CoopPolicy); 4] = [
    ("COOP", Strategy::Coop, CoopPolicy::Guarded),
    ("COOP (thesis SSE)", Strategy::Coop, CoopPolicy::Sse),
    ("NCC (TPDF)", Strategy::Tpdf, CoopPolicy::Guarded),
    ("CD (TPDF)", Strategy::TpdfCd, CoopPolicy::Guarded),
];

/// OpenCV's trackers, by the fixture name `scripts/opencv_real.py` gives them.
pub const OPENCV: [(&str, &str); 3] =
    [("OpenCV matchTemplate", "match"), ("OpenCV CSRT", "csrt"), ("OpenCV KCF", "kcf")];

/// Where the OpenCV fixtures live in the source tree.
pub fn fixtures_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/opencv/real")
}

/// The conditions whose stored OpenCV fixtures were made from other frames than the renderer
/// makes now (their `.fingerprint` differs or is missing): stale fixtures, to regenerate with
/// `scripts/opencv_real.py`. Each entry names the condition and what was found.
pub fn stale_fixtures(conds: &[Condition]) -> Vec<String> {
    conds
        .iter()
        .filter_map(|c| {
            let path = fixtures_dir().join(format!("{}.fingerprint", c.name));
            match std::fs::read_to_string(&path) {
                Ok(stored) if stored.trim() == c.render().fingerprint() => None,
                Ok(_) => Some(format!("{}: fingerprint differs", c.name)),
                Err(e) => Some(format!("{}: no stored fingerprint ({e})", c.name)),
            }
        })
        .collect()
}

/// A tracker's score on one condition.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Score {
    /// RMS error in pixels over the visible frames with a position, if any.
    pub rms: Option<f64>,
    /// Percentage of visible frames with no position or an error above 5 px.
    pub loss: f64,
}

/// Scores per-frame positions `(measured frame, point)` against the truth (see the module docs).
pub fn score(positions: &[Option<(usize, (f64, f64))>], truth: &[Truth], tracked: Tracked) -> Score {
    let (mut sq, mut with, mut lost, mut visible) = (0.0, 0usize, 0usize, 0usize);
    for (k, t) in truth.iter().enumerate() {
        if !t.visible {
            continue;
        }
        visible += 1;
        let err = positions
            .get(k)
            .copied()
            .flatten()
            .filter(|(m, _)| *m <= k && k - m <= MAX_AGE)
            .and_then(|(m, p)| truth.get(m).map(|tm| (p.0 - tracked.of(tm).0).hypot(p.1 - tracked.of(tm).1)));
        match err {
            Some(e) => {
                sq += e * e;
                with += 1;
                if e > LOSS_PX {
                    lost += 1;
                }
            }
            None => lost += 1,
        }
    }
    Score { rms: (with > 0).then(|| (sq / with as f64).sqrt()), loss: 100.0 * lost as f64 / visible.max(1) as f64 }
}

/// Runs one of coopwin's trackers on a condition's frames, at the firmware's native speed, the
/// target given as the true point of frame 0.
pub fn run_ours(c: &Condition, frames: &mut Prerendered, strategy: Strategy, policy: CoopPolicy) -> Result<Score, SimError> {
    run_configured(c, frames, strategy, policy, false)
}

/// [`run_ours`], with the Foveal template adapting to the object's appearance when `adapt`
/// ([`coopwin_firmware::processors::Params::adapt`]).
pub fn run_configured(c: &Condition, frames: &mut Prerendered, strategy: Strategy, policy: CoopPolicy, adapt: bool) -> Result<Score, SimError> {
    let log = simulate_configured(c, frames, strategy, policy, adapt)?;
    Ok(score_log(c, &log, &frames.truth))
}

/// The run of [`run_configured`], as its log.
pub fn simulate_configured(c: &Condition, frames: &mut Prerendered, strategy: Strategy, policy: CoopPolicy, adapt: bool) -> Result<RunLog, SimError> {
    let target = frames.truth.first().map(|t| c.tracked.of(t));
    let mut cfg = SystemConfig { policy, ..SystemConfig::thesis(strategy, CostModel::NATIVE, target) };
    if adapt {
        cfg.params = cfg.params.adaptive();
    }
    system::simulate(&cfg, frames, &mut |_| {})
}

/// A run's [`Score`] on condition `c`.
pub fn score_log(c: &Condition, log: &RunLog, truth: &[Truth]) -> Score {
    let positions: Vec<_> = log.frames.iter().map(|r| r.point.zip(r.measured_frame).map(|(p, m)| (m, p))).collect();
    score(&positions, truth, c.tracked)
}

/// A visible frame of a run, judged against the truth (see [`judge_frames`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Judged {
    /// The frame's index.
    pub frame: usize,
    /// `track`'s `confidence` for a row with a fresh position (vouched for or not), -1 for
    /// every other row.
    pub confidence: f64,
    /// The row's position: the measurement, or else the prediction or last position it carries.
    pub at: Option<(f64, f64)>,
    /// The position is over the distance judged bad from the truth, or there is none.
    pub bad: bool,
}

/// Each visible frame of a run, for [`crate::analysis::metrics::auroc`]: the confidence is the
/// CSV's (`track`'s `confidence` column, [`csv::verdict`] with NCC's acceptance level
/// `acceptance`) for a row with a fresh position, vouched for or not, and -1 for every other
/// row (predicted, searching, lost: not trusted); the frame is bad when the row's position is
/// over `bad_px` from the truth, or it has none.
pub fn judge_frames(c: &Condition, log: &RunLog, truth: &[Truth], acceptance: f32, bad_px: f64) -> Vec<Judged> {
    let err = |p: (f64, f64), k: usize| truth.get(k).map(|t| (p.0 - c.tracked.of(t).0).hypot(p.1 - c.tracked.of(t).1));
    log.frames
        .iter()
        .enumerate()
        .filter(|(k, _)| truth.get(*k).is_some_and(|t| t.visible))
        .map(|(k, r)| {
            let (at, e, confidence) = match (r.fresh(), csv::verdict(r, acceptance).1) {
                (Some((p, m)), Some(c)) => (Some(p), err(p, m), c),
                _ => {
                    let p = r.point.or(r.estimate);
                    (p, p.and_then(|p| err(p, k)), -1.0)
                }
            };
            Judged { frame: k, confidence, at, bad: e.is_none_or(|e| e > bad_px) }
        })
        .collect()
}

/// Reads an OpenCV fixture (`frame,x,y`, empty x,y for no position) and scores it, or `None`
/// when the fixture is missing.
pub fn opencv_score(c: &Condition, truth: &[Truth], tracker: &str) -> Result<Option<Score>, ExperimentError> {
    let path = fixtures_dir().join(format!("{}.{tracker}.csv", c.name));
    let Ok(text) = std::fs::read_to_string(&path) else { return Ok(None) };
    let mut positions = vec![None; truth.len()];
    for (i, line) in text.lines().enumerate().skip(1) {
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        let bad = || ExperimentError::Fixture { path: path.clone(), line: i + 1 };
        let k: usize = f.first().and_then(|s| s.parse().ok()).ok_or_else(bad)?;
        let xy = match (f.get(1), f.get(2)) {
            (Some(x), Some(y)) if !x.is_empty() && !y.is_empty() => {
                Some((x.parse::<f64>().map_err(|_| bad())?, y.parse::<f64>().map_err(|_| bad())?))
            }
            _ => None,
        };
        if let Some(slot) = positions.get_mut(k) {
            *slot = xy.map(|p| (k, p));
        }
    }
    Ok(Some(score(&positions, truth, c.tracked)))
}

/// coopwin's trackers on a condition's frames: their scores, in the table's order.
pub type OurTrackers<'a> = dyn FnMut(&Condition, &mut Prerendered) -> Result<Vec<Score>, SimError> + 'a;

/// Every condition's scores (`table[condition][tracker]`): `ours` runs coopwin's trackers on
/// the condition's frames, then each OpenCV fixture is read (`None` where it is missing).
pub fn score_table(
    conds: &[Condition],
    progress: &mut dyn FnMut(&str),
    ours: &mut OurTrackers<'_>,
) -> Result<Vec<Vec<Option<Score>>>, ExperimentError> {
    let mut table = Vec::new();
    for c in conds {
        progress(&c.name);
        let mut frames = c.render();
        let mut row: Vec<Option<Score>> = ours(c, &mut frames)?.into_iter().map(Some).collect();
        for (_, file) in OPENCV {
            row.push(opencv_score(c, &frames.truth, file)?);
        }
        table.push(row);
    }
    Ok(table)
}

/// Writes `dir/NAME.csv` (`condition,tracker,rms_px,loss_pct`) of every tracker's scores on
/// every condition (`table[condition][tracker]`, `None` where a tracker has no result), and
/// returns the same as a markdown table, RMS px / loss % a cell.
pub fn write_scores(dir: &Path, name: &str, conds: &[Condition], labels: &[&str], table: &[Vec<Option<Score>>]) -> Result<String, ExperimentError> {
    let mut csv = String::from("condition,tracker,rms_px,loss_pct\n");
    let mut md = String::new();
    let _ = writeln!(md, "| condition | {} |", labels.join(" | "));
    let _ = writeln!(md, "|---|{}", "---|".repeat(labels.len()));
    for (c, row) in conds.iter().zip(table) {
        let cells: Vec<String> = row
            .iter()
            .map(|s| s.map_or("-".into(), |s| format!("{} / {:.0}", s.rms.map_or("-".into(), |r| format!("{r:.2}")), s.loss)))
            .collect();
        let _ = writeln!(md, "| {} | {} |", c.name, cells.join(" | "));
        for (label, s) in labels.iter().zip(row).filter_map(|(l, s)| s.map(|s| (l, s))) {
            let rms = s.rms.map_or(String::new(), |r| format!("{r:.3}"));
            let _ = writeln!(csv, "{},{label},{rms},{:.1}", c.name, s.loss);
        }
    }
    let path = dir.join(format!("{name}.csv"));
    std::fs::write(&path, csv).map_err(|source| ExperimentError::Io { action: "write", path, source })?;
    Ok(md)
}

/// A chart of `measure` per condition (1, 2, ... along x), one series per tracker.
pub fn chart_of(
    title: &str,
    y_label: &str,
    conds: &[Condition],
    labels: &[&str],
    table: &[Vec<Option<Score>>],
    measure: &dyn Fn(&Score) -> Option<f64>,
    y_range: Option<(f64, f64)>,
) -> Chart {
    Chart {
        title: title.into(),
        x_label: format!("condition (1-{}: {})", conds.len(), conds.iter().map(|c| c.name.as_str()).collect::<Vec<_>>().join(", ")),
        y_label: y_label.into(),
        series: labels
            .iter()
            .enumerate()
            .map(|(j, l)| Series {
                label: (*l).to_string(),
                points: table.iter().enumerate().map(|(i, row)| (i as f64 + 1.0, row.get(j).copied().flatten().as_ref().and_then(measure))).collect(),
            })
            .collect(),
        y_range,
    }
}

/// The evaluation: every tracker on every condition; writes `real-images.csv`, `.md` and a chart
/// into `dir` and returns the markdown.
pub fn evaluate(dir: &Path, progress: &mut dyn FnMut(&str)) -> Result<String, ExperimentError> {
    let conds = conditions();
    let labels: Vec<&str> = OURS.iter().map(|o| o.0).chain(OPENCV.iter().map(|o| o.0)).collect();
    let table = score_table(&conds, progress, &mut |c, frames| OURS.iter().map(|&(_, strategy, policy)| run_ours(c, frames, strategy, policy)).collect())?;
    let mut md = String::from(
        "## real-images (native profile)\n\nSemi-synthetic sequences from real photographs (`fixtures/real/`): RMS error px / loss % \
         (frames with no position or an error over 5 px), target given at the true point of frame 0.\n\n",
    );
    md.push_str(&write_scores(dir, "real-images", &conds, &labels, &table)?);
    let log_rms = |s: &Score| s.rms.map(|r| r.max(1e-3).log10());
    let chart = chart_of("Real-image sequences: RMS error per condition (log10 px)", "log10 RMS error (px)", &conds, &labels, &table, &log_rms, None);
    plot::write(&chart, dir, "real-images")?;
    md.push_str("\nFiles: `real-images.csv`, `real-images.svg`, `real-images.png`. OpenCV columns come from `fixtures/opencv/real/` (`scripts/opencv_real.py`).\n");
    Ok(md)
}
