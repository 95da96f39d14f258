//! Writes `fixtures/board/windows.bin`, the COOP window stream the Cortex-M4 board replays
//! (thesis 4.2; see `coopwin_testbench::board_stream`).
use coopwin_testbench::board_stream::{record, scene, RecordError};

/// The fixture's path.
const PATH: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../fixtures/board/windows.bin");

/// Why the fixture was not written.
enum Failure {
    /// The stream could not be recorded.
    Record(RecordError),
    /// The file could not be written.
    Write(std::io::Error),
}

/// The reason, as `main` prints it on failure.
impl std::fmt::Debug for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Failure::Record(e) => write!(f, "{e}"),
            Failure::Write(e) => write!(f, "{PATH}: {e}"),
        }
    }
}

fn main() -> Result<(), Failure> {
    let bytes = record(&scene()).map_err(Failure::Record)?;
    std::fs::write(PATH, &bytes).map_err(Failure::Write)?;
    println!("{PATH}: {} bytes", bytes.len());
    Ok(())
}
