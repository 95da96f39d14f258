//! The requests CSV written beside a traced run's VCD (`FILE.requests.csv`: unit,clock,xmin,
//! xmax,ymin,ymax,decimate), and read back by `coopwin audit`: the coordinate sets each
//! processor wrote, in the window unit's coordinates.
use crate::system::RunLog;
use crate::units::window_of;
use coopwin_firmware::types::{Decimation, WindowRequest};
use coopwin_hdl::sim::camera::Window;
use std::fmt::Write as _;

/// A coordinate set as the unit takes it: the window and the decimation line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Set {
    /// The window's bounds.
    pub window: Window,
    /// Every other pixel of every other row.
    pub decimate: bool,
}

impl Set {
    /// The set a request writes.
    pub fn of(req: &WindowRequest) -> Set {
        Set { window: window_of(req), decimate: req.decimation == Decimation::Quarter }
    }
}

impl Default for Set {
    fn default() -> Self {
        Set { window: Window { xmin: 0, xmax: 0, ymin: 0, ymax: 0 }, decimate: false }
    }
}

/// `(xmin, xmax, ymin, ymax, decimate)`, as the audit's messages show a set.
impl std::fmt::Display for Set {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let w = &self.window;
        write!(f, "({}, {}, {}, {}, {})", w.xmin, w.xmax, w.ymin, w.ymax, self.decimate)
    }
}

/// The header line.
const HEADER: &str = "unit,clock,xmin,xmax,ymin,ymax,decimate\n";

/// The requests CSV of a run (unit k is processor k, traced as `uut$k`). With a VCD of chosen
/// frames, the sets taken before the trace began are left out.
pub fn to_csv(log: &RunLog) -> String {
    let mut s = String::from(HEADER);
    let mut skip = log.sets_before_trace.clone();
    for (p, clock, r) in &log.requests {
        if let Some(n) = skip.get_mut(*p).filter(|n| **n > 0) {
            *n -= 1;
            continue;
        }
        let Set { window: w, decimate } = Set::of(r);
        let _ = writeln!(s, "{p},{clock},{},{},{},{},{}", w.xmin, w.xmax, w.ymin, w.ymax, decimate as u8);
    }
    s
}

/// Why a requests CSV cannot be read.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum RequestsError {
    /// A field is not a number.
    NotANumber {
        /// Line number, from 1.
        line: usize,
        /// The field.
        field: String,
    },
    /// A line has other than 7 fields.
    FieldCount {
        /// Line number, from 1.
        line: usize,
    },
}

impl std::fmt::Display for RequestsError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RequestsError::NotANumber { line, field } => write!(f, "requests line {line}: '{field}' is not a number"),
            RequestsError::FieldCount { line } => write!(f, "requests line {line}: expected 7 fields"),
        }
    }
}

impl std::error::Error for RequestsError {}

/// Unit `unit`'s (clock queued, set) pairs in a requests CSV.
pub fn read(text: &str, unit: usize) -> Result<Vec<(usize, Set)>, RequestsError> {
    let mut out = Vec::new();
    for (i, l) in text.lines().enumerate().skip(1) {
        let f: Vec<u32> = l
            .split(',')
            .map(|v| v.trim().parse::<u32>().map_err(|_| RequestsError::NotANumber { line: i + 1, field: v.into() }))
            .collect::<Result<_, _>>()?;
        match f[..] {
            [u, t, xmin, xmax, ymin, ymax, d] if u as usize == unit => {
                out.push((t as usize, Set { window: Window { xmin, xmax, ymin, ymax }, decimate: d != 0 }))
            }
            [_, _, _, _, _, _, _] => {}
            _ => return Err(RequestsError::FieldCount { line: i + 1 }),
        }
    }
    Ok(out)
}
