//! Shared by the tests that call external EDA tools.
// Each test binary that includes this module uses only part of it.
#![allow(dead_code)]
use std::path::Path;
use std::process::{Command, Output};

/// True when `tool` runs. When it does not, the test fails, or with
/// COOPWIN_ALLOW_MISSING_EDA=1 says (visibly) that it is skipped and the caller returns.
pub fn have_tool(tool: &str) -> bool {
    let found = Command::new(tool).arg("-V").output().is_ok();
    if !found {
        missing_tool(tool, "apt-get install -y iverilog verilator yosys nextpnr-ice40");
    }
    found
}

/// A check that needs `what`, which is missing (`why` says what to install). Missing tools
/// fail the test, so a suite never reports `ok` for a check that did not run; with
/// COOPWIN_ALLOW_MISSING_EDA=1 the caller skips instead, and the skip is written straight to
/// the process's stderr (not through `eprintln!`, which the test harness captures and hides
/// for passing tests), so it shows in `cargo test`'s output beside the test's `ok`.
pub fn missing_tool(what: &str, why: &str) {
    if std::env::var("COOPWIN_ALLOW_MISSING_EDA").as_deref() == Ok("1") {
        use std::io::Write;
        let _ = writeln!(std::io::stderr(), "SKIPPED, CHECKED NOTHING (COOPWIN_ALLOW_MISSING_EDA=1): {what} not found ({why})");
    } else {
        panic!("{what} not found ({why}); install it, or set COOPWIN_ALLOW_MISSING_EDA=1 to skip the checks that need it");
    }
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

/// `fusesoc run --target=TARGET CORE ARGS..` with `cores` as the only libraries, building under
/// `work` with an empty configuration (no user library is picked up).
pub fn fusesoc(work: &Path, cores: &[&Path], target: &str, core: &str, args: &[String]) -> (Output, String) {
    std::fs::write(work.join("fusesoc.conf"), "").unwrap();
    let mut cmd = Command::new("fusesoc");
    cmd.current_dir(work).arg("--config").arg(work.join("fusesoc.conf"));
    for root in cores {
        cmd.arg("--cores-root").arg(root);
    }
    let out = cmd
        .args(["run", &format!("--target={target}"), core])
        .args(args)
        .output()
        .expect("run fusesoc");
    let text = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    (out, text)
}
