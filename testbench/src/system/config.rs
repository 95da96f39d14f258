//! A run's configuration: the strategy, the processors' speeds, the window units, COOP's
//! decision policy and the faults to inject (thesis 2.3-2.6, 4.2-4.3, 5.2).
use super::cost::CostModel;
use crate::frames::binned;
use crate::frames::FrameSource;
use crate::units::clocks::Clocks;
use crate::units::UnitBackend;
use coopwin_firmware::processors::Params;
use coopwin_hdl::sim::camera::Jitter;

/// A windowing strategy (thesis 2.3, 4.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Strategy {
    /// Single processor, multiple function.
    Spmf,
    /// Triple processor, dedicated function.
    Tpdf,
    /// Multiple processor (two Watch strips), dedicated function.
    Mpdf,
    /// Cooperative: Watch, Peripheral, and NCC + corner-detector Foveal windows.
    Coop,
    /// TPDF with the corner detector as the Foveal algorithm (Table 4.1's CD).
    TpdfCd,
    /// The corner detector's Foveal window alone, with nothing to recover a loss (Fig. 3.7's
    /// single-window approach).
    SingleCd,
}

impl Strategy {
    /// Lower-case name, as on the command line.
    pub fn name(&self) -> &'static str {
        match self {
            Strategy::Spmf => "spmf",
            Strategy::Tpdf => "tpdf",
            Strategy::Mpdf => "mpdf",
            Strategy::Coop => "coop",
            Strategy::TpdfCd => "cd",
            Strategy::SingleCd => "single-cd",
        }
    }

    /// Window units (= processors) the strategy uses.
    pub fn units(self) -> usize {
        match self {
            Strategy::Spmf | Strategy::SingleCd => 1,
            Strategy::Tpdf | Strategy::TpdfCd => 3,
            Strategy::Mpdf | Strategy::Coop => 4,
        }
    }
}

/// How the COOP master chooses between NCC and the corner detector.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CoopPolicy {
    /// Guarded cooperation: CD only where it measures the tracked point (the default).
    Guarded,
    /// The thesis's least-squares SSE over the last `coop_n` positions (4.3).
    Sse,
    /// A constant-velocity Kalman filter's innovation (the thesis's 5.2 proposal).
    Kalman,
}

/// Where MPDF's two Watch processors look (thesis 2.3.3: "depending on the application").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MpdfWatch {
    /// The thesis's 20-row strips along the top and bottom edges, where an object enters.
    Strips,
    /// The top and bottom halves of the view: an object already in view is seen too.
    Halves,
}

/// A run's configuration.
#[derive(Clone, Debug)]
pub struct SystemConfig {
    /// The strategy.
    pub strategy: Strategy,
    /// Processor speeds.
    pub cost: CostModel,
    /// Window sizes and thresholds.
    pub params: Params,
    /// COOP's data set size n.
    pub coop_n: usize,
    /// The point to track, given (its template is cut from frame 0); otherwise the Watch
    /// mode finds the moving object.
    pub target: Option<(f64, f64)>,
    /// Without a target: the template as a stored model of the part, cut from this frame at
    /// this point; the Watch mode still has to find where the part is. Without either, the
    /// Watch processor cuts the template where it first sees motion.
    pub model: Option<(usize, (f64, f64))>,
    /// Pixel clock in Hz.
    pub pixel_clock_hz: f64,
    /// Window units: the behavioural model, the rust-hdl blocks or the Verilog in Verilator.
    pub backend: UnitBackend,
    /// Pixel width of the clocked window units (8 to 16); the frames' 8-bit pixels fill their
    /// top bits.
    pub unit_pixel_bits: usize,
    /// COOP's decision policy.
    pub policy: CoopPolicy,
    /// MPDF's Watch windows.
    pub mpdf_watch: MpdfWatch,
    /// Fault injection: the request with this index (counting from 0 over the run) is
    /// corrupted on its way to the unit into an invalid set (a one-column window).
    pub corrupt_request: Option<usize>,
    /// Fault injection: the processor does not read the delivered window with this index
    /// (counting from 0 over the run): its pixels are lost.
    pub drop_window: Option<usize>,
    /// Fault injection: the camera's blanking varies from line to line and frame to frame.
    pub jitter: Option<Jitter>,
    /// Fault injection: every coordinate set is held until the raster reaches this clock of a
    /// frame (counting from FVAL rising), so all writes land at one phase of the raster.
    pub write_phase: Option<u64>,
    /// Fingerprint every delivered window's pixels in the log (`RunLog::deliveries`), to
    /// compare backends window for window. Off unless asked: it hashes the Watch's whole frame
    /// every frame, about 8 % of a tracking run's host time.
    pub fingerprint_windows: bool,
    /// The camera bins its sensor's pixels `bin` x `bin` ([`crate::frames::binned`]; 1: not
    /// binned): `target`, `model`, `pixel_clock_hz` and the log's positions are the sensor's,
    /// the windows, `jitter` and `write_phase` (clocks of the binned raster) the binned frames'.
    pub bin: usize,
}

impl SystemConfig {
    /// `strategy` with the thesis's defaults: its window sizes and thresholds, COOP's n = 4
    /// with guarded cooperation, the CA-D1's pixel clock, the behavioural window units and
    /// no faults.
    pub fn thesis(strategy: Strategy, cost: CostModel, target: Option<(f64, f64)>) -> SystemConfig {
        SystemConfig {
            strategy,
            cost,
            params: Params::default(),
            coop_n: 4,
            target,
            model: None,
            pixel_clock_hz: coopwin_hdl::sim::camera::CA_D1_PIXEL_CLOCK_HZ,
            backend: UnitBackend::BehaviouralModel,
            unit_pixel_bits: 8,
            policy: CoopPolicy::Guarded,
            mpdf_watch: MpdfWatch::Strips,
            corrupt_request: None,
            drop_window: None,
            jitter: None,
            write_phase: None,
            fingerprint_windows: false,
            bin: 1,
        }
    }

    /// The pixel clock of the camera binning frames of `size`: binning reads out fewer pixels
    /// in the sensor's frame period, so the frame rate is the sensor's.
    pub fn binned_pixel_clock(&self, size: (usize, usize)) -> f64 {
        if self.bin <= 1 {
            return self.pixel_clock_hz;
        }
        let clocks = |s| Clocks::camera_timing(s).frame_clocks() as f64;
        self.pixel_clock_hz * clocks(binned::binned_size(size, self.bin)) / clocks(size)
    }

    /// The frame period of a run over `source`, seconds: its camera's raster (of the frames
    /// binned, with any jitter) at its pixel clock.
    pub fn frame_period(&self, source: &dyn FrameSource) -> f64 {
        let raster = Clocks::camera_timing(binned::binned_size(source.size(), self.bin));
        Clocks::new(raster, source.len(), self.jitter).period() as f64 / self.binned_pixel_clock(source.size())
    }
}
