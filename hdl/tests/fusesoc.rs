//! The FuseSoC cores (hdl/verilog/window_unit.core, window_unit_axis.core, hdl/soc/coopwin_soc.core)
//! used as an FPGA project uses them, through `fusesoc run`: the `lint` target (Verilator -Wall,
//! whose warnings are fatal) at the sizes the CLI exports (the SoC's with the CPU a black box
//! whose ports are checked against the real core's), and the `sim` target (the self-checking Icarus
//! benches, each with its own reference: the unit's contract model in tb/window_unit_tb.v, the
//! camera model's pixel function in the board bench). Each target is also shown to fail: on a
//! one-line mutant of the unit (sim), on the wrapper's old 16-bit `tdata` assignment and on a
//! narrowed port connection in the SoC (lint).
//! Without fusesoc, Verilator or Icarus these tests fail, or skip visibly with
//! COOPWIN_ALLOW_MISSING_EDA=1.
mod common;
use common::{fusesoc, have_tool, missing_tool, scratch, verilog_dir};
use std::path::Path;
use std::process::Command;

const UNIT: &str = "coopwin:coopwin:window_unit";
const AXIS: &str = "coopwin:coopwin:window_unit_axis";
const SOC: &str = "coopwin:coopwin:soc";

/// The sizes of the exported-size checks: the CA-D1, VGA with 10-bit pixels, 1080p with 12.
const SIZES: [(usize, usize, usize); 3] = [(256, 256, 8), (640, 480, 10), (1920, 1080, 12)];

fn tools(needed: &[&str]) -> bool {
    let fusesoc = Command::new("fusesoc").arg("--version").output().is_ok_and(|o| o.status.success());
    if !fusesoc {
        missing_tool("fusesoc", "pip install fusesoc");
        return false;
    }
    needed.iter().all(|t| have_tool(t))
}

/// A cores folder under `work` with `copies` from `from` as they are and `rtl` written as
/// `name`: a core with a mutant design.
fn mutant_cores(work: &Path, from: &Path, copies: &[&str], name: &str, rtl: String) -> std::path::PathBuf {
    let cores = work.join("cores");
    for f in copies {
        std::fs::create_dir_all(cores.join(f).parent().unwrap()).unwrap();
        std::fs::copy(from.join(f), cores.join(f)).unwrap();
    }
    std::fs::write(cores.join(name), rtl).unwrap();
    cores
}

fn size_args(w: usize, h: usize, p: usize) -> Vec<String> {
    ["--WIDTH", &w.to_string(), "--HEIGHT", &h.to_string(), "--PIXEL_BITS", &p.to_string()].map(String::from).to_vec()
}

#[test]
fn lint_targets_pass_at_every_exported_size() {
    if !tools(&["verilator"]) {
        return;
    }
    let work = scratch("fusesoc_lint");
    for core in [UNIT, AXIS] {
        for (w, h, p) in SIZES {
            let (out, text) = fusesoc(&work, &[&verilog_dir()], "lint", core, &size_args(w, h, p));
            assert!(out.status.success() && !text.contains("%Warning"), "{core} lint at {w}x{h}x{p}:\n{text}");
        }
    }
}

#[test]
fn lint_target_fails_on_a_width_mismatch() {
    if !tools(&["verilator"]) {
        return;
    }
    let work = scratch("fusesoc_lint_mutant");
    // The assignment the wrapper had before it was lint-clean: PIXEL_BITS bits into a
    // whole-byte tdata slice, a WIDTH warning whenever PIXEL_BITS is not a multiple of 8.
    let rtl = std::fs::read_to_string(verilog_dir().join("window_unit_axis.v")).unwrap();
    let fixed = "assign m_axis_tdata[TW*k +: PIXEL_BITS] = q[PIXEL_BITS-1:0];";
    assert_eq!(rtl.matches(fixed).count(), 1);
    let pad = rtl.find("            if (TW > PIXEL_BITS) begin : pad").expect("the padding block");
    let end = pad + rtl[pad..].find("end\n").unwrap() + 4;
    let mutant = format!("{}{}", &rtl[..pad], &rtl[end..]).replace(fixed, "assign m_axis_tdata[TW*k +: TW] = q[PIXEL_BITS-1:0];");
    let cores = mutant_cores(&work, &verilog_dir(), &["window_unit_axis.core", "axil_cdc.v"], "window_unit_axis.v", mutant);
    let (out, text) = fusesoc(&work, &[&cores], "lint", AXIS, &size_args(640, 480, 10));
    assert!(!out.status.success() && text.contains("%Warning-WIDTH"), "the mutant did not fail lint with a WIDTH warning:\n{text}");
}

