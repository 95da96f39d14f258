//! `coopwin track`: tracks a folder of PNG frames with a windowing strategy in simulated time.
use super::{io_error, CliError};
use crate::backend::Trace;
use crate::metrics::{self, Summary};
use crate::system::{self, FrameRecord, FrameSource, RunLog, SystemConfig};
use coopwin_firmware::tracker::{Algo, Mode};
use std::collections::VecDeque;
use std::fmt::Write as _;
use std::io::IsTerminal;
use std::ops::Range;
use std::path::{Path, PathBuf};

/// Smallest and largest frame side accepted.
pub const SIDES: std::ops::RangeInclusive<usize> = 64..=1024;

/// PNG frames in a folder, sorted by name, decoded on demand (a few kept in memory).
pub struct FolderFrames {
    paths: Vec<PathBuf>,
    size: (usize, usize),
    cache: VecDeque<(usize, Vec<u8>)>,
}

impl FolderFrames {
    /// Lists and checks the folder: it must hold PNG frames, all of one size within
    /// [`SIDES`]. Every frame's header is read now, so a bad file fails before tracking.
    pub fn open(dir: &Path) -> Result<Self, CliError> {
        let entries = std::fs::read_dir(dir).map_err(|e| io_error("read the frames folder", dir, e))?;
        let mut paths: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x.eq_ignore_ascii_case("png")))
            .collect();
        paths.sort();
        let first = paths.first().ok_or_else(|| CliError(format!("no PNG frames in {}", dir.display())))?;
        let size = dims(first)?;
        if !SIDES.contains(&size.0) || !SIDES.contains(&size.1) {
            return Err(CliError(format!(
                "{}: frames must be 64x64 to 1024x1024, this one is {}x{}",
                first.display(),
                size.0,
                size.1
            )));
        }
        for p in &paths[1..] {
            let d = dims(p)?;
            if d != size {
                return Err(CliError(format!(
                    "mixed frame sizes: {} is {}x{}, {} is {}x{}",
                    first.display(),
                    size.0,
                    size.1,
                    p.display(),
                    d.0,
                    d.1
                )));
            }
        }
        Ok(FolderFrames { paths, size, cache: VecDeque::new() })
    }
}

fn dims(p: &Path) -> Result<(usize, usize), CliError> {
    let (w, h) = image::image_dimensions(p).map_err(|e| CliError(format!("{}: not a readable PNG ({e})", p.display())))?;
    Ok((w as usize, h as usize))
}

impl FrameSource for FolderFrames {
    fn size(&self) -> (usize, usize) {
        self.size
    }
    fn len(&self) -> usize {
        self.paths.len()
    }
    fn frame(&mut self, k: usize) -> Result<&[u8], String> {
        if let Some(i) = self.cache.iter().position(|(j, _)| *j == k) {
            return Ok(&self.cache[i].1);
        }
        let p = self.paths.get(k).ok_or_else(|| format!("no frame {k}"))?;
        let img = image::open(p).map_err(|e| format!("{}: {e}", p.display()))?.to_luma8();
        if self.cache.len() >= 4 {
            self.cache.pop_front();
        }
        self.cache.push_back((k, img.into_raw()));
        Ok(&self.cache.back().ok_or("cache")?.1)
    }
}

/// A progress bar on stderr when it is a terminal.
pub fn progress_bar(total: usize, label: &'static str) -> impl FnMut(usize) {
    let tty = std::io::stderr().is_terminal();
    move |k: usize| {
        if tty && (k.is_multiple_of(8) || k + 1 == total) {
            let done = (k + 1) * 40 / total.max(1);
            eprint!("\r{label} [{}{}] {}/{}", "#".repeat(done), " ".repeat(40 - done), k + 1, total);
            if k + 1 == total {
                eprintln!();
            }
        }
    }
}

