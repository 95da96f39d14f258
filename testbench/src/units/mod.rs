//! Where the system's windows come from: the window units on the camera bus, one per
//! processor (thesis 2.2, Appendices A and B), in one of three forms ([`UnitBackend`]):
//!
//! - [`model::BehaviouralUnits`]: the behavioural model of `hdl::WindowUnit`, computed per
//!   window (fast);
//! - [`clocked::ClockedUnits`]: the units stepped clock by clock on the camera raster, the
//!   rust-hdl `WindowUnit`s or the exported `window_network` Verilog compiled with Verilator
//!   (`coopwin_hdl::sim::verilator`), written and read by the firmware's port drivers through
//!   `embedded-hal` pins ([`pins`]).
//!
//! [`clocks::Clocks`] holds the raster in run clocks. Clock 0 of a run is the start of the
//! vertical blanking before frame 0; frame k's FVAL rises on clock `blank + k * period`.
pub mod clocked;
pub mod clocks;
pub mod model;
pub mod pins;

use crate::frames::{FrameError, FrameSource};
use clocked::{ClockedUnits, Trace};
use clocks::Clocks;
use coopwin_firmware::ports::hal_pins::PixelPinError;
use coopwin_firmware::types::WindowRequest;
use coopwin_firmware::ports::window::WriteError;
use coopwin_hdl::sim::camera::Window;
use coopwin_hdl::sim::verilator::VerilatorError;
use coopwin_hdl::verilog::GeometryError;
use core::convert::Infallible;
use model::BehaviouralUnits;

/// Which window units a run uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UnitBackend {
    /// The behavioural model, per window.
    BehaviouralModel,
    /// The rust-hdl blocks, clock by clock.
    RustHdl,
    /// The exported Verilog compiled with Verilator, clock by clock.
    Verilator,
}

/// A window delivered to a processor by its unit.
#[derive(Clone, Debug, PartialEq)]
pub struct Delivered {
    /// The unit (and the processor it serves).
    pub unit: usize,
    /// The frame it was cut from.
    pub frame: usize,
    /// The clock its last pixel was strobed.
    pub clock: u64,
    /// The request it answers.
    pub req: WindowRequest,
    /// Its pixels, packed row by row (decimated ones already dropped).
    pub pixels: Vec<u8>,
}

/// What a clock-by-clock bank of units measured over a run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct UnitStats {
    /// Pixel clocks simulated.
    pub clocks: u64,
    /// Wall time spent inside the simulator (rust-hdl or Verilator), seconds.
    pub seconds: f64,
    /// With a VCD of chosen frames: per unit, the sets taken before the trace began.
    pub sets_before_trace: Vec<usize>,
}

/// The window units of a run, as the system simulation sees them.
pub trait WindowUnits {
    /// Processor `unit` writes `req` from clock `at` on; a window the port cannot carry is
    /// refused (and nothing is written).
    fn request(&mut self, unit: usize, req: WindowRequest, at: u64) -> Result<(), RequestRefused>;
    /// The next window completed on or before clock `until` (earliest first, then by unit),
    /// or `None` once the units have run to `until` without completing one.
    fn next_window(&mut self, until: u64, frames: &mut dyn FrameSource) -> Result<Option<Delivered>, UnitError>;
    /// Ends the run (flushing a VCD, if any) and reports what the units measured.
    fn finish(&mut self) -> Result<UnitStats, UnitError> {
        Ok(UnitStats::default())
    }
}

/// `n` units of kind `backend` on the raster `clocks` (the clocked ones built for its frame
/// size with `pixel_bits`-bit pixels); with `trace`, a VCD of the rust-hdl units.
pub fn open(backend: UnitBackend, clocks: Clocks, pixel_bits: usize, n: usize, trace: Option<Trace>) -> Result<Box<dyn WindowUnits>, UnitError> {
    match (backend, trace) {
        (UnitBackend::BehaviouralModel, Some(_)) => Err(UnitError::ModelNotTraced),
        (UnitBackend::BehaviouralModel, None) => Ok(Box::new(BehaviouralUnits::new(clocks, n))),
        (UnitBackend::RustHdl, trace) => Ok(Box::new(ClockedUnits::rust_hdl(clocks, pixel_bits, n, trace)?)),
        (UnitBackend::Verilator, Some(_)) => Err(UnitError::VerilatorNotTraced),
        (UnitBackend::Verilator, None) => Ok(Box::new(ClockedUnits::verilator(clocks, pixel_bits, n)?)),
    }
}

