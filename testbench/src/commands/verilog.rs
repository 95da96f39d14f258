//! `coopwin verilog`: the window logic's Verilog export (thesis Appendix A) for a sensor's size.
use super::args::SensorArgs;
use super::{output::OutFile, CliError};
use coopwin_hdl::verilog::{axis_files, Geometry, Netlist, AXIS_MAX_WINDOWS};
use std::path::{Path, PathBuf};

/// Examples shown after `coopwin verilog --help`.
pub const VERILOG_EXAMPLES: &str = "\
Examples:
  coopwin verilog --out hdl/verilog
      the thesis's 256x256 8-bit camera, 4 units (the committed copy)
  coopwin verilog --width 640 --height 480 --pixel-bits 10 --units 2 --out rtl/
      a VGA sensor with 10-bit pixels: coordinates are then two bytes each, high first
  coopwin verilog --netlist rust-hdl --width 640 --height 480 --out rtl/
      rust-hdl's own netlist of the blocks for that size, proven equivalent to the readable
      module (hdl/tests/equivalence.rs); fixed widths, no parameters
  coopwin verilog --axis --out hdl/verilog
      also window_unit_axis.v, the AXI4-Stream video wrapper with --units windows, and
      axil_cdc.v, its register port on another clock (docs/window-logic.md; the committed copy)
The parameters WIDTH, HEIGHT and PIXEL_BITS of the readable module stay overridable in the
Verilog; these options set their defaults. Check a size with
scripts/icarus-check.sh --size WxH --bits P.";

/// `--netlist`.
#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum NetlistArg {
    /// The readable, parametric module (hdl/src/rtl/window_unit.v)
    Readable,
    /// rust-hdl's generated netlist of the blocks, fixed to the size
    RustHdl,
}

impl From<NetlistArg> for Netlist {
    fn from(n: NetlistArg) -> Netlist {
        match n {
            NetlistArg::Readable => Netlist::Readable,
            NetlistArg::RustHdl => Netlist::RustHdl,
        }
    }
}

/// `coopwin verilog`'s options.
#[derive(clap::Args)]
pub struct VerilogArgs {
    /// Folder to write into (created if missing)
    #[arg(long)]
    pub out: PathBuf,
    /// Window units in window_network (1..64)
    #[arg(long, default_value_t = coopwin_hdl::verilog::DEFAULT_UNITS)]
    pub units: usize,
    /// The sensor's geometry (--width, --height, --pixel-bits)
    #[command(flatten)]
    pub sensor: SensorArgs,
    /// Which window_unit to write
    #[arg(long, value_enum, default_value_t = NetlistArg::Readable)]
    pub netlist: NetlistArg,
    /// Also write window_unit_axis.v (AXI4-Stream video in, --units cropped AXI4-Stream
    /// windows out (1..32), AXI4-Lite registers) and axil_cdc.v (those registers on another clock)
    #[arg(long)]
    pub axis: bool,
}

/// Writes `window_unit.v` and `window_network.v` and says so.
pub fn export(args: VerilogArgs) -> Result<(), CliError> {
    let g = args.sensor.geometry()?;
    for p in write_verilog(&args.out, args.units, &g, args.netlist.into(), args.axis)? {
        println!("wrote {}", p.display());
    }
    println!(
        "{}x{} sensor, {}-bit pixels: {}-bit counters, {}-byte coordinate sets",
        g.width,
        g.height,
        g.pixel_bits,
        g.counter_bits(),
        g.set_bytes()
    );
    Ok(())
}

/// Writes [`verilog_files`] into `out` and returns their paths.
pub fn write_verilog(out: &Path, units: usize, g: &Geometry, netlist: Netlist, axis: bool) -> Result<Vec<PathBuf>, CliError> {
    let files = verilog_files(units, g, netlist, axis)?;
    super::output::create_folder(out, "--out")?;
    let mut written = Vec::new();
    for (name, text) in files {
        let path = out.join(name);
        OutFile::check(&path, "--out")?.write(text.as_bytes())?;
        written.push(path);
    }
    Ok(written)
}

/// `window_unit.v` (`netlist`'s) and `window_network.v` (with `units` units) for `g`, and
/// with `axis` `window_unit_axis.v` (with `units` windows) and `axil_cdc.v`: each file's name
/// and text, in that order (the CLI and the Python package's `coopwin.verilog`).
pub fn verilog_files(units: usize, g: &Geometry, netlist: Netlist, axis: bool) -> Result<Vec<(&'static str, String)>, CliError> {
    if units == 0 || units > 64 {
        return Err(CliError::arg(format!("--units must be 1..64, got {units}")));
    }
    if axis && units > AXIS_MAX_WINDOWS {
        return Err(CliError::arg(format!("--axis takes at most {AXIS_MAX_WINDOWS} windows (--units), got {units}")));
    }
    let files = coopwin_hdl::verilog::exported_netlist(netlist, units, g).map_err(|e| CliError::arg(e.to_string()))?;
    let wrapper = axis.then(|| axis_files(units, g)).into_iter().flatten();
    Ok(files.into_iter().chain(wrapper).collect())
}
