//! `coopwin`: the cooperative-windowing tracker's command line.
use clap::{Parser, Subcommand};
use coopwin_testbench::commands::{hardware, CliError};
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
  coopwin waves --out waves/run.vcd            simulate one acquisition, VCD + Appendix B SVGs
  coopwin waves --out w.vcd --window 10,40,20,50 --frames 2";

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
        window: coopwin_hdl::camera::Window,
        /// Frames to acquire, one coordinate set written before each
        #[arg(long, default_value_t = 1)]
        frames: usize,
    },
}

fn run(cli: Cli) -> Result<(), CliError> {
    match cli.command {
        None => Err(CliError("no command given; see `coopwin --help`".into())),
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
    }
}

fn main() -> ExitCode {
    match run(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
