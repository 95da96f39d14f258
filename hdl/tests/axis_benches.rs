//! The AXI4-Stream wrapper `window_unit_axis` (hdl/verilog/window_unit_axis.v) checked as the
//! unit is (hdl/tests/verilog_benches.rs): its cocotb bench, whose cocotbext-axi drivers feed
//! both the design and a reference model written from the contract (hdl/cocotb/model.py), with
//! the functional coverage goal of every listed situation (`hdl/cocotb/run.py --axis`); and its
//! formal properties of the AXI4-Stream rules, with mutants each a property must catch
//! (`scripts/formal.sh --axis`); and its example integration on the iCE40 board, simulated end
//! to end against the camera model's pixels and built to a bitstream, with mutants the bench
//! must catch (`scripts/board-fpga.sh --axis`). The scripts exit non-zero when a check fails.
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
    assert_eq!(log.matches("coverage: 36/36 bins (100.0%)").count(), 2, "{log}");
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

/// The example integration (hdl/board/coopwin_ice40_axis_top.v): the board's camera pins through
/// coopwin_dvp_axis into window_unit_axis, simulated end to end with the OV7670 model and a host
/// on the UART (hdl/board/tb/coopwin_ice40_axis_tb.v, which checks every delivered pixel against
/// the camera model's pixel function), then built to an iCE40 bitstream.
#[test]
fn axis_board_top_simulates_end_to_end_and_packs_to_a_bitstream() {
    if !["iverilog", "yosys", "nextpnr-ice40", "icepack"].iter().all(|t| have_tool(t)) {
        return;
    }
    let out = scratch("board_fpga_axis");
    run(Command::new("bash").arg(repo().join("scripts/board-fpga.sh")).arg("--axis").arg("--out").arg(&out));
    let log = std::fs::read_to_string(out.join("sim-axis-640x480.log")).unwrap();
    // Pixels checked, by hand from the bench's windows: 16x10 + 10x5 (decimated), twice
    // (without and with tready gaps), 80x2 + 2x60, 10x5 (decimated), 40x10 = 1150, plus the 416
    // delivered in the run made to overflow (the bench checks delivered + OVERFLOWS = 80x8).
    assert!(log.contains("9 windows, 1566 pixels checked, "), "{log}");
    assert!(log.contains(" 0 errors, UART framing errors 0,"), "{log}");
    assert_eq!(log.lines().last(), Some("PASS"), "{log}");
    // An iCE40 HX8K bitstream is 135,100 bytes.
    assert_eq!(std::fs::metadata(out.join("coopwin_ice40_axis_hx8k.bin")).unwrap().len(), 135_100);
}

/// The end-to-end bench fails on a one-line mutant of each block it covers: the IP not counting
/// a dropped beat (a silent loss) and the camera adapter sending the wrong clock's byte.
#[test]
fn axis_board_bench_catches_mutants() {
    if !have_tool("iverilog") {
        return;
    }
    let mutants = [
        ("hdl/verilog/window_unit_axis.v", "if (drops != 32'hFFFF_FFFF) drops <= drops + 32'd1;", "drops <= drops;",
         "delivered + overflows is not the window's size"),
        ("hdl/board/coopwin_dvp_axis.v", "m_axis_tdata <= held;", "m_axis_tdata <= data;",
         "pixels are not the window of the first or second frame after the commit"),
    ];
    for (i, (file, from, to, message)) in mutants.iter().enumerate() {
        let source = std::fs::read_to_string(repo().join(file)).unwrap();
        assert_eq!(source.matches(from).count(), 1, "{file} no longer has `{from}` once");
        let dir = scratch(&format!("board_axis_mutant{i}"));
        let mutant = dir.join("mutant.v");
        std::fs::write(&mutant, source.replace(from, to)).unwrap();
        let out = Command::new("bash")
            .arg(repo().join("scripts/board-fpga.sh"))
            .args(["--axis", "--sim-only", "--out"])
            .arg(&dir)
            .arg("--with")
            .arg(format!("{file}={}", mutant.display()))
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && text.contains("simulation sim-axis-640x480 failed"), "mutant of {file} passed:\n{text}");
        assert!(text.contains(message), "mutant of {file} failed otherwise:\n{text}");
    }
}

/// The register port's clock-domain crossing (hdl/verilog/axil_cdc.v) in front of the wrapper,
/// on two unrelated clocks: its self-checking bench (hdl/verilog/tb/axil_cdc_tb.v, whose
/// reference is the register map) passes with the processor's clock 10 times faster, 10 times
/// slower and nearly equal; and a one-line mutant, the read acknowledged when its address is
/// taken rather than when its data is, fails where the processor's clock is the faster.
#[test]
fn axil_cdc_bench_passes_on_unrelated_clocks_and_catches_a_mutant() {
    if !have_tool("iverilog") {
        return;
    }
    let dir = scratch("axil_cdc");
    let verilog = repo().join("hdl/verilog");
    let bench = |cdc: &std::path::Path, s: &str, m: &str| {
        let vvp = dir.join("tb.vvp");
        run(Command::new("iverilog")
            .args(["-g2012", "-Wall", "-o"])
            .arg(&vvp)
            .args(["-P", &format!("axil_cdc_tb.S_PERIOD={s}"), "-P", &format!("axil_cdc_tb.M_PERIOD={m}")])
            .arg(verilog.join("tb/axil_cdc_tb.v"))
            .arg(cdc)
            .arg(verilog.join("window_unit_axis.v")));
        let out = Command::new("vvp").arg("-n").arg(&vvp).output().expect("run vvp");
        (out.status.success(), String::from_utf8_lossy(&out.stdout).into_owned())
    };
    for (s, m) in [("1", "10"), ("10", "1"), ("7", "7.3")] {
        let (ok, log) = bench(&verilog.join("axil_cdc.v"), s, m);
        assert!(ok && log.contains("PASS axil_cdc") && log.contains("400 writes, 802 reads"), "{s} ns / {m} ns:\n{log}");
    }
    let source = std::fs::read_to_string(verilog.join("axil_cdc.v")).unwrap();
    let (taken, data) = (
        "if (ar_pend & m_axil_arready) ar_pend <= 1'b0;",
        "r_data_m <= m_axil_rdata; r_resp_m <= m_axil_rresp; rd_wait <= 1'b0; r_ack <= ~r_ack;",
    );
    assert_eq!((source.matches(taken).count(), source.matches(data).count()), (1, 1));
    let mutant = source
        .replace(taken, "if (ar_pend & m_axil_arready) begin ar_pend <= 1'b0; r_ack <= ~r_ack; end")
        .replace(data, "r_data_m <= m_axil_rdata; r_resp_m <= m_axil_rresp; rd_wait <= 1'b0;");
    std::fs::write(dir.join("mutant.v"), mutant).unwrap();
    let (ok, log) = bench(&dir.join("mutant.v"), "1", "10");
    assert!(!ok && log.contains("FAIL axil_cdc"), "the mutant passed:\n{log}");
}
