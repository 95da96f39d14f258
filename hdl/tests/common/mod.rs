//! Shared by the tests that call external EDA tools.
// Each test binary that includes this module uses only part of it.
#![allow(dead_code)]
use std::process::Command;

/// True when `tool` runs. When it does not: with COOPWIN_REQUIRE_EDA=1 (CI) the test fails;
/// otherwise it says it is skipped, and why, and the caller returns.
pub fn have_tool(tool: &str) -> bool {
    let found = Command::new(tool).arg("-V").output().is_ok();
    if !found {
        let msg = format!(
            "{tool} not found on PATH (apt-get install -y iverilog verilator yosys nextpnr-ice40)"
        );
        if std::env::var("COOPWIN_REQUIRE_EDA").as_deref() == Ok("1") {
            panic!("COOPWIN_REQUIRE_EDA=1 and {msg}");
        }
        eprintln!("SKIPPED: {msg}");
    }
    found
}

/// Runs a command, failing the test with its output when it does not succeed.
pub fn run(cmd: &mut Command) -> String {
    let out = cmd
        .output()
        .unwrap_or_else(|e| panic!("cannot run {cmd:?}: {e}"));
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.status.success(), "{cmd:?} failed:\n{text}");
    text
}

/// A fresh scratch directory under the target dir.
pub fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch dir");
    dir
}

/// The committed Verilog folder.
pub fn verilog_dir() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("verilog")
}
