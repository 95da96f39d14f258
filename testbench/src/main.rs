//! `coopwin`: the cooperative-windowing tracker's command line.
use clap::{Parser, Subcommand};
use coopwin_testbench::commands::{hardware, kernels, output::OutFile, scene, track, CliError};
use coopwin_testbench::cost::CostModel;
use coopwin_testbench::real_images;
use coopwin_hdl::sim::camera::Jitter;
use coopwin_testbench::system::{CoopPolicy, HdlChoice, Strategy, SystemConfig};
use coopwin_testbench::scene::{PathKind, SceneConfig};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(name = "coopwin", version, about = "Cooperative windowing for real-time visual tracking: window logic, firmware and testbench", after_help = EXAMPLES)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

const EXAMPLES: &str = "Examples:
  coopwin verilog --out hdl/verilog            export window_unit.v and window_network.v
  coopwin waves --out run.vcd                  simulate one acquisition, VCD + Appendix B SVGs
  coopwin waves --out w.vcd --window 10,40,20,50 --frames 2
  coopwin scene --path triangle --speed 100 --frames 300 --lighting ramp --out tri
  coopwin track --frames tri --strategy coop --target 56,56 --out tri.csv
  coopwin experiment table-4.1 --out results
  coopwin track --frames tri --strategy coop --target 56,56 --hdl rust-hdl --vcd run.vcd
  coopwin audit run.vcd --requests run.requests.csv
  coopwin track --frames tri --hdl rust-hdl --vcd part.vcd --vcd-frames 100..103
  coopwin track --frames tri --hdl rust-hdl --blank-jitter 40,6000,7 --write-phase 70177
  coopwin match --image window.png --template tpl.png --method ncc
  coopwin corner --image window.png --threshold 50
  coopwin motion --prev a.png --next b.png --threshold 30
  coopwin                                      the main job: COOP on the built-in scene";

