//! The exported Verilog in real EDA tools: Icarus Verilog and Verilator replay rust-hdl runs
//! clock for clock (two more simulators, each independent of rust-hdl), Verilator lints every
//! size with -Wall, Yosys maps a unit to an iCE40. The replays also check what was delivered
//! against the software crop of each frame (`Window::crop`, an independent model).
//! Without the tools these tests fail, or skip visibly with COOPWIN_ALLOW_MISSING_EDA=1.
mod common;
use common::{have_tool, run, scratch, verilog_dir};
use coopwin_hdl::sim::camera::{CameraBus, RasterTiming, Window};
use coopwin_hdl::sim::driver::UnitOutputs;
use coopwin_hdl::sim::run::{run_bus, run_unit, Recording, Request};
use coopwin_hdl::verilog::Geometry;
use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;

/// The recording's inputs in `replay_tb.v`'s format.
fn stimulus(rec: &Recording) -> String {
    let mut s = String::new();
    for i in &rec.inputs {
        let (c, p) = (i.cam, i.port);
        let b = |v: bool| u8::from(v);
        let _ = writeln!(
            s,
            "{} {} {} {:x} {} {} {:x} {}",
            b(c.fval),
            b(c.lval),
            b(c.pixel_valid),
            c.pixel,
            b(i.reset),
            b(p.strobe),
            p.data,
            b(p.decimate)
        );
    }
    s
}

fn parse_outputs(text: &str) -> Vec<UnitOutputs> {
    text.lines()
        .map(|l| {
            let f: Vec<u32> = l.split_whitespace().map(|w| u32::from_str_radix(w, 16).unwrap_or_else(|_| panic!("bad line {l:?}"))).collect();
            assert_eq!(f.len(), 4, "bad line {l:?}");
            UnitOutputs { coord_ready: f[0] != 0, pixel_strobe: f[1] != 0, pixel_out: f[2] as u16, coord_error: f[3] != 0 }
        })
        .collect()
}

/// `replay_tb` over the committed `window_unit.v`, its parameters overridden to `g`.
enum Simulator {
    Icarus,
    Verilator,
}

fn replay(sim: Simulator, rec: &Recording, g: &Geometry, dir: &Path) -> Vec<UnitOutputs> {
    let (stim, out) = (dir.join("stim.txt"), dir.join("out.txt"));
    std::fs::write(&stim, stimulus(rec)).unwrap();
    let sources = [verilog_dir().join("tb/replay_tb.v"), verilog_dir().join("window_unit.v")];
    let params = [("WIDTH", g.width), ("HEIGHT", g.height), ("PIXEL_BITS", g.pixel_bits)];
    let plusargs = [format!("+stim={}", stim.display()), format!("+out={}", out.display())];
    match sim {
        Simulator::Icarus => {
            let vvp = dir.join("replay.vvp");
            let mut cmd = Command::new("iverilog");
            cmd.args(["-g2012", "-o"]).arg(&vvp);
            for (k, v) in params {
                cmd.arg(format!("-Preplay_tb.{k}={v}"));
            }
            run(cmd.args(&sources));
            run(Command::new("vvp").arg("-n").arg(&vvp).args(&plusargs));
        }
        Simulator::Verilator => {
            let mut cmd = Command::new("verilator");
            cmd.args(["--binary", "--timing", "-j", "2", "--top-module", "replay_tb", "-Mdir"]).arg(dir.join("obj"));
            for (k, v) in params {
                cmd.arg(format!("-G{k}={v}"));
            }
            run(cmd.args(&sources));
            run(Command::new(dir.join("obj/Vreplay_tb")).args(&plusargs));
        }
    }
    parse_outputs(&std::fs::read_to_string(out).unwrap())
}

