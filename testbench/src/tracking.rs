//! A tracking run of `coopwin track`'s options: the options checked against the input, the
//! run's configuration made from them, and the run. The CLI's `track` (which parses the
//! options and writes and prints the results) and the Python package's `Tracker` and
//! `track_video` all run it, so they check alike and give the same rows.
use crate::frames::binned::{self, Binned};
use crate::frames::input::{Input, InputError, RowFacts};
use crate::frames::video::VideoError;
use crate::frames::{FrameError, FrameSource, Interruptible, Skip};
use crate::report::csv::{self, CsvBox, FrameInfo};
use crate::system::cost::CostModel;
use crate::system::{self, CoopPolicy, FrameRecord, MpdfWatch, RunLog, SimError, Strategy, SystemConfig};
use crate::units::clocked::Trace;
use crate::units::clocks::Clocks;
use crate::units::UnitBackend;
use coopwin_firmware::kernels::view::WindowView;
use coopwin_firmware::processors::template::Template;
use coopwin_firmware::processors::Params;
use coopwin_firmware::types::Point;
use coopwin_hdl::sim::camera::Jitter;
use std::ops::Range;
use std::path::Path;

/// What to track.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Target {
    /// The first motion seen (MPDF's lock-on).
    Motion,
    /// A point (pixel centres at integers).
    Point(f64, f64),
    /// A box X,Y,W,H (OpenCV's convention: columns X..X+W-1), tracked by its centre.
    Box(u32, u32, u32, u32),
}

/// A run's options, as `coopwin track` takes them (its `--help` says what each does); the
/// messages of [`TrackError::Option`] name the options as the CLI spells them.
#[derive(Clone, Debug)]
pub struct TrackOptions {
    /// `--strategy`.
    pub strategy: Strategy,
    /// `--template`: the template side (in the binned frames' pixels), else the box's shorter
    /// side binned (up to 32) or 20.
    pub template: Option<u16>,
    /// `--bin`: the camera's binning, else chosen from the box.
    pub bin: Option<usize>,
    /// `--target` or `--target-box`.
    pub target: Target,
    /// `--start-frame`.
    pub start_frame: usize,
    /// `--end-frame`.
    pub end_frame: Option<usize>,
    /// `--fps`.
    pub fps: Option<f64>,
    /// `--search`.
    pub search: u16,
    /// `--fixed-template`.
    pub fixed_template: bool,
    /// `--profile`.
    pub cost: CostModel,
    /// `--watch`.
    pub watch: MpdfWatch,
    /// `--coop-n`.
    pub coop_n: usize,
    /// `--policy`.
    pub policy: CoopPolicy,
    /// `--allow-damaged`.
    pub allow_damaged: bool,
    /// `--hdl`.
    pub backend: UnitBackend,
    /// `--pixel-bits`.
    pub pixel_bits: usize,
    /// `--vcd-frames`.
    pub vcd_frames: Option<Range<usize>>,
    /// `--blank-jitter`.
    pub jitter: Option<Jitter>,
    /// `--write-phase`.
    pub write_phase: Option<u64>,
}

/// Why a run cannot be made or did not finish.
#[derive(Debug)]
pub enum TrackError {
    /// An option that cannot be used (with this input): the message names it.
    Option(String),
    /// The input cannot be opened.
    Input(InputError),
    /// A frame could not be read.
    Frame(FrameError),
    /// The run failed.
    Run(SimError),
    /// The target's template is flat on the first frame tracked.
    FlatTarget {
        /// The template's side, in the frames' pixels (binned: the binned side times K).
        side: u16,
        /// The target.
        at: (f64, f64),
        /// Every pixel's value.
        value: u8,
    },
    /// The first frame cannot be viewed as windows are.
    FirstFrame(String),
}

wrap_errors!(TrackError { Input(InputError), Frame(FrameError), Run(SimError) });

impl From<VideoError> for TrackError {
    fn from(e: VideoError) -> TrackError {
        TrackError::Input(InputError::Video(e))
    }
}

impl std::fmt::Display for TrackError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TrackError::Option(m) => f.write_str(m),
            TrackError::Input(e @ InputError::Damaged(..)) => write!(f, "{e}; --allow-damaged tracks the frames that decode and marks these in the CSV's damaged column"),
            TrackError::Input(e) => e.fmt(f),
            TrackError::Frame(e) => e.fmt(f),
            TrackError::Run(e) => e.fmt(f),
            TrackError::FlatTarget { side: n, at: (x, y), value } => write!(
                f,
                "the {n}x{n} template around the target ({x}, {y}) is flat on the first frame tracked (every pixel {value}): there is nothing there to track. A clip that opens on black or blank frames: --start-frame N starts on the frame the target is on"
            ),
            TrackError::FirstFrame(e) => write!(f, "the first frame: {e}"),
        }
    }
}

