//! The real-footage evaluation (issue 21): `coopwin track`'s default tracker (COOP, the
//! template adapting) on objects in the real clips of Debian's `opencv-doc`
//! (`Megamind.avi`, `Megamind_bugy.avi`, `tree.avi`), chosen and described in
//! `fixtures/footage/`, beside OpenCV's trackers on the same objects
//! (`scripts/opencv_footage.py`, `fixtures/opencv/footage/`). Real footage has no ground
//! truth, so each tracker is scored as that script scores OpenCV's:
//!
//! - positions: the frames with a measured position (`track`'s state `tracking`, or
//!   `unconfirmed`: measured, but not vouched for as the target's, issue 38), of all the
//!   object's frames and of those where CSRT reports the object (how far `ok` 1 rows are
//!   right is `coopwin experiment long-term`'s, against hand labels of the same objects);
//! - forward-backward error: tracked from the object's box forward to its last frame, then
//!   backward from the position there: the distance between the start and where the backward
//!   run ends on the first frame, and the mean distance between the two runs frame by frame;
//! - agreement with CSRT: the mean distance to CSRT's position, and the frames within 5 px of
//!   it, over the frames where both report.
use super::ExperimentError;
use crate::frames::binned;
use crate::frames::video::{self, VideoFrames};
use crate::frames::{FrameError, FrameSource};
use crate::report::plot::{self, Bars, Chart, Series};
use crate::system::cost::CostModel;
use crate::system::{self, RunLog, Strategy, SystemConfig};
use crate::units::clocks::Clocks;
use coopwin_firmware::processors::Params;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Where Debian's `opencv-doc` puts the clips.
pub const DEFAULT_CLIPS: &str = "/usr/share/doc/opencv-doc/examples/data";

/// OpenCV's trackers in the fixtures: (label, file name part).
pub const OPENCV: [(&str, &str); 4] = [("OpenCV matchTemplate", "match"), ("OpenCV CSRT", "csrt"), ("OpenCV KCF", "kcf"), ("OpenCV MOSSE", "mosse")];

/// Within this many pixels of CSRT a position agrees with it.
pub const AGREE_PX: f64 = 5.0;

/// An object of `fixtures/footage/objects.csv`: a box in a clip, over a range of frames.
#[derive(Clone, Debug, PartialEq)]
pub struct Object {
    /// The clip's file stem (`Megamind` is `Megamind.avi`).
    pub clip: String,
    /// The object's name.
    pub name: String,
    /// First and last frame (as FFmpeg and OpenCV number them, from 0).
    pub frames: (usize, usize),
    /// Its box on the first frame: x, y, width, height.
    pub bbox: (u32, u32, u32, u32),
}

impl Object {
    /// `clip-name`, as the fixtures name it.
    pub fn id(&self) -> String {
        format!("{}-{}", self.clip, self.name)
    }

    /// The box's centre, the tracked point.
    pub fn centre(&self) -> (f64, f64) {
        let (x, y, w, h) = self.bbox;
        (f64::from(x) + (f64::from(w) - 1.0) / 2.0, f64::from(y) + (f64::from(h) - 1.0) / 2.0)
    }

    /// The binning and the template side `track --target-box` takes for the box on frames of
    /// `size`.
    pub fn binned_template(&self, size: (usize, usize)) -> (usize, u16) {
        binned::for_box((self.bbox.2, self.bbox.3), size)
    }
}

/// The repository's `fixtures/` folder.
fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join("fixtures")
}

fn bad_line(path: &Path, line: usize) -> ExperimentError {
    ExperimentError::Fixture { path: path.into(), line }
}

fn read(path: &Path) -> Result<String, ExperimentError> {
    std::fs::read_to_string(path).map_err(|source| ExperimentError::Io { action: "read", path: path.into(), source })
}

/// The objects of `fixtures/footage/objects.csv`.
pub fn objects() -> Result<Vec<Object>, ExperimentError> {
    let path = fixtures().join("footage").join("objects.csv");
    let text = read(&path)?;
    text.lines()
        .enumerate()
        .skip(1)
        .filter(|(_, l)| !l.trim().is_empty())
        .map(|(i, l)| {
            let f: Vec<&str> = l.split(',').collect();
            let num = |k: usize| f.get(k).and_then(|v| v.trim().parse::<u32>().ok()).ok_or_else(|| bad_line(&path, i + 1));
            let (first, last) = (num(2)? as usize, num(3)? as usize);
            if f.len() != 8 || last < first {
                return Err(bad_line(&path, i + 1));
            }
            Ok(Object { clip: f[0].into(), name: f[1].into(), frames: (first, last), bbox: (num(4)?, num(5)?, num(6)?, num(7)?) })
        })
        .collect()
}

