//! The `coopwin` binary as a user runs it, on bad inputs and awkward output paths: each case
//! asserts the exit code, the one-line message, and that nothing on disk was harmed. The
//! reference for every case is the rule written in docs/system.md ("Reliability") and the
//! README: exit 2 for a bad argument, 1 for other errors, one line on stderr; outputs written
//! only to a regular file or a new path (replaced atomically) or written through (devices,
//! FIFOs, `-`).
use std::os::unix::fs::FileTypeExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::OnceLock;

struct Run {
    code: i32,
    stdout: String,
    stderr: String,
}

fn coopwin_in(dir: Option<&Path>, args: &[&str]) -> Run {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_coopwin"));
    cmd.args(args);
    if let Some(d) = dir {
        cmd.current_dir(d);
    }
    let out = cmd.output().expect("run coopwin");
    Run {
        code: out.status.code().unwrap_or(-1),
        stdout: String::from_utf8_lossy(&out.stdout).into(),
        stderr: String::from_utf8_lossy(&out.stderr).into(),
    }
}

fn coopwin(args: &[&str]) -> Run {
    coopwin_in(None, args)
}

/// The track CSV's header, as the README documents it.
const HEADER: &str = "frame,x,y,mode,source,measured_frame,file,box_x,box_y,box_w,box_h,confidence,ok,time_s,damaged,state,scale,angle_deg";

fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("reliability").join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Exit `code`, exactly one line on stderr starting `error: ` and containing every one of
/// `expect`, and no panic.
fn fails(r: &Run, code: i32, expect: &[&str], what: &str) {
    assert_eq!(r.code, code, "{what}: exit code; stderr: {}", r.stderr);
    let lines: Vec<&str> = r.stderr.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "{what}: one line on stderr, got {:?}", r.stderr);
    assert!(lines[0].starts_with("error: "), "{what}: {}", r.stderr);
    assert!(!r.stderr.contains("panicked"), "{what}: {}", r.stderr);
    for e in expect {
        assert!(r.stderr.contains(e), "{what}: expected '{e}' in: {}", r.stderr);
    }
}

/// A 12-frame scene (256x256) written once for the tests that only read it; returns the folder
/// and the target (the part's corner in frame 0, from groundtruth.csv).
fn shared_scene() -> &'static (PathBuf, String) {
    static SCENE: OnceLock<(PathBuf, String)> = OnceLock::new();
    SCENE.get_or_init(|| {
        let d = scratch("shared_scene");
        let frames = d.join("frames");
        let r = coopwin(&["scene", "--frames", "12", "--speed", "50", "--out", s(&frames)]);
        assert_eq!(r.code, 0, "{}", r.stderr);
        (frames.clone(), target_of(&frames))
    })
}

fn target_of(frames: &Path) -> String {
    let truth = std::fs::read_to_string(frames.join("groundtruth.csv")).unwrap();
    let f: Vec<&str> = truth.lines().nth(1).unwrap().split(',').collect();
    format!("{},{}", f[3], f[4])
}

// ---- outputs ---------------------------------------------------------------------------

