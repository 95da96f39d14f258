//! `coopwin track`: its options in, one tracking run ([`crate::tracking`]) out, written to
//! the files asked for ([`super::track_files`]: the per-frame CSV, a VCD, an overlay), and the
//! report printed, with the summary against `groundtruth.csv` when the folder has one.
use super::args::{self, HdlArg, PolicyArg, ProfileArg, StrategyArg, WatchArg};
use super::progress::progress_line;
use super::track_files::TrackFiles;
use super::{interrupt, CliError};
use crate::analysis::metrics;
use crate::frames::binned;
use crate::frames::folder::FolderFrames;
use crate::frames::groundtruth;
use crate::report::overlay::OverlayError;
use crate::report::{self, csv};
use crate::tracking::{Target, TrackError, TrackOptions, TrackRun};
use coopwin_hdl::sim::camera::Jitter;
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
    /// Template side N (4..32) [default: 20, or the --target-box's shorter side (binned, see
    /// --bin) up to 32]
    #[arg(long, value_parser = args::parse_in::<u16>(4, 32, "a template side"))]
    pub template: Option<u16>,
    /// Bin the frames K x K before the window units (each pixel the mean of a K x K block, as
    /// a sensor bins; 1..8), so that the template covers more of an object larger than it;
    /// the CSV's positions and the frame rate stay the frames', --template and --search are
    /// in the binned frames' pixels, --blank-jitter and --write-phase in their raster's clocks
    /// [default: for a --target-box without --template, the largest K at which the box
    /// binned is still 22 px across and 32 along (a 44x80 person: 2; 85x146 at 1080p: 3),
    /// else 1]
    #[arg(long, value_name = "K", value_parser = args::parse_in::<usize>(1, binned::MAX_BIN, "a binning"))]
    pub bin: Option<usize>,
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
            bin: self.bin,
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
    let files = TrackFiles::check(&args)?;
    let to_stdout = files.csv_to_stdout();
    let say = |line: String| if to_stdout { eprintln!("{line}") } else { println!("{line}") };
    let options = args.options();
    let mut run = TrackRun::open(&args.frames, &options, &interrupt::requested)?;
    if let Some(damage) = run.input.damage() {
        eprintln!("warning: {}: {damage}", args.frames.display());
    }
    let range = run.range.clone();
    let truth_path = args.frames.join("groundtruth.csv");
    let truth = if args.frames.is_dir() && truth_path.exists() { Some(groundtruth::read(&truth_path)?) } else { None };
    let truth = truth.map(|t| t.get(range.clone()).unwrap_or_default().to_vec());
    let started = std::time::Instant::now();
    let done = files.track(&mut run, args.vcd_frames.clone(), truth.as_deref(), &mut progress_line(range.len(), "tracking"))?;
    let log = done.log;
    done.written.into_iter().for_each(say);
    for line in report::run_lines(&log, started.elapsed().as_secs_f64(), done.tracking_secs, range.start) {
        say(line);
    }
    // After the run: a run that fails says so in one line.
    for note in options.box_notes(run.input.size()) {
        eprintln!("{note}");
    }
    if let Some(t) = &truth {
        let s = metrics::summarise(&log, t);
        say(report::verdict(&s));
        say(report::summary_table(&[(run.cfg.strategy.name(), s)]));
    }
    Ok(())
}