impl std::error::Error for TrackError {}

impl TrackError {
    /// True when the user stopped the run (Ctrl-C, or the Python caller gone).
    pub fn interrupted(&self) -> bool {
        matches!(self, TrackError::Input(InputError::Video(VideoError::Interrupted)))
    }
}

impl TrackOptions {
    /// The camera's binning on frames of `size`: `--bin`; else, for a `--target-box` whose
    /// template is not given, the largest that keeps the box 22 px across and 32 along
    /// ([`binned::factor_for_box`]); else 1.
    pub fn bin(&self, size: (usize, usize)) -> usize {
        match (self.bin, self.template, self.target) {
            (Some(k), ..) => k,
            (None, None, Target::Box(_, _, w, h)) => binned::factor_for_box((w, h), size),
            _ => 1,
        }
    }

    /// The template side on frames binned `k` x `k`: `--template`, the target box's shorter
    /// side binned (at most 32), or 20.
    fn template_side(&self, k: usize) -> u16 {
        match (self.template, self.target) {
            (Some(n), _) => n,
            (None, Target::Box(_, _, w, h)) => binned::box_template((w, h), k),
            (None, _) => 20,
        }
    }

    /// The notes on a `--target-box` on frames of `size`: the frames binned for it, and a box
    /// the template does not cover (the track follows the part of the object under the
    /// template, not the whole box).
    pub fn box_notes(&self, size: (usize, usize)) -> Vec<String> {
        let Target::Box(x, y, w, h) = self.target else { return Vec::new() };
        let k = self.bin(size);
        let n = u32::from(self.template_side(k));
        let span = n * k as u32;
        let binned = (k > 1).then(|| {
            format!("note: the frames are binned {k}x{k} for --target-box {x},{y},{w},{h} (each pixel the mean of a {k}x{k} block, as a sensor bins; --bin 1 tracks them unbinned): its {n}x{n} template spans {span}x{span} of the frames' pixels, and the CSV's positions are in the frames' pixels")
        });
        let larger = (w > span || h > span).then(|| {
            format!("note: --target-box {x},{y},{w},{h} is larger than the {span}x{span} template cut at its centre: that part of the object is tracked (and vouched for), not the whole box, and it is the box's centre that the CSV reports")
        });
        binned.into_iter().chain(larger).collect()
    }

    /// The point to track: the point, or the box's centre.
    fn target_point(&self) -> Option<(f64, f64)> {
        match self.target {
            Target::Motion => None,
            Target::Point(x, y) => Some((x, y)),
            Target::Box(x, y, w, h) => Some((f64::from(x) + (f64::from(w) - 1.0) / 2.0, f64::from(y) + (f64::from(h) - 1.0) / 2.0)),
        }
    }

    /// The box the CSV and the overlay draw around each position on frames of `size`.
    pub fn csv_box(&self, size: (usize, usize)) -> CsvBox {
        let k = self.bin(size);
        let n = usize::from(self.template_side(k)) * k;
        let size = match self.target {
            Target::Box(_, _, w, h) => (w as usize, h as usize),
            _ => (n, n),
        };
        let p = self.params(k);
        CsvBox { size, acceptance: p.correlation(p.adapt).1 }
    }

    /// The processors' parameters on frames binned `k` x `k`: the template side, the search
    /// margin, and the template adapting unless kept fixed. Only guarded cooperation adapts
    /// it: SSE's and Kalman's deciders weigh positions measured against the first template's
    /// look.
    fn params(&self, k: usize) -> Params {
        let n = self.template_side(k);
        let p = Params { target_boxed: matches!(self.target, Target::Box(..)), ..Params::sized(n, self.search) };
        if self.fixed_template || self.policy != CoopPolicy::Guarded {
            p
        } else {
            p.adaptive()
        }
    }

    /// The run the options ask for on frames of `size` from a source of `fps` frames per
    /// second (the pixel clock that gives this rate with the camera's blanking), if known.
    pub fn config(&self, size: (usize, usize), fps: Option<f64>) -> SystemConfig {
        let k = self.bin(size);
        let cfg = SystemConfig {
            params: self.params(k),
            bin: k,
            coop_n: self.coop_n,
            target: self.target_point(),
            backend: self.backend,
            unit_pixel_bits: self.pixel_bits,
            policy: self.policy,
            mpdf_watch: self.watch,
            jitter: self.jitter,
            write_phase: self.write_phase,
            ..SystemConfig::thesis(self.strategy, self.cost, None)
        };
        match fps {
            Some(fps) => SystemConfig { pixel_clock_hz: Clocks::camera_timing(size).frame_clocks() as f64 * fps, ..cfg },
            None => cfg,
        }
    }

