//! The tracking system in simulated time (thesis 2.3-2.5, 4.2): a camera raster, one window
//! unit per processor (a coordinate set applies to the first frame whose FVAL rises after the
//! set is written, and a window is complete when the raster passes its last pixel), the
//! firmware's processors from `coopwin_firmware::processors`, each busy for as long as the cost
//! model says its kernels take, and 20 Mbyte/s links between them. A discrete-event loop.
use crate::backend::{Bank, Clocks, Delivered, HdlBackend, ModelBackend, Trace, WindowBackend};
use crate::cost::CostModel;
use coopwin_firmware::kernels::confidence::{KalmanCoop, SseCoop};
use coopwin_firmware::processors::coop::guard::{Guard, GuardParams};
use coopwin_firmware::ports::link::{FramedLink, Link};
use coopwin_firmware::ports::position::{FramedPositionSink, PositionSink, PositionUpdate};
use coopwin_firmware::processors::{
    Dest, Foveal, FovealKind, Mode, Msg, Params, Peripheral, Policy, Spmf, Step, Template, Watch,
};
use coopwin_firmware::kernels::view::WindowView;
use coopwin_firmware::types::{Decimation, Point, Source, WindowRequest};
use coopwin_hdl::sim::camera::{Jitter, RasterTiming};
use std::cmp::Reverse;
use std::collections::BinaryHeap;

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
    /// Window units: the behavioural model or the rust-hdl blocks.
    pub hdl: HdlChoice,
    /// COOP's decision policy.
    pub policy: CoopPolicy,
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
}

/// What the system knew at the end of a frame period.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameRecord {
    /// Frame index.
    pub frame: usize,
    /// The last tracked point reported, while tracking.
    pub point: Option<(f64, f64)>,
    /// The frame whose window produced `point`.
    pub measured_frame: Option<usize>,
    /// Mode at the end of the frame period.
    pub mode: Mode,
    /// The algorithm behind `point`.
    pub source: Option<Source>,
}

/// A position report: when it was made, for which frame's window, where, and by what.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Report {
    /// Time in seconds.
    pub t: f64,
    /// The frame the window was acquired from.
    pub frame: usize,
    /// The point.
    pub point: Point,
    /// The algorithm.
    pub algo: Source,
}

/// A finished run.
#[derive(Clone, Debug, Default)]
pub struct RunLog {
    /// One record a frame.
    pub frames: Vec<FrameRecord>,
    /// Every position report, in time order.
    pub reports: Vec<Report>,
    /// Times the Foveal window lost the target.
    pub losses: Vec<f64>,
    /// Windows acquired, per processor.
    pub windows: Vec<usize>,
    /// Frame period in seconds.
    pub frame_period: f64,
    /// Every request written: (processor, clock, request as the unit received it).
    pub requests: Vec<(usize, u64, WindowRequest)>,
    /// The robot controller's link: every position report as the firmware's
    /// `FramedPositionSink` sends it (thesis 2.6: position updates to the robot controller).
    pub robot_link: Vec<u8>,
    /// With clock-by-clock window units: pixel clocks simulated, and the wall time spent in
    /// the simulator (rust-hdl or Verilator), for the speed report.
    pub hdl_clocks: u64,
    /// Seconds inside the HDL simulator.
    pub hdl_seconds: f64,
    /// Windows delivered but not read (fault injection): (processor, frame).
    pub dropped: Vec<(usize, usize)>,
    /// Watchdog re-requests: (processor, clock), when a request brought no window for three
    /// frame periods (a set refused by the unit, or lost).
    pub watchdog: Vec<(usize, u64)>,
    /// Every window delivered: (processor, frame, clock, FNV-1a hash of its pixels), so
    /// backends can be compared window for window.
    pub deliveries: Vec<(usize, usize, u64, u64)>,
    /// The frame and point the template was cut at, if known before the run: the tracked
    /// point is that point of the part.
    pub reference: Option<(usize, (f64, f64))>,
    /// Without a target: the frame and point at which a Watch processor cut the template, the
    /// centre of the first motion it saw; the point tracked from then on.
    pub locked_on: Option<(usize, (f64, f64))>,
    /// Requests the coordinate port refused: (processor, clock, why).
    pub refused: Vec<(usize, u64, String)>,
    /// With a VCD of chosen frames: per unit, the sets taken before the trace began.
    pub sets_before_trace: Vec<usize>,
}

