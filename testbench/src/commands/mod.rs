//! One module per `coopwin` subcommand family; each returns a typed error the binary prints.
pub mod hardware;
pub mod kernels;
pub mod main_job;
pub mod output;
pub mod scene;
pub mod track;

/// A failure a person can act on, printed as one line. A bad argument (a value on the command
/// line that cannot be used, found while parsing or after) exits with code 2, anything else
/// (unreadable input, a failed write, a failed run) with code 1.
#[derive(Debug)]
pub struct CliError {
    /// What went wrong and what to do about it.
    pub message: String,
    /// The command line asked for something invalid.
    pub bad_argument: bool,
}

impl CliError {
    /// An error in the run or its inputs (exit code 1).
    pub fn new(message: impl Into<String>) -> Self {
        CliError { message: message.into(), bad_argument: false }
    }

    /// A bad argument (exit code 2).
    pub fn arg(message: impl Into<String>) -> Self {
        CliError { message: message.into(), bad_argument: true }
    }

    /// The process exit code: 2 for a bad argument, 1 otherwise.
    pub fn exit_code(&self) -> u8 {
        if self.bad_argument {
            2
        } else {
            1
        }
    }
}

impl std::fmt::Display for CliError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for CliError {}

/// Wraps an I/O error with the path it concerns.
pub fn io_error(what: &str, path: &std::path::Path, e: std::io::Error) -> CliError {
    CliError::new(format!("cannot {what} {}: {e}", path.display()))
}
