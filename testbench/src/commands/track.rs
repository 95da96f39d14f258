//! `coopwin track`: its options in, one tracking run ([`crate::tracking`]) out; it writes
//! the per-frame CSV (and, with rust-hdl units, a VCD and its requests CSV; on request an
//! overlay GIF or MP4), and prints the summary against `groundtruth.csv` when the folder has
//! one.
use super::args::{self, HdlArg, PolicyArg, ProfileArg, StrategyArg, WatchArg};
use super::output::{self, OutFile};
use super::{interrupt, CliError};
use crate::analysis::audit::requests;
use crate::analysis::metrics;
use crate::frames::folder::FolderFrames;
use crate::frames::{groundtruth, Interruptible};
use crate::report::overlay::{OverlayError, OverlayKind, Painter};
use crate::report::{self, csv};
use crate::tracking::{self, Target, TrackError, TrackOptions, TrackRun};
use crate::units::clocked::Trace;
use coopwin_hdl::sim::camera::Jitter;
use std::io::{IsTerminal, Write};
use std::path::PathBuf;

/// `coopwin track`'s options.
#[derive(clap::Args)]
pub struct TrackArgs {
    /// Folder of PNG frames (8-bit gray or colour, 64x64 to 4096x4096, one size), or a video
    /// file FFmpeg reads (MP4, AVI, MKV, ...; needs the `ffmpeg` program)
    #[arg(long)]
    pub frames: PathBuf,
    /// Windowing strategy
    #[arg(long, value_enum, default_value_t = StrategyArg::Coop)]
    pub strategy: StrategyArg,
    /// Template side N (4..32) [default: 20, or the --target-box's shorter side up to 32]
    #[arg(long, value_parser = args::parse_in::<u16>(4, 32, "a template side"))]
    pub template: Option<u16>,
    /// Point to track as X,Y (pixel centres at integers); default: lock on to motion
    #[arg(long, value_parser = args::parse_point, allow_hyphen_values = true, conflicts_with = "target_box")]
    pub target: Option<(f64, f64)>,
    /// Box to track as X,Y,W,H (OpenCV's convention: columns X..X+W-1, rows Y..Y+H-1); its
    /// centre is tracked with the largest centred square template (up to 32x32), and the CSV
    /// reports a W x H box
    #[arg(long, value_name = "X,Y,W,H", value_parser = args::parse_box, allow_hyphen_values = true)]
    pub target_box: Option<(u32, u32, u32, u32)>,
    /// First frame to track (0-based, in the order FFmpeg and OpenCV number a video's frames,
    /// or the folder's order): --target and --target-box are on this frame, and the CSV keeps
    /// the source's frame numbers (a clip that opens on black frames starts later)
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub start_frame: usize,
    /// Stop before frame N (numbered as --start-frame; N itself is not tracked), e.g. at a
    /// shot cut [default: the last frame]
    #[arg(long, value_name = "N")]
    pub end_frame: Option<usize>,
    /// Frames per second of the source [default: a video's own rate; for PNG frames, the
    /// rate of the thesis camera's 8 MHz pixel clock over the frames' raster,
    /// 8e6 / ((H + 2) (W + 16) + 16): 114 at 256x256, 17.65 at 768x576]
    #[arg(long, value_parser = args::parse_fps)]
    pub fps: Option<f64>,
    /// Foveal search margin R: the Foveal window is the template plus R pixels on each side
    /// (1..16), so the target may move R pixels between two of its windows (the adapting
    /// template's window also grows with the measured motion, up to 14 px more a side)
    #[arg(long, value_name = "R", default_value_t = 2, value_parser = args::parse_in::<u16>(1, 16, "a search margin"))]
    pub search: u16,
    /// Keep the template cut at the start, as the thesis does (by default the Foveal template
    /// adapts to the object's appearance, corrected against the first one, and the Foveal
    /// window is placed where the motion predicts the target; `--policy sse` and `kalman`
    /// always keep it fixed)
    #[arg(long)]
    pub fixed_template: bool,
    /// Processor speeds: our kernels on this machine (native), or the thesis's C40 timing,
    /// which the experiments use
    #[arg(long, value_enum, default_value_t = ProfileArg::Native)]
    pub profile: ProfileArg,
    /// MPDF's two Watch windows: the thesis's 20-row strips at the top and bottom edges
    /// (where an object enters the view), or the two halves of the view (an object already
    /// in it is found too)
    #[arg(long, value_enum, default_value_t = WatchArg::Halves)]
    pub watch: WatchArg,
    /// COOP's confidence data set size n (3..8)
    #[arg(long, default_value_t = 4, value_parser = args::parse_in::<usize>(3, 8, "a data set size"))]
    pub coop_n: usize,
    /// COOP's decision: guarded cooperation, the thesis's least-squares SSE (4.3), or a
    /// Kalman filter (5.2)
    #[arg(long, value_enum, default_value_t = PolicyArg::Guarded)]
    pub policy: PolicyArg,
    /// CSV to write, one line a frame (the columns are listed below); - for standard output
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Animated overlay of the run: FILE.mp4 (needs FFmpeg; every frame, full size), or
    /// FILE.gif (bounded to about 15 MB: frames over 480 px scaled down, and on a long run
    /// every k-th frame; the run's report says what was reduced): each frame with the Watch
    /// (blue), Peripheral (yellow) and Foveal (green; COOP's corner window magenta) windows,
    /// the position and its box (red: NCC, orange: corner detector) and the true point when
    /// groundtruth.csv is there (cyan x)
    #[arg(long, value_name = "FILE")]
    pub overlay: Option<PathBuf>,
    /// Print the frames in the order they are tracked (frame,file) and stop
    #[arg(long)]
    pub list: bool,
    /// Track a damaged video: the frames that decode are tracked, and the damaged ones have
    /// damaged=1 in the CSV. Damage is judged by the pixels: frames after missing or corrupt
    /// data (up to the next key frame), and frames the decoder concealed errors in (pixels
    /// that differ without FFmpeg's error concealment); a decoder error that changes no pixel
    /// is not damage [default: refuse a damaged video, exit 1]
    #[arg(long)]
    pub allow_damaged: bool,
    /// Window units: the behavioural model, the rust-hdl blocks, or the Verilog in Verilator
    #[arg(long, value_enum, default_value_t = HdlArg::Model)]
    pub hdl: HdlArg,
    /// With --hdl rust-hdl or verilator: the window units' pixel width (8 to 16, as `coopwin
    /// verilog --pixel-bits`); the frames' 8-bit pixels enter as its top bits
    #[arg(long, default_value_t = 8, value_name = "BITS", value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(8..=16))]
    pub pixel_bits: usize,
    /// With --hdl rust-hdl: a VCD of every window unit's signals (uut$0, uut$1, ...), and
    /// FILE.requests.csv beside it for `coopwin audit`
    #[arg(long, value_name = "FILE")]
    pub vcd: Option<PathBuf>,
    /// With --vcd: trace only frames FIRST up to END (END excluded, both counted from
    /// --start-frame), e.g. 10..12
    #[arg(long, value_name = "FIRST..END", value_parser = args::parse_frames, requires = "vcd", allow_hyphen_values = true)]
    pub vcd_frames: Option<std::ops::Range<usize>>,
    /// Fault campaign: camera blanking that varies, up to LINE extra clocks before each line
    /// and FRAME after each frame, drawn from SEED (default 1)
    #[arg(long, value_name = "LINE,FRAME[,SEED]", value_parser = args::parse_jitter, allow_hyphen_values = true)]
    pub blank_jitter: Option<Jitter>,
    /// Fault campaign: hold every coordinate write until this clock of a frame (from FVAL
    /// rising), e.g. 0 (the FVAL edge) or 40000 (inside a window)
    #[arg(long, value_name = "CLOCK")]
    pub write_phase: Option<u64>,
}