/// Frames by index, as the run needs them (in nearly increasing order).
pub trait FrameSource {
    /// Width and height of every frame.
    fn size(&self) -> (usize, usize);
    /// Number of frames.
    fn len(&self) -> usize;
    /// True when the source has no frame.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Frame `k`, row-major 8-bit gray.
    fn frame(&mut self, k: usize) -> Result<&[u8], String>;
}

// A run holds one to four processors, so their sizes (a Foveal carries the corner
// detector's 45 KB of buffers) cost nothing worth an indirection.
#[allow(clippy::large_enum_variant)]
enum Proc<'b> {
    Watch(Watch<'b>),
    Peripheral(Peripheral),
    Foveal(Foveal),
    Spmf(Spmf<'b>),
}

#[derive(Clone, Debug, PartialEq)]
enum Event {
    FrameStart(usize),
    /// The message at the head of the link `from` -> `p` has arrived.
    Deliver { p: usize, from: usize },
}

/// Events in clock order (ties in the order they were queued).
struct Queue {
    heap: BinaryHeap<Reverse<(u64, u64)>>,
    events: Vec<Option<Event>>,
}

impl Queue {
    fn push(&mut self, clock: u64, e: Event) {
        self.events.push(Some(e));
        self.heap.push(Reverse((clock, self.events.len() as u64 - 1)));
    }
    fn peek(&self) -> Option<u64> {
        self.heap.peek().map(|Reverse((c, _))| *c)
    }
    fn pop(&mut self) -> Option<(u64, Event)> {
        let Reverse((c, i)) = self.heap.pop()?;
        Some((c, self.events.get_mut(i as usize)?.take()?))
    }
}

/// Which window units the run uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HdlChoice {
    /// The behavioural model.
    Model,
    /// The rust-hdl blocks, clock by clock.
    RustHdl,
    /// The exported Verilog compiled with Verilator, clock by clock.
    Verilator,
}

/// Runs `cfg` over `source` with the window units it names, calling `progress(frame)` at each
/// frame start.
pub fn run(cfg: &SystemConfig, source: &mut dyn FrameSource, progress: &mut dyn FnMut(usize)) -> Result<RunLog, String> {
    run_traced(cfg, source, progress, None)
}

/// [`run`], with a VCD of every window unit (for `vcd`'s frames) when the units are rust-hdl's.
pub fn run_traced(
    cfg: &SystemConfig,
    source: &mut dyn FrameSource,
    progress: &mut dyn FnMut(usize),
    vcd: Option<Trace>,
) -> Result<RunLog, String> {
    let clocks = raster(source, cfg.jitter);
    match cfg.hdl {
        HdlChoice::Model => {
            if vcd.is_some() {
                return Err("a VCD needs the rust-hdl window units (--hdl rust-hdl)".into());
            }
            run_with(cfg, source, &mut ModelBackend::new(clocks, units(cfg.strategy)), progress)
        }
        HdlChoice::RustHdl | HdlChoice::Verilator => {
            if clocks.timing.width > 256 || clocks.timing.height > 256 {
                return Err("the exported window unit has 8-bit counters: frames up to 256x256".into());
            }
            let n = units(cfg.strategy);
            let mut hdl = if cfg.hdl == HdlChoice::RustHdl {
                HdlBackend::rust_hdl(clocks, n, vcd)?
            } else {
                HdlBackend::new(clocks, n, Bank::Verilator(crate::verilator::VerilatorNetwork::new()?), vcd)?
            };
            let mut log = run_with(cfg, source, &mut hdl, progress)?;
            hdl.finish()?;
            log.hdl_clocks = hdl.clocks_stepped;
            log.hdl_seconds = hdl.sim_time.as_secs_f64();
            log.sets_before_trace = hdl.sets_before_trace.clone();
            Ok(log)
        }
    }
}

