//! `coopwin verilog`: the window logic's Verilog export (thesis Appendix A).
use super::{output::OutFile, CliError};
use std::path::{Path, PathBuf};

/// `coopwin verilog`'s options.
#[derive(clap::Args)]
pub struct VerilogArgs {
    /// Folder to write into (created if missing)
    #[arg(long)]
    pub out: PathBuf,
    /// Window units in window_network
    #[arg(long, default_value_t = coopwin_hdl::verilog::DEFAULT_UNITS)]
    pub units: usize,
}

/// Writes `window_unit.v` and `window_network.v` and says so.
pub fn export(args: VerilogArgs) -> Result<(), CliError> {
    for p in write_verilog(&args.out, args.units)? {
        println!("wrote {}", p.display());
    }
    Ok(())
}

/// Writes `window_unit.v` and `window_network.v` (with `units` units) into `out`.
pub fn write_verilog(out: &Path, units: usize) -> Result<Vec<PathBuf>, CliError> {
    if units == 0 || units > 64 {
        return Err(CliError::arg(format!("--units must be 1..64, got {units}")));
    }
    super::output::create_folder(out, "--out")?;
    let files = coopwin_hdl::verilog::exported(units).map_err(CliError::new)?;
    let mut written = Vec::new();
    for (name, text) in files {
        let path = out.join(name);
        OutFile::check(&path, "--out")?.write(text.as_bytes())?;
        written.push(path);
    }
    Ok(written)
}
