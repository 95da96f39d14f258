//! Ground truth and its file, `groundtruth.csv` (frame,centre_x,centre_y,corner_x,corner_y,
//! visible): written beside a scene's frames by `coopwin scene`, read back by `coopwin track`.
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Ground truth of one frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Truth {
    /// Frame index.
    pub frame: usize,
    /// Centre of the part (the centroid of its outline).
    pub centre: (f64, f64),
    /// The tracked corner of the part.
    pub corner: (f64, f64),
    /// Whether the part's centre is inside the image.
    pub visible: bool,
}

/// The file's header line.
const HEADER: &str = "frame,centre_x,centre_y,corner_x,corner_y,visible\n";

/// The text of a `groundtruth.csv` for `truth`.
pub fn to_csv(truth: impl IntoIterator<Item = Truth>) -> String {
    let mut csv = String::from(HEADER);
    for t in truth {
        let _ = writeln!(
            csv,
            "{},{:.4},{:.4},{:.4},{:.4},{}",
            t.frame, t.centre.0, t.centre.1, t.corner.0, t.corner.1, t.visible as u8
        );
    }
    csv
}

/// Why a `groundtruth.csv` cannot be read.
#[derive(Debug)]
pub enum GroundTruthError {
    /// The file cannot be read.
    Io {
        /// The file.
        path: PathBuf,
        /// The reason.
        source: std::io::Error,
    },
    /// A field is missing or not a number.
    BadField {
        /// The file.
        path: PathBuf,
        /// Line number, from 1.
        line: usize,
        /// Field number, from 1.
        field: usize,
    },
}

impl std::fmt::Display for GroundTruthError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            GroundTruthError::Io { path, source } => write!(f, "cannot read {}: {source}", path.display()),
            GroundTruthError::BadField { path, line, field } => write!(f, "{}: line {line}: bad field {field}", path.display()),
        }
    }
}

impl std::error::Error for GroundTruthError {}

/// Reads a `groundtruth.csv`.
pub fn read(path: &Path) -> Result<Vec<Truth>, GroundTruthError> {
    let text = std::fs::read_to_string(path).map_err(|source| GroundTruthError::Io { path: path.into(), source })?;
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let num = |k: usize| -> Result<f64, GroundTruthError> {
            f.get(k)
                .and_then(|s| s.trim().parse::<f64>().ok())
                .ok_or_else(|| GroundTruthError::BadField { path: path.into(), line: i + 1, field: k + 1 })
        };
        out.push(Truth {
            frame: num(0)? as usize,
            centre: (num(1)?, num(2)?),
            corner: (num(3)?, num(4)?),
            visible: num(5)? != 0.0,
        });
    }
    Ok(out)
}