    /// The source's frames to track: `--start-frame` up to `--end-frame` (excluded), checked
    /// against the input's `n` frames.
    fn frame_range(&self, n: usize) -> Result<Range<usize>, TrackError> {
        let last = n.saturating_sub(1);
        let bad = |m: String| Err(TrackError::Option(m));
        if self.start_frame >= n {
            return bad(format!("--start-frame {}: the input has {n} frames (0..{last})", self.start_frame));
        }
        match self.end_frame {
            Some(end) if end <= self.start_frame => bad(format!("--end-frame {end}: the run stops before this frame, so it must come after --start-frame {}", self.start_frame)),
            Some(end) if end > n => bad(format!("--end-frame {end}: the input has {n} frames (0..{last}); --end-frame {n} tracks to the last")),
            Some(end) => Ok(self.start_frame..end),
            None => Ok(self.start_frame..n),
        }
    }

    /// Checks the options that concern the frames against their `(w, h)` size and the
    /// run's `n` frames, naming the option the user gave.
    pub fn check_against(&self, (w, h): (usize, usize), n: usize) -> Result<(), TrackError> {
        let bad = |m: String| Err(TrackError::Option(m));
        let k = self.bin((w, h));
        let (kw, kh) = binned::binned_size((w, h), k);
        if kw < binned::MIN_SIDE || kh < binned::MIN_SIDE {
            return bad(format!("--bin {k}: the {w}x{h} frames binned {k}x{k} are {kw}x{kh}, under the least frame, {0}x{0}", binned::MIN_SIDE));
        }
        // Binning drops the right and bottom columns and rows that make no whole block.
        let (uw, uh) = (kw * k, kh * k);
        let inside = |x: f64, y: f64| x <= (uw - 1) as f64 && y <= (uh - 1) as f64;
        let blocks = if k > 1 { format!(" binned {k}x{k}") } else { String::new() };
        let extent = format!("the {w}x{h} frames{blocks} (X 0..{}, Y 0..{})", uw - 1, uh - 1);
        match self.target {
            Target::Box(x, y, bw, bh) => {
                let (cx, cy) = self.target_point().unwrap_or_default();
                if !inside(cx, cy) {
                    return bad(format!("--target-box {x},{y},{bw},{bh}: its centre ({cx}, {cy}) is outside {extent}"));
                }
            }
            Target::Point(x, y) if !inside(x, y) => return bad(format!("--target {x},{y} is outside {extent}")),
            _ => {}
        }
        if let (Target::Box(_, _, bw, bh), n @ 0..=3) = (self.target, self.template_side(k)) {
            return bad(format!("--bin {k}: the --target-box's {bw}x{bh} binned {k}x{k} leaves a {n}x{n} template, under the least (4x4): a smaller --bin, or --template"));
        }
        if let Some(phase) = self.write_phase {
            let clocks = Clocks::camera_timing((kw, kh)).frame_clocks() as u64;
            if phase >= clocks {
                let binned = if k > 1 { format!(" (the frames binned {k}x{k})") } else { String::new() };
                return bad(format!("--write-phase {phase}: a {kw}x{kh} frame{binned} has {clocks} clocks (0..{})", clocks - 1));
            }
        }
        if let Some(r) = self.vcd_frames.as_ref().filter(|r| r.end > n) {
            return bad(format!("--vcd-frames {}..{}: the run has frames 0..{n} (the end is excluded; counted from --start-frame)", r.start, r.end));
        }
        Ok(())
    }
}

/// The facts of `facts` for the CSV's rows, frames `period` seconds apart where no timestamp
/// says otherwise, the run's frame 0 being the source's `first`.
fn row_info(facts: &RowFacts, period: f64, first: usize) -> FrameInfo<'_> {
    FrameInfo { files: facts.files(), times: facts.times(), damaged: facts.damaged(), period, first }
}

