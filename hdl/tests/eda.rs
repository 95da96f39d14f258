//! The exported Verilog in real EDA tools: Icarus Verilog replays a rust-hdl run clock for
//! clock (a second, independent simulator), Verilator lints it, Yosys maps it to an iCE40.
//! Without the tools these tests skip with a message, unless COOPWIN_REQUIRE_EDA=1.
mod common;
use common::{have_tool, run, scratch, verilog_dir};
use coopwin_hdl::sim::camera::{RasterTiming, Window};
use coopwin_hdl::sim::driver::UnitOutputs;
use coopwin_hdl::sim::run::{run_unit, Recording, Request};
use std::fmt::Write as _;
use std::process::Command;

fn stimulus_hex(rec: &Recording) -> String {
    let mut s = String::new();
    for (cam, port) in &rec.inputs {
        let word = (port.decimate as u32) << 19
            | (port.data & 0xff) << 11
            | (port.strobe as u32) << 10
            | (cam.pixel as u32) << 2
            | (cam.lval as u32) << 1
            | cam.fval as u32;
        let _ = writeln!(s, "{word:05x}");
    }
    s
}

fn parse_outputs(text: &str) -> Vec<UnitOutputs> {
    text.lines()
        .map(|l| {
            let w = u32::from_str_radix(l.trim(), 16).unwrap_or_else(|_| panic!("bad line {l:?}"));
            UnitOutputs {
                coord_ready: w & 1 != 0,
                pixel_strobe: w & 2 != 0,
                pixel_out: (w >> 2) as u8,
                coord_error: w & (1 << 10) != 0,
            }
        })
        .collect()
}

#[test]
fn icarus_replays_the_rust_hdl_run_clock_for_clock() {
    if !have_tool("iverilog") {
        return;
    }
    let t = RasterTiming {
        width: 256,
        height: 256,
        h_blank: 5,
        v_blank_lines: 3,
    };
    let frames: Vec<Vec<u8>> = (0..4)
        .map(|f| {
            (0..65536)
                .map(|i| ((i * 31 + f * 97 + i / 256) % 256) as u8)
                .collect()
        })
        .collect();
    let w = |xmin, xmax, ymin, ymax| Window {
        xmin,
        xmax,
        ymin,
        ymax,
    };
    let mid = t.frame_clocks() + 120 * t.line_clocks();
    let requests = [
        Request {
            at: 0,
            window: w(3, 40, 7, 29),
            decimate: false,
        },
        Request {
            at: mid,
            window: w(100, 131, 200, 255),
            decimate: true,
        },
        Request {
            at: mid + 400,
            window: w(9, 9, 0, 5),
            decimate: false,
        }, // invalid
        Request {
            at: 3 * t.frame_clocks() - 2000,
            window: w(0, 255, 250, 255),
            decimate: false,
        },
    ];
    let rec = run_unit::<8>(&t, &frames, &requests);
    let dir = scratch("icarus_replay");
    std::fs::write(dir.join("stim.hex"), stimulus_hex(&rec)).unwrap();
    let vvp = dir.join("replay.vvp");
    run(Command::new("iverilog")
        .arg("-g2005")
        .arg("-o")
        .arg(&vvp)
        .arg(verilog_dir().join("tb/replay_tb.v"))
        .arg(verilog_dir().join("window_unit.v")));
    run(Command::new("vvp")
        .arg("-n")
        .arg(&vvp)
        .arg(format!("+stim={}", dir.join("stim.hex").display()))
        .arg(format!("+out={}", dir.join("out.hex").display())));
    let icarus = parse_outputs(&std::fs::read_to_string(dir.join("out.hex")).unwrap());
    assert_eq!(icarus.len(), rec.outputs.len());
    if let Some(t) = (0..icarus.len()).find(|&i| icarus[i] != rec.outputs[i]) {
        panic!(
            "clock {t}: icarus {:?} rust-hdl {:?}",
            icarus[t], rec.outputs[t]
        );
    }
    // The run exercised what it should: windows delivered, an error raised.
    let delivered = rec.delivered_per_frame(&t);
    assert_eq!(
        delivered[1],
        requests[0].window.crop(&frames[1], 256, false)
    );
    assert_eq!(delivered[2], requests[1].window.crop(&frames[2], 256, true));
    assert_eq!(
        delivered[3],
        requests[3].window.crop(&frames[3], 256, false)
    );
    assert!(rec.outputs.iter().any(|o| o.coord_error));
}

/// Verilator's -Wall findings other than WIDTH (rust-hdl writes 32-bit literals) and
/// DECLFILENAME (rust-hdl puts each submodule in the unit's file); both are explained in
/// docs/window-logic.md. Anything else fails.
#[test]
fn verilator_lint_is_clean() {
    if !have_tool("verilator") {
        return;
    }
    let dir = verilog_dir();
    let out = Command::new("verilator")
        .args([
            "--lint-only",
            "-Wall",
            "-Wno-WIDTH",
            "-Wno-DECLFILENAME",
            "--top-module",
            "window_network",
        ])
        .arg(dir.join("window_unit.v"))
        .arg(dir.join("window_network.v"))
        .output()
        .expect("run verilator");
    let text = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success() && !text.contains("%Warning"),
        "verilator:\n{text}"
    );
}

/// Yosys maps one unit onto an iCE40 within the budget of 200 LUTs.
#[test]
fn yosys_fits_a_unit_in_200_luts() {
    if !have_tool("yosys") {
        return;
    }
    let unit = verilog_dir().join("window_unit.v");
    let log = run(Command::new("yosys").arg("-p").arg(format!(
        "read_verilog {}; synth_ice40 -top window_unit; stat",
        unit.display()
    )));
    let luts: usize = log
        .lines()
        .filter_map(|l| l.trim().strip_prefix("SB_LUT4"))
        .filter_map(|n| n.trim().parse().ok())
        .next_back()
        .expect("yosys stat lists SB_LUT4");
    assert!(luts <= 200, "{luts} LUTs");
}
