//! Issue 24, through the built `coopwin` binary: a user's footage of any length and size, and
//! the user's files never harmed. The references are the rules of docs/system.md
//! ("Reliability") and the README (exit 2 for a bad argument, 1 for other errors, one line on
//! stderr), FFmpeg's own `ffprobe` for frame counts and timestamps, and the bytes of the input
//! files before the run. Clips are made here with the `ffmpeg` program (`.ci/run` installs it).
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

mod common;

fn coopwin(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_coopwin")).args(args).output().expect("run coopwin")
}

fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("footage").join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into()
}

/// Exit `code` with exactly one line on stderr, starting `error: `, holding every `expect`.
fn fails(o: &Output, code: i32, expect: &[&str], what: &str) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(code), "{what}: exit code; stderr: {err}");
    let lines: Vec<&str> = err.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "{what}: one line on stderr, got {err:?}");
    assert!(lines[0].starts_with("error: ") && !err.contains("panicked"), "{what}: {err}");
    for e in expect {
        assert!(err.contains(e), "{what}: expected '{e}' in: {err}");
    }
}

/// Runs the `ffmpeg` program with `args`, failing the test if it fails.
fn ffmpeg(args: &[&str]) {
    let out = Command::new("ffmpeg")
        .args(["-v", "error", "-nostdin", "-y"])
        .args(args)
        .output()
        .expect("the ffmpeg program (apt-get install ffmpeg) to make the test clip");
    assert!(out.status.success(), "ffmpeg {args:?}: {}", stderr(&out));
}

/// A `seconds`-long clip of FFmpeg's moving test pattern at `size` and `rate`, H.264.
fn clip(dir: &Path, name: &str, size: &str, rate: u32, seconds: f64) -> PathBuf {
    let p = dir.join(name);
    let src = format!("testsrc=size={size}:rate={rate}");
    ffmpeg(&["-f", "lavfi", "-i", &src, "-t", &seconds.to_string(), "-c:v", "libx264", "-pix_fmt", "yuv420p", s(&p)]);
    p
}

/// A 12-frame 256x256 scene folder and its target point.
fn scene(dir: &Path) -> (PathBuf, String) {
    scene_of(dir, "256x256", 12)
}

/// A `frames`-frame scene folder of `size` (WxH) and its target point.
fn scene_of(dir: &Path, size: &str, frames: u32) -> (PathBuf, String) {
    let frames_dir = dir.join("frames");
    let o = coopwin(&["scene", "--size", size, "--frames", &frames.to_string(), "--speed", "50", "--out", s(&frames_dir)]);
    let frames = frames_dir;
    assert!(o.status.success(), "{}", stderr(&o));
    let truth = std::fs::read_to_string(frames.join("groundtruth.csv")).unwrap();
    let f: Vec<&str> = truth.lines().nth(1).unwrap().split(',').collect();
    (frames, format!("{},{}", f[3], f[4]))
}

/// Every file under `dir` with its bytes, to show nothing changed.
fn snapshot(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut v: Vec<_> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).filter(|p| p.is_file()).map(|p| (p.clone(), std::fs::read(&p).unwrap())).collect();
    v.sort();
    v
}

// Issue 24, case 1: an output never overwrites an input or another output.

#[test]
fn an_output_that_is_the_input_video_is_refused_and_the_video_kept() {
    let d = scratch("out_is_input");
    let c = clip(&d, "c.mp4", "160x120", 25, 1.0);
    let before = std::fs::read(&c).unwrap();
    let box_ = "60,40,32,24";
    let o = coopwin(&["track", "--frames", s(&c), "--target-box", box_, "--out", s(&c)]);
    fails(&o, 2, &["--out", "is the input --frames"], "--out = the video");
    let o = coopwin(&["track", "--frames", s(&c), "--target-box", box_, "--overlay", s(&c)]);
    fails(&o, 2, &["--overlay", "is the input --frames"], "--overlay = the video");
    // The same file by other names: a hard link, a symbolic link, a path through `..`.
    std::fs::hard_link(&c, d.join("hard.mp4")).unwrap();
    std::os::unix::fs::symlink(&c, d.join("soft.mp4")).unwrap();
    std::fs::create_dir(d.join("sub")).unwrap();
    for other in [d.join("hard.mp4"), d.join("soft.mp4"), d.join("sub/../c.mp4")] {
        let o = coopwin(&["track", "--frames", s(&c), "--target-box", box_, "--overlay", s(&other)]);
        fails(&o, 2, &["is the input"], &format!("--overlay {}", other.display()));
    }
    assert_eq!(std::fs::read(&c).unwrap(), before, "the video was changed");
}

