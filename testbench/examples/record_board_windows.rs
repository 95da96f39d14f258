//! Writes `fixtures/board/windows.bin`, the COOP window stream the Cortex-M4 board replays
//! (thesis 4.2; see `coopwin_testbench::board_stream`).
fn main() -> Result<(), String> {
    let bytes = coopwin_testbench::board_stream::record(&coopwin_testbench::board_stream::scene())?;
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../fixtures/board/windows.bin");
    std::fs::write(path, &bytes).map_err(|e| format!("{path}: {e}"))?;
    println!("{path}: {} bytes", bytes.len());
    Ok(())
}
