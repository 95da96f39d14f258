//! Tracking a user's own footage through the built `coopwin` binary: a video file decoded by
//! FFmpeg, a target box, the source's frame rate, the CSV's box/confidence/ok columns, the
//! overlays (GIF and MP4), and `scene --size/--colour` to make the footage. The reference is
//! the renderer's exact ground truth (`groundtruth.csv`). Needs the `ffmpeg` program
//! (`.ci/run` installs Debian's).
use std::path::{Path, PathBuf};
use std::process::Command;

fn coopwin(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_coopwin")).args(args).output().expect("run coopwin")
}

fn ok(args: &[&str]) -> String {
    let out = coopwin(args);
    assert!(out.status.success(), "coopwin {args:?}: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stdout).into()
}

fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A 160x120 colour scene of 60 frames (the object's centre on a swing at 30 px/s over a real
/// photograph), encoded at 30 frames/s as a near-lossless H.264 MP4.
fn clip(dir: &Path) -> PathBuf {
    let seq = dir.join("seq");
    ok(&["scene", "--photo", "--path", "swing", "--speed", "30", "--frames", "60", "--noise", "1", "--size", "160x120", "--colour", "--out", s(&seq)]);
    let mp4 = dir.join("clip.mp4");
    let status = Command::new("ffmpeg")
        .args(["-v", "error", "-y", "-framerate", "30", "-i"])
        .arg(seq.join("frame_%05d.png"))
        .args(["-c:v", "libx264", "-crf", "10", "-pix_fmt", "yuv420p"])
        .arg(&mp4)
        .status()
        .expect("the ffmpeg program (apt-get install ffmpeg) to make the test clip");
    assert!(status.success());
    mp4
}

struct Row {
    x: f64,
    y: f64,
    measured: usize,
    bx: f64,
    by: f64,
    bw: f64,
    bh: f64,
    /// The object's measured scale.
    scale: f64,
    confidence: f64,
    ok: bool,
}

fn rows(csv: &Path) -> Vec<Row> {
    let text = std::fs::read_to_string(csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("frame,x,y,mode,source,measured_frame,file,box_x,box_y,box_w,box_h,confidence,ok,time_s,damaged,state,scale,angle_deg"));
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let n = |i: usize| f[i].parse::<f64>().unwrap_or(f64::NAN);
            Row {
                x: n(1),
                y: n(2),
                measured: f[5].parse().unwrap_or(usize::MAX),
                bx: n(7),
                by: n(8),
                bw: n(9),
                bh: n(10),
                scale: n(16),
                confidence: n(11),
                ok: f[12] == "1",
            }
        })
        .collect()
}

fn truth_centres(seq: &Path) -> Vec<(f64, f64)> {
    let text = std::fs::read_to_string(seq.join("groundtruth.csv")).unwrap();
    text.lines().skip(1).map(|l| {
        let f: Vec<f64> = l.split(',').map(|v| v.parse().unwrap()).collect();
        (f[1], f[2])
    }).collect()
}

#[test]
fn a_video_with_a_target_box_is_tracked_with_boxes_confidence_and_an_overlay() {
    let d = scratch("own_video");
    let mp4 = clip(&d);
    let truth = truth_centres(&d.join("seq"));
    // The box 16x12 around the object's centre at frame 0, (80.0, 66.0) in a 160x120 frame:
    // columns 72..87, rows 60..71, so its centre is (79.5, 65.5).
    let (x0, y0) = (truth[0].0, truth[0].1);
    assert_eq!((x0, y0), (80.0, 66.0), "where the swing starts in a 160x120 frame");
    let csv = d.join("t.csv");
    let gif = d.join("o.gif");
    let mp4_overlay = d.join("o.mp4");
    ok(&["track", "--frames", s(&mp4), "--target-box", "72,60,16,12", "--out", s(&csv), "--overlay", s(&gif)]);
    ok(&["track", "--frames", s(&mp4), "--target-box", "72,60,16,12", "--fps", "30", "--search", "4", "--overlay", s(&mp4_overlay)]);
    let rows = rows(&csv);
    assert_eq!(rows.len(), 60);
    // The tracked point is the box's centre, (-0.5, -0.5) from the object's centre.
    let errs: Vec<f64> = rows.iter().map(|r| (r.x + 0.5 - truth[r.measured].0).hypot(r.y + 0.5 - truth[r.measured].1)).collect();
    let rms = (errs.iter().map(|e| e * e).sum::<f64>() / errs.len() as f64).sqrt();
    eprintln!("the 160x120 H.264 clip with a target box: RMS {rms:.3} px");
    assert!(rms < 0.3, "RMS {rms:.3} px against the ground truth through H.264");
    assert!(rows.iter().filter(|r| r.scale.is_finite()).count() * 2 >= rows.len(), "the adapting track measures the object's scale");
    for r in &rows {
        // Every row vouched for, so confident from 0.9 (report/csv.rs, VOUCHED_CONFIDENCE).
        assert!(r.ok && (0.9..=1.0).contains(&r.confidence), "confidence {}", r.confidence);
        // OpenCV's box convention: columns box_x..box_x+W-1 centred on the point; the box
        // scaled by the object's measured scale (where measured). A swing does not change it:
        // measured within 5.3 % of 1 with this 12-pixel template through H.264 (bound 2x).
        let scale = if r.scale.is_nan() { 1.0 } else { r.scale };
        assert!((scale - 1.0).abs() < 0.106, "scale {scale}");
        assert!((r.bw - 16.0 * scale).abs() < 2e-3 && (r.bh - 12.0 * scale).abs() < 2e-3, "{} x {}", r.bw, r.bh);
        assert!((r.bx - (r.x - (r.bw - 1.0) / 2.0)).abs() < 2e-3 && (r.by - (r.y - (r.bh - 1.0) / 2.0)).abs() < 2e-3);
    }
    // The GIF holds one frame per video frame (read back by the gif crate's decoder).
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::Indexed);
    let mut dec = opts.read_info(std::fs::File::open(&gif).unwrap()).unwrap();
    assert_eq!((dec.width(), dec.height()), (160, 120));
    let mut n = 0;
    while dec.read_next_frame().unwrap().is_some() {
        n += 1;
    }
    assert_eq!(n, 60);
    // The MP4 is H.264 with 60 frames, as ffprobe counts them.
    let probe = Command::new("ffprobe")
        .args(["-v", "error", "-count_frames", "-select_streams", "v:0", "-show_entries", "stream=codec_name,nb_read_frames", "-of", "csv=p=0"])
        .arg(&mp4_overlay)
        .output()
        .unwrap();
    assert_eq!(String::from_utf8_lossy(&probe.stdout).trim(), "h264,60");
}

