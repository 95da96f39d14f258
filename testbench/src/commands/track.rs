//! `coopwin track`: tracks a folder of PNG frames or a video with a windowing strategy in
//! simulated time (thesis 2.3-2.5, 4.2), writes the per-frame CSV (and, with rust-hdl units,
//! a VCD and its requests CSV; on request an overlay GIF or MP4), and prints the summary
//! against `groundtruth.csv` when the folder has one.
use super::args::{self, HdlArg, PolicyArg, ProfileArg, StrategyArg, WatchArg};
use super::output::{self, OutFile, Shared};
use super::{interrupt, CliError};
use crate::analysis::audit::requests;
use crate::analysis::metrics;
use crate::frames::folder::FolderFrames;
use crate::frames::input::{Input, InputError, RowFacts};
use crate::frames::video::VideoError;
use crate::frames::{groundtruth, FrameSource, Skip};
use crate::report::csv::{CsvBox, FrameInfo};
use crate::report::overlay::{OverlayError, OverlayKind, Painter};
use crate::report::{self, csv};
use crate::system::{self, RunLog, SystemConfig};
use crate::units::clocked::Trace;
use crate::units::clocks::Clocks;
use coopwin_firmware::kernels::view::WindowView;
use coopwin_firmware::processors::template::Template;
use coopwin_firmware::processors::Params;
use coopwin_firmware::types::Point;
use coopwin_hdl::sim::camera::Jitter;
use std::io::{IsTerminal, Write};
use std::ops::Range;
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
    /// The template side: `--template`, the target box's shorter side (at most 32), or 20.
    fn template_side(&self) -> u16 {
        match (self.template, self.target_box) {
            (Some(n), _) => n,
            (None, Some((_, _, w, h))) => w.min(h).min(32) as u16,
            (None, None) => 20,
        }
    }

    /// The point to track: `--target`, or the centre of `--target-box`.
    fn target_point(&self) -> Option<(f64, f64)> {
        let centre = |(x, y, w, h): (u32, u32, u32, u32)| (f64::from(x) + (f64::from(w) - 1.0) / 2.0, f64::from(y) + (f64::from(h) - 1.0) / 2.0);
        self.target.or(self.target_box.map(centre))
    }

    /// The box the CSV and the overlay draw around each position.
    pub fn csv_box(&self) -> CsvBox {
        let n = usize::from(self.template_side());
        let size = self.target_box.map_or((n, n), |(_, _, w, h)| (w as usize, h as usize));
        let p = self.params();
        CsvBox { size, acceptance: p.correlation(p.adapt).1 }
    }

    /// The processors' parameters: the template side, the search margin, and the template
    /// adapting unless kept fixed.
    fn params(&self) -> Params {
        let n = self.template_side();
        let p = Params { template: n, foveal: n + 2 * self.search, ..Default::default() };
        if self.fixed_template || self.policy != PolicyArg::Guarded {
            p
        } else {
            p.adaptive()
        }
    }

    /// The run the options ask for on frames of `size` from a source of `fps` frames per
    /// second (the pixel clock that gives this rate with the camera's blanking), if known.
    pub fn config(&self, size: (usize, usize), fps: Option<f64>) -> SystemConfig {
        let cfg = SystemConfig {
            params: self.params(),
            coop_n: self.coop_n,
            target: self.target_point(),
            backend: self.hdl.into(),
            unit_pixel_bits: self.pixel_bits,
            policy: self.policy.into(),
            mpdf_watch: self.watch.into(),
            jitter: self.blank_jitter,
            write_phase: self.write_phase,
            ..SystemConfig::thesis(self.strategy.into(), self.profile.into(), None)
        };
        match fps {
            Some(fps) => SystemConfig { pixel_clock_hz: Clocks::camera_timing(size).frame_clocks() as f64 * fps, ..cfg },
            None => cfg,
        }
    }

    /// The source's frames to track: `--start-frame` up to `--end-frame` (excluded), checked
    /// against the input's `n` frames.
    fn frame_range(&self, n: usize) -> Result<Range<usize>, CliError> {
        let last = n.saturating_sub(1);
        if self.start_frame >= n {
            return Err(CliError::arg(format!("--start-frame {}: the input has {n} frames (0..{last})", self.start_frame)));
        }
        match self.end_frame {
            Some(end) if end <= self.start_frame => {
                Err(CliError::arg(format!("--end-frame {end}: the run stops before this frame, so it must come after --start-frame {}", self.start_frame)))
            }
            Some(end) if end > n => Err(CliError::arg(format!("--end-frame {end}: the input has {n} frames (0..{last}); --end-frame {n} tracks to the last"))),
            Some(end) => Ok(self.start_frame..end),
            None => Ok(self.start_frame..n),
        }
    }

    /// Checks the options that concern the frames against their `(w, h)` size and the
    /// run's `n` frames, naming the option the user gave.
    pub fn check_against(&self, (w, h): (usize, usize), n: usize) -> Result<(), CliError> {
        let inside = |x: f64, y: f64| x <= (w - 1) as f64 && y <= (h - 1) as f64;
        let extent = format!("the {w}x{h} frames (X 0..{}, Y 0..{})", w - 1, h - 1);
        if let Some((x, y, bw, bh)) = self.target_box {
            let (cx, cy) = self.target_point().unwrap_or_default();
            if !inside(cx, cy) {
                return Err(CliError::arg(format!("--target-box {x},{y},{bw},{bh}: its centre ({cx}, {cy}) is outside {extent}")));
            }
        } else if let Some((x, y)) = self.target.filter(|&(x, y)| !inside(x, y)) {
            return Err(CliError::arg(format!("--target {x},{y} is outside {extent}")));
        }
        if let Some(phase) = self.write_phase {
            let clocks = Clocks::camera_timing((w, h)).frame_clocks() as u64;
            if phase >= clocks {
                return Err(CliError::arg(format!("--write-phase {phase}: a {w}x{h} frame has {clocks} clocks (0..{})", clocks - 1)));
            }
        }
        if let Some(r) = self.vcd_frames.as_ref().filter(|r| r.end > n) {
            return Err(CliError::arg(format!("--vcd-frames {}..{}: the run has frames 0..{n} (the end is excluded; counted from --start-frame)", r.start, r.end)));
        }
        Ok(())
    }
}