/// Both simulators give rust-hdl's outputs on every clock.
fn assert_replays(name: &str, rec: &Recording, g: &Geometry) {
    for (tool, sim) in [("iverilog", Simulator::Icarus), ("verilator", Simulator::Verilator)] {
        if !have_tool(tool) {
            continue;
        }
        let got = replay(sim, rec, g, &scratch(&format!("{name}_{tool}")));
        assert_eq!(got.len(), rec.outputs.len(), "{tool}: clocks replayed");
        if let Some(t) = (0..got.len()).find(|&i| got[i] != rec.outputs[i]) {
            panic!("{tool}, clock {t}: {:?}, rust-hdl {:?}", got[t], rec.outputs[t]);
        }
    }
}

fn w(xmin: u32, xmax: u32, ymin: u32, ymax: u32) -> Window {
    Window { xmin, xmax, ymin, ymax }
}

#[test]
fn icarus_and_verilator_replay_the_ca_d1_run_clock_for_clock() {
    let t = RasterTiming { width: 256, height: 256, h_blank: 5, v_blank_lines: 3 };
    let frames: Vec<Vec<u8>> =
        (0..4).map(|f| (0..65536).map(|i| ((i * 31 + f * 97 + i / 256) % 256) as u8).collect()).collect();
    let mid = t.frame_clocks() + 120 * t.line_clocks();
    let requests = [
        Request { at: 0, window: w(3, 40, 7, 29), decimate: false },
        Request { at: mid, window: w(100, 131, 200, 255), decimate: true },
        Request { at: mid + 400, window: w(9, 9, 0, 5), decimate: false }, // invalid
        Request { at: 3 * t.frame_clocks() - 2000, window: w(0, 255, 250, 255), decimate: false },
    ];
    let rec = run_unit::<8, 8>(&t, &frames, &requests);
    // The run exercised what it should: windows delivered, an error raised.
    let delivered = rec.delivered_per_frame(&t);
    let wide = |v: Vec<u8>| v.into_iter().map(u16::from).collect::<Vec<_>>();
    assert_eq!(delivered[1], wide(requests[0].window.crop(&frames[1], 256, false)));
    assert_eq!(delivered[2], wide(requests[1].window.crop(&frames[2], 256, true)));
    assert_eq!(delivered[3], wide(requests[3].window.crop(&frames[3], 256, false)));
    assert!(rec.outputs.iter().any(|o| o.coord_error));
    assert_replays("ca_d1", &rec, &Geometry::CA_D1);
}