/// The raster for a source's frame size: the CA-D1's blanking, scaled to the frame, with
/// `jitter`'s extra blanking if any.
pub fn raster(source: &dyn FrameSource, jitter: Option<Jitter>) -> Clocks {
    let (w, h) = source.size();
    Clocks::new(RasterTiming { width: w, height: h, h_blank: 16, v_blank_lines: 2 }, source.len(), jitter)
}

/// The COOP master's policy for `cfg`.
fn coop_policy(cfg: &SystemConfig) -> Result<Policy, String> {
    Ok(match cfg.policy {
        CoopPolicy::Guarded => Policy::Guarded(Guard::new(GuardParams::default())),
        CoopPolicy::Sse => Policy::Sse(SseCoop::new(cfg.coop_n).map_err(|e| format!("COOP data set size {}: {e}", cfg.coop_n))?),
        // Process noise for a part that turns corners at up to ~100 px/s each frame;
        // measurement noise of half a pixel; newest innovation 30%.
        CoopPolicy::Kalman => Policy::Kalman(KalmanCoop::new(1.0e4, 0.25, 0.3).map_err(|e| format!("Kalman policy: {e}"))?),
    })
}

/// Window units (= processors) a strategy uses.
pub fn units(s: Strategy) -> usize {
    match s {
        Strategy::Spmf | Strategy::SingleCd => 1,
        Strategy::Tpdf | Strategy::TpdfCd => 3,
        Strategy::Mpdf | Strategy::Coop => 4,
    }
}

