//! Video files in and out through the `ffmpeg` and `ffprobe` programs (Debian package
//! `ffmpeg`): a clip is scanned once (each frame's timestamp, and the decoding errors FFmpeg
//! logs, [`scan`]) and then decoded to 8-bit gray frames as it is tracked, a few frames held
//! at a time ([`VideoFrames`]); an overlay is encoded to MP4 a frame at a time
//! ([`Mp4Encoder`]). No codec is linked into coopwin; without the programs these give a typed
//! error that says what to install.
use std::collections::VecDeque;
use std::io::{BufRead, BufReader, Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};

/// Why a video could not be read or written.
#[derive(Debug)]
pub enum VideoError {
    /// `ffmpeg` or `ffprobe` is not installed (or not on `PATH`).
    Missing(&'static str),
    /// The program ran and failed.
    Failed {
        /// The video file.
        path: PathBuf,
        /// The last line FFmpeg printed.
        message: String,
    },
    /// The file holds no video stream, or one whose size or length is out of range.
    Unusable {
        /// The video file.
        path: PathBuf,
        /// What is wrong with it.
        why: String,
    },
    /// FFmpeg could not encode the frames given: the last line it printed.
    Encode(String),
    /// Reading or writing the program's pipes failed.
    Io(std::io::Error),
    /// Ctrl-C while decoding.
    Interrupted,
}

impl std::fmt::Display for VideoError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            VideoError::Missing(p) => {
                write!(f, "`{p}` is not installed: video needs FFmpeg (Debian/Ubuntu: apt-get install ffmpeg), or give a folder of PNG frames")
            }
            VideoError::Failed { path, message } => write!(f, "{}: FFmpeg could not read it ({message})", path.display()),
            VideoError::Unusable { path, why } => write!(f, "{}: {why}", path.display()),
            VideoError::Encode(message) => write!(f, "FFmpeg could not encode the MP4: {message}"),
            VideoError::Io(e) => write!(f, "talking to FFmpeg: {e}"),
            VideoError::Interrupted => f.write_str("interrupted"),
        }
    }
}

impl std::error::Error for VideoError {}

fn spawn_error(program: &'static str, e: std::io::Error) -> VideoError {
    if e.kind() == std::io::ErrorKind::NotFound {
        VideoError::Missing(program)
    } else {
        VideoError::Io(e)
    }
}

fn last_line(stderr: &[u8]) -> String {
    let text = String::from_utf8_lossy(stderr);
    text.lines().rev().find(|l| !l.trim().is_empty()).unwrap_or("no message").trim().to_string()
}

/// What `ffprobe` says of a file: the first video stream's size and declared rate, and the
/// container's format name (the name its demuxer logs under).
struct Probe {
    size: (usize, usize),
    fps: Option<f64>,
    container: String,
}

/// Runs `ffprobe` on `path` for `entries`, giving one value a line (its errors are kept, and
/// never reach the user's terminal).
fn ffprobe(path: &Path, stream: bool, entries: &str) -> Result<Vec<String>, VideoError> {
    let mut cmd = Command::new("ffprobe");
    cmd.args(["-v", "error"]);
    if stream {
        cmd.args(["-select_streams", "v:0"]);
    }
    let out = cmd.args(["-show_entries", entries, "-of", "default=nw=1:nk=1"]).arg(path).stdin(Stdio::null()).output().map_err(|e| spawn_error("ffprobe", e))?;
    if !out.status.success() {
        return Err(VideoError::Failed { path: path.into(), message: last_line(&out.stderr) });
    }
    Ok(String::from_utf8_lossy(&out.stdout).lines().map(|l| l.trim().to_string()).collect())
}

/// The file's [`Probe`].
fn probe(path: &Path) -> Result<Probe, VideoError> {
    let unusable = |why: &str| VideoError::Unusable { path: path.into(), why: why.into() };
    let fields = ffprobe(path, true, "stream=width,height,avg_frame_rate")?;
    let [w, h, rate] = &fields[..] else { return Err(unusable("no video stream")) };
    let (Ok(w), Ok(h)) = (w.parse::<usize>(), h.parse::<usize>()) else { return Err(unusable("no video stream")) };
    // "30000/1001", "25/1", or "0/0" for none.
    let fps = rate.split_once('/').and_then(|(n, d)| Some(n.parse::<f64>().ok()? / d.parse::<f64>().ok()?));
    let container = ffprobe(path, false, "format=format_name")?.into_iter().next().unwrap_or_default();
    Ok(Probe { size: (w, h), fps: fps.filter(|r| r.is_finite() && *r > 0.0), container })
}