#[test]
fn video_errors_are_one_clear_line() {
    let d = scratch("own_video_errors");
    // Not a video: FFmpeg's reason is passed on, exit 1.
    let junk = d.join("junk.mp4");
    std::fs::write(&junk, b"not a video").unwrap();
    let out = coopwin(&["track", "--frames", s(&junk)]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("junk.mp4") && err.contains("FFmpeg"), "{err}");
    // FFmpeg missing: the message says what to install.
    let out = Command::new(env!("CARGO_BIN_EXE_coopwin")).args(["track", "--frames", s(&junk)]).env("PATH", "").output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("apt-get install ffmpeg"), "{err}");
    // Bad boxes, rates, margins and overlay names are argument errors (exit 2).
    for args in [
        &["--target-box", "10,10,3,20"][..],
        &["--target-box", "10,10,20"],
        &["--target-box", "10,10,20,20", "--target", "5,5"],
        &["--fps", "0"],
        &["--search", "0"],
        &["--overlay", "o.png"],
    ] {
        let mut all = vec!["track", "--frames", s(&junk)];
        all.extend_from_slice(args);
        assert_eq!(coopwin(&all).status.code(), Some(2), "{args:?}");
    }
}

#[test]
fn scene_writes_frames_at_the_size_and_in_the_colour_asked() {
    let d = scratch("own_video_scene");
    ok(&["scene", "--frames", "2", "--size", "320x200", "--colour", "--out", s(&d.join("c"))]);
    let img = image::open(d.join("c/frame_00001.png")).unwrap();
    assert_eq!((img.width(), img.height(), img.color()), (320, 200, image::ColorType::Rgb8));
    ok(&["scene", "--frames", "2", "--size", "64x1024", "--out", s(&d.join("g"))]);
    let img = image::open(d.join("g/frame_00000.png")).unwrap();
    assert_eq!((img.width(), img.height(), img.color()), (64, 1024, image::ColorType::L8));
    for bad in ["63x64", "5000x100", "640", "axb"] {
        assert_eq!(coopwin(&["scene", "--size", bad, "--out", s(&d.join("x"))]).status.code(), Some(2), "{bad}");
    }
}

#[test]
fn the_search_margin_and_the_frame_rate_change_what_the_foveal_window_can_follow() {
    // The swing at 240 px/s moves the object about 2 px a frame at 114 frames/s, 3.3 at its
    // fastest. Reference: the ground truth (the target is the object's centre at frame 0).
    let d = scratch("own_video_search");
    let seq = d.join("seq");
    ok(&["scene", "--photo", "--path", "swing", "--speed", "240", "--frames", "60", "--noise", "1", "--size", "160x120", "--out", s(&seq)]);
    let truth = truth_centres(&seq);
    let run = |extra: &[&str], name: &str| {
        let csv = d.join(name);
        let mut args = vec!["track", "--frames", s(&seq), "--target", "80,66", "--out", s(&csv)];
        args.extend_from_slice(extra);
        ok(&args);
        rows(&csv)
    };
    let lost = |rows: &[Row]| rows.iter().filter(|r| !r.ok || (r.x - truth[r.measured].0).hypot(r.y - truth[r.measured].1) > 3.0).count();
    // The thesis's Foveal window, on the last point: 1 px wider than the template a side
    // cannot keep up; 4 px can.
    let fixed = |search: &'static str, name: &str| run(&["--fixed-template", "--search", search], name);
    assert!(lost(&fixed("1", "s1.csv")) > 30, "a 1 px margin follows a 3 px/frame object");
    assert_eq!(lost(&fixed("4", "s4.csv")), 0);
    // The default places the window where the motion puts the object (issue 21): the 1 px
    // margin keeps up, with no hand-tuning.
    assert_eq!(lost(&run(&["--search", "1"], "a1.csv")), 0);
    // With the C40's 18 ms Foveal update, at 114 frames/s (8.8 ms a frame) a frame's position
    // was measured in an earlier frame; at 30 frames/s (33 ms a frame) the update fits in the
    // frame, and a third or more of the positions are the frame's own (the thesis's windows).
    let fresh = |rows: &[Row]| rows.iter().enumerate().filter(|(k, r)| r.measured == *k).count();
    let at114 = fresh(&run(&["--fixed-template", "--profile", "c40", "--search", "4"], "c114.csv"));
    let at30 = fresh(&run(&["--fixed-template", "--profile", "c40", "--search", "4", "--fps", "30"], "c30.csv"));
    assert!(at114 == 0 && at30 >= 20, "positions measured in their own frame: {at114} at 114 frames/s, {at30} at 30");
}
