//! The tracking system in simulated time (thesis 2.3-2.5, 4.2): a camera raster, one window
//! unit per processor (a coordinate set applies to the first frame whose FVAL rises after the
//! set is written, and a window is complete when the raster passes its last pixel), the
//! firmware's processors from `coopwin_firmware::tracker`, each busy for as long as the cost
//! model says its kernels take, and 20 Mbyte/s links between them. A discrete-event loop.
use crate::cost::CostModel;
use coopwin_firmware::ports::{Decimation, WindowRequest};
use coopwin_firmware::tracker::{
    Algo, Dest, Foveal, FovealKind, Mode, Msg, Params, Peripheral, Point, Spmf, Step, Template, Watch,
};
use coopwin_firmware::view::WindowView;
use coopwin_hdl::camera::RasterTiming;
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
    pub source: Option<Algo>,
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
    pub algo: Algo,
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
    /// The frame and point the template was cut at, if known before the run: the tracked
    /// point is that point of the part.
    pub reference: Option<(usize, (f64, f64))>,
}

/// Frames by index, as the run needs them (in nearly increasing order).
pub trait FrameSource {
    /// Width and height of every frame.
    fn size(&self) -> (usize, usize);
    /// Number of frames.
    fn len(&self) -> usize;
    /// Frame `k`, row-major 8-bit gray.
    fn frame(&mut self, k: usize) -> Result<&[u8], String>;
}