/// Decodes with FFmpeg's `ffmpeg` program: the options shared by the scan and the decode,
/// so both see the same frames. One decoding thread, so an error is logged just before the
/// frame it damages; every frame the decoder gives, with its own timestamp
/// (`-fps_mode passthrough`: no frame duplicated or dropped to make a constant rate;
/// `-copyts`: timestamps as the file has them, as ffprobe reports them). `input` are
/// decoder options (before `-i`).
fn decoder(path: &Path, input: &[&str]) -> Command {
    let mut cmd = Command::new("ffmpeg");
    cmd.args(["-hide_banner", "-nostdin", "-nostats", "-threads", "1", "-copyts"])
        .args(input)
        .arg("-i")
        .arg(path)
        .args(["-map", "0:v:0", "-fps_mode", "passthrough"])
        .stdin(Stdio::null());
    cmd
}

/// Messages of one decoding problem kept for the report (the rest are counted).
const KEPT_PROBLEMS: usize = 3;

/// What decoding a clip once found (its pixels are not kept): one timestamp and one damage
/// flag per frame, in the order FFmpeg (and OpenCV) number the frames.
///
/// Damage is judged by the pixels, not by FFmpeg's log: a frame is damaged where the file's
/// data is missing (the container's reader reports a corrupt or missing packet, a packet
/// gives no frame, or FFmpeg stops before the end), from there up to the next key frame; or where the decoder had to
/// conceal an error, which shows as a frame whose pixels differ between a decode with error
/// concealment (FFmpeg's default) and one without (`-ec 0`). A decoder error that changes no
/// pixel (a stray unit the decoder skips, as in opencv-doc's `box.mp4`) damages nothing.
#[derive(Clone, Debug, Default)]
pub struct Scan {
    /// Width and height in pixels.
    pub size: (usize, usize),
    /// Frames per second the stream declares (`None` when it declares none).
    pub fps: Option<f64>,
    /// Each frame's presentation time in seconds, from the stream's timestamps (NaN when the
    /// frame has none).
    pub times: Vec<f64>,
    /// Each frame: damaged (see [`Scan`]).
    pub damaged: Vec<bool>,
    /// The first problems that damaged the clip: (the frame decoded next, or the frame count
    /// for the file's end; FFmpeg's message).
    pub problems: Vec<(usize, String)>,
    /// Problems that damaged the clip, in all.
    pub problem_count: usize,
}

impl Scan {
    /// Number of frames.
    pub fn len(&self) -> usize {
        self.times.len()
    }

    /// True when the clip decoded no frame.
    pub fn is_empty(&self) -> bool {
        self.times.is_empty()
    }

    /// True when data is missing or a frame was concealed.
    pub fn is_damaged(&self) -> bool {
        self.problem_count > 0
    }

    /// One line on the damage: how many problems, the damaged frames, FFmpeg's first reasons.
    pub fn damage_report(&self) -> String {
        let flagged = self.damaged.iter().filter(|&&d| d).count();
        let runs = frame_runs(&self.damaged);
        let reasons: Vec<String> = self
            .problems
            .iter()
            .map(|(k, m)| if *k < self.len() { format!("before frame {k}: {m}") } else { format!("at the end of the file: {m}") })
            .collect();
        format!(
            "{} decoding errors; {flagged} of {} frames damaged{}; FFmpeg said: {}",
            self.problem_count,
            self.len(),
            if runs.is_empty() { String::new() } else { format!(" ({runs})") },
            reasons.join("; ")
        )
    }
}

/// Runs of true flags as `a-b` ranges (`3`, `10-19`), the first few.
fn frame_runs(flags: &[bool]) -> String {
    let mut runs = Vec::new();
    let mut k = 0;
    while k < flags.len() {
        if flags[k] {
            let start = k;
            while k < flags.len() && flags[k] {
                k += 1;
            }
            runs.push(if k - start == 1 { format!("frame {start}") } else { format!("frames {start}-{}", k - 1) });
        } else {
            k += 1;
        }
    }
    let more = runs.len().saturating_sub(4);
    runs.truncate(4);
    if more > 0 {
        runs.push(format!("{more} more runs"));
    }
    runs.join(", ")
}