#[derive(Subcommand)]
enum Command {
    /// Export the window logic as Verilog (window_unit.v, window_network.v)
    Verilog {
        /// Folder to write into (created if missing)
        #[arg(long)]
        out: PathBuf,
        /// Window units in window_network
        #[arg(long, default_value_t = coopwin_hdl::verilog::DEFAULT_UNITS)]
        units: usize,
    },
    /// Simulate window acquisitions in rust-hdl: a VCD and the five Appendix B timing diagrams
    Waves {
        /// The VCD to write; the SVGs go beside it as <stem>-b1_<k>.svg
        #[arg(long)]
        out: PathBuf,
        /// Window as XMIN,XMAX,YMIN,YMAX (0-based, inclusive); default the whole frame
        #[arg(long, default_value = "0,255,0,255", value_parser = hardware::parse_window)]
        window: coopwin_hdl::sim::camera::Window,
        /// Frames to acquire, one coordinate set written before each
        #[arg(long, default_value_t = 1)]
        frames: usize,
    },
    /// Write a synthetic scene (PNG frames + groundtruth.csv) with a moving textured part
    Scene {
        /// The target's path: pendulum (Fig. 2.8), triangle (Fig. 3.4), or a swing inside the view
        #[arg(long, value_enum, default_value_t = PathArg::Triangle)]
        path: PathArg,
        /// Target speed in pixels per second
        #[arg(long, default_value_t = 100.0)]
        speed: f64,
        /// Number of frames (at 114 frames/s)
        #[arg(long, default_value_t = 300)]
        frames: usize,
        /// Lighting: constant, or a ~25% brightening over the middle third (Fig. 4.2)
        #[arg(long, value_enum, default_value_t = LightingArg::Constant)]
        lighting: LightingArg,
        /// Static clutter on the background
        #[arg(long)]
        clutter: bool,
        /// A bar occluding the path for a tenth of the run
        #[arg(long)]
        occlusion: bool,
        /// Gaussian noise standard deviation in gray levels
        #[arg(long, default_value_t = 0.0)]
        noise: f64,
        /// Random seed (texture, clutter, noise)
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Real photographs (fixtures/real/) for the part's surface and the background
        #[arg(long)]
        photo: bool,
        /// Output folder
        #[arg(long)]
        out: PathBuf,
        /// Write into a folder that is not empty (the scene's own files are replaced)
        #[arg(long)]
        force: bool,
    },
    /// Track a folder of PNG frames with a windowing strategy, in simulated time
    Track {
        /// Folder of PNG frames (8-bit gray or colour, 64x64 to 1024x1024, one size)
        #[arg(long)]
        frames: PathBuf,
        /// Windowing strategy
        #[arg(long, value_enum, default_value_t = StrategyArg::Coop)]
        strategy: StrategyArg,
        /// Template side N (4..32)
        #[arg(long, default_value_t = 20, value_parser = parse_in::<u16>(4, 32, "a template side"))]
        template: u16,
        /// Point to track as X,Y (pixel centres at integers); default: lock on to motion
        #[arg(long, value_parser = parse_point, allow_hyphen_values = true)]
        target: Option<(f64, f64)>,
        /// Processor speeds: the thesis's C40, or our kernels on this machine
        #[arg(long, value_enum, default_value_t = ProfileArg::C40)]
        profile: ProfileArg,
        /// COOP's confidence data set size n (3..8)
        #[arg(long, default_value_t = 4, value_parser = parse_in::<usize>(3, 8, "a data set size"))]
        coop_n: usize,
        /// COOP's decision: guarded cooperation, the thesis's least-squares SSE (4.3), or a
        /// Kalman filter (5.2)
        #[arg(long, value_enum, default_value_t = PolicyArg::Guarded)]
        policy: PolicyArg,
        /// CSV to write (frame,x,y,mode,source,measured_frame,file); - for standard output
        #[arg(long)]
        out: Option<PathBuf>,
        /// Print the frames in the order they are tracked (frame,file) and stop
        #[arg(long)]
        list: bool,
        /// Window units: the behavioural model, the rust-hdl blocks, or the Verilog in Verilator
        #[arg(long, value_enum, default_value_t = HdlArg::Model)]
        hdl: HdlArg,
        /// With --hdl rust-hdl: a VCD of every window unit's signals (uut$0, uut$1, ...), and
        /// FILE.requests.csv beside it for `coopwin audit`
        #[arg(long, value_name = "FILE")]
        vcd: Option<PathBuf>,
        /// With --vcd: trace only frames FIRST up to END (END excluded), e.g. 10..12
        #[arg(long, value_name = "FIRST..END", value_parser = parse_frames, requires = "vcd", allow_hyphen_values = true)]
        vcd_frames: Option<std::ops::Range<usize>>,
        /// Fault campaign: camera blanking that varies, up to LINE extra clocks before each line
        /// and FRAME after each frame, drawn from SEED (default 1)
        #[arg(long, value_name = "LINE,FRAME[,SEED]", value_parser = parse_jitter, allow_hyphen_values = true)]
        blank_jitter: Option<Jitter>,
        /// Fault campaign: hold every coordinate write until this clock of a frame (from FVAL
        /// rising), e.g. 0 (the FVAL edge) or 40000 (inside a window)
        #[arg(long, value_name = "CLOCK")]
        write_phase: Option<u64>,
    },
    /// Best placement of a template in an image (JSON: x, y, score, subpixel_x, subpixel_y)
    Match {
        /// The search image
        #[arg(long)]
        image: PathBuf,
        /// The template (no larger than the image)
        #[arg(long)]
        template: PathBuf,
        /// Measure: ncc and ssd as in the thesis, sad, or zero-mean ncc
        #[arg(long, value_enum, default_value_t = MethodArg::Ncc)]
        method: MethodArg,
        /// Match at 25% resolution (every other pixel of every other row), as the Peripheral window
        #[arg(long)]
        decimate: bool,
    },
    /// The corner detector of chapter 3 on a window image (JSON)
    Corner {
        /// The window (up to 64x64)
        #[arg(long)]
        image: PathBuf,
        /// Sobel magnitude threshold TH
        #[arg(long, default_value_t = 50, value_parser = clap::value_parser!(u16).range(1..=1442))]
        threshold: u16,
    },
    /// Image differencing between two frames: the motion area (JSON)
    Motion {
        /// Earlier frame
        #[arg(long)]
        prev: PathBuf,
        /// Later frame
        #[arg(long)]
        next: PathBuf,
        /// Difference threshold (a pixel moves when |next - prev| > threshold)
        #[arg(long, default_value_t = 30)]
        threshold: u8,
    },
    /// Check a window unit's VCD against the coordinate sets its processor wrote (Appendix B)
    Audit {
        /// VCD from `coopwin track --hdl rust-hdl --vcd FILE.vcd`
        vcd: PathBuf,
        /// The requests CSV written beside it (FILE.requests.csv)
        #[arg(long)]
        requests: PathBuf,
        /// Which window unit (processor) to audit
        #[arg(long, default_value_t = 0)]
        unit: usize,
    },
    /// Reproduce a table or figure of the thesis (CSV, SVG/PNG chart, markdown)
    Experiment {
        /// table-2.3, fig-2.9, fig-2.10, fig-3.5, fig-3.7, fig-3.10, table-4.1, real-images, or all
        name: String,
        /// Output folder
        #[arg(long)]
        out: PathBuf,
        /// Processor speeds
        #[arg(long, value_enum, default_value_t = ProfileArg::C40)]
        profile: ProfileArg,
        /// Window units: the behavioural model, the rust-hdl blocks, or the Verilog in Verilator
        #[arg(long, value_enum, default_value_t = HdlArg::Model)]
        hdl: HdlArg,
        /// With real-images: also write its sequences (PNG frames + groundtruth.csv) under DIR,
        /// the input of scripts/opencv_real.py
        #[arg(long, value_name = "DIR")]
        sequences: Option<PathBuf>,
    },
}

