//! Video files in and out through the `ffmpeg` and `ffprobe` programs (Debian package
//! `ffmpeg`): a clip is decoded to 8-bit gray frames for tracking, and an overlay is encoded
//! to MP4. No codec is linked into coopwin; without the programs these give a typed error
//! that says what to install.
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

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
        }
    }
}

impl std::error::Error for VideoError {}

/// A decoded clip: gray frames, row by row, and the rate the file declares.
#[derive(Clone, Debug)]
pub struct Clip {
    /// Width and height in pixels.
    pub size: (usize, usize),
    /// Frames per second the stream declares (`None` when it declares none).
    pub fps: Option<f64>,
    /// The frames, `width * height` bytes each.
    pub frames: Vec<Vec<u8>>,
}

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

/// The first video stream's size and declared rate, from `ffprobe`.
fn probe(path: &Path) -> Result<((usize, usize), Option<f64>), VideoError> {
    let out = Command::new("ffprobe")
        .args(["-v", "error", "-select_streams", "v:0", "-show_entries", "stream=width,height,avg_frame_rate", "-of", "csv=p=0"])
        .arg(path)
        .stdin(Stdio::null())
        .output()
        .map_err(|e| spawn_error("ffprobe", e))?;
    if !out.status.success() {
        return Err(VideoError::Failed { path: path.into(), message: last_line(&out.stderr) });
    }
    let text = String::from_utf8_lossy(&out.stdout);
    let fields: Vec<&str> = text.trim().split(',').collect();
    let unusable = |why: &str| VideoError::Unusable { path: path.into(), why: why.into() };
    let [w, h, rate] = fields[..] else { return Err(unusable("no video stream")) };
    let (w, h) = (w.parse::<usize>(), h.parse::<usize>());
    let (Ok(w), Ok(h)) = (w, h) else { return Err(unusable("no video stream")) };
    // "30000/1001", "25/1", or "0/0" for none.
    let fps = rate.split_once('/').and_then(|(n, d)| Some(n.parse::<f64>().ok()? / d.parse::<f64>().ok()?));
    Ok(((w, h), fps.filter(|r| r.is_finite() && *r > 0.0)))
}

/// Decodes every frame of the first video stream of `path` to 8-bit gray (ITU-R BT.601
/// luma, FFmpeg's `gray` format), refusing a frame side outside `sides` or a clip longer
/// than `max_frames`.
pub fn decode(path: &Path, sides: std::ops::RangeInclusive<usize>, max_frames: usize) -> Result<Clip, VideoError> {
    let (size, fps) = probe(path)?;
    if !sides.contains(&size.0) || !sides.contains(&size.1) {
        return Err(VideoError::Unusable {
            path: path.into(),
            why: format!("frames must be {0}x{0} to {1}x{1}, this video is {2}x{3}", sides.start(), sides.end(), size.0, size.1),
        });
    }
    let mut child = Command::new("ffmpeg")
        .args(["-v", "error", "-nostdin", "-i"])
        .arg(path)
        .args(["-map", "0:v:0", "-f", "rawvideo", "-pix_fmt", "gray", "-"])
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| spawn_error("ffmpeg", e))?;
    let n = size.0 * size.1;
    let mut frames = Vec::new();
    let mut stdout = child.stdout.take().ok_or_else(|| VideoError::Io(std::io::Error::other("no pipe")))?;
    loop {
        let mut buf = vec![0u8; n];
        match stdout.read_exact(&mut buf) {
            Ok(()) => frames.push(buf),
            Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => break,
            Err(e) => return Err(VideoError::Io(e)),
        }
        if frames.len() > max_frames {
            let _ = child.kill();
            let _ = child.wait();
            return Err(VideoError::Unusable { path: path.into(), why: format!("longer than {max_frames} frames") });
        }
    }
    let out = child.wait_with_output().map_err(VideoError::Io)?;
    if !out.status.success() || frames.is_empty() {
        return Err(VideoError::Failed { path: path.into(), message: last_line(&out.stderr) });
    }
    Ok(Clip { size, fps, frames })
}

/// Encodes RGB frames (`width * height * 3` bytes each) at `fps` as an H.264 MP4 (yuv420p,
/// so any player shows it; odd sides are padded by one pixel; fragmented, so it streams to
/// any output without seeking) and returns its bytes.
pub fn mp4_bytes(size: (usize, usize), fps: f64, frames: Vec<Vec<u8>>) -> Result<Vec<u8>, VideoError> {
    let mut child = Command::new("ffmpeg")
        .args(["-v", "error", "-nostdin", "-f", "rawvideo", "-pix_fmt", "rgb24"])
        .args(["-s", &format!("{}x{}", size.0, size.1), "-r", &format!("{fps}"), "-i", "-"])
        .args(["-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-pix_fmt", "yuv420p"])
        .args(["-f", "mp4", "-movflags", "frag_keyframe+empty_moov", "-"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| spawn_error("ffmpeg", e))?;
    let mut stdin = child.stdin.take().ok_or_else(|| VideoError::Io(std::io::Error::other("no pipe")))?;
    // A thread feeds the frames while this one collects the output: neither pipe can fill up
    // and stall the other.
    let feeder = std::thread::spawn(move || -> std::io::Result<()> {
        for f in &frames {
            stdin.write_all(f)?;
        }
        Ok(())
    });
    let out = child.wait_with_output().map_err(VideoError::Io)?;
    let fed = feeder.join().unwrap_or_else(|_| Err(std::io::Error::other("the frame feeder stopped")));
    if !out.status.success() || out.stdout.is_empty() {
        return Err(VideoError::Encode(last_line(&out.stderr)));
    }
    fed.map_err(VideoError::Io)?;
    Ok(out.stdout)
}

impl super::FrameSource for Clip {
    fn size(&self) -> (usize, usize) {
        self.size
    }

    fn len(&self) -> usize {
        self.frames.len()
    }

    fn frame(&mut self, k: usize) -> Result<&[u8], super::FrameError> {
        self.frames.get(k).map(Vec::as_slice).ok_or(super::FrameError::Missing(k))
    }
}