/// One line of FFmpeg's log (`-loglevel level+info`), as far as the scan cares.
#[derive(Debug, PartialEq)]
enum LogLine {
    /// The `showinfo` filter's line for a frame: its presentation time, whether it is a key
    /// frame, and the checksum of its pixels.
    Frame { time: f64, key: bool, checksum: Option<u32> },
    /// A decoding problem (an error, or a warning about corrupt data): `lost` when the file's
    /// data is missing (said by the container's demuxer, or by FFmpeg itself of a packet)
    /// rather than by a decoder; the message.
    Problem { lost: bool, text: String },
    /// Anything else.
    Other,
}

/// Reads one log line. A line is `[context @ 0x..] [level] text` or `[level] text`;
/// `container` is the demuxer's context name (ffprobe's format name).
fn log_line(line: &str, container: &str) -> LogLine {
    let is_level = |r: &str| ["info]", "error]", "warning]", "fatal]", "panic]"].iter().any(|l| r.starts_with(l));
    let (context, rest) = match line.strip_prefix('[') {
        Some(r) if !is_level(r) => match r.split_once("] ") {
            Some((c, t)) => (Some(c.split(" @ ").next().unwrap_or(c)), t),
            None => (None, line),
        },
        _ => (None, line),
    };
    let Some((level, text)) = rest.strip_prefix('[').and_then(|r| r.split_once("] ")) else { return LogLine::Other };
    if context.is_some_and(|c| c.starts_with("Parsed_showinfo")) {
        let field = |name: &str| text.split_whitespace().find_map(|t| t.strip_prefix(name));
        if text.trim_start().starts_with("n:") {
            let time = field("pts_time:").and_then(|v| v.parse::<f64>().ok()).unwrap_or(f64::NAN);
            let checksum = field("checksum:").and_then(|v| u32::from_str_radix(v, 16).ok());
            return LogLine::Frame { time, key: field("iskey:") == Some("1"), checksum };
        }
        return LogLine::Other;
    }
    // The muxer's complaints concern the scan's own (discarded) output, not the file.
    if text.contains("muxer") {
        return LogLine::Other;
    }
    let problem = match level {
        "error" | "fatal" | "panic" => true,
        "warning" => text.contains("corrupt"),
        _ => false,
    };
    if !problem {
        return LogLine::Other;
    }
    // FFmpeg's own lines are about packets (one corrupt, or one that gave no frame), except
    // its note of a decoded frame the decoder marked corrupt, which the pixels judge.
    let lost = match context {
        Some(c) => c == container,
        None => !text.contains("corrupt decoded frame"),
    };
    LogLine::Problem { lost, text: text.trim().to_string() }
}

/// One decode of a clip, its pixels reduced to a checksum a frame.
#[derive(Default)]
struct Pass {
    times: Vec<f64>,
    keys: Vec<bool>,
    checksums: Vec<Option<u32>>,
    /// Each frame: decoded after a problem with the file's data, or after a decoder's error.
    after_loss: Vec<bool>,
    after_error: Vec<bool>,
    /// (frame decoded next, lost, message), in order.
    problems: Vec<(usize, bool, String)>,
    /// FFmpeg's exit status was success.
    finished: bool,
}

