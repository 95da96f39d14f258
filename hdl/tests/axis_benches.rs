//! The AXI4-Stream wrapper `window_unit_axis` (hdl/verilog/window_unit_axis.v) checked as the
//! unit is (hdl/tests/verilog_benches.rs): its cocotb bench, whose cocotbext-axi drivers feed
//! both the design and a reference model written from the contract (hdl/cocotb/model.py), with
//! the functional coverage goal of every listed situation (`hdl/cocotb/run.py --axis`); and its
//! formal properties of the AXI4-Stream rules, with mutants each a property must catch
//! (`scripts/formal.sh --axis`). The scripts exit non-zero when a check fails.
//! Without their tools these tests fail, or skip visibly with COOPWIN_ALLOW_MISSING_EDA=1.
mod common;
use common::{have_tool, run, scratch};
use std::path::PathBuf;
use std::process::Command;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

#[test]
fn axis_cocotb_bench_passes_with_full_coverage() {
    let python = Command::new("python3").args(["-c", "import cocotb, cocotb_coverage, cocotbext.axi"]).output();
    if !python.is_ok_and(|o| o.status.success()) {
        common::missing_tool("cocotb, cocotb-coverage or cocotbext-axi", "pip install -r hdl/cocotb/requirements.txt");
        return;
    }
    if !have_tool("iverilog") {
        return;
    }
    let log = run(Command::new("python3").arg(repo().join("hdl/cocotb/run.py")).arg("--axis").arg("--build").arg(scratch("cocotb_axis")));
    // Both default configurations reached every situation.
    assert_eq!(log.matches("coverage: 34/34 bins (100.0%)").count(), 2, "{log}");
}

#[test]
fn axis_formal_properties_hold_and_catch_the_mutants() {
    if !["yosys", "yosys-smtbmc", "z3"].iter().all(|t| have_tool(t)) {
        return;
    }
    let log = run(Command::new("bash").arg(repo().join("scripts/formal.sh")).arg("--axis"));
    let mutants = std::fs::read_dir(repo().join("hdl/formal/broken-axis")).unwrap().count();
    assert!(mutants >= 2, "hdl/formal/broken-axis has {mutants} mutants");
    assert_eq!(log.matches(" CAUGHT ").count(), mutants, "{log}");
}
