//! The FuseSoC cores (hdl/verilog/window_unit.core, window_unit_axis.core) used as an FPGA
//! project uses them, through `fusesoc run`: the `lint` target (Verilator -Wall, whose warnings
//! are fatal) at the sizes the CLI exports, and the `sim` target (the self-checking Icarus
//! benches, each with its own reference: the unit's contract model in tb/window_unit_tb.v, the
//! camera model's pixel function in the board bench). Each target is also shown to fail: on a
//! one-line mutant of the unit (sim) and on the wrapper's old 16-bit `tdata` assignment (lint).
//! Without fusesoc, Verilator or Icarus these tests fail, or skip visibly with
//! COOPWIN_ALLOW_MISSING_EDA=1.
mod common;
use common::{have_tool, missing_tool, scratch, verilog_dir};
use std::path::Path;
use std::process::{Command, Output};

const UNIT: &str = "coopwin:coopwin:window_unit";
const AXIS: &str = "coopwin:coopwin:window_unit_axis";

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

/// `fusesoc run --target=TARGET CORE ARGS..` with `cores` as the only library, building under
/// `work` with an empty configuration (no user library is picked up).
fn fusesoc(work: &Path, cores: &Path, target: &str, core: &str, args: &[String]) -> (Output, String) {
    std::fs::write(work.join("fusesoc.conf"), "").unwrap();
    let out = Command::new("fusesoc")
        .current_dir(work)
        .arg("--config")
        .arg(work.join("fusesoc.conf"))
        .arg("--cores-root")
        .arg(cores)
        .args(["run", &format!("--target={target}"), core])
        .args(args)
        .output()
        .expect("run fusesoc");
    let text = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    (out, text)
}

/// A cores folder under `work` with `copies` from hdl/verilog as they are and `rtl` written as
/// `name`: a core with a mutant design.
fn mutant_cores(work: &Path, copies: &[&str], name: &str, rtl: String) -> std::path::PathBuf {
    let cores = work.join("cores");
    std::fs::create_dir_all(cores.join("tb")).unwrap();
    for f in copies {
        std::fs::copy(verilog_dir().join(f), cores.join(f)).unwrap();
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
            let (out, text) = fusesoc(&work, &verilog_dir(), "lint", core, &size_args(w, h, p));
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
    let cores = mutant_cores(&work, &["window_unit_axis.core", "axil_cdc.v"], "window_unit_axis.v", mutant);
    let (out, text) = fusesoc(&work, &cores, "lint", AXIS, &size_args(640, 480, 10));
    assert!(!out.status.success() && text.contains("%Warning-WIDTH"), "the mutant did not fail lint with a WIDTH warning:\n{text}");
}

#[test]
fn sim_targets_pass() {
    if !tools(&["iverilog"]) {
        return;
    }
    let work = scratch("fusesoc_sim");
    let (out, text) = fusesoc(&work, &verilog_dir(), "sim", UNIT, &[]);
    assert!(out.status.success() && text.contains("PASS window_unit 256x256 8: "), "{text}");
    let (out, text) = fusesoc(&work, &verilog_dir(), "sim", UNIT, &size_args(640, 480, 10));
    assert!(out.status.success() && text.contains("PASS window_unit 640x480 10: "), "{text}");
    let (out, text) = fusesoc(&work, &verilog_dir(), "sim", AXIS, &[]);
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
    let cores = mutant_cores(&work, &["window_unit.core", "tb/window_unit_tb.v"], "window_unit.v", mutant);
    let (out, text) = fusesoc(&work, &cores, "sim", UNIT, &[]);
    assert!(!out.status.success() && text.contains("FAIL window_unit"), "the mutant passed:\n{text}");
}