/// Decodes `path` once with decoder options `input`, reading FFmpeg's log (never shown).
fn decode_pass(path: &Path, input: &[&str], container: &str, stop: &dyn Fn() -> bool) -> Result<Pass, VideoError> {
    let mut child = decoder(path, input)
        .args(["-loglevel", "level+info", "-vf", "showinfo", "-f", "null", "-"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| spawn_error("ffmpeg", e))?;
    let stderr = child.stderr.take().ok_or_else(|| VideoError::Io(std::io::Error::other("no pipe")))?;
    let mut pass = Pass::default();
    let (mut loss, mut error) = (false, false);
    for line in BufReader::new(stderr).split(b'\n') {
        if stop() {
            let _ = child.kill();
            let _ = child.wait();
            return Err(VideoError::Interrupted);
        }
        let line = line.map_err(VideoError::Io)?;
        match log_line(&String::from_utf8_lossy(&line), container) {
            LogLine::Frame { time, key, checksum } => {
                pass.times.push(time);
                pass.keys.push(key);
                pass.checksums.push(checksum);
                pass.after_loss.push(std::mem::take(&mut loss));
                pass.after_error.push(std::mem::take(&mut error));
            }
            LogLine::Problem { lost, text } => {
                if lost {
                    loss = true;
                } else {
                    error = true;
                }
                pass.problems.push((pass.times.len(), lost, text));
            }
            LogLine::Other => {}
        }
    }
    pass.finished = child.wait().map_err(VideoError::Io)?.success();
    Ok(pass)
}

/// Frames flagged by `after`, and the frames predicted from them up to the next key frame.
fn up_to_key(after: &[bool], keys: &[bool]) -> Vec<bool> {
    let mut flags = Vec::with_capacity(after.len());
    for (k, (&a, &key)) in after.iter().zip(keys).enumerate() {
        let previous = k > 0 && flags[k - 1];
        flags.push(a || (previous && !key));
    }
    flags
}

/// Decodes the first video stream of `path`, keeping no pixels: its frames' timestamps, and
/// which frames are damaged (see [`Scan`]; a second decode, without error concealment, is
/// made only when a decoder logged an error). Refuses a frame side outside `sides`. `stop`
/// is asked between log lines (Ctrl-C).
pub fn scan(path: &Path, sides: std::ops::RangeInclusive<usize>, stop: &dyn Fn() -> bool) -> Result<Scan, VideoError> {
    let Probe { size, fps, container } = probe(path)?;
    if !sides.contains(&size.0) || !sides.contains(&size.1) {
        return Err(VideoError::Unusable {
            path: path.into(),
            why: format!("frames must be {0}x{0} to {1}x{1}, this video is {2}x{3}", sides.start(), sides.end(), size.0, size.1),
        });
    }
    let pass = decode_pass(path, &[], &container, stop)?;
    if pass.times.is_empty() {
        let message = pass.problems.last().map_or_else(|| "no frame decoded".into(), |(_, _, m)| m.clone());
        return Err(VideoError::Failed { path: path.into(), message });
    }
    let n = pass.times.len();
    let decoder_errors = pass.problems.iter().any(|(_, lost, _)| !lost);
    // The frames concealment changed; where the two decodes disagree on the frames
    // themselves, the log's word is taken.
    let concealed = if decoder_errors {
        let plain = decode_pass(path, &["-ec", "0"], &container, stop)?;
        if plain.checksums.len() == n && pass.checksums.iter().all(Option::is_some) {
            pass.checksums.iter().zip(&plain.checksums).map(|(a, b)| a != b).collect()
        } else {
            up_to_key(&pass.after_error, &pass.keys)
        }
    } else {
        vec![false; n]
    };
    let lost = up_to_key(&pass.after_loss, &pass.keys);
    let damaged: Vec<bool> = lost.iter().zip(&concealed).map(|(a, b)| *a || *b).collect();
    // The problems that count: the file's data missing, and decoder errors where a frame
    // was concealed.
    let any_concealed = concealed.contains(&true);
    let mut counted: Vec<(usize, String)> = pass.problems.into_iter().filter(|(_, lost, _)| *lost || any_concealed).map(|(k, _, m)| (k, m)).collect();
    if !pass.finished && counted.is_empty() {
        // FFmpeg failed without saying why in a line we read: the file did not decode to its end.
        counted.push((n, "ffmpeg stopped before the end of the file".into()));
    }
    let problem_count = counted.len();
    counted.truncate(KEPT_PROBLEMS);
    Ok(Scan { size, fps, times: pass.times, damaged, problems: counted, problem_count })
}

/// A video decoded as it is tracked: the frames of a [`Scan`] read from FFmpeg in order,
/// the last few kept, so memory does not grow with the clip's length.
pub struct VideoFrames {
    path: PathBuf,
    size: (usize, usize),
    len: usize,
    child: Child,
    stdout: ChildStdout,
    /// Frames read so far.
    next: usize,
    /// The last [`Self::KEPT`] frames read: (index, pixels), oldest first.
    kept: VecDeque<(usize, Vec<u8>)>,
    /// FFmpeg's last log line, collected by a thread so its pipe never fills.
    log: Option<std::thread::JoinHandle<String>>,
}

impl VideoFrames {
    /// Frames kept for a second look (a run asks for frames in order, a window's frame at
    /// most one or two behind the newest).
    const KEPT: usize = 4;

    /// Starts decoding `path`, whose `scan` says how many frames it gives and how large.
    pub fn open(path: &Path, scan: &Scan) -> Result<VideoFrames, VideoError> {
        let mut child = decoder(path, &[])
            .args(["-loglevel", "error", "-f", "rawvideo", "-pix_fmt", "gray", "-"])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| spawn_error("ffmpeg", e))?;
        let no_pipe = || VideoError::Io(std::io::Error::other("no pipe"));
        let stdout = child.stdout.take().ok_or_else(no_pipe)?;
        let log = drain(child.stderr.take().ok_or_else(no_pipe)?);
        Ok(VideoFrames { path: path.into(), size: scan.size, len: scan.len(), child, stdout, next: 0, kept: VecDeque::new(), log: Some(log) })
    }
}

