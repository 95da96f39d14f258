//! Issue 40: the soft-CPU SoC co-simulation (scripts/soc.sh, docs/soc.md). The project's Rust
//! firmware, built for riscv32imac, runs on VexRiscv in Verilator beside the window unit's RTL,
//! the camera fed with a built-in scene's 21 frames. The script fails unless the firmware
//! exits cleanly and refuses both hostile coordinate sets; its references: the UART's bytes
//! against the same tracker on the host over a model of the unit (`soc-replay`), where the
//! SoC measures every frame against `coopwin track`'s rows (this CLI, the testbench's whole
//! system), and the unit's traced signals against the firmware's sets (`coopwin audit`). Needs Verilator, binutils-riscv64-unknown-elf, Debian's rustc-web with
//! rust-web-src and pip's pythondata-cpu-vexriscv (.ci/run installs them).
mod common;
use std::path::Path;
use std::process::Command;

#[test]
fn the_soc_tracks_a_scene_bit_for_bit_with_the_host() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let tools = [
        ("verilator", "apt-get install -y verilator"),
        ("riscv64-unknown-elf-ld", "apt-get install -y binutils-riscv64-unknown-elf"),
        ("/usr/bin/rustc", "apt-get install -y rustc-web cargo-web rust-web-src"),
    ];
    for (tool, how) in tools {
        if Command::new(tool).arg("--version").output().is_err() {
            common::missing_tool(tool, how);
            return;
        }
    }
    let vex = Command::new("python3").args(["-c", "import pythondata_cpu_vexriscv"]).status();
    if !vex.is_ok_and(|s| s.success()) {
        common::missing_tool("pythondata_cpu_vexriscv", "pip install pythondata-cpu-vexriscv (the version .ci/run pins)");
        return;
    }
    let out = Command::new("bash")
        .arg(root.join("scripts/soc.sh"))
        .env("COOPWIN", env!("CARGO_BIN_EXE_coopwin"))
        .output()
        .expect("run scripts/soc.sh");
    let text = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "scripts/soc.sh failed:\n{text}");
    // The script's own checks passed; these lines say which references they were.
    assert!(text.contains("hostile over_edge_refused_by_driver=true reversed_refused_by_unit=true"), "{text}");
    assert!(text.contains("336 UART bytes equal to the host's"), "the every-frame run: 21 updates of 16 bytes\n{text}");
    assert!(text.contains("21 updates equal to"), "the every-frame run against track's rows\n{text}");
    // The audit's line: "C clocks, 64 frames, S sets taken, W windows verified, 0 violations".
    // How many windows the firmware gets through in 64 frames depends on its speed; the lock-on
    // and two more at least.
    let audit = text.lines().find(|l| l.contains("windows verified")).unwrap_or_else(|| panic!("no audit line\n{text}"));
    let verified: usize = audit.split(", ").find_map(|f| f.strip_suffix(" windows verified")).and_then(|n| n.parse().ok()).unwrap_or(0);
    assert!(verified >= 3 && audit.ends_with(", 0 violations"), "coopwin audit on the unit's VCD: {audit}");
}