/// A tracking run: the input opened and checked against the options, and the run they ask for.
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
    /// Opens the frames at `path` (`stop` is asked while a video is scanned) and checks the
    /// options against them.
    pub fn open(path: &Path, options: &TrackOptions, stop: &dyn Fn() -> bool) -> Result<TrackRun, TrackError> {
        if options.backend == UnitBackend::BehaviouralModel && options.pixel_bits != 8 {
            return Err(TrackError::Option("--pixel-bits sets the clocked window units' pixel width: add --hdl rust-hdl or --hdl verilator".into()));
        }
        let input = Input::open(path, options.allow_damaged, stop)?;
        let range = options.frame_range(input.len())?;
        options.check_against(input.size(), range.len())?;
        let fps = options.fps.or(input.declared_fps());
        let cfg = options.config(input.size(), fps);
        let facts = RowFacts::of(&input);
        let shape = options.csv_box(input.size());
        Ok(TrackRun { input, range, cfg, fps, shape, facts })
    }

    /// Tracks the frames, handing each frame's record and its CSV row to `on_row` as the
    /// frame ends; with `vcd`, `stop` and `progress`, as [`track_frames`].
    pub fn track(
        &mut self,
        vcd: Option<Trace>,
        stop: &dyn Fn() -> bool,
        progress: &mut dyn FnMut(usize),
        on_row: &mut dyn FnMut(&FrameRecord, String),
    ) -> Result<RunLog, TrackError> {
        let mut all = self.input.frames()?;
        let mut frames = tracked(&mut all, self.range.clone())?;
        let period = self.cfg.frame_period(&frames);
        let info = row_info(&self.facts, period, self.range.start);
        let shape = self.shape;
        track_frames(&mut frames, &self.cfg, vcd, stop, progress, &mut |r| on_row(r, csv::track_row(r, info, shape)))
    }
}

/// `all`'s frames `range`, the run's (checked when the run was opened): for the run, and for
/// a second pass over its frames such as an overlay's.
pub fn tracked(all: &mut dyn FrameSource, range: Range<usize>) -> Result<Skip<'_>, TrackError> {
    let n = all.len();
    Skip::new(all, range).ok_or(TrackError::Frame(FrameError::Missing(n)))
}

/// The pixel value of a template the run would cut flat at its target (no variance: nothing
/// for NCC to match, as on a clip's black first frame); `None` without a target or where the
/// template has texture.
fn flat_target(frames: &mut dyn FrameSource, cfg: &SystemConfig) -> Result<Option<u8>, TrackError> {
    let Some(target) = cfg.target else { return Ok(None) };
    let (x, y) = binned::to_binned(target, cfg.bin);
    let mut frames = Binned::new(frames, cfg.bin);
    let (w, h) = frames.size();
    let frame0 = frames.frame(0)?;
    let view = WindowView::packed(frame0, w, h).map_err(|e| TrackError::FirstFrame(e.to_string()))?;
    let at = Point { x: x as f32, y: y as f32 };
    let Some(tpl) = Template::capture(&view, at, usize::from(cfg.params.template)) else { return Ok(None) };
    let Some(tv) = tpl.view() else { return Ok(None) };
    let mut px = (0..tv.height()).filter_map(|r| tv.row(r)).flatten().copied();
    let value = px.next();
    Ok(value.filter(|&v| px.all(|p| p == v)))
}

/// Tracks `frames` until `stop` says to (the run then ends with `FrameError::Interrupted`),
/// calling `progress(k)` at each frame's start and handing each frame's record to
/// `on_record` as the frame ends; with `vcd`, every window unit is traced into it (its
/// frames counted from the run's first). A target on a flat template is refused before the run.
pub fn track_frames(
    frames: &mut dyn FrameSource,
    cfg: &SystemConfig,
    vcd: Option<Trace>,
    stop: &dyn Fn() -> bool,
    progress: &mut dyn FnMut(usize),
    on_record: &mut dyn FnMut(&FrameRecord),
) -> Result<RunLog, TrackError> {
    if let (Some(value), Some(at)) = (flat_target(frames, cfg)?, cfg.target) {
        return Err(TrackError::FlatTarget { side: cfg.params.template * cfg.bin as u16, at, value });
    }
    Ok(system::simulate_traced(cfg, &mut Interruptible(frames, stop), progress, on_record, vcd)?)
}

/// A VCD's megabytes a frame of `size` with `units` window units: measured on 2026-12-01,
/// 455 MB for 4 frames of 256x256 with COOP's 4 units, so about 110 MB a frame, in
/// proportion to the pixels and the units.
pub fn vcd_megabytes_a_frame(size: (usize, usize), units: usize) -> f64 {
    110.0 * (size.0 * size.1) as f64 / 65_536.0 * units as f64 / 4.0
}
