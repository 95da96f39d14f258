//! `coopwin`: the cooperative-windowing tracker's command line. Parses the arguments and
//! hands each subcommand to its module under `coopwin_testbench::commands`.
use clap::{Parser, Subcommand};
use coopwin_testbench::commands::{
    audit, corner, experiment, main_job, matching, motion, scene, track, verilog, waves, CliError,
};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(name = "coopwin", version, about = "Cooperative windowing for real-time visual tracking: window logic, firmware and testbench", after_help = EXAMPLES)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

const EXAMPLES: &str = "Examples:
  coopwin verilog --axis --out hdl/verilog     export window_unit.v, window_network.v, window_unit_axis.v, axil_cdc.v
  coopwin waves --out run.vcd                  simulate one acquisition, VCD + Appendix B SVGs
  coopwin waves --out w.vcd --window 10,40,20,50 --frames 2
  coopwin scene --path triangle --speed 100 --frames 300 --lighting ramp --out tri
  coopwin track --frames tri --strategy coop --target 56,56 --out tri.csv
  coopwin track --frames clip.mp4 --target-box 120,80,32,24 --out t.csv --overlay t.gif
  coopwin track --frames clip.mp4 --fps 30 --search 6 --overlay t.mp4   lock on to motion, 30 frames/s
  coopwin scene --path swing --photo --size 640x480 --colour --out mine
  coopwin experiment table-4.1 --out results
  coopwin track --frames tri --strategy coop --target 56,56 --hdl rust-hdl --vcd run.vcd
  coopwin audit run.vcd --requests run.requests.csv
  coopwin track --frames tri --hdl rust-hdl --vcd part.vcd --vcd-frames 100..103
  coopwin track --frames tri --hdl rust-hdl --blank-jitter 40,6000,7 --write-phase 70178
  coopwin match --image window.png --template tpl.png --method ncc
  coopwin corner --image window.png --threshold 50
  coopwin motion --prev a.png --next b.png --threshold 30
  coopwin                                      the main job: COOP on the built-in scene";

const TRACK_EXAMPLES: &str = "Examples:
  coopwin track --frames tri --target 56.32,56.32 --out tri.csv
      a folder of PNG frames (scene writes one), the point to track given
  coopwin track --frames clip.mp4 --target-box 120,80,32,24 --out t.csv --overlay t.gif
      a video (through FFmpeg) at its own frame rate; the box's centre is tracked and the
      CSV gives a 32x24 box, a confidence and an ok flag each frame; t.gif shows the windows
  coopwin track --frames clip.mp4 --fps 30 --search 6 --overlay t.mp4
      no target: lock on to the first motion; a wider Foveal search for fast motion
  coopwin track --frames tri --profile c40 --strategy mpdf
      the thesis's C40 processor timing, as the experiments use it
  coopwin track --frames damaged.mp4 --allow-damaged --out t.csv
      a damaged video (missing data, or pixels the decoder concealed): track what decodes,
      flag the damaged frames
  coopwin track --frames clip.mp4 --start-frame 40 --end-frame 120 --target-box 120,80,32,24
      frames 40 to 119 only (stop before a shot cut at 120)
CSV columns (--out), one row a frame:
  frame                     the source's frame number (as ffprobe -count_frames and OpenCV)
  x, y                      the position, pixel centres at integers: measured, or the
                            estimate (a prediction, or the last position) when not
  mode                      watch, detect or track
  source                    ncc or cd: what measured the position; none
  measured_frame            the frame the position was measured in
  file                      the frame's file name (a folder of PNG frames)
  box_x, box_y, box_w, box_h  the box around the position (OpenCV's convention)
  confidence                the chance the position is the target's: 0.9-1.0 where ok (with
                            NCC's score), 0.6 where not
  ok                        1: a position measured at most 2 frames before that the
                            firmware vouched for (a robot may follow it)
  time_s                    the video's own timestamp, or frame/fps
  damaged                   1: a video frame after missing data, or one the decoder concealed
  state                     tracking, unconfirmed, predicted, searching or lost
  scale, angle_deg          the object's size and turn (degrees, clockwise) against lock-on,
                            where the adapting template measured them (the box keeps
                            the last scale measured on rows without one)
Progress: on a terminal a line redrawn in place; otherwise (a log, a pipe) a line every 5 s
  (COOPWIN_PROGRESS_SECS sets the seconds). The closing line gives the frames/s wall-clock
  on this machine; the run itself is simulated (camera, window units and processors in
  simulated time at the source's frame rate).
Exit codes: 0 done, 1 error (a damaged video too), 2 bad argument (an output that is an
  input too), 130 Ctrl-C (nothing replaced)";

#[derive(Subcommand)]
enum Command {
    /// Export the window logic as Verilog (window_unit.v, window_network.v) for a sensor's size
    #[command(after_help = verilog::VERILOG_EXAMPLES)]
    Verilog(verilog::VerilogArgs),
    /// Simulate window acquisitions in rust-hdl: a VCD and the five Appendix B timing diagrams
    Waves(waves::WavesArgs),
    /// Write a synthetic scene (PNG frames + groundtruth.csv) with a moving textured part
    Scene(scene::SceneArgs),
    /// Track a folder of PNG frames or a video with a windowing strategy, in simulated time
    #[command(after_help = TRACK_EXAMPLES)]
    Track(track::TrackArgs),
    /// Best placement of a template in an image (JSON: x, y, score, subpixel_x, subpixel_y)
    Match(matching::MatchArgs),
    /// The corner detector of chapter 3 on a window image (JSON)
    Corner(corner::CornerArgs),
    /// Image differencing between two frames: the motion area (JSON)
    Motion(motion::MotionArgs),
    /// Check a window unit's VCD against the coordinate sets its processor wrote (Appendix B)
    Audit(audit::AuditArgs),
    /// Reproduce a table or figure of the thesis (CSV, SVG/PNG chart, markdown)
    Experiment(experiment::ExperimentArgs),
}

/// Runs the subcommand (the main job without one).
fn dispatch(command: Option<Command>) -> Result<(), CliError> {
    match command {
        None => main_job::write_report(&PathBuf::from("report")),
        Some(Command::Verilog(args)) => verilog::export(args),
        Some(Command::Waves(args)) => waves::write_waves(args),
        Some(Command::Scene(args)) => scene::write_scene_files(args),
        Some(Command::Track(args)) => track::track_folder(args),
        Some(Command::Match(args)) => matching::print_match(args),
        Some(Command::Corner(args)) => corner::print_corner(args),
        Some(Command::Motion(args)) => motion::print_motion(args),
        Some(Command::Audit(args)) => audit::audit_vcd(args),
        Some(Command::Experiment(args)) => experiment::write_results(args),
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
    match dispatch(cli.command) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}