impl From<InputError> for CliError {
    fn from(e: InputError) -> CliError {
        match e {
            InputError::Video(VideoError::Interrupted) => CliError::interrupted(),
            e @ InputError::Damaged(..) => CliError::new(format!("{e}; --allow-damaged tracks the frames that decode and marks these in the CSV's damaged column")),
            e => CliError::new(e.to_string()),
        }
    }
}

impl From<VideoError> for CliError {
    fn from(e: VideoError) -> CliError {
        CliError::from(InputError::Video(e))
    }
}

impl From<OverlayError> for CliError {
    fn from(e: OverlayError) -> CliError {
        CliError::new(e.to_string())
    }
}

/// The facts of `facts` for the CSV's rows, frames `period` seconds apart where no timestamp
/// says otherwise, the run's frame 0 being the source's `first`.
fn row_info(facts: &RowFacts, period: f64, first: usize) -> FrameInfo<'_> {
    FrameInfo { files: facts.files(), times: facts.times(), damaged: facts.damaged(), period, first }
}

/// A tracking run of `track`'s options: the input opened and checked against them, and the
/// run they ask for. The CLI and the Python package's `track_video` both run it.
pub struct TrackRun {
    /// The frames.
    pub input: Input,
    /// The source's frames tracked.
    pub range: Range<usize>,
    /// The run.
    pub cfg: SystemConfig,
    /// The source's frame rate (`--fps`, or the video's), if known.
    pub fps: Option<f64>,
    /// The box the rows draw around each position.
    pub shape: CsvBox,
    facts: RowFacts,
}