/// Runs `cfg` over `source`, its windows from `backend`.
pub fn run_with(
    cfg: &SystemConfig,
    source: &mut dyn FrameSource,
    backend: &mut dyn WindowBackend,
    progress: &mut dyn FnMut(usize),
) -> Result<RunLog, String> {
    let (w, h) = source.size();
    let n = source.len();
    let clocks = raster(source, cfg.jitter);
    if let Some(phase) = cfg.write_phase.filter(|&p| p >= clocks.timing.frame_clocks() as u64) {
        return Err(format!("write phase {phase}: a frame has {} clocks (0..{})", clocks.timing.frame_clocks(), clocks.timing.frame_clocks() - 1));
    }
    let hz = cfg.pixel_clock_hz;
    let period = clocks.period() as f64 / hz;
    // Seconds from frame 0's FVAL rising, for reports.
    let secs = |c: u64| (c as f64 - clocks.blank() as f64) / hz;
    let busy = |work: &coopwin_firmware::processors::Work| (cfg.cost.seconds(work) * hz).ceil() as u64;
    let link = |bytes: usize| (cfg.cost.link_seconds(bytes) * hz).ceil() as u64;
    let params = Params { frame_w: w as u16, frame_h: h as u16, ..cfg.params };

    // The template: the N x N block nearest the target in frame 0, or the stored model.
    let target = cfg.target.map(|(x, y)| Point { x: x as f32, y: y as f32 });
    let reference = cfg.target.map(|t| (0, t)).or(cfg.model);
    let template = match reference {
        Some((k, (x, y))) => {
            let f = source.frame(k)?;
            let view = WindowView::packed(f, w, h).map_err(|e| format!("frame {k}: {e}"))?;
            let p = Point { x: x as f32, y: y as f32 };
            Some(Template::capture(&view, p, params.template as usize).ok_or_else(|| {
                format!("the {0}x{0} template around ({x}, {y}) does not fit in the frame", params.template)
            })?)
        }
        None => None,
    };

    // Watch buffers: one frame (or strip) each, owned here and lent to the processors.
    let mut bufs: Vec<Vec<u8>> = vec![vec![0u8; w * h]; 2];
    let (b0, b1) = bufs.split_at_mut(1);
    let full = WindowRequest { x0: 0, y0: 0, width: w as u16, height: h as u16, decimation: Decimation::Full };
    let strip = 20.min(h as u16 / 2);
    let top = WindowRequest { height: strip, ..full };
    let bottom = WindowRequest { y0: h as u16 - strip, height: strip, ..full };
    let known = template.is_some();
    let foveal = |kind| Foveal::new(kind, params, template.clone());
    let mut procs: Vec<Proc> = match cfg.strategy {
        Strategy::Spmf => vec![Proc::Spmf(Spmf::new(params, &mut b0[0], template.clone()))],
        Strategy::Tpdf | Strategy::TpdfCd | Strategy::Coop => {
            let kind = match cfg.strategy {
                Strategy::Coop => FovealKind::CoopMaster,
                Strategy::TpdfCd => FovealKind::Cd,
                _ => FovealKind::Ncc,
            };
            let mut v = vec![
                Proc::Watch(Watch::new(full, &mut b0[0], params, known)),
                Proc::Peripheral(Peripheral::new(params, template.clone())),
                Proc::Foveal(foveal(kind).with_policy(coop_policy(cfg)?)),
            ];
            if cfg.strategy == Strategy::Coop {
                v.push(Proc::Foveal(foveal(FovealKind::CoopPartner)));
            }
            v
        }
        Strategy::SingleCd => vec![Proc::Foveal(foveal(FovealKind::Cd))],
        Strategy::Mpdf => vec![
            Proc::Watch(Watch::new(top, &mut b0[0], params, known)),
            Proc::Watch(Watch::new(bottom, &mut b1[0], params, known)),
            Proc::Peripheral(Peripheral::new(params, template.clone())),
            Proc::Foveal(foveal(FovealKind::Ncc)),
        ],
    };
    let fovea: Vec<usize> = (0..procs.len()).filter(|&i| matches!(procs[i], Proc::Foveal(_))).collect();
    let routes = Routes {
        peripheral: procs.iter().position(|p| matches!(p, Proc::Peripheral(_))),
        foveal: fovea.first().copied(),
        partner: fovea.get(1).copied(),
    };

    let np = procs.len();
    if np != units(cfg.strategy) {
        return Err(format!("internal: {np} processors for {} units", units(cfg.strategy)));
    }
    let mut free_at = vec![0u64; np];
    let mut links = Links::new(np, &link);
    // The frame of the last window each processor received.
    let mut window_frame = vec![0usize; np];
    // The request each processor waits on, and since when: the watchdog's state.
    let mut awaiting: Vec<Option<(WindowRequest, u64)>> = vec![None; np];
    let mut link_state =
        LinkState {
        corrupt: cfg.corrupt_request,
        awaiting: &mut awaiting,
        write_phase: cfg.write_phase,
        clocks: &clocks,
        refused: Vec::new(),
    };
    let mut log = RunLog { windows: vec![0; np], frame_period: period, reference, ..RunLog::default() };
    let mut q = Queue { heap: BinaryHeap::new(), events: Vec::new() };

    // Start: the first steps, at the start of the blanking before frame 0.
    for (i, proc) in procs.iter_mut().enumerate() {
        let step = match (proc, target) {
            (Proc::Watch(wp), _) => wp.start(),
            (Proc::Spmf(s), t) => s.start(t),
            (Proc::Peripheral(pp), Some(t)) => pp.start_at(t),
            (Proc::Foveal(f), Some(t)) if Some(i) == routes.foveal => f.start_at(t),
            _ => Step { work: coopwin_firmware::processors::Work::None, request: None, sends: Default::default(), report: None, score: None, lost: None },
        };
        apply(i, step, 0, backend, &mut q, &routes, &mut links, &mut log.requests, &mut link_state)?;
    }
    for k in 0..n {
        q.push(clocks.frame_start(k), Event::FrameStart(k));
    }

    let mut last_report: Option<Report> = None;
    let mut scratch = Vec::new();
    let mut robot = FramedPositionSink::new(Pipe::default());
    loop {
        let until = q.peek().unwrap_or(u64::MAX);
        if let Some(win) = backend.next_window(until, source)? {
            let p = win.p;
            if cfg.drop_window == Some(log.deliveries.len()) {
                // Not read: the processor still waits, and its watchdog will ask again.
                log.deliveries.push((p, win.frame, win.clock, fingerprint(&win.pixels)));
                log.dropped.push((p, win.frame));
                continue;
            }
            log.deliveries.push((p, win.frame, win.clock, fingerprint(&win.pixels)));
            link_state.awaiting[p] = None;
            let view = delivered_view(&win, &mut scratch)?;
            let begin = win.clock.max(free_at[p]);
            log.windows[p] += 1;
            let step = match &mut procs[p] {
                Proc::Watch(x) => x.on_window(&view),
                Proc::Peripheral(x) => x.on_window(&view),
                Proc::Foveal(x) => x.on_window(&view, secs(begin)),
                Proc::Spmf(x) => x.on_window(&view, secs(begin)),
            };
            let end = begin + busy(&step.work);
            free_at[p] = end;
            window_frame[p] = win.frame;
            publish(&step, secs(end), win.frame, &mut log, &mut robot, &mut last_report)?;
            apply(p, step, end, backend, &mut q, &routes, &mut links, &mut log.requests, &mut link_state)?;
            continue;
        }
        let Some((c, ev)) = q.pop() else { break };
        match ev {
            Event::FrameStart(k) => {
                if k > 0 {
                    log.frames.push(record(k - 1, &procs, last_report));
                }
                progress(k);
                // The main loop's watchdog: a request that brought no window in three frame
                // periods is written again.
                for p in 0..np {
                    if let Some((req, since)) = link_state.awaiting[p] {
                        if k >= 3 && since < clocks.frame_start(k - 3) {
                            let written = link_state.write(p, req, req, c, backend, &mut log.requests);
                            log.watchdog.push((p, written));
                        }
                    }
                }
            }
            Event::Deliver { p, from } => {
                let msg = links.receive(from, p)?;
                let begin = c.max(free_at[p]);
                let step = match &mut procs[p] {
                    Proc::Peripheral(x) => x.on_message(&msg),
                    Proc::Foveal(x) => x.on_message(&msg, secs(begin)),
                    _ => continue,
                };
                let end = begin + busy(&step.work);
                free_at[p] = end;
                // A report on a message (COOP's decision once the partner's result is in)
                // measures the processor's last window.
                publish(&step, secs(end), window_frame[p], &mut log, &mut robot, &mut last_report)?;
                apply(p, step, end, backend, &mut q, &routes, &mut links, &mut log.requests, &mut link_state)?;
            }
        }
    }
    if n > 0 {
        log.frames.push(record(n - 1, &procs, last_report));
    }
    log.robot_link = robot.into_inner().0.into();
    log.refused = link_state.refused;
    Ok(log)
}

