//! The `coopwin` subcommands, one file each, with their options (clap) and their work; each
//! returns a [`CliError`] the binary prints. [`output`] holds the one rule for writing output
//! files, [`args`] the values the command line takes.
pub mod args;
pub mod audit;
pub mod corner;
pub mod experiment;
pub mod interrupt;
pub mod main_job;
pub mod matching;
pub mod motion;
pub mod output;
pub mod progress;
pub mod scene;
pub mod track;
pub mod track_files;
pub mod verilog;
pub mod waves;

/// A failure a person can act on, printed as one line. A bad argument (a value on the command
/// line that cannot be used, found while parsing or after) exits with code 2, an interrupted
/// run (Ctrl-C) with 130 (the shells' 128 + SIGINT), anything else (unreadable input, a failed
/// write, a failed run) with code 1.
#[derive(Debug)]
pub struct CliError {
    /// What went wrong and what to do about it.
    pub message: String,
    /// The process exit code.
    pub code: u8,
}

impl CliError {
    /// An error in the run or its inputs (exit code 1).
    pub fn new(message: impl Into<String>) -> Self {
        CliError { message: message.into(), code: 1 }
    }

    /// A bad argument (exit code 2).
    pub fn arg(message: impl Into<String>) -> Self {
        CliError { message: message.into(), code: 2 }
    }

    /// The run was interrupted by Ctrl-C (exit code 130).
    pub fn interrupted() -> Self {
        CliError { message: "interrupted (Ctrl-C): no output written, earlier files left as they were".into(), code: 130 }
    }

    /// The process exit code: 2 for a bad argument, 130 for an interrupted run, 1 otherwise.
    pub fn exit_code(&self) -> u8 {
        self.code
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

/// Failures of the library's work (exit code 1), with their messages.
macro_rules! run_errors {
    ($($t:ty),*) => {
        $(impl From<$t> for CliError {
            fn from(e: $t) -> Self {
                CliError::new(e.to_string())
            }
        })*
    };
}

run_errors!(
    crate::frames::folder::FolderError,
    crate::frames::FrameError,
    crate::frames::gray::ImageError,
    crate::frames::groundtruth::GroundTruthError,
    crate::system::SimError,
    crate::experiments::ExperimentError,
    crate::report::plot::PlotError
);
