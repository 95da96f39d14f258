//! The long-term evaluation (issue 38): does the tracker know when it is *not* on its target?
//! Each set of [`crate::frames::scene::longterm`] is tracked from the target's box on frame 0,
//! with the adapting default and with the thesis's fixed template (`--fixed-template`), and
//! scored as VOT-LT and OxUvA score a tracker ([`crate::analysis::longterm`]): the precision
//! of the `ok` 1 rows, their recall, and the silence (TNR) while the target is hidden or gone.
use super::ExperimentError;
use crate::analysis::longterm::{self, Bin, LongTermScore, Row, Truth};
use crate::frames::{binned, FrameSource};
use crate::frames::scene::longterm::{sets, LongTermFrames, LongTermSet, Presence};
use crate::report::csv;
use crate::report::plot::{self, Chart, Series};
use crate::system::cost::CostModel;
use crate::system::{self, CoopPolicy, RunLog, SimError, Strategy, SystemConfig};
use coopwin_firmware::processors::Params;
use std::fmt::Write as _;
use crate::experiments::real_footage::Clip;
use std::path::Path;

pub mod clips;

/// Foveal search margin, as `track`'s default (`--search 2`).
const SEARCH: u16 = 2;

/// The trackers compared: label, and whether the template adapts.
pub const TRACKERS: [(&str, bool); 2] = [("COOP (default)", true), ("COOP --fixed-template", false)];

/// The run of `track --target-box` on `set`'s frames, the template adapting when `adapt`.
pub fn run(set: &LongTermSet, frames: &mut LongTermFrames, adapt: bool) -> Result<(RunLog, f32), SimError> {
    let (x, y, w, h) = set.start_box();
    let (bin, n) = binned::for_box((w, h), frames.size());
    let centre = (f64::from(x) + (f64::from(w) - 1.0) / 2.0, f64::from(y) + (f64::from(h) - 1.0) / 2.0);
    let params = Params { target_boxed: true, ..Params::sized(n, SEARCH) };
    let params = if adapt { params.adaptive() } else { params };
    let cfg = SystemConfig { params, bin, policy: CoopPolicy::Guarded, ..SystemConfig::thesis(Strategy::Coop, CostModel::NATIVE, Some(centre)) };
    let log = system::simulate(&cfg, frames, &mut |_| {})?;
    Ok((log, params.correlation(adapt).1))
}

/// A run's rows, as its CSV's `ok`, `confidence` and point columns give them.
pub fn rows(log: &RunLog, acceptance: f32) -> Vec<Row> {
    log.frames
        .iter()
        .map(|r| {
            let (ok, confidence) = csv::verdict(r, acceptance);
            Row { ok, confidence: confidence.unwrap_or(-1.0), point: r.point.or(r.estimate) }
        })
        .collect()
}

/// Where the target can be seen in each frame.
pub fn present(frames: &LongTermFrames) -> Vec<Truth> {
    frames.truth.iter().map(|t| Truth::point((t.presence == Presence::Visible).then_some(t.centre))).collect()
}

/// The hand-labelled objects of [`clips::CLIPS`] (decoded from `clip_dir`), each tracker
/// beside OpenCV's: writes `long-term-clips.csv` and returns the markdown.
fn real_clips(dir: &Path, clip_dir: &Path, progress: &mut dyn FnMut(&str)) -> Result<(String, Vec<[Bin; 10]>), ExperimentError> {
    let mut bins = vec![[Bin::default(); 10]; TRACKERS.len()];
    let mut csv = String::from("clip,object,tracker,frames,visible,vouched,wrong,wrong_run,precision,recall,tnr,f,withheld,unmeasured\n");
    let mut md = String::from(
        "\n### Real clips, labelled by hand\n\nThe objects of `fixtures/longterm/` (labelled every 5th frame as visible, hidden or gone; \
         its README gives the procedure), tracked from their start box, scored from the next frame as `scripts/opencv_longterm.py` \
         scores OpenCV's trackers: a row is right when its point is inside the labelled box or within 5 px of its centre. \
         Run: the longest run of consecutive wrong `ok` 1 rows. Missed: of the frames where the object is visible, those \
         measured on it but not vouched for (the recall the verdict withholds) / those without a measured position (the track \
         coasting, lost or searching: the recall the tracking loses). OpenCV's F from `fixtures/longterm/opencv/`.\n\n",
    );
    let _ = writeln!(md, "| clip | object | tracker | precision | recall | TNR | F | wrong / vouched | run | missed | {} |", clips::OPENCV.map(|o| format!("F {}", o.0)).join(" | "));
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|---|{}", "---|".repeat(clips::OPENCV.len()));
    for clip_name in clips::CLIPS {
        let objects = clips::labelled(clip_name)?;
        let opencv = clips::opencv_scores(clip_name)?;
        let clip = Clip::decode(&clip_dir.join(format!("{clip_name}.avi")))?;
        for o in &objects {
            let name = &o.object.name;
            progress(&format!("{clip_name} {name}"));
            let theirs = opencv_f(&opencv, name);
            for (((label, _), (s, more)), bins) in TRACKERS.iter().zip(clips::score_object(&clip, o)?).zip(&mut bins) {
                longterm::pool(bins, &more);
                let opt = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:.4}"));
                let _ = writeln!(
                    csv,
                    "{clip_name},{name},{label},{},{},{},{},{},{:.4},{:.4},{},{:.4},{},{}",
                    s.frames,
                    s.visible,
                    s.vouched,
                    s.wrong,
                    s.wrong_run,
                    s.precision,
                    s.recall,
                    opt(s.tnr),
                    s.f,
                    s.withheld,
                    s.unmeasured
                );
                let _ = writeln!(
                    md,
                    "| {clip_name} | {name} | {label} | {:.3} | {:.3} | {} | {:.3} | {} / {} | {} | {} / {} | {} |",
                    s.precision,
                    s.recall,
                    s.tnr.map_or("-".into(), |v| format!("{v:.2}")),
                    s.f,
                    s.wrong,
                    s.vouched,
                    s.wrong_run,
                    s.withheld,
                    s.unmeasured,
                    theirs
                );
            }
        }
    }
    std::fs::create_dir_all(dir).map_err(|source| ExperimentError::Io { action: "create", path: dir.into(), source })?;
    let path = dir.join("long-term-clips.csv");
    std::fs::write(&path, csv).map_err(|source| ExperimentError::Io { action: "write", path, source })?;
    Ok((md, bins))
}