/// What a step finished at `t` seconds tells the outside: its position report, measured in
/// `frame`, goes to the robot controller and the log; a loss of track is logged and ends the
/// last report's validity.
fn publish(
    step: &Step,
    t: f64,
    frame: usize,
    log: &mut RunLog,
    robot: &mut FramedPositionSink<Pipe>,
    last: &mut Option<Report>,
) -> Result<(), String> {
    let template_cut = step.sends.iter().any(|(_, m)| matches!(m, Msg::Template(_)));
    if let Some(Msg::Motion { xmin, xmax, ymin, ymax }) = step.sends.iter().map(|(_, m)| m).find(|m| matches!(m, Msg::Motion { .. })) {
        if template_cut && log.locked_on.is_none() {
            let centre = |a: u16, b: u16| f64::from(f32::from(a + b) / 2.0);
            log.locked_on = Some((frame, (centre(*xmin, *xmax), centre(*ymin, *ymax))));
        }
    }
    if let Some((point, algo)) = step.report {
        let r = Report { t, frame, point, algo };
        emit(robot, &r)?;
        log.reports.push(r);
        *last = Some(r);
    }
    if step.lost.is_some() {
        log.losses.push(t);
        *last = None;
    }
    Ok(())
}

/// Sends a report to the robot controller through the firmware's position sink.
fn emit(sink: &mut FramedPositionSink<Pipe>, r: &Report) -> Result<(), String> {
    let source = r.algo;
    let update = PositionUpdate { t_us: (r.t.max(0.0) * 1e6) as u32, x: r.point.x, y: r.point.y, source };
    sink.emit(&update).map_err(|e| format!("robot link: {e:?}"))
}

/// A 64-bit fingerprint of a window's pixels (FNV-1a's multiply over 8-byte words, so a
/// full frame takes microseconds): equal windows give equal fingerprints, and a changed pixel
/// changes it.
pub fn fingerprint(bytes: &[u8]) -> u64 {
    let mut chunks = bytes.chunks_exact(8);
    let mut h = 0xcbf2_9ce4_8422_2325_u64 ^ bytes.len() as u64;
    for c in chunks.by_ref() {
        let word = u64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]);
        h = (h ^ word).wrapping_mul(0x0100_0000_01b3).rotate_left(29);
    }
    for &b in chunks.remainder() {
        h = (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
    }
    h
}