#[test]
fn an_output_inside_the_frames_folder_is_refused_and_the_frames_kept() {
    let d = scratch("out_in_folder");
    let (frames, target) = scene(&d);
    let before = snapshot(&frames);
    for (name, why) in [("frame_00003.png", "is the input --frames"), ("groundtruth.csv", "is the input --frames"), ("new.csv", "inside the input folder")] {
        let o = coopwin(&["track", "--frames", s(&frames), "--target", &target, "--out", s(&frames.join(name))]);
        fails(&o, 2, &[why], name);
    }
    assert!(!frames.join("new.csv").exists());
    // A hard link to a frame from outside the folder is that frame.
    std::fs::hard_link(frames.join("frame_00005.png"), d.join("five.png")).unwrap();
    let o = coopwin(&["track", "--frames", s(&frames), "--target", &target, "--out", s(&d.join("five.png"))]);
    fails(&o, 2, &["is the input --frames"], "hard link to a frame");
    assert_eq!(snapshot(&frames), before, "the frames folder changed");
}

#[test]
fn two_outputs_on_one_file_are_refused() {
    let d = scratch("two_outputs");
    let (frames, target) = scene(&d);
    let gif = d.join("s.gif");
    std::fs::write(&gif, "keep").unwrap();
    let o = coopwin(&["track", "--frames", s(&frames), "--target", &target, "--out", s(&gif), "--overlay", s(&gif)]);
    fails(&o, 2, &["--overlay", "is also the output of --out"], "--out = --overlay");
    // Both new: the same path, written two ways.
    let o = coopwin(&["track", "--frames", s(&frames), "--target", &target, "--out", s(&d.join("n.gif")), "--overlay", s(&d.join("./n.gif"))]);
    fails(&o, 2, &["is also the output of --out"], "new path twice");
    assert_eq!(std::fs::read_to_string(&gif).unwrap(), "keep");
    assert!(!d.join("n.gif").exists());
}

#[test]
fn an_output_that_cannot_be_written_is_named_before_the_input_is_read() {
    // The folder's last frame is corrupt, which the run would meet after the outputs are
    // checked: the error must be the output's.
    let d = scratch("unwritable");
    let (frames, target) = scene(&d);
    std::fs::write(frames.join("frame_00011.png"), b"not a png").unwrap();
    let o = coopwin(&["track", "--frames", s(&frames), "--target", &target, "--out", "/proc/nope.csv"]);
    fails(&o, 1, &["/proc/nope.csv"], "unwritable --out");
}

// Issue 24, cases 2 and 3: frames as the file has them, and damage reported.

/// `ffprobe`'s answer for `args` on `clip`, one value a line (blank lines dropped).
fn ffprobe(clip: &Path, args: &[&str]) -> Vec<String> {
    let out = Command::new("ffprobe")
        .args(["-v", "error", "-threads", "1", "-select_streams", "v:0"])
        .args(args)
        .args(["-of", "csv=p=0"])
        .arg(clip)
        .output()
        .expect("the ffprobe program (apt-get install ffmpeg)");
    String::from_utf8_lossy(&out.stdout).lines().map(|l| l.trim_end_matches(',').to_string()).filter(|l| !l.is_empty()).collect()
}

/// The frames FFmpeg decodes from `clip`, counted by ffprobe.
fn frame_count(clip: &Path) -> usize {
    ffprobe(clip, &["-count_frames", "-show_entries", "stream=nb_read_frames"])[0].parse().unwrap()
}

/// The track CSV's rows as fields, checking its header.
fn csv_rows(text: &str) -> Vec<Vec<String>> {
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("frame,x,y,mode,source,measured_frame,file,box_x,box_y,box_w,box_h,confidence,ok,time_s,damaged,state,scale,angle_deg"));
    lines.map(|l| l.split(',').map(String::from).collect()).collect()
}

