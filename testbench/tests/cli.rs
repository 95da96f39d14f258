//! The `coopwin` binary's error paths and outputs, run as a user would.
use std::path::{Path, PathBuf};
use std::process::Command;

fn coopwin(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_coopwin")).args(args).output().expect("run coopwin");
    (out.status.success(), String::from_utf8_lossy(&out.stdout).into(), String::from_utf8_lossy(&out.stderr).into())
}

fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn one_error_line(stderr: &str) {
    let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "{stderr}");
    assert!(lines[0].starts_with("error: "), "{stderr}");
    assert!(!stderr.contains("panicked"));
}

fn track_fails(dir: &Path, expect: &str) {
    // Beside the folder, which may not exist (an output's folder must).
    let out = dir.with_extension("out.csv");
    let (ok, _, err) = coopwin(&["track", "--frames", dir.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert!(!ok);
    one_error_line(&err);
    assert!(err.contains(expect), "{err}");
    assert!(!out.exists(), "nothing half-written");
}

#[test]
fn track_refuses_bad_folders_with_one_clear_line() {
    let d = scratch("cli_missing");
    track_fails(&d.join("nope"), "no such file or folder");
    track_fails(&d, "no PNG frames");
    let mixed = scratch("cli_mixed");
    image::GrayImage::new(64, 64).save(mixed.join("a.png")).unwrap();
    image::GrayImage::new(80, 64).save(mixed.join("b.png")).unwrap();
    track_fails(&mixed, "mixed frame sizes");
    let corrupt = scratch("cli_corrupt");
    image::GrayImage::new(64, 64).save(corrupt.join("a.png")).unwrap();
    std::fs::write(corrupt.join("b.png"), b"not a png").unwrap();
    track_fails(&corrupt, "not a readable PNG");
    let tiny = scratch("cli_tiny");
    image::GrayImage::new(32, 32).save(tiny.join("a.png")).unwrap();
    track_fails(&tiny, "64x64 to 4096x4096");
}

/// A `frames`-frame triangle scene at 50 px/s written by `coopwin scene` into a scratch
/// folder `name`: the folder and the frames' folder in it.
fn triangle_scene(name: &str, frames: u32) -> (PathBuf, PathBuf) {
    let d = scratch(name);
    let out = d.join("frames");
    let (ok, _, err) = coopwin(&["scene", "--path", "triangle", "--frames", &frames.to_string(), "--speed", "50", "--out", out.to_str().unwrap()]);
    assert!(ok, "{err}");
    (d, out)
}

#[test]
fn scene_then_track_writes_the_csv_with_the_documented_columns() {
    let (d, frames) = triangle_scene("cli_scene", 40);
    let truth = std::fs::read_to_string(frames.join("groundtruth.csv")).unwrap();
    let first: Vec<f64> = truth.lines().nth(1).unwrap().split(',').map(|v| v.parse().unwrap()).collect();
    let target = format!("{},{}", first[3], first[4]);
    let csv = d.join("t.csv");
    let (ok, out, err) = coopwin(&[
        "track", "--frames", frames.to_str().unwrap(), "--strategy", "tpdf", "--target", &target, "--out", csv.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert!(out.contains("| tpdf |"), "summary printed: {out}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next().unwrap(), "frame,x,y,mode,source,measured_frame,file,box_x,box_y,box_w,box_h,confidence,ok,time_s,damaged,state,scale,angle_deg");
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 40);
    assert!(rows.iter().any(|r| r[3] == "track" && r[4] == "ncc" && !r[1].is_empty()));
}

#[test]
fn a_flat_target_is_refused_and_start_frame_tracks_from_a_later_frame() {
    // A clip that opens on a black frame (as opencv-doc's Megamind.avi): the target's template
    // there is flat, and the run is refused with the way out, not tracked to nothing.
    let (d, frames) = triangle_scene("cli_start_frame", 12);
    let mut names: Vec<String> = std::fs::read_dir(&frames).unwrap().filter_map(|e| e.ok()?.file_name().into_string().ok()).filter(|n| n.ends_with(".png")).collect();
    names.sort();
    let (w, h) = image::image_dimensions(frames.join(&names[0])).unwrap();
    image::GrayImage::new(w, h).save(frames.join(&names[0])).unwrap();
    let truth = std::fs::read_to_string(frames.join("groundtruth.csv")).unwrap();
    let corner = |k: usize| {
        let f: Vec<f64> = truth.lines().nth(1 + k).unwrap().split(',').map(|v| v.parse().unwrap()).collect();
        format!("{},{}", f[3], f[4])
    };
    let csv = d.join("t.csv");
    let track = |extra: &[&str], target: &str| {
        let mut args = vec!["track", "--frames", frames.to_str().unwrap(), "--target", target, "--out", csv.to_str().unwrap()];
        args.extend_from_slice(extra);
        coopwin(&args)
    };
    let (ok, _, err) = track(&[], &corner(0));
    assert!(!ok);
    one_error_line(&err);
    assert!(err.contains("flat on the first frame tracked (every pixel 0)") && err.contains("--start-frame"), "{err}");
    assert!(!csv.exists(), "nothing written");
    // From frame 1, where the target is: the rows keep the folder's numbers and file names.
    let (ok, out, err) = track(&["--start-frame", "1"], &corner(1));
    assert!(ok, "{err}");
    assert!(out.contains("11 frames, 11 tracked"), "{out}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let rows: Vec<Vec<&str>> = text.lines().skip(1).map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 11);
    for (k, r) in rows.iter().enumerate() {
        assert_eq!((r[0], r[6]), ((k + 1).to_string().as_str(), names[k + 1].as_str()));
    }
    assert_eq!(rows[0][5], "1", "measured in frame 1");
    // Times are the source's too: frame 1 one period after frame 0, not at 0.
    let time = |r: &Vec<&str>| r[13].parse::<f64>().unwrap();
    let period = time(&rows[1]) - time(&rows[0]);
    assert!(period > 0.0 && (time(&rows[0]) - period).abs() < 1e-5, "{} {period}", time(&rows[0]));
    // A start past the end is an argument error.
    let (ok, _, err) = track(&["--start-frame", "12"], &corner(1));
    assert!(!ok);
    one_error_line(&err);
    assert!(err.contains("--start-frame 12: the input has 12 frames (0..11)"), "{err}");
}

#[test]
fn bad_arguments_exit_non_zero() {
    for args in [
        vec!["waves", "--out", "x.vcd", "--window", "5,5,1,2"],
        vec!["verilog", "--out", "/tmp/x", "--units", "0"],
        vec!["experiment", "fig-9.9", "--out", "/tmp/x"],
        vec!["track", "--frames", "/tmp", "--coop-n", "12"],
        vec!["track", "--frames", "/tmp", "--blank-jitter", "5"],
        vec!["track", "--frames", "/tmp", "--blank-jitter", "5,x"],
        vec!["track", "--frames", "/tmp", "--blank-jitter", "5000,10"],
        vec!["track", "--frames", "/tmp", "--write-phase", "-3"],
    ] {
        let (ok, _, err) = coopwin(&args);
        assert!(!ok, "{args:?}");
        assert!(!err.contains("panicked"), "{err}");
    }
}

#[test]
fn fault_options_are_checked_against_the_raster() {
    let d = scratch("cli_faults");
    let frames = d.join("frames");
    let (ok, _, err) = coopwin(&["scene", "--frames", "3", "--out", frames.to_str().unwrap()]);
    assert!(ok, "{err}");
    // A 256x256 frame is 70 192 clocks: a later phase is never reached within a frame.
    let (ok, _, err) = coopwin(&["track", "--frames", frames.to_str().unwrap(), "--write-phase", "70192"]);
    assert!(!ok);
    one_error_line(&err);
    assert!(err.contains("70192"), "{err}");
    let (ok, _, err) = coopwin(&["track", "--frames", frames.to_str().unwrap(), "--blank-jitter", "8,100,3"]);
    assert!(ok, "{err}");
}

#[test]
fn kernel_commands_answer_in_json_and_refuse_bad_input() {
    // Reference: a template cut from the image at a known place must be found there.
    let d = scratch("cli_kernels");
    let img = image::GrayImage::from_fn(40, 40, |x, y| image::Luma([((x * 7 + y * 13 + x * y) % 251) as u8]));
    let tpl = image::imageops::crop_imm(&img, 9, 14, 16, 16).to_image();
    img.save(d.join("img.png")).unwrap();
    tpl.save(d.join("tpl.png")).unwrap();
    for method in ["ncc", "zncc", "ssd", "sad"] {
        let (ok, out, err) = coopwin(&["match", "--image", d.join("img.png").to_str().unwrap(), "--template", d.join("tpl.png").to_str().unwrap(), "--method", method]);
        assert!(ok, "{err}");
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        assert_eq!((v["x"].as_u64(), v["y"].as_u64()), (Some(9), Some(14)), "{method}: {out}");
    }
    let (ok, _, err) = coopwin(&["match", "--image", d.join("tpl.png").to_str().unwrap(), "--template", d.join("img.png").to_str().unwrap()]);
    assert!(!ok);
    one_error_line(&err);
    assert!(err.contains("larger than the image"));
    let (ok, _, err) = coopwin(&["corner", "--image", d.join("missing.png").to_str().unwrap(), "--threshold", "50"]);
    assert!(!ok);
    one_error_line(&err);
    // A bright square's top-left corner in a 24x24 window: the corner is near (8, 8).
    let sq = image::GrayImage::from_fn(24, 24, |x, y| image::Luma([if x >= 8 && y >= 8 { 200 } else { 40 }]));
    sq.save(d.join("sq.png")).unwrap();
    let (ok, out, err) = coopwin(&["corner", "--image", d.join("sq.png").to_str().unwrap(), "--threshold", "50"]);
    assert!(ok, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(v["edge_pixels"].as_u64().unwrap() > 0, "{out}");
    // Motion: one pixel changed by more than the threshold.
    let mut b = img.clone();
    b.put_pixel(30, 5, image::Luma([img.get_pixel(30, 5)[0].wrapping_add(100)]));
    b.save(d.join("b.png")).unwrap();
    let (ok, out, err) = coopwin(&["motion", "--prev", d.join("img.png").to_str().unwrap(), "--next", d.join("b.png").to_str().unwrap(), "--threshold", "30"]);
    assert!(ok, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!((v["xmin"].as_u64(), v["ymin"].as_u64(), v["count"].as_u64()), (Some(30), Some(5), Some(1)), "{out}");
}

// Issue 39: the CLI's rough edges, each through the binary.

/// Runs coopwin with `envs` set: (exit code, stdout, stderr).
fn coopwin_env(args: &[&str], envs: &[(&str, &str)]) -> (Option<i32>, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_coopwin")).args(args).envs(envs.iter().copied()).output().expect("run coopwin");
    (out.status.code(), String::from_utf8_lossy(&out.stdout).into(), String::from_utf8_lossy(&out.stderr).into())
}

#[test]
fn errors_name_the_option_given_and_a_missing_input_is_no_such_file() {
    let (d, frames) = triangle_scene("cli_option_named", 4);
    let f = frames.to_str().unwrap();
    // A box whose centre (259.5, 259.5) is off the 256x256 frames: named as given.
    let (code, _, err) = coopwin_env(&["track", "--frames", f, "--target-box", "240,240,40,40"], &[]);
    assert_eq!(code, Some(2), "{err}");
    one_error_line(&err);
    assert!(err.contains("--target-box 240,240,40,40: its centre (259.5, 259.5) is outside the 256x256 frames"), "{err}");
    assert!(!err.contains("--target "), "an option the user did not give: {err}");
    let (code, _, err) = coopwin_env(&["track", "--frames", f, "--target", "300,10"], &[]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("--target 300,10 is outside the 256x256 frames"), "{err}");
    // A missing video is no such file, not a folder that cannot be read.
    let missing = d.join("missing.avi");
    let (code, _, err) = coopwin_env(&["track", "--frames", missing.to_str().unwrap(), "--target-box", "10,10,20,20"], &[]);
    assert_eq!(code, Some(1), "{err}");
    one_error_line(&err);
    assert!(err.contains("missing.avi: no such file or folder") && !err.contains("folder missing.avi"), "{err}");
}

/// A box the template does not cover is noted, once, with the template's side (the box's
/// shorter side up to 32, as `--help` says); a box it covers is not. The closing line counts
/// the rows vouched for apart from those tracked.
#[test]
fn a_box_larger_than_the_template_is_noted() {
    let (d, frames) = triangle_scene("cli_box_note", 4);
    let (f, csv) = (frames.to_str().unwrap(), d.join("t.csv"));
    let track = |bbox: &str| coopwin_env(&["track", "--frames", f, "--target-box", bbox, "--out", csv.to_str().unwrap()], &[]);
    let (code, out, err) = track("100,100,40,60");
    assert_eq!(code, Some(0), "{err}");
    assert_eq!(err.matches("note: --target-box 100,100,40,60 is larger than the 32x32 template cut at its centre").count(), 1, "{err}");
    assert!(out.contains("4 frames, ") && out.contains(" vouched for (the CSV's ok 1"), "{out}");
    let (code, _, err) = track("100,100,20,30");
    assert_eq!(code, Some(0), "{err}");
    assert!(err.contains("larger than the 20x20 template"), "{err}");
    let (code, _, err) = track("100,100,24,24");
    assert_eq!(code, Some(0), "{err}");
    assert!(!err.contains("note:"), "{err}");
}

/// `--bin 2` tracks the frames binned 2x2 and reports in the frames' pixels. Reference: the
/// scene's ground truth (the renderer's exact centre); a position left in the binned frames'
/// pixels would be half of it, 36-40 px off. A binning the frames or the box cannot take is
/// refused, naming `--bin`; a box larger than the template is binned unasked, and says so.
#[test]
fn a_binned_run_reports_in_the_frames_pixels() {
    let (d, frames) = triangle_scene("cli_bin", 20);
    let (f, csv) = (frames.to_str().unwrap(), d.join("t.csv"));
    let truth = std::fs::read_to_string(frames.join("groundtruth.csv")).unwrap();
    let truth: Vec<Vec<f64>> = truth.lines().skip(1).map(|l| l.split(',').map(|v| v.parse().unwrap()).collect()).collect();
    let target = format!("{},{}", truth[0][1], truth[0][2]);
    let track = |extra: &[&str]| {
        let mut args = vec!["track", "--frames", f, "--out", csv.to_str().unwrap()];
        args.extend_from_slice(extra);
        coopwin_env(&args, &[])
    };
    let (code, _, err) = track(&["--target", &target, "--bin", "2"]);
    assert_eq!(code, Some(0), "{err}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let rows: Vec<Vec<&str>> = text.lines().skip(1).map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 20);
    // The frames' rate, not the binned frames': 8e6 / ((256 + 2) (256 + 16) + 16) = 113.97/s.
    let period = (16.0 + 258.0 * 272.0) / 8e6;
    assert!((rows[1][13].parse::<f64>().unwrap() - period).abs() < 1e-6, "{:?}", rows[1]);
    for (r, t) in rows.iter().zip(&truth) {
        assert_eq!(r[12], "1", "{r:?}");
        let (x, y): (f64, f64) = (r[1].parse().unwrap(), r[2].parse().unwrap());
        // Within half a pixel of the truth (0.36 px at most, measured): a mapping half a binned
        // pixel off would put some rows 0.5-0.9 px off.
        assert!((x - t[1]).hypot(y - t[2]) < 0.5, "frame {}: ({x}, {y}) against ({}, {})", r[0], t[1], t[2]);
        // The default template's 20x20 spans 40x40 of the frames' pixels (times the scale the
        // adapting track measures, 0.98-1.00 here).
        assert!((r[9].parse::<f64>().unwrap() - 40.0).abs() < 1.0, "{r:?}");
    }
    let (code, _, err) = track(&["--target", &target, "--bin", "8"]);
    assert_eq!(code, Some(2), "{err}");
    one_error_line(&err);
    assert!(err.contains("--bin 8: the 256x256 frames binned 8x8 are 32x32, under the least frame, 64x64"), "{err}");
    // A target in the last column, which 3x3 blocks (85 of them, 255 columns) drop, is refused.
    let (code, _, err) = track(&["--target", "255,100", "--bin", "3"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("--target 255,100 is outside the 256x256 frames binned 3x3 (X 0..254, Y 0..254)"), "{err}");
    // A template that does not fit is named in the frames' pixels: 20x20 binned is 40x40.
    let (code, _, err) = track(&["--target", "255,100", "--bin", "2"]);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("the 40x40 template around (255, 100) does not fit"), "{err}");
    let (code, _, err) = track(&["--target-box", "60,60,12,12", "--bin", "4"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("--bin 4: the --target-box's 12x12 binned 4x4 leaves a 3x3 template"), "{err}");
    // 48x80: binned 2x2 (24x40), its 24x24 template spanning 48x48, so the box is noted too.
    let (code, _, err) = track(&["--target-box", "50,40,48,80"]);
    assert_eq!(code, Some(0), "{err}");
    assert!(err.contains("note: the frames are binned 2x2 for --target-box 50,40,48,80") && err.contains("its 24x24 template spans 48x48"), "{err}");
    assert!(err.contains("larger than the 48x48 template cut at its centre"), "{err}");
}

#[test]
fn end_frame_stops_before_the_frame_named() {
    let (d, frames) = triangle_scene("cli_end_frame", 20);
    let (f, csv) = (frames.to_str().unwrap(), d.join("t.csv"));
    let truth = std::fs::read_to_string(frames.join("groundtruth.csv")).unwrap();
    let t: Vec<f64> = truth.lines().nth(3).unwrap().split(',').map(|v| v.parse().unwrap()).collect();
    let target = format!("{},{}", t[3], t[4]);
    let track = |extra: &[&str]| {
        let mut args = vec!["track", "--frames", f, "--target", &target, "--out", csv.to_str().unwrap()];
        args.extend_from_slice(extra);
        coopwin_env(&args, &[])
    };
    let (code, out, err) = track(&["--start-frame", "2", "--end-frame", "12"]);
    assert_eq!(code, Some(0), "{err}");
    assert!(out.contains("10 frames, "), "{out}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let numbers: Vec<usize> = text.lines().skip(1).map(|l| l.split(',').next().unwrap().parse().unwrap()).collect();
    assert_eq!(numbers, (2..12).collect::<Vec<_>>(), "frames 2 to 11, the source's numbers");
    for (extra, expect) in [
        (["--start-frame", "2", "--end-frame", "2"], "--end-frame 2: the run stops before this frame, so it must come after --start-frame 2"),
        (["--start-frame", "0", "--end-frame", "21"], "--end-frame 21: the input has 20 frames (0..19); --end-frame 20 tracks to the last"),
    ] {
        let (code, _, err) = track(&extra);
        assert_eq!(code, Some(2), "{extra:?}: {err}");
        one_error_line(&err);
        assert!(err.contains(expect), "{err}");
    }
}

#[test]
fn progress_goes_to_a_log_as_lines_and_the_closing_line_says_wall_clock() {
    let (d, frames) = triangle_scene("cli_progress", 30);
    let truth = std::fs::read_to_string(frames.join("groundtruth.csv")).unwrap();
    let t: Vec<f64> = truth.lines().nth(1).unwrap().split(',').map(|v| v.parse().unwrap()).collect();
    let target = format!("{},{}", t[3], t[4]);
    let csv = d.join("t.csv");
    let args = ["track", "--frames", frames.to_str().unwrap(), "--target", &target, "--out", csv.to_str().unwrap()];
    // Standard error is a pipe here, not a terminal: whole lines, never redrawn in place.
    // With no pause between lines, one a frame.
    let (code, out, err) = coopwin_env(&args, &[("COOPWIN_PROGRESS_SECS", "0")]);
    assert_eq!(code, Some(0), "{err}");
    assert!(!err.contains('\r'), "no carriage returns in a log: {err:?}");
    let lines: Vec<&str> = err.lines().filter(|l| l.starts_with("tracking: frame ")).collect();
    assert_eq!(lines.len(), 30, "{err}");
    assert!(lines[29].starts_with("tracking: frame 30/30, ") && lines[29].contains(" frames/s, ETA 0:00"), "{}", lines[29]);
    // The default: at most one line every 5 s of the run.
    let started = std::time::Instant::now();
    let (code, _, err) = coopwin_env(&args, &[]);
    let secs = started.elapsed().as_secs_f64();
    assert_eq!(code, Some(0), "{err}");
    let shown = err.lines().filter(|l| l.starts_with("tracking: frame ")).count();
    assert!(shown as f64 <= secs / 5.0, "{shown} lines in {secs:.1} s: {err}");
    // The closing line: frames/s wall-clock, and what is simulated at which rate. Reference:
    // the rate is the one the CSV's times step at.
    let closing = out.lines().find(|l| l.starts_with("30 frames, ")).unwrap_or_else(|| panic!("{out}"));
    assert!(closing.contains(" frames/s wall-clock (") && closing.contains("s on this machine); simulated: the camera, window units and processors in simulated time"), "{closing}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let times: Vec<f64> = text.lines().skip(1).map(|l| l.split(',').nth(13).unwrap().parse().unwrap()).collect();
    let rate = format!("at the source's {:.2} frames/s", 1.0 / (times[1] - times[0]));
    assert!(closing.contains(&rate), "{rate} in {closing}");
}

#[test]
fn every_csv_column_is_explained_in_track_help_and_the_readme() {
    let (d, frames) = triangle_scene("cli_columns", 3);
    let csv = d.join("t.csv");
    let (ok, _, err) = coopwin(&["track", "--frames", frames.to_str().unwrap(), "--out", csv.to_str().unwrap()]);
    assert!(ok, "{err}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let header = text.lines().next().unwrap().to_string();
    let (ok, help, _) = coopwin(&["track", "--help"]);
    assert!(ok);
    // The help's column list: a line per column (or group), its names, then what it holds.
    let explained: Vec<String> = help
        .lines()
        .skip_while(|l| !l.starts_with("CSV columns"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .filter_map(|l| l.trim().split_once("  ").map(|(names, what)| (names.to_string(), what.trim().to_string())))
        .filter(|(_, what)| !what.is_empty())
        .flat_map(|(names, _)| names.split(", ").map(str::to_string).collect::<Vec<_>>())
        .collect();
    // The README names each in backticks, alone or in a group, besides the header itself.
    let readme = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../README.md")).unwrap();
    let spans: Vec<&str> = readme.split('`').skip(1).step_by(2).filter(|s| *s != header).collect();
    for column in header.split(',') {
        assert!(explained.iter().any(|c| c == column), "`track --help` does not explain {column}: {explained:?}");
        assert!(spans.iter().any(|s| s.split(',').any(|c| c.trim() == column)), "the README does not name `{column}`");
    }
}