/// The window unit's coordinates for a request.
pub fn window_of(req: &WindowRequest) -> Window {
    Window {
        xmin: u32::from(req.x0),
        xmax: u32::from(req.x0) + u32::from(req.width) - 1,
        ymin: u32::from(req.y0),
        ymax: u32::from(req.y0) + u32::from(req.height) - 1,
    }
}

/// A request the coordinate port refused (nothing was written).
#[derive(Clone, Debug, PartialEq)]
pub enum RequestRefused {
    /// A window with no column or no row.
    Empty {
        /// The unit.
        unit: usize,
        /// The request.
        req: WindowRequest,
    },
    /// The port driver cannot carry the window.
    Unwritable {
        /// The unit.
        unit: usize,
        /// The request.
        req: WindowRequest,
        /// The driver's reason.
        reason: WriteError,
    },
}

impl std::fmt::Display for RequestRefused {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RequestRefused::Empty { unit, req } => write!(f, "processor {unit}: the empty window {req:?} cannot be written"),
            RequestRefused::Unwritable { unit, req, reason } => {
                write!(f, "processor {unit}: window {req:?} cannot be written: {reason}")
            }
        }
    }
}

impl std::error::Error for RequestRefused {}

/// Why the window units cannot be set up or stepped.
#[derive(Debug)]
pub enum UnitError {
    /// A frame could not be had.
    Frame(FrameError),
    /// A VCD was asked of the behavioural model.
    ModelNotTraced,
    /// A VCD was asked of the Verilator units.
    VerilatorNotTraced,
    /// No window unit is exported for the frames' size or the pixel width.
    Geometry {
        /// Frame width.
        width: usize,
        /// Frame height.
        height: usize,
        /// What is out of range.
        reason: GeometryError,
    },
    /// The strategy needs more units than the Verilator network has.
    TooFewVerilatorUnits {
        /// Units in the network.
        have: usize,
        /// Units the strategy needs.
        need: usize,
    },
    /// The traced frames are not frames of the run.
    TraceFrames {
        /// The frames asked for.
        frames: std::ops::Range<usize>,
        /// Frames in the run.
        run: usize,
    },
    /// A unit strobed a pixel with no window armed.
    StrobeWithoutWindow {
        /// The unit.
        unit: usize,
        /// The clock.
        clock: u64,
    },
    /// The firmware's pixel receiver refused a pixel.
    Receive {
        /// The unit.
        unit: usize,
        /// The clock.
        clock: u64,
        /// The receiver's reason.
        error: PixelPinError<Infallible>,
    },
    /// The VCD could not be written.
    Vcd(std::io::Error),
    /// The Verilator model could not be built or loaded.
    Verilator(VerilatorError),
}

impl std::fmt::Display for UnitError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            UnitError::Frame(e) => write!(f, "{e}"),
            UnitError::ModelNotTraced => f.write_str("a VCD needs the rust-hdl window units (--hdl rust-hdl)"),
            UnitError::VerilatorNotTraced => f.write_str("--vcd records the rust-hdl units (--hdl rust-hdl)"),
            UnitError::Geometry { width, height, reason } => {
                write!(f, "no window unit for {width}x{height} frames: {reason} (the behavioural model, --hdl model, has no limit)")
            }
            UnitError::TooFewVerilatorUnits { have, need } => {
                write!(f, "the Verilator network has {have} units, the strategy needs {need}")
            }
            UnitError::TraceFrames { frames, run } => {
                write!(f, "VCD frames {}..{}: the run has frames 0..{run}", frames.start, frames.end)
            }
            UnitError::StrobeWithoutWindow { unit, clock } => {
                write!(f, "unit {unit} strobed a pixel on clock {clock} with no window armed")
            }
            UnitError::Receive { unit, clock, error } => write!(f, "unit {unit}, clock {clock}: {error:?}"),
            UnitError::Vcd(e) => write!(f, "cannot write the VCD: {e}"),
            UnitError::Verilator(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for UnitError {}

wrap_errors!(UnitError { Frame(FrameError), Verilator(VerilatorError) });
