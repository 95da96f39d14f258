//! The Verilog's own checks, for users who do not use Rust, run here so the test suite covers
//! them: the self-checking Icarus bench at every contract size (`scripts/icarus-check.sh`),
//! the formal proofs and their mutants (`scripts/formal.sh`), the cocotb bench with its
//! functional coverage (`hdl/cocotb/run.py`), and the iCE40 board build from simulation to
//! bitstream (`scripts/board-fpga.sh`). Each has its own reference (a model written from the
//! contract, the properties, the coverage goals); the scripts exit non-zero when it is not met.
//! Without their tools these tests fail, or skip visibly with COOPWIN_ALLOW_MISSING_EDA=1.
mod common;
use common::{have_tool, run, scratch};
use std::path::PathBuf;
use std::process::Command;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

#[test]
fn icarus_bench_passes_at_every_contract_size() {
    if !have_tool("iverilog") {
        return;
    }
    let log = run(Command::new("bash").arg(repo().join("scripts/icarus-check.sh")));
    // One PASS line per size and seed of the default list: 16x16 x 4 seeds, 17x300 x 2,
    // 256x256 x 2, then 640x480, 4096x16, 1280x720 and 1920x1080 once each.
    assert_eq!(log.matches("PASS window_unit").count(), 12, "{log}");
}

#[test]
fn formal_proofs_pass_and_catch_the_mutants() {
    if !["yosys", "yosys-smtbmc", "z3"].iter().all(|t| have_tool(t)) {
        return;
    }
    run(Command::new("bash").arg(repo().join("scripts/formal.sh")));
}

#[test]
fn cocotb_bench_passes_with_full_coverage() {
    let cocotb = Command::new("python3").args(["-c", "import cocotb, cocotb_coverage"]).output().is_ok_and(|o| o.status.success());
    if !cocotb {
        common::missing_tool("cocotb", "pip install -r hdl/cocotb/requirements.txt");
        return;
    }
    if !have_tool("iverilog") {
        return;
    }
    run(Command::new("python3").arg(repo().join("hdl/cocotb/run.py")).arg("--build").arg(scratch("cocotb")));
}

#[test]
fn board_top_simulates_and_packs_to_a_bitstream() {
    if !["iverilog", "yosys", "nextpnr-ice40", "icepack"].iter().all(|t| have_tool(t)) {
        return;
    }
    let out = scratch("board_fpga");
    run(Command::new("bash").arg(repo().join("scripts/board-fpga.sh")).arg("--out").arg(&out));
    let bin = std::fs::read_dir(&out).unwrap().flatten().find(|e| e.path().extension().is_some_and(|x| x == "bin"));
    let size = bin.map_or(0, |b| b.metadata().unwrap().len());
    // An iCE40 HX8K bitstream is 135,100 bytes.
    assert_eq!(size, 135_100);
}
