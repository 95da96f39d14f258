//! The command line's values: the choices shared by several subcommands and the parsers of
//! numbers, ranges, points, windows and jitter, each refusing a bad value with the reason.
use crate::frames::folder::SIDES;
use crate::system::cost::CostModel;
use crate::system::{CoopPolicy, MpdfWatch, Strategy};
use crate::units::UnitBackend;
use super::CliError;
use coopwin_hdl::sim::camera::{Jitter, Window};
use coopwin_hdl::verilog::Geometry;
use std::fmt::Display;

/// `--strategy`.
#[derive(Clone, Copy, clap::ValueEnum)]
// No doc comments on the variants: clap would list them as help beside each value.
#[allow(missing_docs)]
pub enum StrategyArg {
    Spmf,
    Tpdf,
    Mpdf,
    Coop,
}

impl From<StrategyArg> for Strategy {
    fn from(s: StrategyArg) -> Strategy {
        match s {
            StrategyArg::Spmf => Strategy::Spmf,
            StrategyArg::Tpdf => Strategy::Tpdf,
            StrategyArg::Mpdf => Strategy::Mpdf,
            StrategyArg::Coop => Strategy::Coop,
        }
    }
}

/// `--policy`.
#[derive(Clone, Copy, PartialEq, clap::ValueEnum)]
pub enum PolicyArg {
    /// The corner detector only where it measures the tracked point
    Guarded,
    /// The thesis's least-squares SSE (4.3)
    Sse,
    /// A Kalman filter's innovation (5.2)
    Kalman,
}

impl From<PolicyArg> for CoopPolicy {
    fn from(p: PolicyArg) -> CoopPolicy {
        match p {
            PolicyArg::Guarded => CoopPolicy::Guarded,
            PolicyArg::Sse => CoopPolicy::Sse,
            PolicyArg::Kalman => CoopPolicy::Kalman,
        }
    }
}

/// `--watch`.
#[derive(Clone, Copy, PartialEq, clap::ValueEnum)]
// No doc comments on the variants: clap would list them as help beside each value.
#[allow(missing_docs)]
pub enum WatchArg {
    Strips,
    Halves,
}

impl From<WatchArg> for MpdfWatch {
    fn from(w: WatchArg) -> MpdfWatch {
        match w {
            WatchArg::Strips => MpdfWatch::Strips,
            WatchArg::Halves => MpdfWatch::Halves,
        }
    }
}

/// `--hdl`.
#[derive(Clone, Copy, PartialEq, clap::ValueEnum)]
// No doc comments on the variants: clap would list them as help beside each value.
#[allow(missing_docs)]
pub enum HdlArg {
    Model,
    RustHdl,
    Verilator,
}

impl From<HdlArg> for UnitBackend {
    fn from(h: HdlArg) -> UnitBackend {
        match h {
            HdlArg::Model => UnitBackend::BehaviouralModel,
            HdlArg::RustHdl => UnitBackend::RustHdl,
            HdlArg::Verilator => UnitBackend::Verilator,
        }
    }
}

/// `--profile`.
#[derive(Clone, Copy, clap::ValueEnum)]
// No doc comments on the variants: clap would list them as help beside each value.
#[allow(missing_docs)]
pub enum ProfileArg {
    C40,
    Native,
}

impl From<ProfileArg> for CostModel {
    fn from(p: ProfileArg) -> CostModel {
        match p {
            ProfileArg::C40 => CostModel::C40,
            ProfileArg::Native => CostModel::NATIVE,
        }
    }
}