impl Drop for VideoFrames {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl super::FrameSource for VideoFrames {
    fn size(&self) -> (usize, usize) {
        self.size
    }

    fn len(&self) -> usize {
        self.len
    }

    fn frame(&mut self, k: usize) -> Result<&[u8], super::FrameError> {
        if k >= self.len {
            return Err(super::FrameError::Missing(k));
        }
        while self.next <= k {
            // Reuse the oldest buffer once the window is full.
            let mut buf = if self.kept.len() >= Self::KEPT { self.kept.pop_front().map(|(_, b)| b).unwrap_or_default() } else { Vec::new() };
            buf.resize(self.size.0 * self.size.1, 0);
            if let Err(e) = self.stdout.read_exact(&mut buf) {
                let _ = self.child.kill();
                let _ = self.child.wait();
                let why = if e.kind() == std::io::ErrorKind::UnexpectedEof { "ended" } else { "failed" };
                let log = self.log.take().and_then(|t| t.join().ok()).unwrap_or_default();
                return Err(super::FrameError::Video(format!(
                    "{}: FFmpeg's decoding {why} at frame {} of the {} its scan found ({log})",
                    self.path.display(),
                    self.next,
                    self.len
                )));
            }
            self.kept.push_back((self.next, buf));
            self.next += 1;
        }
        match self.kept.iter().find(|(j, _)| *j == k) {
            Some((_, b)) => Ok(b),
            None => Err(super::FrameError::Video(format!("internal: frame {k} asked for after frame {} of a video decoded in order", self.next - 1))),
        }
    }
}

/// Collects a child's log on a thread (so its pipe never fills) and gives its last line.
fn drain(mut pipe: impl Read + Send + 'static) -> std::thread::JoinHandle<String> {
    std::thread::spawn(move || {
        let mut text = Vec::new();
        let _ = pipe.read_to_end(&mut text);
        last_line(&text)
    })
}

/// An H.264 MP4 (yuv420p, so any player shows it; fragmented, so it streams to any output
/// without seeking) encoded by FFmpeg from yuv420p frames pushed one at a time, its bytes
/// copied into `W` as they come. x264's fastest preset on two threads: an overlay costs
/// about what decoding the clip again does, and at 1080p its encoder stays near 120 MB.
pub struct Mp4Encoder<W> {
    child: Child,
    stdin: Option<ChildStdin>,
    copier: std::thread::JoinHandle<std::io::Result<W>>,
    log: std::thread::JoinHandle<String>,
}

impl<W: Write + Send + 'static> Mp4Encoder<W> {
    /// Starts encoding frames of `size` (both sides even) at `fps` into `out`.
    pub fn start(size: (usize, usize), fps: f64, mut out: W) -> Result<Self, VideoError> {
        let mut child = Command::new("ffmpeg")
            .args(["-v", "error", "-nostdin", "-f", "rawvideo", "-pix_fmt", "yuv420p"])
            .args(["-s", &format!("{}x{}", size.0, size.1), "-r", &format!("{fps}"), "-i", "-"])
            .args(["-c:v", "libx264", "-preset", "ultrafast", "-threads", "2"])
            .args(["-f", "mp4", "-movflags", "frag_keyframe+empty_moov", "-"])
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| spawn_error("ffmpeg", e))?;
        let no_pipe = || VideoError::Io(std::io::Error::other("no pipe"));
        let stdin = child.stdin.take().ok_or_else(no_pipe)?;
        let mut stdout = child.stdout.take().ok_or_else(no_pipe)?;
        let log = drain(child.stderr.take().ok_or_else(no_pipe)?);
        // The output is copied on its own thread, so neither pipe can fill and stall the other.
        let copier = std::thread::spawn(move || std::io::copy(&mut stdout, &mut out).map(|_| out));
        Ok(Mp4Encoder { child, stdin: Some(stdin), copier, log })
    }

    /// Encodes one frame (yuv420p: `width * height * 3 / 2` bytes).
    pub fn push(&mut self, yuv: &[u8]) -> Result<(), VideoError> {
        let stdin = self.stdin.as_mut().ok_or_else(|| VideoError::Encode("the encoder is closed".into()))?;
        if stdin.write_all(yuv).is_err() {
            // FFmpeg stopped: its own reason is in its log.
            self.stdin = None;
            let _ = self.child.wait();
            return Err(VideoError::Encode("ffmpeg stopped taking frames".into()));
        }
        Ok(())
    }

    /// Ends the MP4 and gives its writer back.
    pub fn finish(mut self) -> Result<W, VideoError> {
        drop(self.stdin.take());
        let status = self.child.wait().map_err(VideoError::Io)?;
        let copied = self.copier.join().unwrap_or_else(|_| Err(std::io::Error::other("the copier stopped")));
        let log = self.log.join().unwrap_or_default();
        if !status.success() {
            return Err(VideoError::Encode(log));
        }
        copied.map_err(VideoError::Io)
    }
}