/// The processor's view of a delivered window. A 25% window arrives packed; it is spread back
/// onto its full-resolution grid in `scratch` so the view carries the 2-pixel step and the
/// kernels report frame positions.
fn delivered_view<'s>(win: &'s Delivered, scratch: &'s mut Vec<u8>) -> Result<WindowView<'s>, String> {
    let req = &win.req;
    let (x0, y0) = (u32::from(req.x0), u32::from(req.y0));
    let bad = |e| format!("window {req:?}: {e:?}");
    match req.decimation {
        Decimation::Full => {
            let (w, h) = req.delivered_size();
            WindowView::new(&win.pixels, w, h, w, x0, y0).map_err(bad)
        }
        Decimation::Quarter => {
            let (w, h) = (usize::from(req.width), usize::from(req.height));
            let (dw, _) = req.delivered_size();
            scratch.clear();
            scratch.resize(w * h, 0);
            for (i, &v) in win.pixels.iter().enumerate() {
                if let Some(slot) = scratch.get_mut((i / dw) * 2 * w + (i % dw) * 2) {
                    *slot = v;
                }
            }
            Ok(WindowView::new(scratch, w, h, w, x0, y0).map_err(bad)?.decimated())
        }
    }
}

/// The coordinate links' state: fault injection and what each processor waits for.
struct LinkState<'a> {
    corrupt: Option<usize>,
    awaiting: &'a mut [Option<(WindowRequest, u64)>],
    write_phase: Option<u64>,
    clocks: &'a Clocks,
    refused: Vec<(usize, u64, String)>,
}

impl LinkState<'_> {
    /// Processor `p`'s request `req`, arriving as `sent`, is written to its unit from clock `at`
    /// (held to the write phase, if any) and logged, and `p` waits for its window (the
    /// watchdog writes it again if none comes). A request the port refuses is logged in
    /// `refused`. Returns the clock of the write.
    fn write(
        &mut self,
        p: usize,
        req: WindowRequest,
        sent: WindowRequest,
        at: u64,
        backend: &mut dyn WindowBackend,
        requests: &mut Vec<(usize, u64, WindowRequest)>,
    ) -> u64 {
        let written = self.write_phase.map_or(at, |phase| self.clocks.next_phase(at, phase));
        match backend.request(p, sent, written) {
            Ok(()) => requests.push((p, written, sent)),
            Err(why) => self.refused.push((p, written, why)),
        }
        self.awaiting[p] = Some((req, written));
        written
    }
}

/// Which processor plays each role messages are addressed to.
struct Routes {
    peripheral: Option<usize>,
    foveal: Option<usize>,
    partner: Option<usize>,
}

impl Routes {
    fn to(&self, d: Dest) -> Option<usize> {
        match d {
            Dest::Peripheral => self.peripheral,
            Dest::Foveal => self.foveal,
            Dest::FovealCd => self.partner,
        }
    }
}

#[allow(clippy::too_many_arguments)]
/// Carries out a step finished on clock `at`: its request is written to its unit, its
/// messages go over the links.
fn apply(
    p: usize,
    step: Step,
    at: u64,
    backend: &mut dyn WindowBackend,
    q: &mut Queue,
    routes: &Routes,
    links: &mut Links,
    requests: &mut Vec<(usize, u64, WindowRequest)>,
    state: &mut LinkState,
) -> Result<(), String> {
    if let Some(req) = step.request {
        let sent = if state.corrupt == Some(requests.len()) { WindowRequest { width: 1, ..req } } else { req };
        state.write(p, req, sent, at, backend, requests);
    }
    for (d, m) in step.sends {
        if let Some(to) = routes.to(d) {
            let arrives = links.send(p, to, &m, at)?;
            q.push(arrives, Event::Deliver { p: to, from: p });
        }
    }
    Ok(())
}

/// An in-memory byte stream: what one processor writes, the other reads (and the robot link's
/// record of what it was sent).
#[derive(Default)]
struct Pipe(std::collections::VecDeque<u8>);