/// Why a value on the command line cannot be used.
#[derive(Debug)]
pub enum ValueError {
    /// The value's form is wrong: what is expected instead.
    Expected(&'static str),
    /// Not a number.
    NotANumber(String),
    /// A negative number where `what` is asked for.
    Negative {
        /// The value.
        value: String,
        /// What the value is.
        what: &'static str,
    },
    /// A fraction where a whole number is asked for.
    NotWhole {
        /// The value.
        value: String,
        /// What the value is.
        what: &'static str,
    },
    /// A number too large for its type.
    TooLarge {
        /// The value.
        value: String,
        /// What the value is.
        what: &'static str,
    },
    /// A number outside `lo..hi`.
    OutOfRange {
        /// The value.
        value: String,
        /// The range's bounds.
        range: (String, String),
    },
    /// A value refused for `error`, with the range it should lie in.
    Ranged {
        /// Why the value was refused.
        error: Box<ValueError>,
        /// The range's bounds.
        range: (String, String),
    },
    /// A range whose end comes before its start.
    ReversedRange(usize, usize),
    /// A range with no frame in it.
    EmptyRange(usize),
    /// Blanking jitter beyond a stalled camera's.
    JitterTooLarge(u32, u32),
    /// A negative pixel coordinate.
    NegativeCoordinate(String),
    /// A coordinate past the largest frame.
    BeyondFrames(String),
    /// A window coordinate that is not a number.
    NotACoordinate(String),
    /// A window with other than four coordinates.
    WindowValues(usize),
    /// A window off the largest sensor a unit is exported for (4096x4096).
    WindowOffCamera,
    /// A window with no area.
    WindowEmpty,
    /// A box with other than four values.
    BoxValues(usize),
    /// A box side under the smallest template.
    BoxTooSmall(u32, u32),
    /// A frame size that is not WxH within the sides accepted.
    Size(String),
}

impl Display for ValueError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ValueError::Expected(what) => f.write_str(what),
            ValueError::NotANumber(v) => write!(f, "'{v}' is not a number"),
            ValueError::Negative { value, what } => write!(f, "'{value}' is negative ({what})"),
            ValueError::NotWhole { value, what } => write!(f, "'{value}' is not a whole number ({what})"),
            ValueError::TooLarge { value, what } => write!(f, "'{value}' is too large for {what}"),
            ValueError::OutOfRange { value, range: (lo, hi) } => write!(f, "{value} is out of range; expected {lo}..{hi}"),
            ValueError::Ranged { error, range: (lo, hi) } => write!(f, "{error}; expected {lo}..{hi}"),
            ValueError::ReversedRange(a, b) => {
                write!(f, "the range is reversed (FIRST {a} is after END {b}); write {b}..{a}")
            }
            ValueError::EmptyRange(a) => {
                write!(f, "the range is empty (END is excluded); for frame {a} alone write {a}..{}", a + 1)
            }
            ValueError::JitterTooLarge(line, frame) => {
                write!(f, "at most 4096 clocks a line and 8000000 a frame, got {line},{frame}")
            }
            ValueError::NegativeCoordinate(v) => write!(f, "'{v}' is negative; pixel centres start at 0 (the top-left pixel)"),
            ValueError::BeyondFrames(v) => {
                write!(f, "'{v}' is beyond the largest frame (coordinates run 0..{})", SIDES.end() - 1)
            }
            ValueError::NotACoordinate(v) => write!(f, "'{v}' is not a coordinate"),
            ValueError::WindowValues(n) => write!(f, "expected XMIN,XMAX,YMIN,YMAX, got {n} values"),
            ValueError::WindowOffCamera => f.write_str("coordinates must be 0..4095 (the largest sensor, 4096x4096)"),
            ValueError::WindowEmpty => f.write_str("a window needs XMIN < XMAX and YMIN < YMAX"),
            ValueError::BoxValues(n) => write!(f, "expected X,Y,W,H (e.g. 40,36,24,20), got {n} values"),
            ValueError::Size(v) => write!(f, "'{v}' is not a frame size WxH with sides {}..{} (e.g. 640x480)", SIDES.start(), SIDES.end()),
            ValueError::BoxTooSmall(w, h) => write!(f, "a {w}x{h} box is too small: W and H must be at least 4 (the smallest template)"),
        }
    }
}

impl std::error::Error for ValueError {}

/// `--vcd-frames FIRST..END`.
pub fn parse_frames(s: &str) -> Result<std::ops::Range<usize>, ValueError> {
    let (a, b) = s.split_once("..").ok_or(ValueError::Expected("expected FIRST..END, e.g. 10..12"))?;
    let n = |v: &str| whole::<usize>(v, "a frame number");
    let r = n(a)?..n(b)?;
    if r.start > r.end {
        return Err(ValueError::ReversedRange(r.start, r.end));
    }
    if r.start == r.end {
        return Err(ValueError::EmptyRange(r.start));
    }
    Ok(r)
}

/// A whole number, with a reason when it is negative or not a number (`what` names it).
fn whole<T: std::str::FromStr>(v: &str, what: &'static str) -> Result<T, ValueError> {
    let v = v.trim();
    v.parse::<T>().map_err(|_| match v.parse::<f64>() {
        Ok(x) if x < 0.0 => ValueError::Negative { value: v.into(), what },
        Ok(x) if x.is_finite() => ValueError::NotWhole { value: v.into(), what },
        Ok(_) => ValueError::NotANumber(v.into()),
        Err(_) if v.parse::<i128>().is_ok() => ValueError::TooLarge { value: v.into(), what },
        Err(_) => ValueError::NotANumber(v.into()),
    })
}

/// A whole number in LO..=HI (`what` names it).
pub fn parse_in<T>(lo: T, hi: T, what: &'static str) -> impl Fn(&str) -> Result<T, ValueError> + Clone + Send + Sync + 'static
where
    T: std::str::FromStr + PartialOrd + Display + Copy + Send + Sync + 'static,
{
    move |s: &str| {
        let range = || (lo.to_string(), hi.to_string());
        let v = whole::<T>(s, what).map_err(|e| ValueError::Ranged { error: Box::new(e), range: range() })?;
        if v < lo || v > hi {
            return Err(ValueError::OutOfRange { value: v.to_string(), range: range() });
        }
        Ok(v)
    }
}

/// `--blank-jitter LINE,FRAME[,SEED]`.
pub fn parse_jitter(s: &str) -> Result<Jitter, ValueError> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let n = |v: &str| whole::<u32>(v, "a number of clocks");
    let j = match parts[..] {
        [line, frame] => Jitter { seed: 1, line_max: n(line)?, frame_max: n(frame)? },
        [line, frame, seed] => Jitter { seed: whole(seed, "a seed")?, line_max: n(line)?, frame_max: n(frame)? },
        _ => return Err(ValueError::Expected("expected LINE,FRAME or LINE,FRAME,SEED")),
    };
    // Beyond these a frame takes seconds of camera time: a stalled camera, not jitter.
    if j.line_max > 4_096 || j.frame_max > 8_000_000 {
        return Err(ValueError::JitterTooLarge(j.line_max, j.frame_max));
    }
    Ok(j)
}