#[test]
fn sim_targets_pass() {
    if !tools(&["iverilog"]) {
        return;
    }
    let work = scratch("fusesoc_sim");
    let (out, text) = fusesoc(&work, &[&verilog_dir()], "sim", UNIT, &[]);
    assert!(out.status.success() && text.contains("PASS window_unit 256x256 8: "), "{text}");
    let (out, text) = fusesoc(&work, &[&verilog_dir()], "sim", UNIT, &size_args(640, 480, 10));
    assert!(out.status.success() && text.contains("PASS window_unit 640x480 10: "), "{text}");
    let (out, text) = fusesoc(&work, &[&verilog_dir()], "sim", AXIS, &[]);
    // The board bench's summary (docs/board.md): nine windows, every pixel checked.
    assert!(out.status.success() && text.contains("9 windows, ") && text.contains(" 0 errors, ") && text.contains("\nPASS\n"), "{text}");
}

#[test]
fn sim_target_fails_on_a_mutant() {
    if !tools(&["iverilog"]) {
        return;
    }
    let work = scratch("fusesoc_sim_mutant");
    // hdl/formal/broken/decimation_parity.sed: decimated windows take the odd columns.
    let rtl = std::fs::read_to_string(verilog_dir().join("window_unit.v")).unwrap();
    assert_eq!(rtl.matches("((xcount[0] == xn[0])").count(), 1);
    let mutant = rtl.replace("((xcount[0] == xn[0])", "((xcount[0] != xn[0])");
    let cores = mutant_cores(&work, &verilog_dir(), &["window_unit.core", "tb/window_unit_tb.v"], "window_unit.v", mutant);
    let (out, text) = fusesoc(&work, &[&cores], "sim", UNIT, &[]);
    assert!(!out.status.success() && text.contains("FAIL window_unit"), "the mutant passed:\n{text}");
}

/// hdl/soc, the SoC's core folder.
fn soc_dir() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("soc")
}

#[test]
fn soc_lint_targets_pass() {
    if !tools(&["verilator"]) {
        return;
    }
    let work = scratch("fusesoc_soc_lint");
    for target in ["lint", "lint_ulx3s"] {
        let (out, text) = fusesoc(&work, &[&verilog_dir(), &soc_dir()], target, SOC, &[]);
        assert!(out.status.success() && !text.contains("%Warning"), "{SOC} {target}:\n{text}");
    }
}

#[test]
fn soc_lint_target_fails_on_a_narrowed_port() {
    if !tools(&["verilator"]) {
        return;
    }
    let work = scratch("fusesoc_soc_lint_mutant");
    // The CPU's 32-bit reset vector tied to a 16-bit constant: a WIDTH warning against the
    // black box's port, which only a faithful port list gives.
    let rtl = std::fs::read_to_string(soc_dir().join("coopwin_soc.v")).unwrap();
    let tie = ".externalResetVector(32'h0000_0000)";
    assert_eq!(rtl.matches(tie).count(), 1);
    let mutant = rtl.replace(tie, ".externalResetVector(16'h0000)");
    let cores = mutant_cores(&work, &soc_dir(), &["coopwin_soc.core", "soc_ram.v", "lint/VexRiscv.v"], "coopwin_soc.v", mutant);
    let (out, text) = fusesoc(&work, &[&verilog_dir(), &cores], "lint", SOC, &[]);
    assert!(!out.status.success() && text.contains("%Warning-WIDTH"), "the mutant did not fail lint with a WIDTH warning:\n{text}");
}

/// The lint's black box (hdl/soc/lint/VexRiscv.v) has the port list of the core the SoC is
/// built with (pip's pythondata-cpu-vexriscv, VexRiscv_IMAC.v), line for line.
#[test]
fn soc_cpu_black_box_has_the_real_cores_ports() {
    let out = Command::new("python3").args(["-c", "import pythondata_cpu_vexriscv as p; print(p.data_location)"]).output();
    let Some(dir) = out.ok().filter(|o| o.status.success()).map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string()) else {
        missing_tool("pythondata_cpu_vexriscv", "pip install pythondata-cpu-vexriscv (the version .ci/run pins)");
        return;
    };
    let header = |path: &Path| -> Vec<String> {
        let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let lines: Vec<String> = text.lines().map(str::to_string).collect();
        let start = lines.iter().position(|l| l.starts_with("module VexRiscv (")).unwrap_or_else(|| panic!("{}: no `module VexRiscv (`", path.display()));
        let end = start + lines[start..].iter().position(|l| l.starts_with(");")).unwrap_or_else(|| panic!("{}: no `);`", path.display()));
        lines[start..=end].to_vec()
    };
    let real = header(&Path::new(&dir).join("VexRiscv_IMAC.v"));
    assert!(real.len() > 20, "the real core's header: {real:?}");
    assert_eq!(header(&soc_dir().join("lint/VexRiscv.v")), real);
}