impl TrackRun {
    /// Opens `args`' input (`stop` is asked while a video is scanned) and checks the options
    /// against it.
    pub fn open(args: &TrackArgs, stop: &dyn Fn() -> bool) -> Result<TrackRun, CliError> {
        if matches!(args.hdl, HdlArg::Model) && args.pixel_bits != 8 {
            return Err(CliError::arg("--pixel-bits sets the clocked window units' pixel width: add --hdl rust-hdl or --hdl verilator"));
        }
        let input = Input::open(&args.frames, args.allow_damaged, stop)?;
        let range = args.frame_range(input.len())?;
        args.check_against(input.size(), range.len())?;
        let fps = args.fps.or(input.declared_fps());
        let cfg = args.config(input.size(), fps);
        let facts = RowFacts::of(&input);
        Ok(TrackRun { input, range, cfg, fps, shape: args.csv_box(), facts })
    }

    /// Tracks the frames, handing each frame's record and its CSV row to `on_row` as the
    /// frame ends; with `vcd`, `stop` and `progress`, as [`track_frames`].
    pub fn track(
        &mut self,
        vcd: Option<(&OutFile, Option<Range<usize>>)>,
        stop: &dyn Fn() -> bool,
        progress: &mut dyn FnMut(usize),
        on_row: &mut dyn FnMut(&system::FrameRecord, String),
    ) -> Result<(RunLog, Option<Shared>), CliError> {
        let TrackRun { input, range, cfg, shape, facts, .. } = self;
        let mut all = input.frames()?;
        let mut frames = from_to(&mut all, range.clone())?;
        // The run's frame period, as the run computes it.
        let info = row_info(facts, Clocks::for_frames(&frames, cfg.jitter).period() as f64 / cfg.pixel_clock_hz, range.start);
        track_frames(&mut frames, cfg, vcd, stop, progress, &mut |r| on_row(r, csv::track_row(r, info, *shape)))
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
    let mut run = TrackRun::open(&args, &interrupt::requested)?;
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
    let (log, vcd_stream) = run.track(vcd.as_ref().map(|(v, _)| (v, args.vcd_frames.clone())), &interrupt::requested, &mut progress_line(range.len(), "tracking"), &mut |_, row| {
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
        let mut all = run.input.frames()?;
        let mut frames = from_to(&mut all, range.clone())?;
        let (stream, reduced) = kind.write(o.stream()?, &mut interrupt::Interruptible(&mut frames, &interrupt::requested), painter, run.fps.unwrap_or(1.0 / log.frame_period))?;
        let reduced = reduced.map(|r| format!(" ({r}, to bound the GIF's size; an .mp4 overlay keeps every frame at full size)")).unwrap_or_default();
        done.push((stream, Some(format!("wrote {}{reduced}", o.path.display()))));
    }
    if interrupt::requested() {
        return Err(CliError::interrupted());
    }
    if let Some(v) = vcd_stream {
        v.finish()?;
    }
    for (stream, line) in done {
        stream.finish()?;
        if let Some(l) = line {
            say(l);
        }
    }
    let secs = started.elapsed().as_secs_f64().max(1e-9);
    let tracked = log.frames.iter().filter(|r| r.point.is_some()).count();
    if log.hdl_clocks > 0 {
        say(format!(
            "window units: {} pixel clocks, {:.2} M clocks/s over the run, about {:.0}% of the time in the HDL simulator",
            log.hdl_clocks,
            log.hdl_clocks as f64 / tracking_secs.max(1e-9) / 1e6,
            (100.0 * log.hdl_seconds / tracking_secs.max(1e-9)).min(100.0)
        ));
    }
    let n = log.frames.len();
    say(format!(
        "{n} frames, {tracked} tracked, {} position reports; {:.0} frames/s wall-clock ({secs:.1} s on this machine); simulated: the camera, window units and processors in simulated time, at the source's {:.2} frames/s ({:.2} s of camera time)",
        log.reports.len(),
        n as f64 / secs,
        1.0 / log.frame_period,
        n as f64 * log.frame_period
    ));
    if let Some((k, (x, y))) = log.locked_on {
        say(format!("locked on in frame {}: tracking the object's point at ({x:.1}, {y:.1}) there, the centre of the first motion seen", k + range.start));
    }
    if !(log.losses.is_empty() && log.watchdog.is_empty() && log.refused.is_empty()) {
        say(format!(
            "log: {} losses of track, {} sets written again by the watchdog, {} requests refused",
            log.losses.len(),
            log.watchdog.len(),
            log.refused.len()
        ));
        for (_, clock, why) in log.refused.iter().take(3) {
            say(format!("  refused on clock {clock}: {why}"));
        }
    }
    if let Some(s) = summary {
        say(report::verdict(&s));
        say(report::summary_table(&[(run.cfg.strategy.name(), s)]));
    }
    Ok(())
}

/// The pixel value of a template the run would cut flat at its target (no variance: nothing
/// for NCC to match, as on a clip's black first frame); `None` without a target or where the
/// template has texture.
fn flat_target(frames: &mut dyn FrameSource, cfg: &SystemConfig) -> Result<Option<u8>, CliError> {
    let Some((x, y)) = cfg.target else { return Ok(None) };
    let (w, h) = frames.size();
    let frame0 = frames.frame(0).map_err(|e| CliError::new(e.to_string()))?;
    let view = WindowView::packed(frame0, w, h).map_err(|e| CliError::new(format!("the first frame: {e}")))?;
    let at = Point { x: x as f32, y: y as f32 };
    let Some(tpl) = Template::capture(&view, at, usize::from(cfg.params.template)) else { return Ok(None) };
    let Some(tv) = tpl.view() else { return Ok(None) };
    let mut px = (0..tv.height()).filter_map(|r| tv.row(r)).flatten().copied();
    let value = px.next();
    Ok(value.filter(|&v| px.all(|p| p == v)))
}

/// `frames`' frames `range` (checked by [`TrackArgs::frame_range`]).
fn from_to<'a>(frames: &'a mut dyn FrameSource, range: Range<usize>) -> Result<Skip<'a>, CliError> {
    let n = frames.len();
    Skip::new(frames, range.clone()).ok_or_else(|| CliError::new(format!("internal: frames {}..{} of {n}", range.start, range.end)))
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

/// Tracks `frames` until `stop` says to (the run then ends with `FrameError::Interrupted`),
/// calling `progress(k)` at each frame's start and handing each frame's record to
/// `on_record` as the frame ends; with `vcd`, every window unit is traced into it,
/// for the frames in its range (all without), and its stream is returned for the caller to
/// finish. A target on a flat template is refused before the run.
pub fn track_frames(
    frames: &mut dyn FrameSource,
    cfg: &SystemConfig,
    vcd: Option<(&OutFile, Option<Range<usize>>)>,
    stop: &dyn Fn() -> bool,
    progress: &mut dyn FnMut(usize),
    on_record: &mut dyn FnMut(&system::FrameRecord),
) -> Result<(RunLog, Option<Shared>), CliError> {
    let (w, h) = frames.size();
    if let (Some(value), Some((x, y))) = (flat_target(frames, cfg)?, cfg.target) {
        let n = cfg.params.template;
        return Err(CliError::new(format!(
            "the {n}x{n} template around the target ({x}, {y}) is flat on the first frame tracked (every pixel {value}): there is nothing there to track. A clip that opens on black or blank frames: --start-frame N starts on the frame the target is on"
        )));
    }
    let n = frames.len();
    let mut stream = None;
    let trace = match vcd {
        Some((out, range)) => {
            let range = range.unwrap_or(0..n);
            // Measured on 2026-12-01: 455 MB for 4 frames of 256x256 with COOP's 4 units, so
            // about 110 MB a frame, in proportion to the pixels and the units.
            let mb = 110.0 * (w * h) as f64 / 65_536.0 * cfg.strategy.units() as f64 / 4.0;
            if range.len() > 4 {
                eprintln!(
                    "warning: --vcd traces {} frames, about {:.0} MB each ({:.1} GB); --vcd-frames FIRST..END traces fewer",
                    range.len(),
                    mb,
                    mb * range.len() as f64 / 1000.0
                );
            }
            let shared = out.stream()?.shared();
            stream = Some(shared.clone());
            Some(Trace { out: Box::new(shared), frames: range })
        }
        None => None,
    };
    let log = system::simulate_traced(cfg, &mut interrupt::Interruptible(frames, stop), progress, on_record, trace)?;
    Ok((log, stream))
}