/// `--target X,Y`.
pub fn parse_point(s: &str) -> Result<(f64, f64), ValueError> {
    let (x, y) = s.split_once(',').ok_or(ValueError::Expected("expected X,Y, e.g. 56.3,60"))?;
    let p = |v: &str| {
        let v = v.trim();
        match v.parse::<f64>() {
            Ok(x) if !x.is_finite() => Err(ValueError::NotANumber(v.into())),
            Ok(x) if x < 0.0 => Err(ValueError::NegativeCoordinate(v.into())),
            // Frames are at most `SIDES.end()` pixels a side (see `coopwin track --help`).
            Ok(x) if x > (SIDES.end() - 1) as f64 => Err(ValueError::BeyondFrames(v.into())),
            Ok(x) => Ok(x),
            Err(_) => Err(ValueError::NotANumber(v.into())),
        }
    };
    Ok((p(x)?, p(y)?))
}

/// `--window XMIN,XMAX,YMIN,YMAX`: a valid window of the 256x256 camera.
pub fn parse_window(s: &str) -> Result<Window, ValueError> {
    let v: Vec<u32> = s.split(',').map(|p| p.trim().parse::<u32>().map_err(|_| ValueError::NotACoordinate(p.into()))).collect::<Result<_, _>>()?;
    let [xmin, xmax, ymin, ymax] = v[..] else {
        return Err(ValueError::WindowValues(v.len()));
    };
    let w = Window { xmin, xmax, ymin, ymax };
    if xmax > 4095 || ymax > 4095 {
        return Err(ValueError::WindowOffCamera);
    }
    if !w.is_valid() {
        return Err(ValueError::WindowEmpty);
    }
    Ok(w)
}

/// `--target-box X,Y,W,H`: whole pixels, W and H at least 4, inside the largest frame.
pub fn parse_box(s: &str) -> Result<(u32, u32, u32, u32), ValueError> {
    let v: Vec<&str> = s.split(',').map(str::trim).collect();
    let [x, y, w, h] = v[..] else { return Err(ValueError::BoxValues(v.len())) };
    let whole = |v: &str| {
        if v.starts_with('-') {
            return Err(ValueError::NegativeCoordinate(v.into()));
        }
        let n = v.parse::<u32>().map_err(|_| ValueError::NotACoordinate(v.into()))?;
        if n as usize > *SIDES.end() {
            return Err(ValueError::BeyondFrames(v.into()));
        }
        Ok(n)
    };
    let (x, y, w, h) = (whole(x)?, whole(y)?, whole(w)?, whole(h)?);
    if w < 4 || h < 4 {
        return Err(ValueError::BoxTooSmall(w, h));
    }
    Ok((x, y, w, h))
}

/// `--fps F`: a frame rate between 0.1 and 100000 frames a second.
pub fn parse_fps(s: &str) -> Result<f64, ValueError> {
    let v = s.trim();
    match v.parse::<f64>() {
        Ok(f) if f.is_finite() && (0.1..=100_000.0).contains(&f) => Ok(f),
        Ok(_) => Err(ValueError::OutOfRange { value: v.into(), range: ("0.1".into(), "100000".into()) }),
        Err(_) => Err(ValueError::NotANumber(v.into())),
    }
}

/// `--size WxH`: each side within the frame sides `track` accepts.
pub fn parse_size(s: &str) -> Result<(usize, usize), ValueError> {
    let bad = || ValueError::Size(s.trim().into());
    let (w, h) = s.trim().split_once(['x', 'X']).ok_or_else(bad)?;
    let (w, h) = (w.parse::<usize>().map_err(|_| bad())?, h.parse::<usize>().map_err(|_| bad())?);
    if SIDES.contains(&w) && SIDES.contains(&h) {
        Ok((w, h))
    } else {
        Err(bad())
    }
}

/// A sensor's size and pixel width (`verilog`, `waves`).
#[derive(clap::Args)]
pub struct SensorArgs {
    /// Sensor width: pixels per line (16..4096)
    #[arg(long, default_value_t = Geometry::CA_D1.width)]
    pub width: usize,
    /// Sensor height: lines per frame (16..4096)
    #[arg(long, default_value_t = Geometry::CA_D1.height)]
    pub height: usize,
    /// Bits per pixel (8..16)
    #[arg(long, default_value_t = Geometry::CA_D1.pixel_bits)]
    pub pixel_bits: usize,
}

impl SensorArgs {
    /// The geometry, or an argument error naming what is out of range.
    pub fn geometry(&self) -> Result<Geometry, CliError> {
        Geometry::new(self.width, self.height, self.pixel_bits).map_err(|e| CliError::arg(e.to_string()))
    }
}