impl TrackArgs {
    /// The run's options (all but the input and the outputs).
    pub fn options(&self) -> TrackOptions {
        let target = match (self.target, self.target_box) {
            (_, Some((x, y, w, h))) => Target::Box(x, y, w, h),
            (Some((x, y)), None) => Target::Point(x, y),
            (None, None) => Target::Motion,
        };
        TrackOptions {
            strategy: self.strategy.into(),
            template: self.template,
            target,
            start_frame: self.start_frame,
            end_frame: self.end_frame,
            fps: self.fps,
            search: self.search,
            fixed_template: self.fixed_template,
            cost: self.profile.into(),
            watch: self.watch.into(),
            coop_n: self.coop_n,
            policy: self.policy.into(),
            allow_damaged: self.allow_damaged,
            backend: self.hdl.into(),
            pixel_bits: self.pixel_bits,
            vcd_frames: self.vcd_frames.clone(),
            jitter: self.blank_jitter,
            write_phase: self.write_phase,
        }
    }
}

impl From<TrackError> for CliError {
    fn from(e: TrackError) -> CliError {
        match e {
            e if e.interrupted() => CliError::interrupted(),
            e @ TrackError::Option(_) => CliError::arg(e.to_string()),
            e => CliError::new(e.to_string()),
        }
    }
}

