//! The files `coopwin track` writes ([`output`]'s rule for each): the CSV, a row as each frame
//! ends; with rust-hdl units a VCD and its requests CSV; an overlay GIF or MP4. All are checked
//! before the run and completed together after it, so an interrupted or failed run replaces
//! none of them.
use super::args::HdlArg;
use super::output::{self, OutFile, Shared, Stream};
use super::track::TrackArgs;
use super::{interrupt, io_error, CliError};
use crate::analysis::audit::requests;
use crate::analysis::metrics;
use crate::frames::{binned, groundtruth::Truth, Interruptible};
use crate::report::csv;
use crate::report::overlay::{OverlayKind, Painter};
use crate::system::RunLog;
use crate::tracking::{self, TrackError, TrackRun};
use crate::units::clocked::Trace;
use std::io::Write;
use std::ops::Range;

/// A finished run: its log, and what the files took.
pub struct Tracked {
    /// The run's log.
    pub log: RunLog,
    /// Seconds the tracking took (the files completed after it not counted).
    pub tracking_secs: f64,
    /// A line for each file written.
    pub written: Vec<String>,
}

/// The outputs a `track` run was asked for, checked.
pub struct TrackFiles {
    csv: Option<OutFile>,
    /// The VCD and its requests CSV beside it.
    vcd: Option<(OutFile, OutFile)>,
    overlay: Option<(OverlayKind, OutFile)>,
}

impl TrackFiles {
    /// Checks `--out`, `--vcd` and `--overlay` before any work (a bad path costs no tracking
    /// time), and that none is an input or another output.
    pub fn check(args: &TrackArgs) -> Result<TrackFiles, CliError> {
        let csv = args.out.as_ref().map(|p| OutFile::check(p, "--out")).transpose()?;
        let vcd = match &args.vcd {
            Some(v) if v.as_os_str() == "-" => {
                return Err(CliError::arg("--vcd -: the VCD needs a file name (its requests CSV is written beside it)"));
            }
            Some(v) => Some((OutFile::check(v, "--vcd")?, OutFile::check(&v.with_extension("requests.csv"), "--vcd")?)),
            None => None,
        };
        if matches!(args.hdl, HdlArg::Model) && vcd.is_some() {
            return Err(CliError::arg("--vcd traces the window units' signals: add --hdl rust-hdl"));
        }
        let overlay = match &args.overlay {
            Some(p) => {
                let kind = OverlayKind::of(p).ok_or_else(|| CliError::arg(format!("--overlay {}: name a .gif or an .mp4 file", p.display())))?;
                Some((kind, OutFile::check(p, "--overlay")?))
            }
            None => None,
        };
        let files = TrackFiles { csv, vcd, overlay };
        let named = [("--out", files.csv.as_ref()), ("--overlay", files.overlay.as_ref().map(|(_, o)| o))]
            .into_iter()
            .chain(files.vcd.iter().flat_map(|(v, r)| [("--vcd", Some(v)), ("--vcd", Some(r))]))
            .filter_map(|(option, o)| o.map(|o| (option, o)))
            .collect::<Vec<_>>();
        output::check_apart(&[("--frames", &args.frames)], &named)?;
        Ok(files)
    }

    /// Whether the CSV goes to standard output (the report then goes to standard error).
    pub fn csv_to_stdout(&self) -> bool {
        self.csv.as_ref().is_some_and(OutFile::is_stdout)
    }

    /// Tracks `run` (tracing `vcd_frames` of it, counted from its first, into the VCD), then
    /// completes every file, the overlay drawing `truth`'s points.
    pub fn track(
        self,
        run: &mut TrackRun,
        vcd_frames: Option<Range<usize>>,
        truth: Option<&[Truth]>,
        progress: &mut dyn FnMut(usize),
    ) -> Result<Tracked, CliError> {
        let range = run.range.clone();
        let started = std::time::Instant::now();
        let mut csv_out = match &self.csv {
            Some(o) => {
                let mut stream = o.stream()?;
                writeln!(stream, "{}", csv::TRACK_HEADER).map_err(|e| io_error("write", &o.path, e))?;
                Some((o, stream, None))
            }
            None => None,
        };
        // The VCD is shared: the run writes into it, and it is finished here with the others.
        let vcd_stream = self.vcd.as_ref().map(|(v, _)| Self::vcd_stream(v, run, vcd_frames.unwrap_or(0..range.len()))).transpose()?;
        let trace = vcd_stream.as_ref().map(|(shared, frames)| Trace { out: Box::new(shared.clone()), frames: frames.clone() });
        let log = run.track(trace, &interrupt::requested, progress, &mut |_, row| {
            if let Some((_, stream, error @ None)) = &mut csv_out {
                *error = writeln!(stream, "{row}").err();
            }
        })?;
        let tracking_secs = started.elapsed().as_secs_f64();
        let mut done: Vec<(Stream, Option<String>)> = Vec::new();
        if let Some((o, stream, error)) = csv_out {
            if let Some(e) = error {
                return Err(io_error("write", &o.path, e));
            }
            done.push((stream, (!o.is_stdout()).then(|| format!("wrote {}", o.path.display()))));
        }
        if let Some((v, req)) = &self.vcd {
            let mut stream = req.stream()?;
            stream.write_all(requests::to_csv(&log).as_bytes()).map_err(|e| io_error("write", &req.path, e))?;
            let line = format!("wrote {} and {} (every unit; check one with `coopwin audit --unit K`)", v.path.display(), req.path.display());
            done.push((stream, Some(line)));
        }
        if let Some((kind, o)) = &self.overlay {
            let points = truth.map(|t| metrics::true_points(&log, t));
            let painter = Painter::new(&log, points.as_deref(), run.shape.size).numbered_from(range.start).binned(run.cfg.bin);
            let mut all = run.input.frames().map_err(TrackError::from)?;
            let mut frames = tracking::tracked(&mut all, range.clone())?;
            let (stream, reduced) = kind.write(o.stream()?, &mut Interruptible(&mut frames, &interrupt::requested), painter, run.fps.unwrap_or(1.0 / log.frame_period))?;
            let reduced = reduced.map(|r| format!(" ({r}, to bound the GIF's size; an .mp4 overlay keeps every frame at full size)")).unwrap_or_default();
            done.push((stream, Some(format!("wrote {}{reduced}", o.path.display()))));
        }
        if interrupt::requested() {
            return Err(CliError::interrupted());
        }
        if let Some((v, _)) = vcd_stream {
            v.finish()?;
        }
        let mut written = Vec::new();
        for (stream, line) in done {
            stream.finish()?;
            written.extend(line);
        }
        Ok(Tracked { log, tracking_secs, written })
    }

    /// The VCD's stream, and the frames it traces, with a warning when they are many.
    fn vcd_stream(v: &OutFile, run: &TrackRun, frames: Range<usize>) -> Result<(Shared, Range<usize>), CliError> {
        let mb = tracking::vcd_megabytes_a_frame(binned::binned_size(run.input.size(), run.cfg.bin), run.cfg.strategy.units());
        if frames.len() > 4 {
            eprintln!(
                "warning: --vcd traces {} frames, about {mb:.0} MB each ({:.1} GB); --vcd-frames FIRST..END traces fewer",
                frames.len(),
                mb * frames.len() as f64 / 1000.0
            );
        }
        Ok((v.stream()?.shared(), frames))
    }
}