/// Positions a tracker reported on each frame of an object's range (`None`: none trusted).
pub type Track = Vec<Option<(f64, f64)>>;

/// A tracker's forward and backward runs over an object's frames (index 0 is the first frame).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Runs {
    /// From the box, forward.
    pub forward: Track,
    /// From the forward run's position on the last frame, backward (empty without one).
    pub backward: Track,
}

/// OpenCV's `tracker` runs on `o` from its fixture (`frame,x,y,back_x,back_y`).
pub fn opencv_runs(o: &Object, tracker: &str) -> Result<Runs, ExperimentError> {
    let path = fixtures().join("opencv").join("footage").join(format!("{}.{tracker}.csv", o.id()));
    let text = read(&path)?;
    let n = o.frames.1 - o.frames.0 + 1;
    let mut runs = Runs { forward: vec![None; n], backward: vec![None; n] };
    for (i, l) in text.lines().enumerate().skip(1).filter(|(_, l)| !l.trim().is_empty()) {
        let f: Vec<&str> = l.split(',').collect();
        let frame = f.first().and_then(|v| v.parse::<usize>().ok()).filter(|k| (o.frames.0..=o.frames.1).contains(k));
        let (Some(k), true) = (frame, f.len() == 5) else { return Err(bad_line(&path, i + 1)) };
        let point = |a: usize| match (f[a], f[a + 1]) {
            ("", "") => Ok(None),
            (x, y) => x.parse().ok().zip(y.parse().ok()).map(Some).ok_or_else(|| bad_line(&path, i + 1)),
        };
        runs.forward[k - o.frames.0] = point(1)?;
        runs.backward[k - o.frames.0] = point(3)?;
    }
    if runs.backward.iter().all(Option::is_none) {
        runs.backward.clear();
    }
    Ok(runs)
}

/// An object's frames, decoded, in the order a run takes them.
struct Frames<'a> {
    frames: Vec<&'a [u8]>,
    size: (usize, usize),
}

impl FrameSource for Frames<'_> {
    fn size(&self) -> (usize, usize) {
        self.size
    }
    fn len(&self) -> usize {
        self.frames.len()
    }
    fn frame(&mut self, k: usize) -> Result<&[u8], FrameError> {
        self.frames.get(k).copied().ok_or(FrameError::Missing(k))
    }
}

/// A clip, decoded whole: its frames, size and declared frame rate.
pub struct Clip {
    frames: Vec<Vec<u8>>,
    size: (usize, usize),
    fps: f64,
}

impl Clip {
    /// Decodes `path` (through FFmpeg, every frame as the file has it).
    pub fn decode(path: &Path) -> Result<Clip, ExperimentError> {
        let failed = |why: String| ExperimentError::Clip { path: path.into(), why };
        if !path.exists() {
            return Err(failed("no such file: the clips come with Debian's opencv-doc (apt-get install opencv-doc), or give --clips DIR".into()));
        }
        let scan = video::scan(path, 1..=4096, &|| false).map_err(|e| failed(e.to_string()))?;
        let mut source = VideoFrames::open(path, &scan).map_err(|e| failed(e.to_string()))?;
        let frames = (0..scan.len()).map(|k| source.frame(k).map(<[u8]>::to_vec)).collect::<Result<_, _>>().map_err(|e| failed(e.to_string()))?;
        Ok(Clip { frames, size: scan.size, fps: scan.fps.unwrap_or(30.0) })
    }

    /// The frames' width and height.
    pub fn size(&self) -> (usize, usize) {
        self.size
    }

    /// `track --target-box`'s run on `frames` (indices into the clip) from `o`'s box centred
    /// on `start`, adapting (the default) or fixed (`--fixed-template`), as its log.
    pub fn simulate(&self, frames: impl Iterator<Item = usize>, start: (f64, f64), o: &Object, adapt: bool) -> Result<RunLog, ExperimentError> {
        let mut source = Frames { frames: frames.filter_map(|k| self.frames.get(k).map(Vec::as_slice)).collect(), size: self.size };
        let (bin, side) = o.binned_template(self.size);
        let params = Params { adapt, target_boxed: true, ..Params::sized(side, 2) };
        let mut cfg = SystemConfig { params, bin, target: Some(start), ..SystemConfig::thesis(Strategy::Coop, CostModel::NATIVE, None) };
        cfg.pixel_clock_hz = Clocks::camera_timing(self.size).frame_clocks() as f64 * self.fps;
        system::simulate(&cfg, &mut source, &mut |_| {}).map_err(ExperimentError::Run)
    }

    /// `track`'s forward run on `o`, as its log.
    pub fn forward_log(&self, o: &Object) -> Result<RunLog, ExperimentError> {
        let (first, last) = o.frames;
        self.simulate(first..=last, o.centre(), o, true)
    }

