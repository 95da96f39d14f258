//! One module per `coopwin` subcommand family; each returns a typed error the binary prints.
pub mod hardware;
pub mod kernels;
pub mod main_job;
pub mod scene;
pub mod track;

/// A failure a person can act on: printed as one line, exit code 1.
#[derive(Debug)]
pub struct CliError(pub String);

impl std::fmt::Display for CliError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for CliError {}

/// Wraps an I/O error with the path it concerns.
pub fn io_error(what: &str, path: &std::path::Path, e: std::io::Error) -> CliError {
    CliError(format!("cannot {what} {}: {e}", path.display()))
}