impl From<OverlayError> for CliError {
    fn from(e: OverlayError) -> CliError {
        CliError::new(e.to_string())
    }
}

/// Tracks the frames, writes the outputs asked for and prints the report (on standard error
/// when the CSV goes to standard output). Ctrl-C ends it with exit code 130, nothing written.
pub fn track_folder(args: TrackArgs) -> Result<(), CliError> {
    interrupt::install();
    track(args).map_err(|e| if interrupt::requested() { CliError::interrupted() } else { e })
}

fn track(args: TrackArgs) -> Result<(), CliError> {
    if args.list {
        print!("{}", csv::frame_listing(&FolderFrames::open(&args.frames)?.names()));
        return Ok(());
    }
    // Outputs are checked before the run, so a bad path costs no tracking time.
    let out = args.out.as_ref().map(|p| OutFile::check(p, "--out")).transpose()?;
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
    let overlay_out = match &args.overlay {
        Some(p) => {
            let kind = OverlayKind::of(p).ok_or_else(|| CliError::arg(format!("--overlay {}: name a .gif or an .mp4 file", p.display())))?;
            Some((kind, OutFile::check(p, "--overlay")?))
        }
        None => None,
    };
    let named = [("--out", out.as_ref()), ("--overlay", overlay_out.as_ref().map(|(_, o)| o))]
        .into_iter()
        .chain(vcd.iter().flat_map(|(v, r)| [("--vcd", Some(v)), ("--vcd", Some(r))]))
        .filter_map(|(option, o)| o.map(|o| (option, o)))
        .collect::<Vec<_>>();
    output::check_apart(&[("--frames", &args.frames)], &named)?;
    // With the CSV on standard output, the report goes to standard error.
    let to_stdout = out.as_ref().is_some_and(OutFile::is_stdout);
    let say = |line: String| if to_stdout { eprintln!("{line}") } else { println!("{line}") };
    let mut run = TrackRun::open(&args.frames, &args.options(), &interrupt::requested)?;
    if let Some(damage) = run.input.damage() {
        eprintln!("warning: {}: {damage}", args.frames.display());
    }
    let range = run.range.clone();
    let started = std::time::Instant::now();
    let truth_path = args.frames.join("groundtruth.csv");
    let truth = if args.frames.is_dir() && truth_path.exists() { Some(groundtruth::read(&truth_path)?) } else { None };
    let truth = truth.map(|t| t.get(range.clone()).unwrap_or_default().to_vec());
    let shape = run.shape;
    // The CSV is written a row as each frame ends (into a temporary file, put in place once
    // every output is written).
    let mut csv_out = match &out {
        Some(o) => {
            let mut stream = o.stream()?;
            writeln!(stream, "{}", csv::TRACK_HEADER).map_err(|e| super::io_error("write", &o.path, e))?;
            Some((o, stream, None))
        }
        None => None,
    };
    // The VCD is shared: the run writes into it, and it is finished here with the others.
    let vcd_stream = match &vcd {
        Some((v, _)) => {
            let frames = args.vcd_frames.clone().unwrap_or(0..range.len());
            let mb = tracking::vcd_megabytes_a_frame(run.input.size(), run.cfg.strategy.units());
            if frames.len() > 4 {
                eprintln!(
                    "warning: --vcd traces {} frames, about {mb:.0} MB each ({:.1} GB); --vcd-frames FIRST..END traces fewer",
                    frames.len(),
                    mb * frames.len() as f64 / 1000.0
                );
            }
            Some((v.stream()?.shared(), frames))
        }
        None => None,
    };
    let trace = vcd_stream.as_ref().map(|(shared, frames)| Trace { out: Box::new(shared.clone()), frames: frames.clone() });
    let log = run.track(trace, &interrupt::requested, &mut progress_line(range.len(), "tracking"), &mut |_, row| {
        if let Some((_, stream, error @ None)) = &mut csv_out {
            *error = writeln!(stream, "{row}").err();
        }
    })?;
    let summary = truth.as_ref().map(|t| metrics::summarise(&log, t));
    let tracking_secs = started.elapsed().as_secs_f64();
    // Every output is completed only once all are written: an interrupted or failed run
    // replaces none of them.
    let mut done = Vec::new();
    if let Some((o, stream, error)) = csv_out {
        if let Some(e) = error {
            return Err(super::io_error("write", &o.path, e));
        }
        done.push((stream, (!to_stdout).then(|| format!("wrote {}", o.path.display()))));
    }
    if let Some((v, req)) = &vcd {
        let mut stream = req.stream()?;
        stream.write_all(requests::to_csv(&log).as_bytes()).map_err(|e| super::io_error("write", &req.path, e))?;
        let line = format!("wrote {} and {} (every unit; check one with `coopwin audit --unit K`)", v.path.display(), req.path.display());
        done.push((stream, Some(line)));
    }
    if let Some((kind, o)) = &overlay_out {
        let points = truth.as_ref().map(|t| metrics::true_points(&log, t));
        let painter = Painter::new(&log, points.as_deref(), shape.size).numbered_from(range.start);
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
    for (stream, line) in done {
        stream.finish()?;
        if let Some(l) = line {
            say(l);
        }
    }
    for line in report::run_lines(&log, started.elapsed().as_secs_f64(), tracking_secs, range.start) {
        say(line);
    }
    if let Some(s) = summary {
        say(report::verdict(&s));
        say(report::summary_table(&[(run.cfg.strategy.name(), s)]));
    }
    Ok(())
}

/// Seconds between two progress lines when standard error is not a terminal (a log file, a
/// pipe): a long run shows it is alive without filling the log. `COOPWIN_PROGRESS_SECS`
/// sets another.
const LOG_PROGRESS_SECS: f64 = 5.0;

/// A progress line on stderr: frames done, frames/s (wall-clock) and the time left; on a
/// terminal redrawn in place at most four times a second, elsewhere a line every
/// [`LOG_PROGRESS_SECS`].
pub fn progress_line(total: usize, label: &'static str) -> impl FnMut(usize) {
    let tty = std::io::stderr().is_terminal();
    let log_secs = std::env::var("COOPWIN_PROGRESS_SECS").ok().and_then(|v| v.parse::<f64>().ok()).filter(|s| s.is_finite() && *s >= 0.0);
    let every = if tty { 0.25 } else { log_secs.unwrap_or(LOG_PROGRESS_SECS) };
    let started = std::time::Instant::now();
    let mut shown = started;
    move |k: usize| {
        let now = std::time::Instant::now();
        let last = k + 1 == total;
        let due = now.duration_since(shown).as_secs_f64() >= every;
        if !(due || (last && tty)) {
            return;
        }
        shown = now;
        let rate = (k + 1) as f64 / now.duration_since(started).as_secs_f64().max(1e-9);
        let left = (total - k - 1) as f64 / rate.max(1e-9);
        let line = format!("{label}: frame {}/{total}, {rate:.0} frames/s, ETA {}:{:02}", k + 1, left as u64 / 60, left as u64 % 60);
        if tty {
            eprint!("\r{line}   ");
            if last {
                eprintln!();
            }
        } else {
            eprintln!("{line}");
        }
    }
}