    /// `track`'s forward and backward runs on `o`.
    pub fn runs(&self, o: &Object) -> Result<Runs, ExperimentError> {
        self.runs_from(o, &self.forward_log(o)?)
    }

    /// `track`'s runs on `o` from its forward run's log `forward` ([`Clip::forward_log`]): the
    /// backward run is made from where it ends.
    pub fn runs_from(&self, o: &Object, forward: &RunLog) -> Result<Runs, ExperimentError> {
        let (first, last) = o.frames;
        let forward = measured(forward);
        let backward = match forward.last().copied().flatten() {
            Some(end) => {
                let mut back = measured(&self.simulate((first..=last).rev(), end, o, true)?);
                back.reverse();
                back
            }
            None => Vec::new(),
        };
        Ok(Runs { forward, backward })
    }
}

/// A run's measured position of each frame, at most [`crate::system::MAX_AGE`] frames old.
fn measured(log: &RunLog) -> Track {
    log.frames.iter().map(|r| r.fresh().map(|(p, _)| p)).collect()
}

/// A tracker's figures on an object (see the module documentation).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Figures {
    /// Frames of the object.
    pub frames: usize,
    /// Frames with a position.
    pub positions: usize,
    /// Frames where CSRT reports.
    pub csrt_frames: usize,
    /// Of the frames where CSRT reports, those with a position.
    pub where_csrt: usize,
    /// Forward-backward error on the first frame, px (`None`: the backward run ended lost).
    pub fb_first: Option<f64>,
    /// Mean forward-backward distance, px, over the frames both runs report.
    pub fb_mean: Option<f64>,
    /// Mean distance to CSRT, px, and the share within [`AGREE_PX`] (%), where both report.
    pub to_csrt: Option<(f64, f64)>,
}

fn dist(a: (f64, f64), b: (f64, f64)) -> f64 {
    (a.0 - b.0).hypot(a.1 - b.1)
}

