//! The tracking system in simulated time (thesis 2.3-2.5, 4.2): a camera raster, one window
//! unit per processor (a coordinate set applies to the first frame whose FVAL rises after the
//! set is written, and a window is complete when the raster passes its last pixel), the
//! firmware's processors from `coopwin_firmware::tracker`, each busy for as long as the cost
//! model says its kernels take, and 20 Mbyte/s links between them. A discrete-event loop.
//!
//! - [`config`]: what a run is asked to do (the strategy among it); [`cost`]: how long the processors take;
//! - [`roster`]: the processors of each strategy and their roles;
//! - [`event_loop`]: the loop itself, over `events`, `links` and `writes` (coordinate
//!   writes, the watchdog and the injected faults);
//! - [`log`]: what a run records.
pub mod config;
pub mod cost;
pub mod event_loop;
mod events;
mod links;
pub mod log;
pub mod roster;
mod writes;

pub use config::{CoopPolicy, MpdfWatch, Strategy, SystemConfig};
pub use event_loop::simulate_with;
pub use log::{FrameRecord, Report, Role, RunLog, TrackState, MAX_AGE};

use crate::frames::binned::{self, Binned};
use crate::frames::{FrameError, FrameSource};
use crate::units::clocked::Trace;
use crate::units::clocks::Clocks;
use crate::units::{self, UnitError};
use coopwin_firmware::kernels::confidence::ConfidenceError;
use coopwin_firmware::ports::frame::FrameWriteError;
use coopwin_firmware::ports::link::LinkError;
use coopwin_firmware::types::WindowRequest;
use coopwin_firmware::kernels::view::ViewError;
use core::convert::Infallible;

/// Runs `cfg` over `source` with the window units it names, calling `progress(frame)` at each
/// frame start.
pub fn simulate(cfg: &SystemConfig, source: &mut dyn FrameSource, progress: &mut dyn FnMut(usize)) -> Result<RunLog, SimError> {
    simulate_traced(cfg, source, progress, &mut |_| {}, None)
}

/// [`simulate`], calling `on_record` with each frame's record as the frame ends (see
/// [`simulate_with`]), and with a VCD of every window unit (for `vcd`'s frames) when the
/// units are rust-hdl's. A binning camera (`cfg.bin`) runs over the binned frames, its
/// target taken and its positions given back in the sensor's pixels.
pub fn simulate_traced(
    cfg: &SystemConfig,
    source: &mut dyn FrameSource,
    progress: &mut dyn FnMut(usize),
    on_record: &mut dyn FnMut(&FrameRecord),
    vcd: Option<Trace>,
) -> Result<RunLog, SimError> {
    let k = cfg.bin;
    if k > 1 {
        let in_bins = |p| binned::to_binned(p, k);
        let pixel_clock_hz = cfg.binned_pixel_clock(source.size());
        let cfg = SystemConfig { bin: 1, pixel_clock_hz, target: cfg.target.map(in_bins), model: cfg.model.map(|(f, p)| (f, in_bins(p))), ..cfg.clone() };
        let mut binned = Binned::new(source, k);
        let mut log = simulate_traced(&cfg, &mut binned, progress, &mut |r| on_record(&r.to_sensor(k)), vcd).map_err(|e| e.into_sensor(k))?;
        log.to_sensor(k)?;
        return Ok(log);
    }
    let clocks = Clocks::for_frames(source, cfg.jitter);
    let mut units = units::open(cfg.backend, clocks, cfg.unit_pixel_bits, cfg.strategy.units(), vcd)?;
    let mut log = simulate_with(cfg, source, units.as_mut(), progress, on_record)?;
    let stats = units.finish()?;
    log.hdl_clocks = stats.clocks;
    log.hdl_seconds = stats.seconds;
    log.sets_before_trace = stats.sets_before_trace;
    Ok(log)
}

/// Why a run failed.
#[derive(Debug)]
pub enum SimError {
    /// The window units failed.
    Units(UnitError),
    /// A frame could not be had.
    Frame(FrameError),
    /// The write phase lies past the end of a frame.
    WritePhase {
        /// The phase asked for.
        phase: u64,
        /// Clocks in a frame.
        clocks: u64,
    },
    /// A frame cannot be viewed.
    FrameView {
        /// The frame.
        frame: usize,
        /// The reason.
        error: ViewError,
    },
    /// The template does not fit in the frame around the target.
    TemplateDoesNotFit {
        /// The template's side.
        side: u16,
        /// The point it is centred on.
        at: (f64, f64),
    },
    /// COOP's SSE policy refused the data set size.
    CoopSize {
        /// The size.
        n: usize,
        /// The reason.
        error: ConfidenceError,
    },
    /// The Kalman policy refused its parameters.
    Kalman(ConfidenceError),
    /// The strategy's processors and its units disagree (a defect).
    Roster {
        /// Processors built.
        processors: usize,
        /// Units of the strategy.
        units: usize,
    },
    /// A message addressed to a link that does not exist (a defect).
    NoLink,
    /// A link between processors failed.
    Link {
        /// The sender.
        from: usize,
        /// The receiver.
        to: usize,
        /// The link's error.
        error: LinkError<Infallible>,
    },
    /// The robot controller's link failed.
    RobotLink(FrameWriteError<Infallible>),
    /// A delivered window cannot be viewed.
    Window {
        /// The window's request.
        req: WindowRequest,
        /// The reason.
        error: ViewError,
    },
}

impl std::fmt::Display for SimError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SimError::Units(e) => write!(f, "{e}"),
            SimError::Frame(e) => write!(f, "{e}"),
            SimError::WritePhase { phase, clocks } => {
                write!(f, "write phase {phase}: a frame has {clocks} clocks (0..{})", clocks - 1)
            }
            SimError::FrameView { frame, error } => write!(f, "frame {frame}: {error}"),
            SimError::TemplateDoesNotFit { side, at: (x, y) } => {
                write!(f, "the {side}x{side} template around ({x}, {y}) does not fit in the frame")
            }
            SimError::CoopSize { n, error } => write!(f, "COOP data set size {n}: {error}"),
            SimError::Kalman(e) => write!(f, "Kalman policy: {e}"),
            SimError::Roster { processors, units } => write!(f, "internal: {processors} processors for {units} units"),
            SimError::NoLink => f.write_str("internal: no such link"),
            SimError::Link { from, to, error } => write!(f, "link {from} -> {to}: {error:?}"),
            SimError::RobotLink(e) => write!(f, "robot link: {e:?}"),
            SimError::Window { req, error } => write!(f, "window {req:?}: {error:?}"),
        }
    }
}

impl std::error::Error for SimError {}

impl SimError {
    /// The error of a run over frames binned `k` x `k`, its template and point the sensor's.
    fn into_sensor(self, k: usize) -> SimError {
        match self {
            SimError::TemplateDoesNotFit { side, at } => SimError::TemplateDoesNotFit { side: side * k as u16, at: binned::to_sensor(at, k) },
            e => e,
        }
    }
}

wrap_errors!(SimError { Units(UnitError), Frame(FrameError) });