/// The VGA case: 640x480, 10-bit pixels, two-byte coordinates, a camera that sends
/// 10 columns and 2 lines beyond the sensor's size (never delivered, never wrapped), gaps in
/// `pixel_valid` inside lines, and a reset in the middle of a window.
#[test]
fn a_640x480_10_bit_run_with_gaps_and_a_reset_replays_and_delivers_the_crops() {
    let g = Geometry::new(640, 480, 10).unwrap();
    let t = RasterTiming { width: 650, height: 482, h_blank: 12, v_blank_lines: 2 };
    let image = |f: usize| move |x: usize, y: usize| ((x * 7 + y * 13 + f * 101) ^ (x >> 3) ^ (y << 4)) as u16 & 0x3ff;
    let lead = vec![CameraBus { fval: false, lval: false, pixel: 0, pixel_valid: true }; 40];
    let frames: Vec<Vec<CameraBus>> = (0..3)
        .map(|f| t.frame_with_gaps(image(f), |x, y| [0, 0, 0, 1, 0, 2, 0, 0, 3, 0, 0][(x * 5 + y * 3 + f) % 11]))
        .collect();
    let starts: Vec<usize> = (0..3).map(|f| lead.len() + frames[..f].iter().map(Vec::len).sum::<usize>()).collect();
    let reset_at = starts[1] + frames[1].len() / 2;
    let requests = [
        // Right and bottom edges of the sensor, next to the columns and lines beyond it.
        Request { at: 0, window: w(600, 639, 440, 479), decimate: false },
        // Written during frame 0, armed in frame 1 and cut short there by the reset.
        Request { at: starts[0] + 5000, window: w(3, 200, 100, 300), decimate: true },
        // Written after the reset: armed in frame 2.
        Request { at: reset_at + 20, window: w(320, 330, 5, 9), decimate: false },
        // Invalid: xmax is past the sensor's last column.
        Request { at: starts[2] + 1000, window: w(10, 640, 0, 20), decimate: false },
    ];
    let buses = lead.iter().chain(frames.iter().flatten()).copied();
    let rec = run_bus::<10, 10>((640, 480), buses, &requests, &[reset_at]);

    // Reference: the software crop of each frame's image (650 columns wide).
    let crop = |f: usize, r: &Request| {
        let img: Vec<u16> = (0..t.height).flat_map(|y| (0..t.width).map(move |x| (x, y))).map(|(x, y)| image(f)(x, y)).collect();
        r.window.crop(&img, t.width, r.decimate)
    };
    let strobed = |from: usize, to: usize| -> Vec<u16> { rec.outputs[from..to].iter().filter(|o| o.pixel_strobe).map(|o| o.pixel_out).collect() };
    let end = rec.outputs.len();
    assert!(strobed(0, starts[0]).is_empty());
    assert_eq!(strobed(starts[0], starts[1]), crop(0, &requests[0]));
    let cut = strobed(starts[1], starts[2]);
    let whole = crop(1, &requests[1]);
    assert!(!cut.is_empty() && cut.len() < whole.len() && whole.starts_with(&cut), "{} of {}", cut.len(), whole.len());
    assert!(strobed(reset_at, starts[2]).is_empty(), "nothing after the reset");
    assert!(!rec.outputs[reset_at + 1].coord_error);
    assert_eq!(strobed(starts[2], end), crop(2, &requests[2]));
    assert!(rec.outputs[end - 1].coord_error, "the invalid set is refused");
    assert_eq!(rec.completed.len(), 4, "four 8-byte sets taken");

    assert_replays("vga", &rec, &g);
}

/// Verilator's -Wall finds nothing in any generated file (the unit, a 2-unit network, the
/// AXI4-Stream wrapper with 1, 4 and 32 windows and its AXI4-Lite crossing) at any contract size, with no warning switched
/// off, and every generated file sets its `timescale (Icarus warns without one, and Verilator
/// refuses a design where only some modules have one).
#[test]
fn verilator_lint_is_clean_for_every_size() {
    if !have_tool("verilator") {
        return;
    }
    let dir = scratch("lint");
    let lint = |top: &str, files: &[&str], params: &[String], what: &str| {
        let out = Command::new("verilator")
            .args(["--lint-only", "-Wall", "--top-module", top])
            .args(params)
            .args(files.iter().map(|f| dir.join(f)))
            .output()
            .expect("run verilator");
        let text = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success() && !text.contains("%Warning"), "{what}:\n{text}");
    };
    for (wd, ht, bits) in [(256, 256, 8), (640, 480, 10), (1920, 1080, 12), (16, 16, 8), (4096, 4096, 16), (17, 300, 9)] {
        let g = Geometry::new(wd, ht, bits).unwrap();
        let wrapper = coopwin_hdl::verilog::axis_files(4, &g);
        for (name, text) in coopwin_hdl::verilog::exported(2, &g).into_iter().chain(wrapper) {
            assert!(text.lines().any(|l| l == "`timescale 1ns / 1ps"), "{name} at {wd}x{ht}x{bits} has no `timescale");
            std::fs::write(dir.join(name), text).unwrap();
        }
        let size = format!("{wd}x{ht}x{bits}");
        lint("window_network", &["window_unit.v", "window_network.v"], &[], &size);
        for windows in [1, 4, 32] {
            lint("window_unit_axis", &["window_unit_axis.v"], &[format!("-GWINDOWS={windows}")], &format!("axis {size}, {windows} windows"));
        }
        lint("axil_cdc", &["axil_cdc.v"], &[], "axil_cdc");
    }
}