fn mean(v: &[f64]) -> Option<f64> {
    (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
}

/// The figures of `runs` on `o`, against CSRT's forward run `csrt`.
pub fn figures(o: &Object, runs: &Runs, csrt: &Track) -> Figures {
    let fwd = &runs.forward;
    let both = |a: &Track, b: &Track| -> Vec<f64> { a.iter().zip(b).filter_map(|(p, q)| Some(dist((*p)?, (*q)?))).collect() };
    let to_csrt = both(fwd, csrt);
    Figures {
        frames: fwd.len(),
        positions: fwd.iter().flatten().count(),
        csrt_frames: csrt.iter().flatten().count(),
        where_csrt: fwd.iter().zip(csrt).filter(|(p, q)| p.is_some() && q.is_some()).count(),
        fb_first: runs.backward.first().copied().flatten().map(|p| dist(p, o.centre())),
        fb_mean: mean(&both(fwd, &runs.backward)),
        to_csrt: mean(&to_csrt).map(|m| (m, 100.0 * to_csrt.iter().filter(|&&d| d <= AGREE_PX).count() as f64 / to_csrt.len() as f64)),
    }
}

/// Largest distance the per-frame charts show, px (farther is drawn at the top).
const CHART_PX: f64 = 20.0;

/// `o`'s chart: frame by frame, the distance to CSRT's point of COOP's forward run (`ours`)
/// and of each of `theirs` (OpenCV's other trackers), and COOP's forward-backward distance;
/// gaps where a run has no position.
fn distance_chart(o: &Object, ours: &Runs, theirs: &[(&str, Track)], csrt: &Track) -> Chart {
    let series = |label: &str, a: &Track, b: &Track| Series {
        label: label.into(),
        points: a.iter().zip(b).enumerate().map(|(k, (p, q))| ((o.frames.0 + k) as f64, p.zip(*q).map(|(p, q)| dist(p, q)))).collect(),
    };
    // COOP's lines last, drawn over the others where they coincide.
    let mut all: Vec<Series> = theirs.iter().map(|(label, t)| series(label.trim_start_matches("OpenCV "), t, csrt)).collect();
    all.extend([series("COOP", &ours.forward, csrt), series("COOP fwd-bwd", &ours.forward, &ours.backward)]);
    Chart {
        title: format!("{}: distance to CSRT's point, and COOP's forward-backward (px)", o.id()),
        x_label: "frame".into(),
        y_label: "px (gaps: no position)".into(),
        series: all,
        y_range: Some((0.0, CHART_PX)),
    }
}

/// The evaluation on the clips in `clips`: writes `real-footage.csv` and a chart into `dir`
/// and returns the markdown.
pub fn evaluate(dir: &Path, clips: &Path, progress: &mut dyn FnMut(&str)) -> Result<String, ExperimentError> {
    let objects = objects()?;
    let labels: Vec<&str> = std::iter::once("COOP").chain(OPENCV.iter().map(|o| o.0)).collect();
    let mut table: Vec<Vec<Figures>> = Vec::new();
    let mut charts = Vec::new();
    let mut clip: Option<(String, Clip)> = None;
    for o in &objects {
        progress(&o.id());
        if clip.as_ref().is_none_or(|(name, _)| name != &o.clip) {
            clip = Some((o.clip.clone(), Clip::decode(&clips.join(format!("{}.avi", o.clip)))?));
        }
        let Some((_, decoded)) = &clip else { continue };
        let csrt = opencv_runs(o, "csrt")?.forward;
        let ours = decoded.runs(o)?;
        let mut row = vec![figures(o, &ours, &csrt)];
        let mut theirs = Vec::new();
        for (label, file) in OPENCV {
            let runs = opencv_runs(o, file)?;
            row.push(figures(o, &runs, &csrt));
            if file != "csrt" {
                theirs.push((label, runs.forward));
            }
        }
        table.push(row);
        charts.push(distance_chart(o, &ours, &theirs, &csrt));
    }
    let mut csv = String::from("object,tracker,frames,positions,csrt_frames,positions_where_csrt,fb_first_px,fb_mean_px,csrt_mean_px,csrt_within5_pct\n");
    let mut md = String::from(
        "## real-footage (native profile)\n\nObjects in the clips of Debian's opencv-doc (`fixtures/footage/`), tracked as `coopwin track --target-box` \
         tracks them (COOP, the template adapting) and by OpenCV 4.10 (`scripts/opencv_footage.py`). Real footage has no ground \
         truth: each cell gives positions % / positions % where CSRT reports / forward-backward error on the first frame px \
         (`lost`: the backward run ended without the object) / frames within 5 px of CSRT %.\n\n",
    );
    let _ = writeln!(md, "| object | frames | {} |", labels.join(" | "));
    let _ = writeln!(md, "|---|---|{}", "---|".repeat(labels.len()));
    let opt = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:.3}"));
    for (o, row) in objects.iter().zip(&table) {
        let cells: Vec<String> = row
            .iter()
            .map(|f| {
                let pct = |a: usize, b: usize| if b == 0 { "-".to_string() } else { format!("{:.0}", 100.0 * a as f64 / b as f64) };
                let fb = f.fb_first.map_or("lost".into(), |v| format!("{v:.1}"));
                let agree = f.to_csrt.map_or("-".into(), |(_, p)| format!("{p:.0}"));
                format!("{} / {} / {fb} / {agree}", pct(f.positions, f.frames), pct(f.where_csrt, f.csrt_frames))
            })
            .collect();
        let _ = writeln!(md, "| {} | {} | {} |", o.id(), o.frames.1 - o.frames.0 + 1, cells.join(" | "));
        for (label, f) in labels.iter().zip(row) {
            let (m, p) = f.to_csrt.map_or((None, None), |(m, p)| (Some(m), Some(p)));
            let _ = writeln!(
                csv,
                "{},{label},{},{},{},{},{},{},{},{}",
                o.id(),
                f.frames,
                f.positions,
                f.csrt_frames,
                f.where_csrt,
                opt(f.fb_first),
                opt(f.fb_mean),
                opt(m),
                p.map_or(String::new(), |p| format!("{p:.1}"))
            );
        }
    }
    std::fs::create_dir_all(dir).map_err(|source| ExperimentError::Io { action: "create", path: dir.into(), source })?;
    let path = dir.join("real-footage.csv");
    std::fs::write(&path, csv).map_err(|source| ExperimentError::Io { action: "write", path, source })?;
    let chart = Bars {
        title: "Real footage: frames with a position where CSRT reports the object (%)".into(),
        y_label: "frames with a position (%)".into(),
        groups: objects.iter().map(Object::id).collect(),
        series: labels
            .iter()
            .enumerate()
            .map(|(j, l)| {
                let share = |row: &Vec<Figures>| row.get(j).filter(|f| f.csrt_frames > 0).map(|f| 100.0 * f.where_csrt as f64 / f.csrt_frames as f64);
                ((*l).to_string(), table.iter().map(share).collect())
            })
            .collect(),
        y_range: (0.0, 100.0),
    };
    plot::write_svg(&chart.svg(), dir, "real-footage")?;
    for (o, chart) in objects.iter().zip(&charts) {
        plot::write(chart, dir, &format!("real-footage-{}", o.id()))?;
    }
    md.push_str("\nFiles: `real-footage.csv`, `real-footage.svg`, `real-footage.png`, and per object `real-footage-OBJECT.svg`/`.png`: the distance to CSRT's point frame by frame. OpenCV columns come from `fixtures/opencv/footage/` (`scripts/opencv_footage.py`).\n");
    Ok(md)
}
