//! Helpers shared by the testbench's tests: the fault tests' dropout, and the rule for a
//! missing EDA tool.
// Each test binary that includes this module uses only part of it.
#![allow(dead_code)]
use coopwin_testbench::frames::scene::SceneFrames;
use coopwin_testbench::frames::{FrameError, FrameSource};

/// The scene with frames `dark` replaced by all zeros (a camera dropout).
pub struct Dropout {
    /// The scene.
    pub inner: SceneFrames,
    /// The dark frames.
    pub dark: std::ops::Range<usize>,
    /// One all-zero frame.
    pub zeros: Vec<u8>,
}

impl FrameSource for Dropout {
    fn size(&self) -> (usize, usize) {
        self.inner.size()
    }
    fn len(&self) -> usize {
        self.inner.len()
    }
    fn frame(&mut self, k: usize) -> Result<&[u8], FrameError> {
        if self.dark.contains(&k) {
            return Ok(&self.zeros);
        }
        self.inner.frame(k)
    }
}

/// True when `verilator` runs; when it does not, the test fails (see [`missing_tool`]).
pub fn have_verilator() -> bool {
    let found = std::process::Command::new("verilator").arg("--version").output().is_ok();
    if !found {
        missing_tool("verilator", "apt-get install -y verilator");
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
