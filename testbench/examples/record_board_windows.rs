//! Writes `fixtures/board/windows.bin`, `windows_adaptive.bin` and `windows_covered.bin`, the
//! COOP window streams the Cortex-M4 board replays (thesis 4.2; see
//! `coopwin_testbench::board_stream`).
use coopwin_testbench::board_stream::{adaptive, covered, record, thesis, RecordError};

/// The fixtures' directory.
const DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../fixtures/board");

/// Why the fixture was not written.
enum Failure {
    /// The stream could not be recorded.
    Record(RecordError),
    /// The file could not be written.
    Write(String, std::io::Error),
}

/// The reason, as `main` prints it on failure.
impl std::fmt::Debug for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Failure::Record(e) => write!(f, "{e}"),
            Failure::Write(path, e) => write!(f, "{path}: {e}"),
        }
    }
}

fn main() -> Result<(), Failure> {
    for (file, rec) in [("windows.bin", thesis()), ("windows_adaptive.bin", adaptive()), ("windows_covered.bin", covered())] {
        let bytes = record(&rec).map_err(Failure::Record)?;
        let path = format!("{DIR}/{file}");
        std::fs::write(&path, &bytes).map_err(|e| Failure::Write(path.clone(), e))?;
        println!("{path}: {} bytes", bytes.len());
    }
    Ok(())
}