/// OpenCV's F on `object` (a set, or a clip's object) as the tables' cells, in
/// [`clips::OPENCV`]'s order (`-` where the fixture has none).
fn opencv_f(opencv: &[clips::OpencvScore], object: &str) -> String {
    let cell = |file: &str| opencv.iter().find(|r| r.0 == file && r.1 == object).map_or("-".into(), |r| format!("{:.3}", r.3));
    clips::OPENCV.map(|(_, file)| cell(file)).join(" | ")
}

/// Every tracker on every set: `table[set][tracker]`, with the rows and truth of each run for
/// the reliability diagram.
pub type Runs = Vec<Vec<(LongTermScore, Vec<Row>, Vec<Truth>)>>;

/// Runs every tracker of [`TRACKERS`] on every set.
pub fn run_all(progress: &mut dyn FnMut(&str)) -> Result<(Vec<LongTermSet>, Runs), SimError> {
    let sets = sets();
    let mut table = Vec::new();
    for set in &sets {
        progress(set.name);
        let mut frames = set.render_all();
        let truth = present(&frames);
        let mut row = Vec::new();
        for &(_, adapt) in &TRACKERS {
            let (log, acceptance) = run(set, &mut frames, adapt)?;
            let rows = rows(&log, acceptance);
            row.push((longterm::score(&rows, &truth), rows, truth.clone()));
        }
        table.push(row);
    }
    Ok((sets, table))
}

