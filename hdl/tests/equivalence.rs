//! One design: rust-hdl's own netlist of the blocks (`verilog::rust_hdl_unit`, what
//! `coopwin verilog --netlist rust-hdl` writes) is proven equivalent to the shipped, parametric
//! `hdl/verilog/window_unit.v` by Yosys, at the six sizes of the contract's corners.
//!
//! The proof: the readable module with its parameters set (`chparam`), rust-hdl's netlist
//! flattened and each of its flip-flops renamed to the readable module's register of that name
//! (`fvc$q` -> `fvc`, `port.set_xn$q` -> `set_xn`), then `equiv_make` pairs every signal of the
//! same name, `equiv_simple` and `equiv_induct` prove the pairs together (an induction over the
//! paired registers: no camera or processor assumption is needed, the two agree on every input
//! sequence from any state where their registers agree) and `equiv_status -assert` fails on any
//! pair left unproven. Reference: the readable module, itself checked by the formal proofs, the
//! cocotb bench and the replays (docs/formal.md, docs/cocotb.md, hdl/tests/eda.rs).
//!
//! Two mutants, one a side, each a one-line change, must be found different: the proof must
//! leave pairs unproven, and a bounded check from power-on (a `miter` of the outputs, `sat
//! -seq`) must reach an output that differs, so the difference is real and not an artefact of
//! the induction. Without Yosys these tests fail, unless COOPWIN_ALLOW_MISSING_EDA=1 skips them.
mod common;
use common::{have_tool, scratch};
use coopwin_hdl::verilog::{rust_hdl_unit, Geometry};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The sizes of the issue: the CA-D1, VGA and HD with wider pixels, the smallest sensor, the
/// largest (12-bit counters, 16-bit pixels) and a narrow tall one (two-byte coordinates from
/// the height alone, a width that is no power of two).
const SIZES: [(usize, usize, usize); 6] =
    [(256, 256, 8), (640, 480, 10), (1920, 1080, 12), (16, 16, 8), (4096, 4096, 16), (17, 300, 9)];

fn shipped() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("verilog/window_unit.v")
}

/// The rename map: each flip-flop of rust-hdl's netlist (a `Reg` instance, its output stub
/// `NAME$q` in `window_unit` or `window_unit$port`) to the readable module's register `NAME`.
fn rename_map(netlist: &str) -> Vec<(String, String)> {
    let mut map = Vec::new();
    let mut module = "";
    for line in netlist.lines().map(str::trim) {
        if let Some(rest) = line.strip_prefix("module ") {
            module = rest.split('(').next().unwrap_or("");
            continue;
        }
        let prefix = match module {
            "window_unit" => "",
            "window_unit$port" => "port.",
            _ => continue,
        };
        // Stub declarations: `wire [7:0] sh5$q;` (rust-hdl's output stubs of a child).
        if let Some(name) = line.strip_prefix("wire ").and_then(|l| l.trim_end_matches(';').split_whitespace().last()) {
            if let Some(reg) = name.strip_suffix("$q") {
                map.push((format!("{prefix}{reg}$q"), reg.to_string()));
            }
        }
    }
    map
}

/// The registers the readable module declares (`reg ... name = init, name = init;`), sorted.
fn shipped_registers() -> Vec<&'static str> {
    static TEXT: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    let text = TEXT.get_or_init(|| std::fs::read_to_string(shipped()).unwrap());
    let mut regs: Vec<&str> = text
        .lines()
        .map(str::trim)
        .filter(|l| l.starts_with("reg "))
        .flat_map(|l| l.split("//").next().unwrap_or("").trim_end_matches(';').split(','))
        .filter_map(|decl| decl.split('=').next()?.split_whitespace().last())
        .collect();
    regs.sort_unstable();
    regs
}

/// Yosys' commands that read the shipped module at `g` as `gold` and rust-hdl's netlist as
/// `gate`, flattened, with the rename map applied.
fn read_both(gold: &Path, gate: &Path, g: &Geometry, map: &[(String, String)]) -> String {
    let renames: String = map.iter().map(|(from, to)| format!("rename {from} {to}\n")).collect();
    format!(
        "read_verilog -sv {gold}\n\
         chparam -set WIDTH {w} -set HEIGHT {h} -set PIXEL_BITS {p} window_unit\n\
         rename window_unit gold\n\
         read_verilog {gate}\n\
         rename window_unit gate\n\
         proc\n\
         flatten\n\
         cd gate\n\
         {renames}\
         cd ..\n",
        gold = gold.display(),
        gate = gate.display(),
        w = g.width,
        h = g.height,
        p = g.pixel_bits,
    )
}

/// The equivalence proof; returns (proven, Yosys' log).
fn prove(gold: &Path, netlist: &str, g: &Geometry, dir: &Path) -> (bool, String) {
    let gate = dir.join("rust_hdl.v");
    std::fs::write(&gate, netlist).unwrap();
    let map = rename_map(netlist);
    let script = format!(
        "{}equiv_make gold gate equiv\n\
         hierarchy -top equiv\n\
         equiv_simple -seq 2\n\
         equiv_induct -seq 2\n\
         equiv_status -assert\n",
        read_both(gold, &gate, g, &map)
    );
    yosys(&script, dir, "equiv")
}