enum Proc<'b> {
    Watch(Watch<'b>),
    Peripheral(Peripheral),
    Foveal(Foveal),
    Spmf(Spmf<'b>),
}

#[derive(Clone, Debug, PartialEq)]
enum Event {
    FrameStart(usize),
    WindowDone { p: usize, frame: usize, req: WindowRequest },
    Deliver { p: usize, msg: Msg },
}

struct Queue {
    heap: BinaryHeap<Reverse<(u64, u64, usize)>>,
    events: Vec<Option<Event>>,
    seq: u64,
}

impl Queue {
    fn push(&mut self, t: f64, e: Event) {
        self.seq += 1;
        self.events.push(Some(e));
        let ns = (t.max(0.0) * 1e9).round() as u64;
        self.heap.push(Reverse((ns, self.seq, self.events.len() - 1)));
    }
    fn pop(&mut self) -> Option<(f64, Event)> {
        let Reverse((ns, _, i)) = self.heap.pop()?;
        Some((ns as f64 / 1e9, self.events.get_mut(i)?.take()?))
    }
}

/// Runs `cfg` over `source`, calling `progress(frame)` at each frame start.
pub fn run(cfg: &SystemConfig, source: &mut dyn FrameSource, progress: &mut dyn FnMut(usize)) -> Result<RunLog, String> {
    let (w, h) = source.size();
    let n = source.len();
    let timing = RasterTiming { width: w, height: h, h_blank: 16, v_blank_lines: 2 };
    let period = timing.frame_clocks() as f64 / cfg.pixel_clock_hz;
    let clock = 1.0 / cfg.pixel_clock_hz;
    let params = Params { frame_w: w as u16, frame_h: h as u16, ..cfg.params };

    // The template: the N x N block nearest the target in frame 0, or the stored model.
    let target = cfg.target.map(|(x, y)| Point { x: x as f32, y: y as f32 });
    let reference = cfg.target.map(|t| (0, t)).or(cfg.model);
    let template = match reference {
        Some((k, (x, y))) => {
            let f = source.frame(k)?;
            let view = WindowView::packed(f, w, h).map_err(|e| format!("frame {k}: {e:?}"))?;
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
    let foveal = |kind| Foveal::new(kind, params, template.clone(), cfg.coop_n).map_err(|e| format!("{e:?}"));
    let mut procs: Vec<Proc> = match cfg.strategy {
        Strategy::Spmf => vec![Proc::Spmf(Spmf::new(params, &mut b0[0], template.clone()).map_err(|e| format!("{e:?}"))?)],
        Strategy::Tpdf | Strategy::TpdfCd | Strategy::Coop => {
            let kind = match cfg.strategy {
                Strategy::Coop => FovealKind::CoopMaster,
                Strategy::TpdfCd => FovealKind::Cd,
                _ => FovealKind::Ncc,
            };
            let mut v = vec![
                Proc::Watch(Watch::new(full, &mut b0[0], params, known)),
                Proc::Peripheral(Peripheral::new(params, template.clone())),
                Proc::Foveal(foveal(kind)?),
            ];
            if cfg.strategy == Strategy::Coop {
                v.push(Proc::Foveal(foveal(FovealKind::CoopPartner)?));
            }
            v
        }
        Strategy::SingleCd => vec![Proc::Foveal(foveal(FovealKind::Cd)?)],
        Strategy::Mpdf => vec![
            Proc::Watch(Watch::new(top, &mut b0[0], params, known)),
            Proc::Watch(Watch::new(bottom, &mut b1[0], params, known)),
            Proc::Peripheral(Peripheral::new(params, template.clone())),
            Proc::Foveal(foveal(FovealKind::Ncc)?),
        ],
    };
    let fovea: Vec<usize> = (0..procs.len()).filter(|&i| matches!(procs[i], Proc::Foveal(_))).collect();
    let routes = Routes {
        peripheral: procs.iter().position(|p| matches!(p, Proc::Peripheral(_))),
        foveal: fovea.first().copied(),
        partner: fovea.get(1).copied(),
    };

    let np = procs.len();
    let mut pending: Vec<Option<(WindowRequest, f64)>> = vec![None; np];
    let mut free_at = vec![f64::MIN; np];
    let mut log = RunLog { windows: vec![0; np], frame_period: period, reference, ..RunLog::default() };
    let mut q = Queue { heap: BinaryHeap::new(), events: Vec::new(), seq: 0 };
    let t_start = -period / 2.0;
    // Writing a set: four bytes at about five clocks each (the handshake of hdl/coord_port).
    let write_latency = 20.0 * clock;

    // Start: the first steps, at the end of the blanking before frame 0.
    for i in 0..np {
        let step = match (&mut procs[i], target) {
            (Proc::Watch(wp), _) => wp.start(),
            (Proc::Spmf(s), t) => s.start(t),
            (Proc::Peripheral(pp), Some(t)) => pp.start_at(t),
            (Proc::Foveal(f), Some(t)) if Some(i) == routes.foveal => f.start_at(t),
            _ => Step { work: coopwin_firmware::tracker::Work::None, request: None, sends: Default::default(), report: None },
        };
        apply(i, step, t_start, &mut pending, &mut q, &routes, write_latency, &cfg.cost);
    }
    for k in 0..n {
        q.push(k as f64 * period, Event::FrameStart(k));
    }

    let mut last_report: Option<Report> = None;
    while let Some((t, ev)) = q.pop() {
        match ev {
            Event::FrameStart(k) => {
                if k > 0 {
                    log.frames.push(record(k - 1, &procs, last_report));
                }
                progress(k);
                for (i, slot) in pending.iter_mut().enumerate() {
                    if let Some((req, ready)) = *slot {
                        // A set completed at least two clocks before FVAL rises arms this frame.
                        if ready <= t - 2.0 * clock {
                            *slot = None;
                            let last = timing.h_blank
                                + (usize::from(req.y0) + usize::from(req.height) - 1) * timing.line_clocks()
                                + usize::from(req.x0)
                                + usize::from(req.width)
                                - 1;
                            // The unit strobes a pixel one clock after it is on the bus.
                            q.push(t + (last + 2) as f64 * clock, Event::WindowDone { p: i, frame: k, req });
                        }
                    }
                }
            }
            Event::WindowDone { p, frame, req } => {
                let begin = t.max(free_at[p]);
                let img = source.frame(frame)?;
                let full_view = WindowView::packed(img, w, h).map_err(|e| format!("frame {frame}: {e:?}"))?;
                let sub = full_view
                    .sub(req.x0.into(), req.y0.into(), req.width.into(), req.height.into())
                    .ok_or_else(|| format!("window {req:?} outside the frame"))?;
                let win = match req.decimation {
                    Decimation::Full => sub,
                    Decimation::Quarter => sub.decimated(),
                };
                log.windows[p] += 1;
                let step = match &mut procs[p] {
                    Proc::Watch(x) => x.on_window(&win),
                    Proc::Peripheral(x) => x.on_window(&win),
                    Proc::Foveal(x) => x.on_window(&win, begin),
                    Proc::Spmf(x) => x.on_window(&win, begin),
                };
                let end = begin + cfg.cost.seconds(&step.work);
                free_at[p] = end;
                if let Some((point, algo)) = step.report {
                    let r = Report { t: end, frame, point, algo };
                    log.reports.push(r);
                    last_report = Some(r);
                }
                if step.sends.iter().any(|(_, m)| matches!(m, Msg::Lost(_))) {
                    log.losses.push(end);
                    last_report = None;
                }
                apply(p, step, end, &mut pending, &mut q, &routes, write_latency, &cfg.cost);
            }
            Event::Deliver { p, msg } => {
                let begin = t.max(free_at[p]);
                let step = match &mut procs[p] {
                    Proc::Peripheral(x) => x.on_message(&msg),
                    Proc::Foveal(x) => x.on_message(&msg, begin),
                    _ => continue,
                };
                let end = begin + cfg.cost.seconds(&step.work);
                free_at[p] = end;
                if let Some((point, algo)) = step.report {
                    let frame = (begin / period).floor().max(0.0) as usize;
                    let r = Report { t: end, frame, point, algo };
                    log.reports.push(r);
                    last_report = Some(r);
                }
                apply(p, step, end, &mut pending, &mut q, &routes, write_latency, &cfg.cost);
            }
        }
    }
    if n > 0 {
        log.frames.push(record(n - 1, &procs, last_report));
    }
    Ok(log)
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

/// Carries out a step finished at `at`: its request is written to the unit (complete after
/// the handshake), its messages go over the links.
#[allow(clippy::too_many_arguments)]
fn apply(
    p: usize,
    step: Step,
    at: f64,
    pending: &mut [Option<(WindowRequest, f64)>],
    q: &mut Queue,
    routes: &Routes,
    write_latency: f64,
    cost: &CostModel,
) {
    if let Some(req) = step.request {
        pending[p] = Some((req, at + write_latency));
    }
    for (d, m) in step.sends {
        if let Some(to) = routes.to(d) {
            q.push(at + cost.link_seconds(m.bytes()), Event::Deliver { p: to, msg: m });
        }
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
    let tracked = if mode == Mode::Track { last } else { None };
    FrameRecord {
        frame,
        point: tracked.map(|r| (f64::from(r.point.x), f64::from(r.point.y))),
        measured_frame: tracked.map(|r| r.frame),
        mode,
        source: tracked.map(|r| r.algo),
    }
}
