//! `coopwin audit`: a window unit's VCD checked against the coordinate sets its processor
//! wrote and the window logic's rules (thesis Appendix B).
use super::{io_error, CliError};
use crate::analysis::audit::{self, requests};
use std::path::PathBuf;

/// `coopwin audit`'s options.
#[derive(clap::Args)]
pub struct AuditArgs {
    /// VCD from `coopwin track --hdl rust-hdl --vcd FILE.vcd`
    pub vcd: PathBuf,
    /// The requests CSV written beside it (FILE.requests.csv)
    #[arg(long)]
    pub requests: PathBuf,
    /// Which window unit (processor) to audit
    #[arg(long, default_value_t = 0)]
    pub unit: usize,
}

/// Audits the unit, prints what was checked and every violation; fails when the waveform
/// breaks a rule or nothing could be verified.
pub fn audit_vcd(args: AuditArgs) -> Result<(), CliError> {
    let AuditArgs { vcd, requests, unit } = args;
    let f = std::fs::File::open(&vcd).map_err(|e| io_error("open", &vcd, e))?;
    let samples = audit::read_vcd(std::io::BufReader::new(f), unit).map_err(|e| CliError::new(format!("{}: {e}", vcd.display())))?;
    let text = std::fs::read_to_string(&requests).map_err(|e| io_error("read", &requests, e))?;
    let sets = requests::read(&text, unit).map_err(|e| CliError::new(format!("{}: {e}", requests.display())))?;
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