/// A bounded check from power-on: the first clock (1-based) of an input sequence of up to
/// `depth` clocks on which an output of the two designs differs, if `sat` finds one (every
/// register starts at its initial value, 0).
fn differ_within(gold: &Path, netlist: &str, g: &Geometry, depth: usize, dir: &Path) -> (Option<usize>, String) {
    let gate = dir.join("rust_hdl.v");
    std::fs::write(&gate, netlist).unwrap();
    let script = format!(
        "{}miter -equiv -flatten -make_assert gold gate miter\n\
         hierarchy -top miter\n\
         sat -verify -seq {depth} -set-init-zero -prove-asserts -show-ports miter\n",
        read_both(gold, &gate, g, &[])
    );
    let (held, log) = yosys(&script, dir, "miter");
    // The trace's rows: "  <step> \trigger <decimal> <hex> <binary>".
    let first = log.lines().find_map(|l| match l.split_whitespace().collect::<Vec<_>>()[..] {
        [step, "\\trigger", "1", ..] => step.parse().ok(),
        _ => None,
    });
    (if held { None } else { first }, log)
}

/// Runs a Yosys script; returns (exit status success, log).
fn yosys(script: &str, dir: &Path, name: &str) -> (bool, String) {
    let ys = dir.join(format!("{name}.ys"));
    std::fs::write(&ys, script).unwrap();
    let out = Command::new("yosys").arg("-q").arg("-l").arg(dir.join(format!("{name}.log"))).arg("-s").arg(&ys).output().expect("run yosys");
    let log = std::fs::read_to_string(dir.join(format!("{name}.log"))).unwrap_or_default();
    (out.status.success(), format!("{log}{}", String::from_utf8_lossy(&out.stderr)))
}

/// `equiv_status`'s count of pairs, and how many of them it found unproven ("Found N $equiv
/// cells in equiv:" and "Of those cells P are proven and U are unproven.").
fn status(log: &str) -> (usize, usize) {
    let pairs = log
        .lines()
        .find_map(|l| l.trim().strip_prefix("Found ")?.strip_suffix(" $equiv cells in equiv:")?.parse().ok())
        .unwrap_or(0);
    let unproven = log
        .lines()
        .find_map(|l| l.trim().strip_prefix("Of those cells ")?.split(" and ").nth(1)?.strip_suffix(" are unproven.")?.parse().ok())
        .unwrap_or(0);
    (pairs, unproven)
}

#[test]
fn rust_hdl_netlist_equals_the_shipped_module_at_six_sizes() {
    if !have_tool("yosys") {
        return;
    }
    for (w, h, p) in SIZES {
        let g = Geometry::new(w, h, p).unwrap();
        let netlist = rust_hdl_unit(&g).unwrap();
        let map = rename_map(&netlist);
        // Every register of the readable module has its rust-hdl flip-flop, and no other.
        let mut twins: Vec<&str> = map.iter().map(|(_, to)| to.as_str()).collect();
        twins.sort_unstable();
        assert_eq!(twins, shipped_registers(), "{w}x{h}x{p}");
        let dir = scratch(&format!("equiv_{w}x{h}x{p}"));
        let t0 = std::time::Instant::now();
        let (ok, log) = prove(&shipped(), &netlist, &g, &dir);
        let (pairs, unproven) = status(&log);
        assert!(ok && unproven == 0, "{w}x{h}x{p}: not proven equivalent ({unproven} of {pairs} pairs unproven):\n{log}");
        // Every output and every renamed register was paired (and so proven).
        assert!(pairs > map.len() + 4, "{w}x{h}x{p}: only {pairs} pairs");
        eprintln!("{w}x{h}x{p}: equivalent, {pairs} pairs proven in {:.1} s", t0.elapsed().as_secs_f64());
    }
}

/// A one-line change to either design breaks the proof, and the change is a real difference:
/// some input sequence from power-on makes an output differ.
#[test]
fn a_one_line_change_to_either_design_is_found() {
    if !have_tool("yosys") {
        return;
    }
    let g = Geometry::new(16, 16, 8).unwrap();
    let netlist = rust_hdl_unit(&g).unwrap();
    let shipped_text = std::fs::read_to_string(shipped()).unwrap();
    // The shipped module with the enable the rust-hdl block had before the two were aligned:
    // the X count advances only on pixels of the frame (fvc & lvc & pvc).
    let (from, to) = ("else if (pvc & (xcount != COUNT_MAX))", "else if (pv & (xcount != COUNT_MAX))");
    assert_eq!(shipped_text.matches(from).count(), 1, "mutant site in the shipped module");
    let dir = scratch("equiv_mutant_shipped");
    let mutant = dir.join("window_unit.v");
    std::fs::write(&mutant, shipped_text.replace(from, to)).unwrap();
    check_mutant("shipped xcount enable", &mutant, &netlist, &g, &dir);

    // rust-hdl's netlist with the arming margin widened by a clock (the formal mutant
    // arm_margin, here on the rust-hdl side): a set completing as the frame starts arms it.
    let (from, to) = ("arm = fvlh & start$q;", "arm = fvlh & (start$q | port$loaded);");
    assert_eq!(netlist.matches(from).count(), 1, "mutant site in rust-hdl's netlist");
    let dir = scratch("equiv_mutant_rust_hdl");
    check_mutant("rust-hdl arm", &shipped(), &netlist.replace(from, to), &g, &dir);
}

fn check_mutant(name: &str, gold: &Path, netlist: &str, g: &Geometry, dir: &Path) {
    let (ok, log) = prove(gold, netlist, g, dir);
    let (pairs, unproven) = status(&log);
    assert!(!ok && unproven > 0, "{name}: the proof passed ({pairs} pairs):\n{log}");
    let (differ, log) = differ_within(gold, netlist, g, 30, dir);
    let Some(clock) = differ else { panic!("{name}: no output differs within 30 clocks:\n{log}") };
    eprintln!("{name}: {unproven} of {pairs} pairs unproven; an output differs on clock {clock} from power-on");
}