/// Tracks `clip` with `extra` options, the CSV to standard output; returns the run and its rows.
fn track_clip(clip: &Path, extra: &[&str]) -> (Output, Vec<Vec<String>>) {
    let mut args = vec!["track", "--frames", s(clip), "--target-box", "60,40,32,24", "--out", "-"];
    args.extend_from_slice(extra);
    let o = coopwin(&args);
    let rows = if o.status.success() { csv_rows(&String::from_utf8_lossy(&o.stdout)) } else { Vec::new() };
    (o, rows)
}

#[test]
fn a_variable_rate_clip_gives_one_row_a_frame_with_the_files_timestamps() {
    // 31 frames at 25 frames/s with two gaps (12 and 7 frame periods): a constant-rate decode
    // would fill the gaps with copies. Reference: ffprobe's frame count and timestamps.
    let d = scratch("vfr");
    let c = d.join("vfr.mkv");
    let src = "testsrc=size=160x120:rate=25";
    let gaps = "setpts='(N+gt(N,10)*12+gt(N,30)*7)/25/TB'";
    ffmpeg(&["-f", "lavfi", "-i", src, "-frames:v", "40", "-vf", gaps, "-fps_mode", "passthrough", "-c:v", "libx264", "-g", "25", "-pix_fmt", "yuv420p", s(&c)]);
    let want = ffprobe(&c, &["-show_entries", "frame=best_effort_timestamp_time"]);
    assert_eq!(want.len(), frame_count(&c));
    assert_eq!(want.len(), 40);
    let (o, rows) = track_clip(&c, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(rows.len(), want.len(), "one row a decoded frame");
    for (k, (row, t)) in rows.iter().zip(&want).enumerate() {
        assert_eq!(row[0], k.to_string());
        let (got, t): (f64, f64) = (row[13].parse().unwrap(), t.parse().unwrap());
        assert!((got - t).abs() < 1e-6, "frame {k}: time_s {got}, ffprobe {t}");
        assert_eq!(row[14], "0", "frame {k} is not damaged");
    }
}

/// A 8-second 160x120 clip with a key frame every second, and `damage` applied to its bytes.
fn damaged_clip(dir: &Path, name: &str, damage: impl Fn(&mut Vec<u8>)) -> (PathBuf, PathBuf) {
    let good = dir.join("good.mp4");
    let src = "testsrc=size=160x120:rate=25";
    ffmpeg(&["-f", "lavfi", "-i", src, "-t", "8", "-c:v", "libx264", "-g", "25", "-pix_fmt", "yuv420p", "-movflags", "+faststart", s(&good)]);
    let mut bytes = std::fs::read(&good).unwrap();
    damage(&mut bytes);
    let bad = dir.join(name);
    std::fs::write(&bad, bytes).unwrap();
    (good, bad)
}

#[test]
fn a_clip_cut_short_is_refused_and_tracked_only_when_allowed() {
    let d = scratch("truncated");
    let (good, bad) = damaged_clip(&d, "half.mp4", |b| b.truncate(b.len() / 2));
    let (o, _) = track_clip(&good, &[]);
    assert!(o.status.success(), "the whole clip tracks: {}", stderr(&o));
    let (o, _) = track_clip(&bad, &[]);
    fails(&o, 1, &["half.mp4", "damaged", "--allow-damaged", "FFmpeg said"], "truncated clip");
    let (o, rows) = track_clip(&bad, &["--allow-damaged"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("warning:"), "the damage is reported: {}", stderr(&o));
    // Reference: ffprobe's count of the frames that decode.
    assert_eq!(rows.len(), frame_count(&bad));
    assert!(rows.len() < 200, "half the clip decodes, not {}", rows.len());
}

/// FFmpeg's MD5 of each decoded frame of `clip`, with `input` decoder options (`-ec 0`: no
/// error concealment).
fn frame_md5s(clip: &Path, input: &[&str]) -> Vec<String> {
    let out = Command::new("ffmpeg").args(["-v", "quiet", "-nostdin", "-threads", "1"]).args(input).arg("-i").arg(clip).args(["-map", "0:v:0", "-fps_mode", "passthrough", "-f", "framemd5", "-"]).output().expect("ffmpeg");
    String::from_utf8_lossy(&out.stdout).lines().filter(|l| !l.starts_with('#')).filter_map(|l| l.rsplit(',').next().map(|m| m.trim().to_string())).collect()
}

#[test]
fn a_clip_whose_decoder_errors_change_no_pixel_tracks_with_no_row_damaged() {
    // Issue 39: opencv-doc's box.mp4 has a stray unit in its first packet, which FFmpeg logs as
    // errors; the decoder skips it. The reference is FFmpeg's own per-frame MD5s: every frame
    // decodes to the same pixels with error concealment off (`-ec 0`) as with it on, so no
    // frame was concealed, and none may be called damaged (OpenCV plays the clip as well).
    let gz = Path::new("/usr/share/doc/opencv-doc/opencv4/html/box.mp4.gz");
    if !gz.exists() {
        common::missing_tool("opencv-doc's box.mp4", "apt-get install -y opencv-doc");
        return;
    }
    let d = scratch("box");
    let clip = d.join("box.mp4");
    let unzipped = Command::new("gzip").arg("-dc").arg(gz).output().expect("gzip");
    std::fs::write(&clip, unzipped.stdout).unwrap();
    let logged = Command::new("ffmpeg").args(["-v", "error", "-nostdin", "-i", s(&clip), "-map", "0:v:0", "-f", "null", "-"]).output().unwrap();
    assert!(stderr(&logged).contains("[h264 @"), "FFmpeg logs decoding errors on this clip: {}", stderr(&logged));
    let (concealed, plain) = (frame_md5s(&clip, &[]), frame_md5s(&clip, &["-ec", "0"]));
    assert!(!concealed.is_empty());
    assert_eq!(concealed, plain, "the same pixels with and without concealment");
    let o = coopwin(&["track", "--frames", s(&clip), "--target-box", "395,50,140,70", "--out", "-"]);
    assert!(o.status.success(), "box.mp4 tracks by default: {}", stderr(&o));
    // FFmpeg's own log lines never reach the user, nor a warning of damage.
    assert!(!stderr(&o).contains(" @ 0x") && !stderr(&o).contains("warning"), "stderr: {}", stderr(&o));
    let rows = csv_rows(&String::from_utf8_lossy(&o.stdout));
    // Reference: ffprobe's count of the frames that decode.
    assert_eq!(rows.len(), frame_count(&clip));
    assert!(rows.iter().all(|r| r[14] == "0"), "no row damaged");
}

#[test]
fn garbage_in_the_middle_is_refused_and_its_frames_flagged_when_allowed() {
    let d = scratch("garbage");
    // 4000 bytes of pseudo-random garbage from the middle on (an LCG, so the test is fixed).
    let (_, bad) = damaged_clip(&d, "garbage.mp4", |b| {
        let mid = b.len() / 2;
        let mut x = 12345u32;
        for v in &mut b[mid..mid + 4000] {
            x = x.wrapping_mul(1_103_515_245).wrapping_add(12345);
            *v = (x >> 16) as u8;
        }
    });
    let (o, _) = track_clip(&bad, &[]);
    fails(&o, 1, &["garbage.mp4", "damaged", "frames"], "garbage clip");
    let (o, rows) = track_clip(&bad, &["--allow-damaged"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(rows.len(), frame_count(&bad));
    let damaged: Vec<usize> = rows.iter().filter(|r| r[14] == "1").map(|r| r[0].parse().unwrap()).collect();
    assert!(!damaged.is_empty(), "some frames are flagged");
    // The garbage sits mid-file; the first and the last second decode clean (key frames every 25).
    assert!(damaged.iter().all(|&k| k >= 25 && k + 25 < rows.len()), "flagged: {damaged:?} of {}", rows.len());
}

// Issue 24, case 4: streaming, with memory bounded whatever the clip's length.

/// Runs coopwin with `args` and returns its exit status and its peak resident memory in
/// KiB (the larger of coopwin's and its FFmpeg children's, from the kernel's wait4 record).
// The child is reaped by `wait4`, which clippy does not see.
#[allow(clippy::zombie_processes)]
fn peak_rss(args: &[&str]) -> (std::process::ExitStatus, i64) {
    use std::os::unix::process::ExitStatusExt;
    let child = Command::new(env!("CARGO_BIN_EXE_coopwin")).args(args).stdout(std::process::Stdio::null()).stderr(std::process::Stdio::null()).spawn().unwrap();
    let mut status = 0;
    // SAFETY: an all-zero rusage is a valid value; wait4 fills it for our own child.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    let pid = unsafe { libc::wait4(child.id() as i32, &mut status, 0, &mut usage) };
    assert_eq!(pid, child.id() as i32);
    (std::process::ExitStatus::from_raw(status), usage.ru_maxrss)
}

#[test]
fn memory_does_not_grow_with_the_clip() {
    // 200 and 2000 frames of 160x120 (19.2 kB a frame gray, 57.6 kB as an RGB canvas): a run
    // that kept the clip, or the overlay, would grow by at least 2.0 MB per 100 frames. The
    // reference is that arithmetic; the bound asserted is the one docs/system.md states: a few
    // frames of pixels plus under 1 kB of log per frame.
    let d = scratch("memory");
    let mut peaks = Vec::new();
    for n in [200u32, 2000] {
        let c = d.join(format!("c{n}.mp4"));
        ffmpeg(&["-f", "lavfi", "-i", "testsrc=size=160x120:rate=25", "-frames:v", &n.to_string(), "-c:v", "libx264", "-pix_fmt", "yuv420p", s(&c)]);
        let (out, gif) = (d.join(format!("c{n}.csv")), d.join(format!("c{n}.gif")));
        let (status, kib) = peak_rss(&["track", "--frames", s(&c), "--target-box", "60,40,32,24", "--out", s(&out), "--overlay", s(&gif)]);
        assert!(status.success(), "{n} frames: {status}");
        assert_eq!(std::fs::read_to_string(&out).unwrap().lines().count(), n as usize + 1);
        peaks.push(kib);
    }
    let growth = (peaks[1] - peaks[0]) * 1024 / 1800;
    println!("peak RSS: {} KiB at 200 frames, {} KiB at 2000: {growth} bytes a frame", peaks[0], peaks[1]);
    assert!(growth < 1024, "memory grows by {growth} bytes a frame ({peaks:?} KiB)");
}

#[test]
#[ignore = "long: a 30,000-frame 640x480 clip; run with cargo test -p coopwin-testbench --test footage -- --ignored --nocapture"]
fn a_30000_frame_640x480_clip_tracks_in_under_200_mb() {
    // Issue 24's figure: peak memory under 200 MB for 30,000 frames at 640x480 (a run that kept
    // the clip would need 9.2 GB).
    let d = scratch("long");
    let c = d.join("long.mp4");
    ffmpeg(&["-f", "lavfi", "-i", "testsrc=size=640x480:rate=30", "-frames:v", "30000", "-c:v", "libx264", "-preset", "ultrafast", "-pix_fmt", "yuv420p", s(&c)]);
    let out = d.join("long.csv");
    let (status, kib) = peak_rss(&["track", "--frames", s(&c), "--target-box", "300,220,32,32", "--out", s(&out)]);
    assert!(status.success(), "{status}");
    assert_eq!(std::fs::read_to_string(&out).unwrap().lines().count(), 30_001);
    println!("30,000 frames at 640x480: peak RSS {} MB", kib / 1024);
    assert!(kib < 200 * 1024, "peak RSS {kib} KiB");
}

// Issue 24, case 4: Ctrl-C ends a run cleanly.

#[test]
fn ctrl_c_exits_130_and_leaves_earlier_outputs_as_they_were() {
    let d = scratch("ctrl_c");
    let c = d.join("c.mp4");
    // 30,000 frames: the tracker runs this small clip at thousands of frames a second.
    ffmpeg(&["-f", "lavfi", "-i", "testsrc=size=160x120:rate=25", "-frames:v", "30000", "-c:v", "libx264", "-preset", "ultrafast", "-pix_fmt", "yuv420p", s(&c)]);
    let (frames, target) = scene(&d);
    let (out, gif, vcd) = (d.join("t.csv"), d.join("t.gif"), d.join("t.vcd"));
    for f in [&out, &gif, &vcd] {
        std::fs::write(f, "earlier\n").unwrap();
    }
    let video = ["track", "--frames", s(&c), "--target-box", "60,40,32,24", "--out", s(&out), "--overlay", s(&gif)];
    // The rust-hdl units with a VCD: the trace is written as the run goes.
    let traced = ["track", "--frames", s(&frames), "--target", &target, "--hdl", "rust-hdl", "--vcd", s(&vcd), "--vcd-frames", "0..4", "--out", s(&out)];
    for args in [&video[..], &traced[..]] {
        let child = Command::new(env!("CARGO_BIN_EXE_coopwin")).args(args).stdout(std::process::Stdio::piped()).stderr(std::process::Stdio::piped()).spawn().unwrap();
        // An output's temporary file, as the run writes it (None before it exists).
        let partial = |name: &str| std::fs::read_dir(&d).unwrap().map(|e| e.unwrap().path()).find(|p| p.to_string_lossy().contains(&format!(".{name}.")));
        let rows = || partial("t.csv").map_or(0, |p| std::fs::read_to_string(p).unwrap_or_default().lines().count());
        // Polled from the start, so the interrupt comes as soon as the run is writing, however
        // fast the machine (a 3,000-frame clip once ended before a fixed sleep did: CI, stop 28).
        let waited = std::time::Instant::now();
        let writing = || {
            if args == &video[..] {
                // The CSV is written a row as each frame ends (issue 24: written as they go):
                // its temporary file holds rows (a write buffer's worth, about 75) while the
                // run is far from done (30,000 frames, then the overlay).
                rows() >= 2
            } else {
                // The VCD is written as the run goes: the rust-hdl units take about 3 s a frame
                // of the 12 (33 s measured), the trace's first frames start at once.
                partial("t.vcd").and_then(|p| std::fs::metadata(p).ok()).is_some_and(|m| m.len() > 0)
            }
        };
        while !writing() && waited.elapsed().as_secs() < 60 {
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        assert!(writing(), "no output written within 60 s of {args:?}");
        if args == &video[..] {
            let n = rows();
            assert!(n < 30_000, "{n} lines in the CSV's temporary file mid-run");
        }
        // SAFETY: signals our own child.
        assert_eq!(unsafe { libc::kill(child.id() as i32, libc::SIGINT) }, 0);
        let o = child.wait_with_output().unwrap();
        fails(&o, 130, &["interrupted"], &format!("Ctrl-C during {args:?}"));
        for f in [&out, &gif, &vcd] {
            assert_eq!(std::fs::read_to_string(f).unwrap(), "earlier\n", "{}", f.display());
        }
    }
    let left: Vec<String> = std::fs::read_dir(&d).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).filter(|n| n.contains("partial")).collect();
    assert!(left.is_empty(), "temporary files left: {left:?}");
}

#[test]
fn progress_is_redrawn_on_a_terminal_and_written_as_lines_elsewhere() {
    // `script` (util-linux) runs the command on a pseudo-terminal.
    let d = scratch("progress");
    let c = clip(&d, "c.mp4", "160x120", 25, 2.0);
    let cmd = format!("{} track --frames {} --target-box 60,40,32,24", env!("CARGO_BIN_EXE_coopwin"), s(&c));
    let tty = Command::new("script").args(["-qec", &cmd, "/dev/null"]).output().expect("the script program (util-linux)");
    let text = String::from_utf8_lossy(&tty.stdout);
    assert!(tty.status.success(), "{text}");
    assert!(text.contains("frame 50/50") && text.contains("frames/s") && text.contains("ETA"), "{text}");
    assert!(text.contains('\r'), "redrawn in place: {text:?}");
    // Piped, a whole line every few seconds (tests/cli.rs counts them), never redrawn.
    let piped = coopwin(&["track", "--frames", s(&c), "--target-box", "60,40,32,24"]);
    assert!(piped.status.success() && !stderr(&piped).contains('\r'), "{}", stderr(&piped));
}

// Issue 24, case 5: frames up to the largest sensor the Verilog takes.

#[test]
fn a_1080p_clip_tracks() {
    // Refused above 1024 px before. Reference: the frame count ffprobe gives.
    let d = scratch("hd");
    let c = clip(&d, "hd.mp4", "1920x1080", 25, 0.4);
    let o = coopwin(&["track", "--frames", s(&c), "--target-box", "1660,640,32,32", "--out", "-"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let rows = csv_rows(&String::from_utf8_lossy(&o.stdout));
    assert_eq!(rows.len(), frame_count(&c));
    // A textured patch of testsrc's colour bars: it is tracked (ok=1) on every frame.
    assert!(rows.iter().all(|r| r[12] == "1"), "{rows:?}");
    // The small clips' box (60,40) falls on testsrc's black border at this size: a flat
    // template, refused with the way out rather than tracked to nothing.
    let (o, _) = track_clip(&c, &[]);
    fails(&o, 1, &["flat on the first frame tracked (every pixel 0)", "--start-frame"], "a flat target");
    // Past 4096 a side: refused with the limits named.
    let big = d.join("big.mp4");
    ffmpeg(&["-f", "lavfi", "-i", "color=size=4112x64:rate=5", "-frames:v", "2", "-c:v", "libx264", "-pix_fmt", "yuv420p", s(&big)]);
    fails(&coopwin(&["track", "--frames", s(&big), "--out", "/dev/null"]), 1, &["64x64 to 4096x4096", "4112x64"], "4112 px wide");
}

#[test]
fn overlays_are_bounded_an_mp4_at_1080p_under_200_mb_and_a_gif_to_its_pixel_budget() {
    // Issue 39's bound for the MP4: peak memory under 200 MB at 1080p (the kernel's wait4
    // record: the largest of coopwin and its FFmpeg children; it was 527 MB). Reference for
    // the file: ffprobe's frame count and size.
    let d = scratch("overlay_bounds");
    let hd = clip(&d, "hd.mp4", "1920x1080", 25, 1.0);
    let mp4 = d.join("o.mp4");
    let (status, kib) = peak_rss(&["track", "--frames", s(&hd), "--target-box", "1660,640,32,32", "--overlay", s(&mp4)]);
    assert!(status.success(), "{status}");
    println!("1080p MP4 overlay: peak {kib} KiB");
    assert!(kib < 200 * 1024, "peak {kib} KiB");
    assert_eq!(ffprobe(&mp4, &["-count_frames", "-show_entries", "stream=width,height,nb_read_frames"]), ["1920,1080,25"]);
    // The GIF: 300 frames of 640x480 are scaled to 480x360 (480 px a side at most), and
    // 300 of those would be 51.8 M pixels, over the 50 M budget: one frame in 2 is kept, each
    // shown 2/25 s. Reference: that arithmetic, and the gif crate reading the file back.
    let vga = clip(&d, "vga.mp4", "640x480", 25, 12.0);
    let gif_path = d.join("o.gif");
    let o = coopwin(&["track", "--frames", s(&vga), "--target-box", "300,220,40,40", "--overlay", s(&gif_path)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("(scaled from 640x480 to 480x360, one frame in 2 kept"), "{out}");
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::Indexed);
    let mut dec = opts.read_info(std::fs::File::open(&gif_path).unwrap()).unwrap();
    let mut frames = 0;
    while let Some(f) = dec.read_next_frame().unwrap() {
        assert_eq!((f.width, f.height, f.delay), (480, 360, 8));
        frames += 1;
    }
    assert_eq!(frames, 150);
}

// Issue 24, case 5 (and issue 22, item 4): the clocked window units at any geometry
// `coopwin verilog` exports, written by the firmware's writer (eight-byte sets above 256).

/// `coopwin track` over `frames` with `extra` options; its CSV.
fn track_csv(dir: &Path, name: &str, frames: &Path, target: &str, extra: &[&str]) -> String {
    let out = dir.join(name);
    let mut args = vec!["track", "--frames", s(frames), "--target", target, "--out", s(&out)];
    args.extend_from_slice(extra);
    let o = coopwin(&args);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    std::fs::read_to_string(&out).unwrap()
}

#[test]
fn rust_hdl_units_track_640x480x10_as_the_model_does_and_pass_the_audit() {
    // The reference is the behavioural model of the window unit (--hdl model): the clocked
    // units must deliver the same windows, so the CSVs must be identical. Three frames of COOP
    // (4 units, about 316,000 clocks a frame each); then SPMF (1 unit) with a VCD of frame 1.
    let d = scratch("hdl_640x480");
    let (frames, target) = scene_of(&d, "640x480", 3);
    let model = track_csv(&d, "model.csv", &frames, &target, &[]);
    assert_eq!(model.lines().count(), 4, "{model}");
    let hdl = track_csv(&d, "hdl.csv", &frames, &target, &["--hdl", "rust-hdl", "--pixel-bits", "10"]);
    assert_eq!(hdl, model, "COOP: rust-hdl units at 640x480x10 against the behavioural model");
    let model1 = track_csv(&d, "model1.csv", &frames, &target, &["--strategy", "spmf"]);
    let vcd = d.join("spmf.vcd");
    let hdl1 = track_csv(&d, "hdl1.csv", &frames, &target, &["--strategy", "spmf", "--hdl", "rust-hdl", "--pixel-bits", "10", "--vcd", s(&vcd), "--vcd-frames", "1..2"]);
    assert_eq!(hdl1, model1, "SPMF: rust-hdl units at 640x480x10 against the behavioural model");
    // The audit decodes eight-byte sets (a four-byte reading would not match the requests).
    let o = coopwin(&["audit", s(&vcd), "--requests", s(&vcd.with_extension("requests.csv")), "--unit", "0"]);
    let report = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(o.status.success(), "audit: {report}{}", stderr(&o));
    assert!(report.contains(" 0 violations") && !report.contains(" 0 windows verified"), "{report}");
    let _ = std::fs::remove_file(&vcd);
}

#[test]
fn verilator_units_track_640x480x10_as_the_model_does() {
    // The exported Verilog compiled at 640x480x10 (its own cache key); the reference is the
    // behavioural model, as above.
    if !common::have_verilator() {
        return;
    }
    let d = scratch("verilator_640x480");
    let (frames, target) = scene_of(&d, "640x480", 3);
    let model = track_csv(&d, "model.csv", &frames, &target, &[]);
    let hdl = track_csv(&d, "verilator.csv", &frames, &target, &["--hdl", "verilator", "--pixel-bits", "10"]);
    assert_eq!(hdl, model, "COOP: Verilator units at 640x480x10 against the behavioural model");
}

/// Per rising clock edge of a `coopwin waves` VCD: the named signals' values.
fn flags_after_edges(vcd: &str, names: &[&str]) -> Vec<Vec<u32>> {
    let mut codes = std::collections::HashMap::new();
    for l in vcd.lines().filter(|l| l.starts_with("$var")) {
        let f: Vec<&str> = l.split_whitespace().collect();
        if let Some(k) = names.iter().position(|n| *n == f[4]) {
            codes.insert(f[3].to_string(), k);
        }
    }
    let (mut now, mut out, mut rose) = (vec![0u32; names.len()], Vec::new(), false);
    for l in vcd.lines().skip_while(|l| !l.starts_with("$enddefinitions")).skip(1) {
        if l.starts_with('#') {
            if rose {
                out.push(now.clone());
            }
            rose = false;
        } else if l == "1!" {
            rose = true;
        } else if let Some(v) = l.strip_prefix('b') {
            let (bits, code) = v.split_once(' ').unwrap();
            if let Some(&k) = codes.get(code) {
                now[k] = u32::from_str_radix(bits, 2).unwrap();
            }
        } else if let Some(&k) = codes.get(&l[1..]) {
            now[k] = u32::from(&l[..1] == "1");
        }
    }
    if rose {
        out.push(now);
    }
    out
}

#[test]
fn waves_run_at_640x480x10_with_eight_byte_sets() {
    // References, by hand: a 640-wide sensor takes two bytes a coordinate (eight CRDY1 rises
    // for the set); the test card's pixel is its column, so the window's columns 300..=339
    // (past 255: a 10-bit bus) come out in raster order for each of its 30 rows.
    let d = scratch("waves_640x480");
    let vcd = d.join("w.vcd");
    let o = coopwin(&["waves", "--out", s(&vcd), "--width", "640", "--height", "480", "--pixel-bits", "10", "--window", "300,339,200,229"]);
    assert!(o.status.success(), "{}", stderr(&o));
    for k in 1..=5 {
        assert!(d.join(format!("w-b1_{k}.svg")).exists(), "diagram {k}");
    }
    let edges = flags_after_edges(&std::fs::read_to_string(&vcd).unwrap(), &["coord_ready", "pixel_strobe", "pixel_out"]);
    let rises = edges.windows(2).filter(|w| w[1][0] == 1 && w[0][0] == 0).count() + usize::from(edges[0][0] == 1);
    assert_eq!(rises, 8, "CRDY1 rises: one eight-byte set");
    let got: Vec<u32> = edges.iter().filter(|e| e[1] == 1).map(|e| e[2]).collect();
    let want: Vec<u32> = (200..=229).flat_map(|_| 300..=339).collect();
    assert_eq!(got, want);
}
