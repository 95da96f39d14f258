//! `coopwin track`: tracks a folder of PNG frames with a windowing strategy in simulated time
//! (thesis 2.3-2.5, 4.2), writes the per-frame CSV (and, with rust-hdl units, a VCD and its
//! requests CSV), and prints the summary against `groundtruth.csv` when the folder has one.
use super::args::{self, HdlArg, PolicyArg, ProfileArg, StrategyArg};
use super::output::OutFile;
use super::CliError;
use crate::analysis::audit::requests;
use crate::analysis::metrics::{self, Summary};
use crate::frames::folder::FolderFrames;
use crate::frames::{groundtruth, FrameSource};
use crate::report::{self, csv};
use crate::system::{self, RunLog, SystemConfig};
use crate::units::clocked::Trace;
use crate::units::clocks::Clocks;
use coopwin_hdl::sim::camera::Jitter;
use std::io::IsTerminal;
use std::ops::Range;
use std::path::{Path, PathBuf};

/// `coopwin track`'s options.
#[derive(clap::Args)]
pub struct TrackArgs {
    /// Folder of PNG frames (8-bit gray or colour, 64x64 to 1024x1024, one size)
    #[arg(long)]
    pub frames: PathBuf,
    /// Windowing strategy
    #[arg(long, value_enum, default_value_t = StrategyArg::Coop)]
    pub strategy: StrategyArg,
    /// Template side N (4..32)
    #[arg(long, default_value_t = 20, value_parser = args::parse_in::<u16>(4, 32, "a template side"))]
    pub template: u16,
    /// Point to track as X,Y (pixel centres at integers); default: lock on to motion
    #[arg(long, value_parser = args::parse_point, allow_hyphen_values = true)]
    pub target: Option<(f64, f64)>,
    /// Processor speeds: the thesis's C40, or our kernels on this machine
    #[arg(long, value_enum, default_value_t = ProfileArg::C40)]
    pub profile: ProfileArg,
    /// COOP's confidence data set size n (3..8)
    #[arg(long, default_value_t = 4, value_parser = args::parse_in::<usize>(3, 8, "a data set size"))]
    pub coop_n: usize,
    /// COOP's decision: guarded cooperation, the thesis's least-squares SSE (4.3), or a
    /// Kalman filter (5.2)
    #[arg(long, value_enum, default_value_t = PolicyArg::Guarded)]
    pub policy: PolicyArg,
    /// CSV to write (frame,x,y,mode,source,measured_frame,file); - for standard output
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print the frames in the order they are tracked (frame,file) and stop
    #[arg(long)]
    pub list: bool,
    /// Window units: the behavioural model, the rust-hdl blocks, or the Verilog in Verilator
    #[arg(long, value_enum, default_value_t = HdlArg::Model)]
    pub hdl: HdlArg,
    /// With --hdl rust-hdl: a VCD of every window unit's signals (uut$0, uut$1, ...), and
    /// FILE.requests.csv beside it for `coopwin audit`
    #[arg(long, value_name = "FILE")]
    pub vcd: Option<PathBuf>,
    /// With --vcd: trace only frames FIRST up to END (END excluded), e.g. 10..12
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
    /// The run the options ask for.
    fn config(&self) -> SystemConfig {
        SystemConfig {
            params: coopwin_firmware::processors::Params { template: self.template, foveal: self.template + 4, ..Default::default() },
            coop_n: self.coop_n,
            target: self.target,
            backend: self.hdl.into(),
            policy: self.policy.into(),
            jitter: self.blank_jitter,
            write_phase: self.write_phase,
            ..SystemConfig::thesis(self.strategy.into(), self.profile.into(), None)
        }
    }
}

