//! Helpers shared by the testbench's tests: the fault tests' dropout, the rule for a missing
//! EDA tool, and what every track's rows must say.
// Each test binary that includes this module uses only part of it.
#![allow(dead_code)]
use coopwin_testbench::frames::scene::SceneFrames;
use coopwin_testbench::frames::{FrameError, FrameSource};
use coopwin_testbench::system::RunLog;

/// Issue 21, item 2: every frame's row has a position, a measured one exactly when its state
/// is `tracking` or `unconfirmed` (issue 38; else the predicted one, or where the target was
/// last seen).
pub fn assert_rows_are_honest(name: &str, log: &RunLog) {
    for r in &log.frames {
        assert_eq!(r.point.is_some(), r.state.measured(), "{name}, frame {}: {:?} with point {:?}", r.frame, r.state, r.point);
        assert!(r.point.or(r.estimate).is_some(), "{name}, frame {}: {:?} row without a position", r.frame, r.state);
    }
}

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

/// The hdl crate's test helpers: the one rule for a missing EDA tool, `fusesoc run` and the
/// scratch folders it builds in.
#[path = "../../../hdl/tests/common/mod.rs"]
pub mod eda;
pub use eda::missing_tool;