#[cfg(test)]
mod tests {
    use super::{frame_runs, log_line, up_to_key, LogLine};

    #[test]
    fn ffmpeg_log_lines_are_read_as_frames_and_problems() {
        // Reference: lines as FFmpeg 5.1 prints them with `-loglevel level+info -vf showinfo`.
        let mp4 = "mov,mp4,m4a,3gp,3g2,mj2";
        let line = |l: &str| log_line(l, mp4);
        let frame = "[Parsed_showinfo_0 @ 0x55a5f5a82cc0] [info] n:  12 pts:   6144 pts_time:0.48    pos:     5678 fmt:yuv420p sar:1/1 s:160x120 i:P iskey:0 type:P checksum:7EA557FD";
        assert_eq!(line(frame), LogLine::Frame { time: 0.48, key: false, checksum: Some(0x7EA5_57FD) });
        let key = "[Parsed_showinfo_0 @ 0x1] [info] n:   0 pts:      0 pts_time:0       pos:       48 iskey:1 type:I";
        assert_eq!(line(key), LogLine::Frame { time: 0.0, key: true, checksum: None });
        // A decoder's error: the pixels decide.
        let error = "[h264 @ 0x55e41ed2d680] [error] Invalid NAL unit size (121 > 119).";
        assert_eq!(line(error), LogLine::Problem { lost: false, text: "Invalid NAL unit size (121 > 119).".into() });
        // The file's data missing: FFmpeg's reader, and the container's demuxer.
        assert_eq!(line("[warning] half.mp4: corrupt input packet in stream 0"), LogLine::Problem { lost: true, text: "half.mp4: corrupt input packet in stream 0".into() });
        let demuxer = "[mov,mp4,m4a,3gp,3g2,mj2 @ 0x55c830224980] [warning] Packet corrupt (stream = 0, dts = 45568).";
        assert_eq!(line(demuxer), LogLine::Problem { lost: true, text: "Packet corrupt (stream = 0, dts = 45568).".into() });
        assert_eq!(line("[error] Error while decoding stream #0:0: Invalid data found when processing input"), LogLine::Problem { lost: true, text: "Error while decoding stream #0:0: Invalid data found when processing input".into() });
        assert_eq!(line("[warning] g.mp4: corrupt decoded frame in stream 0"), LogLine::Problem { lost: false, text: "g.mp4: corrupt decoded frame in stream 0".into() });
        // Not problems with the file: other warnings, the scan's own muxer, the banner.
        assert_eq!(line("[swscaler @ 0x1] [warning] deprecated pixel format used"), LogLine::Other);
        assert_eq!(line("[null @ 0x1] [error] Application provided invalid, non monotonically increasing dts to muxer in stream 0: 28 >= 28"), LogLine::Other);
        assert_eq!(line("[Parsed_showinfo_0 @ 0x1] [info] config in time_base: 1/12800, frame_rate: 25/1"), LogLine::Other);
        assert_eq!(line("[info] Input #0, mov,mp4,m4a,3gp,3g2,mj2, from 'c.mp4':"), LogLine::Other);
    }

    #[test]
    fn damage_runs_to_the_next_key_frame() {
        // Reference: worked by hand: a problem before frame 1 damages 1 and 2 (predicted),
        // not 3 (a key frame); one before frame 4 damages 4 only.
        let after = [false, true, false, false, true, false];
        let keys = [true, false, false, true, false, true];
        assert_eq!(up_to_key(&after, &keys), [false, true, true, false, true, false]);
    }

    #[test]
    fn damaged_frames_are_listed_as_runs() {
        // Reference: the runs written out by hand.
        let f = [false, true, true, false, true, false, false, true, true, true];
        assert_eq!(frame_runs(&f), "frames 1-2, frame 4, frames 7-9");
    }
}