#[derive(Clone, Copy, PartialEq, clap::ValueEnum)]
enum PolicyArg {
    /// The corner detector only where it measures the tracked point
    Guarded,
    /// The thesis's least-squares SSE (4.3)
    Sse,
    /// A Kalman filter's innovation (5.2)
    Kalman,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum HdlArg {
    Model,
    RustHdl,
    Verilator,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum StrategyArg {
    Spmf,
    Tpdf,
    Mpdf,
    Coop,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum MethodArg {
    Ncc,
    Zncc,
    Ssd,
    Sad,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum ProfileArg {
    C40,
    Native,
}

fn parse_frames(s: &str) -> Result<std::ops::Range<usize>, String> {
    let (a, b) = s.split_once("..").ok_or("expected FIRST..END, e.g. 10..12")?;
    let n = |v: &str| whole::<usize>(v, "a frame number");
    let r = n(a)?..n(b)?;
    if r.start > r.end {
        return Err(format!("the range is reversed (FIRST {} is after END {}); write {}..{}", r.start, r.end, r.end, r.start));
    }
    if r.start == r.end {
        return Err(format!("the range is empty (END is excluded); for frame {0} alone write {0}..{1}", r.start, r.end + 1));
    }
    Ok(r)
}

/// A whole number, with a reason when it is negative or not a number (`what` names it).
fn whole<T: std::str::FromStr>(v: &str, what: &str) -> Result<T, String> {
    let v = v.trim();
    v.parse::<T>().map_err(|_| match v.parse::<f64>() {
        Ok(x) if x < 0.0 => format!("'{v}' is negative ({what})"),
        Ok(x) if x.is_finite() => format!("'{v}' is not a whole number ({what})"),
        Ok(_) => format!("'{v}' is not a number"),
        Err(_) if v.parse::<i128>().is_ok() => format!("'{v}' is too large for {what}"),
        Err(_) => format!("'{v}' is not a number"),
    })
}

/// A whole number in LO..=HI (`what` names it).
fn parse_in<T>(lo: T, hi: T, what: &'static str) -> impl Fn(&str) -> Result<T, String> + Clone + Send + Sync + 'static
where
    T: std::str::FromStr + PartialOrd + std::fmt::Display + Copy + Send + Sync + 'static,
{
    move |s: &str| {
        let v = whole::<T>(s, what).map_err(|e| format!("{e}; expected {lo}..{hi}"))?;
        if v < lo || v > hi {
            return Err(format!("{v} is out of range; expected {lo}..{hi}"));
        }
        Ok(v)
    }
}

fn parse_jitter(s: &str) -> Result<Jitter, String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let n = |v: &str| whole::<u32>(v, "a number of clocks");
    let j = match parts[..] {
        [line, frame] => Jitter { seed: 1, line_max: n(line)?, frame_max: n(frame)? },
        [line, frame, seed] => Jitter {
            seed: whole(seed, "a seed")?,
            line_max: n(line)?,
            frame_max: n(frame)?,
        },
        _ => return Err("expected LINE,FRAME or LINE,FRAME,SEED".into()),
    };
    // Beyond these a frame takes seconds of camera time: a stalled camera, not jitter.
    if j.line_max > 4_096 || j.frame_max > 8_000_000 {
        return Err(format!("at most 4096 clocks a line and 8000000 a frame, got {},{}", j.line_max, j.frame_max));
    }
    Ok(j)
}

fn parse_point(s: &str) -> Result<(f64, f64), String> {
    let (x, y) = s.split_once(',').ok_or("expected X,Y, e.g. 56.3,60")?;
    let p = |v: &str| {
        let v = v.trim();
        match v.parse::<f64>() {
            Ok(x) if !x.is_finite() => Err(format!("'{v}' is not a number")),
            Ok(x) if x < 0.0 => Err(format!("'{v}' is negative; pixel centres start at 0 (the top-left pixel)")),
            // Frames are at most 1024 pixels a side (see `coopwin track --help`).
            Ok(x) if x > (track::SIDES.end() - 1) as f64 => {
                Err(format!("'{v}' is beyond the largest frame (coordinates run 0..{})", track::SIDES.end() - 1))
            }
            Ok(x) => Ok(x),
            Err(_) => Err(format!("'{v}' is not a number")),
        }
    };
    Ok((p(x)?, p(y)?))
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum PathArg {
    Pendulum,
    Triangle,
    Swing,
}

#[derive(Clone, Copy, PartialEq, clap::ValueEnum)]
enum LightingArg {
    Constant,
    Ramp,
}

fn run(cli: Cli) -> Result<(), CliError> {
    match cli.command {
        None => coopwin_testbench::commands::main_job::run(&PathBuf::from("report")),
        Some(Command::Match { image, template, method, decimate }) => {
            use coopwin_firmware::kernels::matching::Method;
            let m = match method {
                MethodArg::Ncc => Method::Ncc,
                MethodArg::Zncc => Method::Zncc,
                MethodArg::Ssd => Method::Ssd,
                MethodArg::Sad => Method::Sad,
            };
            println!("{}", kernels::match_images(&image, &template, m, decimate)?);
            Ok(())
        }
        Some(Command::Audit { vcd, requests, unit }) => {
            use coopwin_testbench::audit;
            let f = std::fs::File::open(&vcd).map_err(|e| coopwin_testbench::commands::io_error("open", &vcd, e))?;
            let samples = audit::read_vcd(std::io::BufReader::new(f), unit).map_err(|e| CliError::new(format!("{}: {e}", vcd.display())))?;
            let text = std::fs::read_to_string(&requests)
                .map_err(|e| coopwin_testbench::commands::io_error("read", &requests, e))?;
            let sets = audit::read_requests(&text, unit).map_err(|e| CliError::new(format!("{}: {e}", requests.display())))?;
            let a = audit::audit(&samples, &sets);
            println!(
                "{} clocks, {} frames, {} sets taken, {} windows verified, {} violations",
                a.clocks,
                a.frames,
                a.sets,
                a.windows,
                a.violations.len()
            );
            for v in &a.violations {
                println!("  {v}");
            }
            if a.windows == 0 {
                Err(CliError::new(format!(
                    "nothing verified: unit {unit} delivered no window in this trace ({} sets taken); audit a busy unit with --unit, or trace frames where unit {unit} works",
                    a.sets
                )))
            } else if a.violations.is_empty() {
                Ok(())
            } else {
                Err(CliError::new(format!("the waveform breaks {} rule(s)", a.violations.len())))
            }
        }
        Some(Command::Corner { image, threshold }) => {
            println!("{}", kernels::corner_image(&image, threshold)?);
            Ok(())
        }
        Some(Command::Motion { prev, next, threshold }) => {
            println!("{}", kernels::motion_images(&prev, &next, threshold)?);
            Ok(())
        }
        Some(Command::Experiment { name, out, profile, hdl, sequences }) => {
            let hdl = match hdl {
                HdlArg::Model => HdlChoice::Model,
                HdlArg::RustHdl => HdlChoice::RustHdl,
                HdlArg::Verilator => HdlChoice::Verilator,
            };
            let cost = match profile {
                ProfileArg::C40 => CostModel::C40,
                ProfileArg::Native => CostModel::NATIVE,
            };
            if let Some(root) = &sequences {
                coopwin_testbench::commands::output::create_folder(root, "--sequences")?;
                real_images::write_sequences(root, &mut |s| eprintln!("  sequence {s}")).map_err(CliError::new)?;
            }
            let real = name == "real-images" || name == "all";
            if !real && !coopwin_testbench::experiments::NAMES.contains(&name.as_str()) {
                return Err(CliError::arg(format!(
                    "unknown experiment '{name}'; expected one of {}, real-images or all",
                    coopwin_testbench::experiments::NAMES.join(", ")
                )));
            }
            coopwin_testbench::commands::output::create_folder(&out, "--out")?;
            let results = OutFile::check(&out.join("results.md"), "--out")?;
            let names: Vec<&str> = match name.as_str() {
                "all" => coopwin_testbench::experiments::NAMES.to_vec(),
                "real-images" => Vec::new(),
                n => vec![n],
            };
            let mut all = String::from("# Experiments\n\n");
            for n in names {
                eprintln!("experiment {n}");
                let o = coopwin_testbench::experiments::run(n, &out, cost, hdl, &mut |s| eprintln!("  {s}"))
                    .map_err(CliError::new)?;
                println!("{}", o.markdown);
                all.push_str(&o.markdown);
            }
            if real {
                eprintln!("experiment real-images");
                let md = real_images::run(&out, &mut |s| eprintln!("  {s}")).map_err(CliError::new)?;
                println!("{md}");
                all.push_str(&md);
            }
            results.write(all.as_bytes())?;
            println!("wrote {}", results.path.display());
            Ok(())
        }
        Some(Command::Verilog { out, units }) => {
            for p in hardware::verilog(&out, units)? {
                println!("wrote {}", p.display());
            }
            Ok(())
        }
        Some(Command::Waves {
            out,
            window,
            frames,
        }) => {
            let svgs = hardware::waves(&out, window, frames)?;
            println!("wrote {}", out.display());
            for p in svgs {
                println!("wrote {}", p.display());
            }
            Ok(())
        }
        Some(Command::Scene { path, speed, frames, lighting, clutter, occlusion, noise, seed, photo, out, force }) => {
            let cfg = SceneConfig {
                path: match path {
                    PathArg::Pendulum => PathKind::Pendulum,
                    PathArg::Triangle => PathKind::Triangle,
                    PathArg::Swing => PathKind::Swing,
                },
                speed,
                frames,
                lighting_ramp: lighting == LightingArg::Ramp,
                clutter,
                occlusion,
                noise,
                seed,
                photo,
                ..SceneConfig::default()
            };
            let n = scene::write_scene(cfg, &out, force)?;
            println!("wrote {n} frames and groundtruth.csv to {}", out.display());
            Ok(())
        }
        Some(Command::Track {
            frames,
            strategy,
            template,
            target,
            profile,
            coop_n,
            policy,
            out,
            list,
            hdl,
            vcd,
            vcd_frames,
            blank_jitter,
            write_phase,
        }) => {
            if list {
                print!("{}", track::FolderFrames::open(&frames)?.listing());
                return Ok(());
            }
            // Outputs are checked before the run, so a bad path costs no tracking time.
            let out = out.map(|p| OutFile::check(&p, "--out")).transpose()?;
            let vcd = match &vcd {
                Some(v) if v.as_os_str() == "-" => {
                    return Err(CliError::arg("--vcd -: the VCD needs a file name (its requests CSV is written beside it)"));
                }
                Some(v) => Some((OutFile::check(v, "--vcd")?, OutFile::check(&v.with_extension("requests.csv"), "--vcd")?)),
                None => None,
            };
            if matches!(hdl, HdlArg::Model) && vcd.is_some() {
                return Err(CliError::arg("--vcd traces the window units' signals: add --hdl rust-hdl"));
            }
            // With the CSV on standard output, the report goes to standard error.
            let to_stdout = out.as_ref().is_some_and(OutFile::is_stdout);
            macro_rules! say {
                ($($t:tt)*) => { if to_stdout { eprintln!($($t)*) } else { println!($($t)*) } };
            }
            let cfg = SystemConfig {
                strategy: match strategy {
                    StrategyArg::Spmf => Strategy::Spmf,
                    StrategyArg::Tpdf => Strategy::Tpdf,
                    StrategyArg::Mpdf => Strategy::Mpdf,
                    StrategyArg::Coop => Strategy::Coop,
                },
                cost: match profile {
                    ProfileArg::C40 => CostModel::C40,
                    ProfileArg::Native => CostModel::NATIVE,
                },
                params: coopwin_firmware::processors::Params {
                    template,
                    foveal: template + 4,
                    ..Default::default()
                },
                coop_n,
                target,
                model: None,
                pixel_clock_hz: coopwin_hdl::sim::camera::CA_D1_PIXEL_CLOCK_HZ,
                hdl: match hdl {
                    HdlArg::Model => HdlChoice::Model,
                    HdlArg::RustHdl => HdlChoice::RustHdl,
                    HdlArg::Verilator => HdlChoice::Verilator,
                },
                policy: match policy {
                    PolicyArg::Guarded => CoopPolicy::Guarded,
                    PolicyArg::Sse => CoopPolicy::Sse,
                    PolicyArg::Kalman => CoopPolicy::Kalman,
                },
                corrupt_request: None,
                drop_window: None,
                jitter: blank_jitter,
                write_phase,
            };
            let started = std::time::Instant::now();
            let (log, summary, names) = track::track(&frames, &cfg, vcd.as_ref().map(|(v, _)| (v, vcd_frames)))?;
            let secs = started.elapsed().as_secs_f64();
            if let Some(o) = &out {
                o.write(track::csv(&log.frames, Some(&names)).as_bytes())?;
                if !to_stdout {
                    say!("wrote {}", o.path.display());
                }
            }
            if let Some((v, req)) = &vcd {
                req.write(track::requests_csv(&log).as_bytes())?;
                say!("wrote {} and {} (every unit; check one with `coopwin audit --unit K`)", v.path.display(), req.path.display());
            }
            let tracked = log.frames.iter().filter(|r| r.point.is_some()).count();
            if log.hdl_clocks > 0 {
                say!(
                    "window units: {} pixel clocks, {:.2} M clocks/s over the run, about {:.0}% of the time in the HDL simulator",
                    log.hdl_clocks,
                    log.hdl_clocks as f64 / secs.max(1e-9) / 1e6,
                    (100.0 * log.hdl_seconds / secs.max(1e-9)).min(100.0)
                );
            }
            say!(
                "{} frames, {} tracked, {} position reports, {:.0} frames/s simulated",
                log.frames.len(),
                tracked,
                log.reports.len(),
                log.frames.len() as f64 / secs.max(1e-9)
            );
            if let Some((k, (x, y))) = log.locked_on {
                say!("locked on in frame {k}: tracking the object's point at ({x:.1}, {y:.1}) there, the centre of the first motion seen");
            }
            if !(log.losses.is_empty() && log.watchdog.is_empty() && log.refused.is_empty()) {
                say!(
                    "log: {} losses of track, {} sets written again by the watchdog, {} requests refused",
                    log.losses.len(),
                    log.watchdog.len(),
                    log.refused.len()
                );
                for (_, clock, why) in log.refused.iter().take(3) {
                    say!("  refused on clock {clock}: {why}");
                }
            }
            if let Some(s) = summary {
                say!("{}", coopwin_testbench::report::verdict(&s));
                say!("{}", coopwin_testbench::report::summary_table(&[(cfg.strategy.name(), s)]));
            }
            Ok(())
        }
    }
}

/// The command line, with negative numbers taken as values (so `--threshold -5` is refused
/// for being negative, not read as an unknown option).
fn command() -> clap::Command {
    use clap::CommandFactory;
    let mut cmd = Cli::command();
    let names: Vec<String> = cmd.get_subcommands().map(|s| s.get_name().to_string()).collect();
    for n in names {
        cmd = cmd.mut_subcommand(n, |s| s.allow_negative_numbers(true));
    }
    cmd
}

/// A clap error as one line: its first paragraph, with a pointer to --help.
fn one_line(e: &clap::Error) -> String {
    let text = e.render().to_string();
    let first = text.split("\n\n").next().unwrap_or("").lines().map(str::trim).collect::<Vec<_>>().join(" ");
    let first = first.strip_prefix("error: ").unwrap_or(&first);
    // A negative value for an unsigned option: say so rather than "invalid digit".
    let negative = e.get(clap::error::ContextKind::InvalidValue).is_some_and(|v| v.to_string().starts_with('-'));
    let first = match first.strip_suffix("invalid digit found in string") {
        Some(head) if negative => format!("{head}a negative number is not allowed here"),
        _ => first.to_string(),
    };
    format!("{first} (see --help)")
}

/// A closed pipe (`coopwin ... | head`) ends the program quietly, as it does other Unix
/// tools; Rust ignores SIGPIPE, which turns the next `println!` into a panic.
fn default_sigpipe() {
    // SAFETY: sets a signal's disposition to the default, before any other thread exists.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

fn main() -> ExitCode {
    use clap::FromArgMatches;
    default_sigpipe();
    let cli = match command().try_get_matches().and_then(|m| Cli::from_arg_matches(&m)) {
        Ok(cli) => cli,
        Err(e) if matches!(e.kind(), clap::error::ErrorKind::DisplayHelp | clap::error::ErrorKind::DisplayVersion) => e.exit(),
        Err(e) if e.kind() == clap::error::ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => e.exit(),
        Err(e) => {
            eprintln!("error: {}", one_line(&e));
            return ExitCode::from(2);
        }
    };
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}