/// The evaluation: writes `long-term.csv`, `.md`, a precision/recall chart and the trackers'
/// reliability diagram into `dir`, and returns the markdown.
pub fn evaluate(dir: &Path, clip_dir: &Path, progress: &mut dyn FnMut(&str)) -> Result<String, ExperimentError> {
    // Read first: a missing fixture fails before the runs.
    let opencv = clips::opencv_set_scores()?;
    let (sets, table) = run_all(progress)?;
    let mut csv = String::from("set,tracker,frames,visible,vouched,wrong,precision,recall,tnr,f,tau,auroc,withheld,unmeasured\n");
    let mut md = String::from(
        "## long-term (native profile)\n\nThe target among look-alikes, behind occluders and out of the view (`frames/scene/longterm.rs`), \
         tracked from its box on frame 0 as `track --target-box` does. Precision of the `ok` 1 rows (within 5 px of the visible \
         target), OxUvA's TPR (recall) and TNR (silence while the target is hidden or gone), VOT-LT's F at the best confidence \
         threshold, wrong `ok` 1 rows of all vouched, the confidence's AUROC, and the frames missed where the target is visible: \
         measured on it but not vouched for / without a measured position; OpenCV's F on the same frames, scored alike \
         (`fixtures/longterm/opencv/sets/`, `scripts/opencv_longterm.py --sets`).\n\n",
    );
    let _ = writeln!(md, "| set | what happens | tracker | precision | recall | TNR | F | wrong / vouched | AUROC | missed | {} |", clips::OPENCV.map(|o| format!("F {}", o.0)).join(" | "));
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|---|{}", "---|".repeat(clips::OPENCV.len()));
    let opt = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.2}"));
    for (set, row) in sets.iter().zip(&table) {
        let theirs = opencv_f(&opencv, set.name);
        for ((label, _), (s, _, _)) in TRACKERS.iter().zip(row) {
            let _ = writeln!(
                csv,
                "{},{label},{},{},{},{},{:.4},{:.4},{},{:.4},{:.3},{},{},{}",
                set.name,
                s.frames,
                s.visible,
                s.vouched,
                s.wrong,
                s.precision,
                s.recall,
                s.tnr.map_or(String::new(), |v| format!("{v:.4}")),
                s.f,
                s.tau,
                s.auroc.map_or(String::new(), |v| format!("{v:.4}")),
                s.withheld,
                s.unmeasured
            );
            let _ = writeln!(
                md,
                "| {} | {} | {label} | {:.3} | {:.3} | {} | {:.3} | {} / {} | {} | {} / {} | {theirs} |",
                set.name,
                set.about,
                s.precision,
                s.recall,
                opt(s.tnr),
                s.f,
                s.wrong,
                s.vouched,
                opt(s.auroc),
                s.withheld,
                s.unmeasured
            );
        }
    }
    std::fs::create_dir_all(dir).map_err(|source| ExperimentError::Io { action: "create", path: dir.into(), source })?;
    let path = dir.join("long-term.csv");
    std::fs::write(&path, csv).map_err(|source| ExperimentError::Io { action: "write", path, source })?;
    let per_set = |k: usize, f: &dyn Fn(&LongTermScore) -> f64| Series {
        label: TRACKERS[k].0.to_string(),
        points: table.iter().enumerate().map(|(i, r)| (i as f64 + 1.0, Some(f(&r[k].0)))).collect(),
    };
    // The names would not fit under the axis: long-term.md lists the sets in this order.
    let chart = Chart {
        title: "Long-term sets: precision of the ok=1 rows".into(),
        x_label: format!("set 1-{}, in long-term.md's order", sets.len()),
        y_label: "precision".into(),
        series: (0..TRACKERS.len()).map(|k| per_set(k, &|s| s.precision)).collect(),
        y_range: Some((0.0, 1.0)),
    };
    plot::write(&chart, dir, "long-term")?;
    let (clips_md, clip_bins) = real_clips(dir, clip_dir, progress)?;
    md.push_str(&clips_md);
    // Each tracker's reliability on the sets and on the clips: the share of right rows per
    // tenth of the confidence, against the diagonal a calibrated confidence follows.
    let mut families = Vec::new();
    for (k, (label, _)) in TRACKERS.iter().enumerate() {
        let mut on_sets = [Bin::default(); 10];
        for row in &table {
            let (_, rows, truth) = &row[k];
            longterm::pool(&mut on_sets, &longterm::reliability(rows, truth));
        }
        families.push((format!("{label}, sets"), on_sets));
        families.push((format!("{label}, clips"), clip_bins[k]));
    }
    let centre = |b: usize| (b as f64 + 0.5) / 10.0;
    let share = |b: &Bin| (b.rows > 0).then(|| b.right as f64 / b.rows as f64);
    // The legend's width: "(default), sets", "fixed-template, clips".
    let mut series: Vec<Series> = families.iter().map(|(label, bins)| Series { label: label.replace("COOP ", "").replace("--", ""), points: bins.iter().enumerate().map(|(b, bin)| (centre(b), share(bin))).collect() }).collect();
    series.push(Series { label: "calibrated".into(), points: (0..10).map(|b| (centre(b), Some(centre(b)))).collect() });
    let diagram = Chart {
        title: "Reliability of the confidence (long-term sets and labelled clips)".into(),
        x_label: "confidence (bins of 0.1)".into(),
        y_label: "share of rows on the target".into(),
        series,
        y_range: Some((0.0, 1.0)),
    };
    plot::write(&diagram, dir, "long-term-reliability")?;
    let _ = writeln!(
        md,
        "\nReliability of the confidence: every row with one (vouched for or not) by tenth of the confidence, as rows / share on the target \
         (within 5 px, or inside the labelled box), and the expected calibration error (ECE: the rows' mean distance between a tenth's mean \
         confidence and its share on the target):\n"
    );
    let _ = writeln!(md, "| tracker, sequences | {} | ECE |", (0..10).map(|b| format!("{:.1}-{:.1}", b as f64 / 10.0, (b + 1) as f64 / 10.0)).collect::<Vec<_>>().join(" | "));
    let _ = writeln!(md, "|---|{}---|", "---|".repeat(10));
    for (label, bins) in &families {
        let cells: Vec<String> = bins.iter().map(|b| share(b).map_or("-".into(), |v| format!("{} / {v:.2}", b.rows))).collect();
        let ece = longterm::calibration_error(bins).map_or("-".into(), |e| format!("{e:.3}"));
        let _ = writeln!(md, "| {label} | {} | {ece} |", cells.join(" | "));
    }
    md.push_str("\nFiles: `long-term.csv`, `long-term-clips.csv`, `long-term.svg`/`.png` (precision per set), `long-term-reliability.svg`/`.png`.\n");
    let path = dir.join("long-term.md");
    std::fs::write(&path, &md).map_err(|source| ExperimentError::Io { action: "write", path, source })?;
    Ok(md)
}