/// Tracks the folder, writes the outputs asked for and prints the report (on standard error
/// when the CSV goes to standard output).
pub fn track_folder(args: TrackArgs) -> Result<(), CliError> {
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
    // With the CSV on standard output, the report goes to standard error.
    let to_stdout = out.as_ref().is_some_and(OutFile::is_stdout);
    let say = |line: String| if to_stdout { eprintln!("{line}") } else { println!("{line}") };
    let cfg = args.config();
    let started = std::time::Instant::now();
    let (log, summary, names) = track_frames(&args.frames, &cfg, vcd.as_ref().map(|(v, _)| (v, args.vcd_frames.clone())))?;
    let secs = started.elapsed().as_secs_f64();
    if let Some(o) = &out {
        o.write(csv::track_csv(&log.frames, Some(&names)).as_bytes())?;
        if !to_stdout {
            say(format!("wrote {}", o.path.display()));
        }
    }
    if let Some((v, req)) = &vcd {
        req.write(requests::to_csv(&log).as_bytes())?;
        say(format!("wrote {} and {} (every unit; check one with `coopwin audit --unit K`)", v.path.display(), req.path.display()));
    }
    let tracked = log.frames.iter().filter(|r| r.point.is_some()).count();
    if log.hdl_clocks > 0 {
        say(format!(
            "window units: {} pixel clocks, {:.2} M clocks/s over the run, about {:.0}% of the time in the HDL simulator",
            log.hdl_clocks,
            log.hdl_clocks as f64 / secs.max(1e-9) / 1e6,
            (100.0 * log.hdl_seconds / secs.max(1e-9)).min(100.0)
        ));
    }
    say(format!(
        "{} frames, {} tracked, {} position reports, {:.0} frames/s simulated",
        log.frames.len(),
        tracked,
        log.reports.len(),
        log.frames.len() as f64 / secs.max(1e-9)
    ));
    if let Some((k, (x, y))) = log.locked_on {
        say(format!("locked on in frame {k}: tracking the object's point at ({x:.1}, {y:.1}) there, the centre of the first motion seen"));
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
        say(report::summary_table(&[(cfg.strategy.name(), s)]));
    }
    Ok(())
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

/// Tracks the frames in `dir`; returns the run, its summary (against `groundtruth.csv`
/// when the folder has one) and the frames' file names.
/// With `vcd`, every window unit is traced into it, for the frames in its range (all without).
/// The target, the traced range and the write phase are checked against the frames before
/// the run (bad ones are argument errors).
pub fn track_frames(dir: &Path, cfg: &SystemConfig, vcd: Option<(&OutFile, Option<Range<usize>>)>) -> Result<(RunLog, Option<Summary>, Vec<String>), CliError> {
    let mut frames = FolderFrames::open(dir)?;
    let (w, h) = frames.size();
    if let Some((x, y)) = cfg.target {
        if !(x.is_finite() && y.is_finite() && x >= 0.0 && y >= 0.0 && x <= (w - 1) as f64 && y <= (h - 1) as f64) {
            return Err(CliError::arg(format!("--target {x},{y} is outside the {w}x{h} frames (X 0..{}, Y 0..{})", w - 1, h - 1)));
        }
    }
    if let Some(phase) = cfg.write_phase {
        let clocks = Clocks::for_frames(&frames, cfg.jitter).timing.frame_clocks() as u64;
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
                return Err(CliError::arg(format!("--vcd-frames {}..{}: the folder has frames 0..{n} (the end is excluded)", range.start, range.end)));
            }
            let shared = out.stream()?.shared();
            stream = Some(shared.clone());
            Some(Trace { out: Box::new(shared), frames: range })
        }
        None => None,
    };
    let names = frames.names();
    let log = system::simulate_traced(cfg, &mut frames, &mut progress_bar(n, "tracking"), trace)?;
    if let Some(s) = stream {
        s.finish()?;
    }
    let truth_path = dir.join("groundtruth.csv");
    let summary = if truth_path.exists() { Some(metrics::summarise(&log, &groundtruth::read(&truth_path)?)) } else { None };
    Ok((log, summary, names))
}
