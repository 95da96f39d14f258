//! `coopwin track`: tracks a folder of PNG frames with a windowing strategy in simulated time.
use super::{io_error, output::OutFile, CliError};
use crate::backend::Trace;
use crate::metrics::{self, Summary};
use crate::system::{self, FrameRecord, FrameSource, RunLog, SystemConfig};
use coopwin_firmware::processors::Mode;
use coopwin_firmware::types::Source;
use std::collections::VecDeque;
use std::fmt::Write as _;
use std::io::IsTerminal;
use std::ops::Range;
use std::path::{Path, PathBuf};

/// Smallest and largest frame side accepted.
pub const SIDES: std::ops::RangeInclusive<usize> = 64..=1024;

/// PNG frames in a folder, in natural order of their names (`img2.png` before `img10.png`),
/// decoded on demand (a few kept in memory).
pub struct FolderFrames {
    paths: Vec<PathBuf>,
    size: (usize, usize),
    cache: VecDeque<(usize, Vec<u8>)>,
}

impl FolderFrames {
    /// Lists and checks the folder: it must hold PNG frames, all of one size within
    /// [`SIDES`]. Every frame is decoded now, so a bad file (unreadable, truncated, another
    /// size) is named with the reason before tracking starts.
    pub fn open(dir: &Path) -> Result<Self, CliError> {
        let entries = std::fs::read_dir(dir).map_err(|e| io_error("read the frames folder", dir, e))?;
        let mut paths: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x.eq_ignore_ascii_case("png")))
            .collect();
        paths.sort_by(|a, b| natural_cmp(&a.to_string_lossy(), &b.to_string_lossy()));
        let first = paths.first().ok_or_else(|| CliError::new(format!("no PNG frames in {}", dir.display())))?;
        let size = decoded_size(first)?;
        if !SIDES.contains(&size.0) || !SIDES.contains(&size.1) {
            return Err(CliError::new(format!(
                "{}: frames must be 64x64 to 1024x1024, this one is {}x{}",
                first.display(),
                size.0,
                size.1
            )));
        }
        for p in &paths[1..] {
            let d = decoded_size(p)?;
            if d != size {
                return Err(CliError::new(format!(
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

    /// The frames' file names, in tracking order.
    pub fn names(&self) -> Vec<String> {
        self.paths.iter().map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default()).collect()
    }

    /// `frame,file` lines: the order the frames are tracked in.
    pub fn listing(&self) -> String {
        let mut s = String::from("frame,file\n");
        for (k, n) in self.names().iter().enumerate() {
            let _ = writeln!(s, "{k},{}", csv_field(n));
        }
        s
    }
}

/// Decodes the whole of `p` (a truncated or corrupt file fails here) and returns its size.
fn decoded_size(p: &Path) -> Result<(usize, usize), CliError> {
    let img = image::open(p).map_err(|e| CliError::new(format!("{}: not a readable PNG ({e})", p.display())))?;
    Ok((img.width() as usize, img.height() as usize))
}

/// Orders names as a person would: runs of digits compare by their value, so `img2` comes
/// before `img10`; names equal by that measure fall back to plain text order.
pub fn natural_cmp(a: &str, b: &str) -> std::cmp::Ordering {
    use std::cmp::Ordering;
    let (mut x, mut y) = (a.as_bytes(), b.as_bytes());
    while let (Some(&c), Some(&d)) = (x.first(), y.first()) {
        let ord = if c.is_ascii_digit() && d.is_ascii_digit() {
            let run = |s: &[u8]| s.iter().take_while(|b| b.is_ascii_digit()).count();
            let (m, n) = (run(x), run(y));
            let trim = |s: &[u8]| {
                let z = s.iter().take_while(|&&b| b == b'0').count();
                s[z..].to_vec()
            };
            let (p, q) = (trim(&x[..m]), trim(&y[..n]));
            let o = p.len().cmp(&q.len()).then_with(|| p.cmp(&q));
            x = &x[m..];
            y = &y[n..];
            o
        } else {
            x = &x[1..];
            y = &y[1..];
            c.cmp(&d)
        };
        if ord != Ordering::Equal {
            return ord;
        }
    }
    x.len().cmp(&y.len()).then_with(|| a.cmp(b))
}

/// A CSV field: quoted when it holds a comma, a quote or a line break.
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
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

/// The CSV of a run: frame,x,y,mode,source,measured_frame,file (the frame's file name, empty
/// for frames that come from no file).
pub fn csv(frames: &[FrameRecord], files: Option<&[String]>) -> String {
    let mut s = String::from("frame,x,y,mode,source,measured_frame,file\n");
    for r in frames {
        let (x, y) = r.point.map(|(x, y)| (format!("{x:.3}"), format!("{y:.3}"))).unwrap_or_default();
        let file = files.and_then(|f| f.get(r.frame)).map(|n| csv_field(n)).unwrap_or_default();
        let _ = writeln!(
            s,
            "{},{x},{y},{},{},{},{file}",
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
pub fn algo_name(a: Source) -> &'static str {
    match a {
        Source::Ncc => "ncc",
        Source::Cd => "cd",
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
        let dec = r.decimation == coopwin_firmware::types::Decimation::Quarter;
        let _ = writeln!(s, "{p},{clock},{},{},{},{},{}", w.xmin, w.xmax, w.ymin, w.ymax, dec as u8);
    }
    s
}

/// Tracks the frames in `dir`; returns the run, its summary (against `groundtruth.csv`
/// when the folder has one) and the frames' file names.
/// With `vcd`, every window unit is traced into it, for the frames in its range (all without).
/// The target, the traced range and the write phase are checked against the frames before
/// the run (bad ones are argument errors).
pub fn track(
    dir: &Path,
    cfg: &SystemConfig,
    vcd: Option<(&OutFile, Option<Range<usize>>)>,
) -> Result<(RunLog, Option<Summary>, Vec<String>), CliError> {
    let mut frames = FolderFrames::open(dir)?;
    let (w, h) = frames.size;
    if let Some((x, y)) = cfg.target {
        if !(x.is_finite() && y.is_finite() && x >= 0.0 && y >= 0.0 && x <= (w - 1) as f64 && y <= (h - 1) as f64) {
            return Err(CliError::arg(format!(
                "--target {x},{y} is outside the {w}x{h} frames (X 0..{}, Y 0..{})",
                w - 1,
                h - 1
            )));
        }
    }
    if let Some(phase) = cfg.write_phase {
        let clocks = system::raster(&frames, cfg.jitter).timing.frame_clocks() as u64;
        if phase >= clocks {
            return Err(CliError::arg(format!("--write-phase {phase}: a {w}x{h} frame has {clocks} clocks (0..{})", clocks - 1)));
        }
    }
    let n = frames.len();
    let mut stream = None;
    let trace = match vcd {
        Some((out, range)) => {
            let range = range.unwrap_or(0..n);
            if range.end > n {
                return Err(CliError::arg(format!(
                    "--vcd-frames {}..{}: the folder has frames 0..{n} (the end is excluded)",
                    range.start, range.end
                )));
            }
            let shared = out.stream()?.shared();
            stream = Some(shared.clone());
            Some(Trace { out: Box::new(shared), frames: range })
        }
        None => None,
    };
    let names = frames.names();
    let log = system::run_traced(cfg, &mut frames, &mut progress_bar(n, "tracking"), trace).map_err(CliError::new)?;
    if let Some(s) = stream {
        s.finish()?;
    }
    let truth_path = dir.join("groundtruth.csv");
    let summary = if truth_path.exists() {
        let truth = metrics::read_truth(&truth_path)?;
        Some(metrics::summarise(&log, &truth))
    } else {
        None
    };
    Ok((log, summary, names))
}

#[cfg(test)]
mod tests {
    use super::natural_cmp;

    #[test]
    fn names_sort_by_the_value_of_their_numbers() {
        // Reference: the order a person numbering the files meant, written out by hand.
        let want = ["a.png", "img0.png", "img2.png", "img002b.png", "img10.png", "img11.png", "img100.png", "img100x2.png", "img100x10.png"];
        let mut got = want.to_vec();
        got.reverse();
        got.sort_by(|a, b| natural_cmp(a, b));
        assert_eq!(got, want);
        // Equal values with different zero padding still have a fixed order.
        assert_eq!(natural_cmp("f01.png", "f1.png"), "f01.png".cmp("f1.png"));
    }
}