/// Yosys maps one 256x256 unit onto an iCE40 within a budget of 200 LUTs.
#[test]
fn yosys_fits_a_unit_in_200_luts() {
    if !have_tool("yosys") {
        return;
    }
    let unit = verilog_dir().join("window_unit.v");
    let log = run(Command::new("yosys").arg("-p").arg(format!("read_verilog {}; synth_ice40 -top window_unit; stat", unit.display())));
    let luts: usize = log
        .lines()
        .filter_map(|l| l.trim().strip_prefix("SB_LUT4"))
        .filter_map(|n| n.trim().parse().ok())
        .next_back()
        .expect("yosys stat lists SB_LUT4");
    assert!(luts <= 200, "{luts} LUTs");
}

/// docs/synthesis.md's iCE40 cell counts are what Yosys gives for the committed unit and
/// AXI4-Stream wrapper today (`scripts/synth-report.sh --check`; regenerate with
/// `scripts/synth-report.sh`, the wrapper's section with `--axis`).
#[test]
fn synthesis_table_is_current() {
    if !have_tool("yosys") {
        return;
    }
    let script = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scripts/synth-report.sh");
    run(Command::new("bash").arg(script).arg("--check"));
}

/// The other sizes of the synthesis table, replayed too: 1280x720 with 8-bit and 1920x1080
/// with 12-bit pixels (11-bit counters), on frames of 24 full-length lines (the unit counts
/// whatever the camera sends; the window lies in them), each with a window, a decimated one
/// and a reset.
#[test]
fn hd_sizes_replay_clock_for_clock() {
    for (g, cols) in [(Geometry::new(1280, 720, 8).unwrap(), 1290), (Geometry::new(1920, 1080, 12).unwrap(), 1925)] {
        let t = RasterTiming { width: cols, height: 24, h_blank: 6, v_blank_lines: 1 };
        let mask = (1u32 << g.pixel_bits) - 1;
        let image = |f: usize| move |x: usize, y: usize| (((x as u32).wrapping_mul(2654435761) ^ (y * 97 + f) as u32) & mask) as u16;
        let lead = vec![CameraBus { fval: false, lval: false, pixel: 0, pixel_valid: true }; 80];
        let frames: Vec<Vec<CameraBus>> = (0..3).map(|f| t.frame_with_gaps(image(f), |x, _| usize::from(x % 7 == 3))).collect();
        let starts: Vec<usize> = (0..3).map(|f| lead.len() + frames[..f].iter().map(Vec::len).sum::<usize>()).collect();
        let xmax = g.width as u32 - 1;
        let requests = [
            Request { at: 0, window: w(xmax - 300, xmax, 2, 20), decimate: false },
            Request { at: starts[0] + 100, window: w(0, 999, 0, 23), decimate: true },
        ];
        let reset_at = starts[1] + frames[1].len() / 2;
        let buses = lead.iter().chain(frames.iter().flatten()).copied();
        let rec = match g.pixel_bits {
            8 => run_bus::<11, 8>((g.width, g.height), buses, &requests, &[reset_at]),
            _ => run_bus::<11, 12>((g.width, g.height), buses, &requests, &[reset_at]),
        };
        let strobed: Vec<u16> = rec.outputs[starts[0]..starts[1]].iter().filter(|o| o.pixel_strobe).map(|o| o.pixel_out).collect();
        let img: Vec<u16> = (0..t.height).flat_map(|y| (0..t.width).map(move |x| (x, y))).map(|(x, y)| image(0)(x, y)).collect();
        assert_eq!(strobed, requests[0].window.crop(&img, t.width, false), "{}x{}", g.width, g.height);
        assert!(rec.outputs[starts[1]..].iter().any(|o| o.pixel_strobe), "the decimated window starts");
        assert!(!rec.outputs[reset_at + 1..].iter().any(|o| o.pixel_strobe), "and the reset ends it");
        assert_replays(&format!("hd{}", g.width), &rec, &g);
    }
}