impl embedded_io::ErrorType for Pipe {
    type Error = core::convert::Infallible;
}

impl embedded_io::Read for Pipe {
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, Self::Error> {
        let n = buf.len().min(self.0.len());
        for (b, v) in buf.iter_mut().zip(self.0.drain(..n)) {
            *b = v;
        }
        Ok(n)
    }
}

impl embedded_io::Write for Pipe {
    fn write(&mut self, buf: &[u8]) -> Result<usize, Self::Error> {
        self.0.extend(buf);
        Ok(buf.len())
    }
    fn flush(&mut self) -> Result<(), Self::Error> {
        Ok(())
    }
}

/// The processors' comm-port links (thesis 2.2), one per ordered pair. Messages travel as
/// bytes through the firmware's `FramedLink`, first in first out: each takes the link time of
/// its bytes, from when it is sent or the one before it has arrived, whichever is later.
struct Links<'c> {
    np: usize,
    pairs: Vec<(FramedLink<Pipe>, u64)>,
    /// Clocks to carry a message of so many bytes.
    time: &'c dyn Fn(usize) -> u64,
}

impl<'c> Links<'c> {
    fn new(np: usize, time: &'c dyn Fn(usize) -> u64) -> Self {
        Links { np, pairs: (0..np * np).map(|_| (FramedLink::new(Pipe::default()), 0)).collect(), time }
    }

    /// Sends `m` from processor `from` to `to` at clock `at`; the clock it has arrived.
    fn send(&mut self, from: usize, to: usize, m: &Msg, at: u64) -> Result<u64, String> {
        let (link, free) = self.pairs.get_mut(from * self.np + to).ok_or("internal: no such link")?;
        let before = link.io_mut().0.len();
        link.send(m).map_err(|e| format!("link {from} -> {to}: {e:?}"))?;
        let bytes = link.io_mut().0.len() - before;
        *free = at.max(*free) + (self.time)(bytes);
        Ok(*free)
    }

    /// The message at the head of the link from `from` to `to`.
    fn receive(&mut self, from: usize, to: usize) -> Result<Msg, String> {
        let (link, _) = self.pairs.get_mut(from * self.np + to).ok_or("internal: no such link")?;
        link.receive().map_err(|e| format!("link {from} -> {to}: {e:?}"))
    }
}

fn record(frame: usize, procs: &[Proc], last: Option<Report>) -> FrameRecord {
    let mut mode = Mode::Watch;
    for p in procs {
        let m = match p {
            Proc::Spmf(s) => s.mode(),
            Proc::Foveal(f) => f.mode(),
            Proc::Peripheral(x) => x.mode(),
            Proc::Watch(_) => Mode::Watch,
        };
        mode = match (mode, m) {
            (Mode::Track, _) | (_, Mode::Track) => Mode::Track,
            (Mode::Detect, _) | (_, Mode::Detect) => Mode::Detect,
            _ => Mode::Watch,
        };
    }
    // A coasting COOP track has no current position: its last one is not this frame's.
    let coasting = procs.iter().any(|p| matches!(p, Proc::Foveal(f) if f.coasting()));
    let tracked = if mode == Mode::Track && !coasting { last } else { None };
    FrameRecord {
        frame,
        point: tracked.map(|r| (f64::from(r.point.x), f64::from(r.point.y))),
        measured_frame: tracked.map(|r| r.frame),
        mode,
        source: tracked.map(|r| r.algo),
    }
}

#[cfg(test)]
mod tests {
    use super::fingerprint;

    #[test]
    fn fingerprint_sees_every_changed_pixel() {
        // Reference: by construction, the same bytes give the same value; flip any one byte of
        // a buffer with a ragged tail and the value changes.
        let base: Vec<u8> = (0..37u32).map(|i| (i * 29 + 7) as u8).collect();
        let h = fingerprint(&base);
        assert_eq!(h, fingerprint(&base.clone()));
        for i in 0..base.len() {
            let mut b = base.clone();
            b[i] ^= 1;
            assert_ne!(fingerprint(&b), h, "byte {i}");
        }
        assert_ne!(fingerprint(&base[..36]), h, "length counts");
    }
}