#[test]
fn out_to_standard_output_writes_the_csv_there_and_no_file_named_dash() {
    let (frames, target) = shared_scene();
    let d = scratch("out_dash");
    let r = coopwin_in(Some(&d), &["track", "--frames", s(frames), "--target", target, "--out", "-"]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    let mut lines = r.stdout.lines();
    assert_eq!(lines.next(), Some(HEADER), "{}", r.stdout);
    assert_eq!(lines.count(), 12, "one row per frame and nothing else on stdout: {}", r.stdout);
    assert!(!d.join("-").exists(), "a file named '-' was written");
    assert!(r.stderr.contains("frames,"), "the report goes to stderr: {}", r.stderr);
}

#[test]
fn out_through_a_symlink_replaces_the_linked_file_and_keeps_the_link() {
    let (frames, target) = shared_scene();
    let d = scratch("out_symlink");
    let real = d.join("real.csv");
    std::fs::write(&real, "old\n").unwrap();
    let link = d.join("link.csv");
    std::os::unix::fs::symlink(&real, &link).unwrap();
    let r = coopwin(&["track", "--frames", s(frames), "--target", target, "--out", s(&link)]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink(), "the link became a file");
    assert!(std::fs::read_to_string(&real).unwrap().starts_with("frame,x,y"), "the linked file was not written");
    let left: Vec<_> = std::fs::read_dir(&d).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(left.len(), 2, "no temporary file left behind: {left:?}");
    // A dangling link is refused, and stays as it was.
    let dangling = d.join("dangling.csv");
    std::os::unix::fs::symlink(d.join("missing/target.csv"), &dangling).unwrap();
    let r = coopwin(&["track", "--frames", s(frames), "--out", s(&dangling)]);
    fails(&r, 2, &["symbolic link"], "dangling link");
    assert!(std::fs::symlink_metadata(&dangling).unwrap().file_type().is_symlink());
}

#[test]
fn out_to_a_fifo_writes_through_and_the_fifo_stays() {
    let (frames, target) = shared_scene();
    let d = scratch("out_fifo");
    let fifo = d.join("pipe");
    assert!(Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
    };
    let r = coopwin(&["track", "--frames", s(frames), "--target", target, "--out", s(&fifo)]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    let got = reader.join().unwrap();
    assert!(got.starts_with(&format!("{HEADER}\n")), "{got}");
    assert_eq!(got.lines().count(), 13);
    assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo(), "the FIFO was replaced");
}

#[test]
fn out_to_dev_null_leaves_the_device_in_place() {
    let (frames, _) = shared_scene();
    let r = coopwin(&["track", "--frames", s(frames), "--out", "/dev/null"]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    assert!(std::fs::metadata("/dev/null").unwrap().file_type().is_char_device());
}

#[test]
fn out_paths_that_cannot_be_written_are_refused_before_the_run_and_named() {
    let (frames, _) = shared_scene();
    let d = scratch("out_refused");
    // A folder.
    let r = coopwin(&["track", "--frames", s(frames), "--out", s(&d)]);
    fails(&r, 2, &["is a folder"], "folder");
    // A missing parent folder: refused, nothing created.
    let deep = d.join("no/such/dir/x.csv");
    let r = coopwin(&["track", "--frames", s(frames), "--out", s(&deep)]);
    fails(&r, 2, &["does not exist", "create it first"], "missing parent");
    assert!(!d.join("no").exists(), "a folder was created");
    let r = coopwin(&["waves", "--out", s(&deep.with_extension("vcd"))]);
    fails(&r, 2, &["does not exist"], "waves, missing parent");
    assert!(!d.join("no").exists(), "waves created a folder");
    // A folder that exists but cannot take files: the message names the path asked for.
    let r = coopwin(&["track", "--frames", s(frames), "--out", "/proc/nope.csv"]);
    fails(&r, 1, &["/proc/nope.csv"], "/proc");
    assert!(!r.stderr.contains("partial"), "{}", r.stderr);
    // `--vcd -` has no folder for its requests CSV.
    let r = coopwin(&["track", "--frames", s(frames), "--hdl", "rust-hdl", "--vcd", "-"]);
    fails(&r, 2, &["file name"], "--vcd -");
}

#[test]
fn a_failed_run_leaves_an_existing_output_as_it_was() {
    let d = scratch("out_kept");
    let bad = d.join("frames");
    std::fs::create_dir(&bad).unwrap();
    image::GrayImage::new(64, 64).save(bad.join("a.png")).unwrap();
    std::fs::write(bad.join("b.png"), b"not a png").unwrap();
    let out = d.join("out.csv");
    std::fs::write(&out, "keep me\n").unwrap();
    let r = coopwin(&["track", "--frames", s(&bad), "--out", s(&out)]);
    fails(&r, 1, &["b.png", "not a readable PNG"], "corrupt frame");
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "keep me\n");
    let names: Vec<_> = std::fs::read_dir(&d).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(names.len(), 2, "nothing else written: {names:?}");
}

#[test]
fn scene_refuses_a_folder_that_is_not_empty_unless_forced_and_never_mixes_scenes() {
    let d = scratch("scene_nonempty");
    let out = d.join("scene");
    std::fs::create_dir(&out).unwrap();
    std::fs::write(out.join("notes.txt"), "mine\n").unwrap();
    let r = coopwin(&["scene", "--frames", "3", "--out", s(&out)]);
    fails(&r, 2, &["not empty", "--force"], "non-empty folder");
    assert_eq!(std::fs::read_dir(&out).unwrap().count(), 1, "something was written");
    // With --force the scene goes in beside the other file.
    let r = coopwin(&["scene", "--frames", "3", "--out", s(&out), "--force"]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    assert_eq!(std::fs::read_to_string(out.join("notes.txt")).unwrap(), "mine\n");
    assert_eq!(std::fs::read_to_string(out.join("groundtruth.csv")).unwrap().lines().count(), 4);
    // A shorter scene over it would leave frame_00002.png from the first: refused.
    let before = std::fs::read_to_string(out.join("groundtruth.csv")).unwrap();
    let r = coopwin(&["scene", "--frames", "2", "--out", s(&out), "--force"]);
    fails(&r, 2, &["mix two scenes"], "stale frames");
    assert_eq!(std::fs::read_to_string(out.join("groundtruth.csv")).unwrap(), before);
    // A missing parent is refused, as for every output.
    let r = coopwin(&["scene", "--frames", "3", "--out", s(&d.join("a/b"))]);
    fails(&r, 2, &["does not exist"], "scene, missing parent");
    assert!(!d.join("a").exists());
}

// ---- frames ----------------------------------------------------------------------------

#[test]
fn frames_are_taken_in_natural_order_listed_on_request_and_named_in_the_csv() {
    let d = scratch("natural");
    let frames = d.join("frames");
    std::fs::create_dir(&frames).unwrap();
    for k in 0..12 {
        image::GrayImage::from_pixel(64, 64, image::Luma([k as u8 * 10])).save(frames.join(format!("img{k}.png"))).unwrap();
    }
    // Reference: the names written above, in the order they were numbered.
    let want: Vec<String> = (0..12).map(|k| format!("img{k}.png")).collect();
    let r = coopwin(&["track", "--frames", s(&frames), "--list"]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    let listed: Vec<String> = r.stdout.lines().skip(1).map(|l| l.split_once(',').unwrap().1.to_string()).collect();
    assert_eq!(listed, want);
    let idx: Vec<usize> = r.stdout.lines().skip(1).map(|l| l.split_once(',').unwrap().0.parse().unwrap()).collect();
    assert_eq!(idx, (0..12).collect::<Vec<_>>());
    let out = d.join("t.csv");
    let r = coopwin(&["track", "--frames", s(&frames), "--out", s(&out)]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    let csv = std::fs::read_to_string(&out).unwrap();
    // The seventh column (no name here holds a comma).
    let files: Vec<String> = csv.lines().skip(1).map(|l| l.split(',').nth(6).unwrap().to_string()).collect();
    assert_eq!(files, want);
}

/// A 10-frame scene with `damage` done to the bytes of its frame_00005.png, tracked: the run
/// and where its CSV would be.
fn track_with_a_damaged_frame(name: &str, damage: impl FnOnce(&mut Vec<u8>)) -> (Run, PathBuf) {
    let d = scratch(name);
    let frames = d.join("frames");
    let r = coopwin(&["scene", "--frames", "10", "--out", s(&frames)]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    let victim = frames.join("frame_00005.png");
    let mut bytes = std::fs::read(&victim).unwrap();
    damage(&mut bytes);
    std::fs::write(&victim, &bytes).unwrap();
    let out = d.join("t.csv");
    (coopwin(&["track", "--frames", s(&frames), "--target", &target_of(&frames), "--out", s(&out)]), out)
}

#[test]
fn a_truncated_frame_is_named_before_the_run() {
    let (r, out) = track_with_a_damaged_frame("truncated", |b| b.truncate(b.len() / 2));
    fails(&r, 1, &["frame_00005.png", "not a readable PNG"], "truncated PNG");
    assert!(!out.exists(), "a CSV was written for a folder with a bad frame");
    assert!(!r.stdout.contains("tracked"), "the run started: {}", r.stdout);
}

#[test]
fn a_frame_damaged_inside_is_named_when_reached_and_nothing_is_written() {
    // Its header and its end are whole, so the folder's check before the run passes; its
    // pixel data is not, and decoding it (once, when tracked) names it.
    let (r, out) = track_with_a_damaged_frame("damaged_inside", |b| {
        let mid = b.len() / 2;
        b[mid - 32..mid + 32].fill(0xff);
    });
    fails(&r, 1, &["frame_00005.png"], "PNG damaged inside");
    assert!(!out.exists(), "a CSV was written for a folder with a bad frame");
}

// ---- arguments -------------------------------------------------------------------------

#[test]
fn every_bad_argument_exits_2_with_one_line_that_says_why() {
    let (frames, _) = shared_scene();
    let f = s(frames);
    let d = scratch("args");
    let big_scene = d.join("big");
    let cases: Vec<(Vec<&str>, Vec<&str>)> = vec![
        (vec!["track", "--frames", f, "--template", "0"], vec!["4..32"]),
        (vec!["track", "--frames", f, "--template=-3"], vec!["negative", "4..32"]),
        (vec!["track", "--frames", f, "--template", "33"], vec!["4..32"]),
        (vec!["track", "--frames", f, "--coop-n", "12"], vec!["3..8"]),
        (vec!["track", "--frames", f, "--target", "-5,10"], vec!["negative"]),
        (vec!["track", "--frames", f, "--target", "NaN,NaN"], vec!["not a number"]),
        (vec!["track", "--frames", f, "--target", "inf,4"], vec!["not a number"]),
        (vec!["track", "--frames", f, "--target", "1e308,5"], vec!["beyond the largest frame", "0..4095"]),
        (vec!["track", "--frames", f, "--target", "300,10"], vec!["outside the 256x256 frames"]),
        (vec!["track", "--frames", f, "--target", "10"], vec!["X,Y"]),
        (vec!["track", "--frames", f, "--hdl", "rust-hdl", "--vcd", "v.vcd", "--vcd-frames", "5..3"], vec!["reversed"]),
        (vec!["track", "--frames", f, "--hdl", "rust-hdl", "--vcd", "v.vcd", "--vcd-frames", "4..4"], vec!["empty"]),
        (vec!["track", "--frames", f, "--hdl", "rust-hdl", "--vcd", "v.vcd", "--vcd-frames", "3..99"], vec!["0..12"]),
        (vec!["track", "--frames", f, "--vcd", "v.vcd"], vec!["--hdl rust-hdl"]),
        (vec!["track", "--frames", f, "--write-phase", "-3"], vec!["negative"]),
        (vec!["track", "--frames", f, "--write-phase", "70192"], vec!["70192 clocks"]),
        (vec!["track", "--frames", f, "--blank-jitter", "-5,10"], vec!["negative"]),
        (vec!["track", "--frames", f, "--blank-jitter", "5000,10"], vec!["4096"]),
        (vec!["corner", "--image", "x.png", "--threshold", "-5"], vec!["-5"]),
        (vec!["motion", "--prev", "a.png", "--next", "b.png", "--threshold", "-5"], vec!["-5", "0..=255"]),
        (vec!["scene", "--frames", "100000000", "--out", s(&big_scene)], vec!["20000"]),
        (vec!["scene", "--frames", "0", "--out", s(&big_scene)], vec!["1..20000"]),
        (vec!["scene", "--speed", "NaN", "--out", s(&big_scene)], vec!["not a number"]),
        (vec!["scene", "--speed", "-5", "--out", s(&big_scene)], vec!["--speed", "0..10000", "-5"]),
        (vec!["scene", "--noise", "1e300", "--out", s(&big_scene)], vec!["--noise", "0..255"]),
        (vec!["waves", "--out", "x.vcd", "--frames", "0"], vec!["1..100"]),
        (vec!["waves", "--out", "x.vcd", "--window", "5,5,1,2"], vec!["XMIN < XMAX"]),
        (vec!["waves", "--out", "x.vcd", "--window", "0,300,0,10"], vec!["xmax <= 255"]),
        (vec!["waves", "--out", "x.vcd", "--width", "640", "--height", "480", "--window", "0,700,0,10"], vec!["xmax <= 639"]),
        (vec!["waves", "--out", "x.vcd", "--width", "8"], vec!["16 to 4096", "8"]),
        (vec!["waves", "--out", "x.vcd", "--pixel-bits", "17"], vec!["8 to 16"]),
        (vec!["track", "--frames", f, "--hdl", "rust-hdl", "--pixel-bits", "7"], vec!["--pixel-bits", "8..=16"]),
        (vec!["track", "--frames", f, "--pixel-bits", "10"], vec!["--hdl rust-hdl or --hdl verilator"]),
        (vec!["verilog", "--out", s(&d), "--units", "0"], vec!["1..64"]),
        (vec!["experiment", "fig-9.9", "--out", s(&d)], vec!["unknown experiment"]),
        (vec!["track"], vec!["--frames"]),
        (vec!["track", "--frames", f, "--strategy", "best"], vec!["best"]),
    ];
    for (args, expect) in cases {
        let r = coopwin_in(Some(&d), &args);
        fails(&r, 2, &expect, &format!("{args:?}"));
        assert!(r.stderr.len() < 300, "{args:?}: a long message: {}", r.stderr);
    }
    assert!(!big_scene.exists(), "a refused scene wrote files");
    assert!(!d.join("v.vcd").exists() && !d.join("x.vcd").exists(), "a refused run wrote a VCD");
}

#[test]
fn match_refuses_degenerate_templates() {
    let d = scratch("match_degenerate");
    let img = image::GrayImage::from_fn(40, 40, |x, y| image::Luma([((x * 7 + y * 13 + x * y) % 251) as u8]));
    img.save(d.join("img.png")).unwrap();
    image::GrayImage::from_pixel(1, 1, image::Luma([90])).save(d.join("one.png")).unwrap();
    image::GrayImage::from_pixel(8, 8, image::Luma([90])).save(d.join("flat.png")).unwrap();
    // 4x4 is enough at full resolution; at 25% (every other pixel of every other row) it is 2x2.
    image::imageops::crop_imm(&img, 3, 4, 4, 4).to_image().save(d.join("four.png")).unwrap();
    let m = |t: &str, method: &str, extra: &[&str]| {
        let mut a = vec!["match", "--image", "img.png", "--template", t, "--method", method];
        a.extend_from_slice(extra);
        coopwin_in(Some(&d), &a)
    };
    fails(&m("one.png", "ncc", &[]), 1, &["one.png", "1x1", "3x3"], "1x1 ncc");
    fails(&m("one.png", "ssd", &[]), 1, &["3x3"], "1x1 ssd");
    fails(&m("flat.png", "ncc", &[]), 1, &["flat.png", "flat"], "flat ncc");
    fails(&m("flat.png", "zncc", &[]), 1, &["flat"], "flat zncc");
    // SSD has a meaning for a flat template (the closest gray patch): allowed.
    assert_eq!(m("flat.png", "ssd", &[]).code, 0);
    // The cut 4x4 patch is found where it was cut.
    let r = m("four.png", "ncc", &[]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    let v: serde_json::Value = serde_json::from_str(&r.stdout).unwrap();
    assert_eq!((v["x"].as_u64(), v["y"].as_u64()), (Some(3), Some(4)), "{}", r.stdout);
    fails(&m("four.png", "ncc", &["--decimate"]), 1, &["2x2", "25%"], "4x4 at 25%");
}

#[test]
fn an_audit_that_verified_nothing_fails() {
    let (frames, target) = shared_scene();
    let d = scratch("audit_nothing");
    let vcd = d.join("run.vcd");
    // Reference (found by running it): with the C40's timing, in COOP's frame 2 units 1-3 take
    // windows and unit 0 none; the audit of unit 1 verifies one, the audit of unit 0 nothing.
    let r = coopwin(&["track", "--frames", s(frames), "--target", target, "--profile", "c40", "--hdl", "rust-hdl", "--vcd", s(&vcd), "--vcd-frames", "2..3"]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    let req = d.join("run.requests.csv");
    let r = coopwin(&["audit", s(&vcd), "--requests", s(&req), "--unit", "1"]);
    assert_eq!(r.code, 0, "unit 1 works in this trace: {} {}", r.stdout, r.stderr);
    assert!(r.stdout.contains(" 1 windows verified, 0 violations"), "{}", r.stdout);
    let r = coopwin(&["audit", s(&vcd), "--requests", s(&req), "--unit", "0"]);
    fails(&r, 1, &["nothing verified"], "audit of nothing");
}

// ---- the summary -----------------------------------------------------------------------

#[test]
fn a_lost_run_reads_as_lost_before_any_error_figure() {
    let d = scratch("lost");
    let frames = d.join("frames");
    let r = coopwin(&["scene", "--frames", "30", "--speed", "60", "--out", s(&frames)]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    // Reference: the same scene with every frame after the first replaced by a flat gray
    // frame: the part is gone, so no run can track it, whatever it reports.
    for k in 1..30 {
        image::GrayImage::from_pixel(256, 256, image::Luma([128])).save(frames.join(format!("frame_{k:05}.png"))).unwrap();
    }
    let r = coopwin(&["track", "--frames", s(&frames), "--target", &target_of(&frames)]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    let verdict = r.stdout.lines().position(|l| l.starts_with("LOST:"));
    let table = r.stdout.lines().position(|l| l.contains("RMS error"));
    assert!(verdict.is_some() && verdict < table, "the loss is not said first: {}", r.stdout);
}

// ---- the Verilator model -----------------------------------------------------------------

mod common;
use common::have_verilator as verilator;

#[test]
fn two_processes_build_the_verilator_model_from_nothing_at_once() {
    if !verilator() {
        return;
    }
    let (frames, target) = shared_scene();
    // A cache folder no run has used: both processes find no library and build it together.
    let tmp = scratch("verilator_race");
    let start = || {
        Command::new(env!("CARGO_BIN_EXE_coopwin"))
            .args(["track", "--frames", s(frames), "--target", target, "--hdl", "verilator", "--out", "-"])
            .env("XDG_CACHE_HOME", &tmp)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap()
    };
    let (a, b) = (start(), start());
    let (a, b) = (a.wait_with_output().unwrap(), b.wait_with_output().unwrap());
    for o in [&a, &b] {
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    // Reference: the behavioural model's CSV for the same run.
    let model = coopwin(&["track", "--frames", s(frames), "--target", target, "--out", "-"]);
    assert_eq!(a.stdout, model.stdout.as_bytes(), "Verilator and the model disagree");
    assert_eq!(a.stdout, b.stdout);
    // One library, and no build folder left behind.
    let keyed: Vec<PathBuf> = std::fs::read_dir(tmp.join("coopwin")).unwrap().map(|e| e.unwrap().path()).collect();
    assert_eq!(keyed.len(), 1, "{keyed:?}");
    let inside: Vec<String> = std::fs::read_dir(&keyed[0]).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into()).collect();
    assert_eq!(inside, vec!["libwindow_network.so".to_string()]);
}