/// The CSV of a run: frame,x,y,mode,source,measured_frame.
pub fn csv(frames: &[FrameRecord]) -> String {
    let mut s = String::from("frame,x,y,mode,source,measured_frame\n");
    for r in frames {
        let (x, y) = r.point.map(|(x, y)| (format!("{x:.3}"), format!("{y:.3}"))).unwrap_or_default();
        let _ = writeln!(
            s,
            "{},{x},{y},{},{},{}",
            r.frame,
            mode_name(r.mode),
            r.source.map(algo_name).unwrap_or("none"),
            r.measured_frame.map(|f| f.to_string()).unwrap_or_default()
        );
    }
    s
}

/// `watch`, `detect` or `track`.
pub fn mode_name(m: Mode) -> &'static str {
    match m {
        Mode::Watch => "watch",
        Mode::Detect => "detect",
        Mode::Track => "track",
    }
}

/// `ncc`, `cd` or `ssd`.
pub fn algo_name(a: Algo) -> &'static str {
    match a {
        Algo::Ncc => "ncc",
        Algo::Cd => "cd",
        Algo::Ssd => "ssd",
    }
}

/// The requests CSV beside a VCD: unit,clock,xmin,xmax,ymin,ymax,decimate (unit k is
/// processor k, traced as `uut$k`).
/// With a VCD of chosen frames, the sets taken before the trace began are left out.
pub fn requests_csv(log: &RunLog) -> String {
    let mut s = String::from("unit,clock,xmin,xmax,ymin,ymax,decimate\n");
    let mut skip = log.sets_before_trace.clone();
    for (p, clock, r) in &log.requests {
        if let Some(n) = skip.get_mut(*p).filter(|n| **n > 0) {
            *n -= 1;
            continue;
        }
        let w = crate::backend::window_of(r);
        let dec = r.decimation == coopwin_firmware::ports::Decimation::Quarter;
        let _ = writeln!(s, "{p},{clock},{},{},{},{},{}", w.xmin, w.xmax, w.ymin, w.ymax, dec as u8);
    }
    s
}

/// Writes `text` to `path` through a temporary file, so a failed run leaves nothing behind.
pub fn write_atomic(path: &Path, text: &str) -> Result<(), CliError> {
    let tmp = path.with_extension("partial");
    std::fs::write(&tmp, text).map_err(|e| io_error("write", &tmp, e))?;
    std::fs::rename(&tmp, path).map_err(|e| io_error("write", path, e))
}

/// Tracks the frames in `dir`; returns the run and its summary (against `groundtruth.csv`
/// when the folder has one).
/// With `vcd`, every window unit is traced into it, for the frames in its range (all without).
pub fn track(
    dir: &Path,
    cfg: &SystemConfig,
    vcd: Option<(&Path, Option<Range<usize>>)>,
) -> Result<(RunLog, Option<Summary>), CliError> {
    let mut frames = FolderFrames::open(dir)?;
    if let Some((x, y)) = cfg.target {
        let (w, h) = frames.size;
        if !(x.is_finite() && y.is_finite() && x >= 0.0 && y >= 0.0 && x <= (w - 1) as f64 && y <= (h - 1) as f64) {
            return Err(CliError(format!("--target {x},{y} is outside the {w}x{h} frames")));
        }
    }
    let n = frames.len();
    let trace = match vcd {
        Some((p, frames)) => {
            let frames = frames.unwrap_or(0..n);
            if frames.start >= frames.end || frames.end > n {
                return Err(CliError(format!(
                    "--vcd-frames {}..{}: the folder has frames 0..{n} (the end is excluded)",
                    frames.start, frames.end
                )));
            }
            let out = std::io::BufWriter::new(std::fs::File::create(p).map_err(|e| io_error("create", p, e))?);
            Some(Trace { out: Box::new(out), frames })
        }
        None => None,
    };
    let log = system::run_traced(cfg, &mut frames, &mut progress_bar(n, "tracking"), trace).map_err(CliError)?;
    let truth_path = dir.join("groundtruth.csv");
    let summary = if truth_path.exists() {
        let truth = metrics::read_truth(&truth_path)?;
        Some(metrics::summarise(&log, &truth))
    } else {
        None
    };
    Ok((log, summary))
}
