//! A user's frames (`coopwin track --frames`): a folder of PNG files or a video file, and
//! what a run's CSV rows say of them beyond the run's record.
use super::folder::{FolderError, FolderFrames, SIDES};
use super::video::{self, Scan, VideoError, VideoFrames};
use super::{FrameError, FrameSource};
use std::path::{Path, PathBuf};

/// Where the frames come from: a folder of PNG frames or a video, decoded as it is tracked.
pub enum Input {
    /// A folder of PNG frames.
    Folder(FolderFrames),
    /// A video file and what its scan found.
    Video {
        /// The file.
        path: PathBuf,
        /// Its frames' timestamps and damage.
        scan: Scan,
    },
}

/// Why an input cannot be tracked.
#[derive(Debug)]
pub enum InputError {
    /// Nothing at the path.
    NoSuchFile(PathBuf),
    /// The folder's frames cannot be used.
    Folder(FolderError),
    /// The video cannot be read.
    Video(VideoError),
    /// The video is damaged (see [`Scan`]) and damage was not allowed: its path and the
    /// scan's report.
    Damaged(PathBuf, String),
}

wrap_errors!(InputError { Folder(FolderError), Video(VideoError) });

impl std::fmt::Display for InputError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            InputError::NoSuchFile(p) => write!(f, "{}: no such file or folder", p.display()),
            InputError::Folder(e) => e.fmt(f),
            InputError::Video(e) => e.fmt(f),
            InputError::Damaged(p, report) => write!(f, "{}: the video is damaged: {report}", p.display()),
        }
    }
}

impl std::error::Error for InputError {}

impl Input {
    /// Opens `path`: a folder of frames, or a video file, scanned once through FFmpeg (`stop`
    /// is asked during the scan: Ctrl-C). A damaged video is refused unless `allow_damaged`.
    pub fn open(path: &Path, allow_damaged: bool, stop: &dyn Fn() -> bool) -> Result<Input, InputError> {
        if !path.exists() {
            return Err(InputError::NoSuchFile(path.into()));
        }
        if !path.is_file() {
            return Ok(Input::Folder(FolderFrames::open(path)?));
        }
        let scan = video::scan(path, SIDES, stop)?;
        if scan.is_damaged() && !allow_damaged {
            return Err(InputError::Damaged(path.into(), scan.damage_report()));
        }
        Ok(Input::Video { path: path.into(), scan })
    }

    /// A pass over the frames, from the first (a video is decoded again for each pass).
    pub fn frames(&mut self) -> Result<Frames<'_>, VideoError> {
        match self {
            Input::Folder(f) => Ok(Frames::Folder(f)),
            Input::Video { path, scan } => Ok(Frames::Video(VideoFrames::open(path, scan)?)),
        }
    }

    /// Width and height of the frames.
    pub fn size(&self) -> (usize, usize) {
        match self {
            Input::Folder(f) => f.size(),
            Input::Video { scan, .. } => scan.size,
        }
    }

    /// Number of frames.
    pub fn len(&self) -> usize {
        match self {
            Input::Folder(f) => f.len(),
            Input::Video { scan, .. } => scan.len(),
        }
    }

    /// True when the input has no frame.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The rate the source declares (a video's), if any.
    pub fn declared_fps(&self) -> Option<f64> {
        match self {
            Input::Folder(_) => None,
            Input::Video { scan, .. } => scan.fps,
        }
    }

    /// The damage a video's scan found, as one line, when it found any.
    pub fn damage(&self) -> Option<String> {
        match self {
            Input::Video { scan, .. } if scan.is_damaged() => Some(scan.damage_report()),
            _ => None,
        }
    }
}

/// One pass over an input's frames.
pub enum Frames<'a> {
    /// A folder's frames, decoded on demand.
    Folder(&'a mut FolderFrames),
    /// A video being decoded.
    Video(VideoFrames),
}

impl FrameSource for Frames<'_> {
    fn size(&self) -> (usize, usize) {
        match self {
            Frames::Folder(f) => f.size(),
            Frames::Video(v) => v.size(),
        }
    }
    fn len(&self) -> usize {
        match self {
            Frames::Folder(f) => f.len(),
            Frames::Video(v) => v.len(),
        }
    }
    fn frame(&mut self, k: usize) -> Result<&[u8], FrameError> {
        match self {
            Frames::Folder(f) => f.frame(k),
            Frames::Video(v) => v.frame(k),
        }
    }
}

/// What a run's rows say of each frame beyond the run's record: the folder's file names,
/// or the video's timestamps and damage; taken from the input before its frames are read,
/// so rows are written during the run.
pub struct RowFacts {
    names: Vec<String>,
    video: Option<(Vec<f64>, Vec<bool>)>,
}

impl RowFacts {
    /// The facts of `input`'s frames.
    pub fn of(input: &Input) -> RowFacts {
        match input {
            Input::Folder(f) => RowFacts { names: f.names(), video: None },
            Input::Video { scan, .. } => RowFacts { names: Vec::new(), video: Some((scan.times.clone(), scan.damaged.clone())) },
        }
    }

    /// A folder's file names, in the order tracked.
    pub fn files(&self) -> Option<&[String]> {
        self.video.is_none().then_some(self.names.as_slice())
    }

    /// A video's frame times in seconds (NaN where a frame has none).
    pub fn times(&self) -> Option<&[f64]> {
        self.video.as_ref().map(|(t, _)| t.as_slice())
    }

    /// A video's damaged frames (see [`Scan`]).
    pub fn damaged(&self) -> Option<&[bool]> {
        self.video.as_ref().map(|(_, d)| d.as_slice())
    }
}
