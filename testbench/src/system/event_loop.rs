//! The discrete-event loop: windows from the units and messages over the links, each handed
//! to its processor when the processor is free, its step's effects (a report, a request, its
//! messages) carried out when the processor has finished; frame records and the watchdog at
//! each frame start (thesis 2.3-2.5, 4.2).
use super::config::SystemConfig;
use super::events::{Event, EventQueue};
use super::links::{Links, Timing};
use super::log::{FrameRecord, Recorder, RunLog};
use super::roster::{Roles, Roster};
use super::writes::CoordinateWrites;
use super::SimError;
use crate::frames::{fingerprint, FrameSource};
use crate::units::clocks::Clocks;
use crate::units::{Delivered, WindowUnits};
use coopwin_firmware::types::Decimation;
use coopwin_firmware::processors::{Params, Step, Template};
use coopwin_firmware::types::Point;
use coopwin_firmware::kernels::view::WindowView;

/// Runs `cfg` over `source`, its windows from `units`, calling `progress(frame)` at each
/// frame start and `on_record` with each frame's record as the frame ends (the next frame's
/// FVAL rising, or the end of the run), so a caller can write it out as the run goes. A
/// source of [`Clocks::OPEN_ENDED`] frames runs until it fails to give a frame: frame `k`'s
/// record comes before frame `k + 1`'s pixels are asked for.
pub fn simulate_with(
    cfg: &SystemConfig,
    source: &mut dyn FrameSource,
    units: &mut dyn WindowUnits,
    progress: &mut dyn FnMut(usize),
    on_record: &mut dyn FnMut(&FrameRecord),
) -> Result<RunLog, SimError> {
    let (w, h) = source.size();
    let n = source.len();
    let clocks = Clocks::for_frames(source, cfg.jitter);
    let frame_clocks = clocks.timing.frame_clocks() as u64;
    if let Some(phase) = cfg.write_phase.filter(|&p| p >= frame_clocks) {
        return Err(SimError::WritePhase { phase, clocks: frame_clocks });
    }
    let timing = Timing { cost: cfg.cost, hz: cfg.pixel_clock_hz, blank: clocks.blank() };
    let params = Params { frame_w: w as u16, frame_h: h as u16, ..cfg.params };
    // The template: the N x N block nearest the target in frame 0, or the stored model.
    let reference = cfg.target.map(|t| (0, t)).or(cfg.model);
    let template = match reference {
        Some((k, at)) => Some(template_at(source, k, at, params.template)?),
        None => None,
    };
    // Watch buffers: one frame (or strip) each, owned here and lent to the processors.
    let [mut b0, mut b1] = [vec![0u8; w * h], vec![0u8; w * h]];
    let roster = Roster::build(cfg, params, template, [&mut b0, &mut b1])?;
    let np = roster.len();
    let log = RunLog { windows: vec![0; np], roles: roster.processor_roles(), frame_period: clocks.period() as f64 / timing.hz, reference, ..RunLog::default() };
    let mut run = Run {
        wiring: Wiring {
            units,
            writes: CoordinateWrites::new(cfg, &clocks, np),
            links: Links::new(np, timing),
            queue: EventQueue::default(),
            roles: roster.roles,
        },
        roster,
        recorder: Recorder::new(log),
        timing,
        free_at: vec![0; np],
        window_frame: vec![0; np],
        drop_window: cfg.drop_window,
        fingerprint_windows: cfg.fingerprint_windows,
        scratch: Vec::new(),
    };
    // Start: the first steps, at the start of the blanking before frame 0.
    let target = cfg.target.map(|(x, y)| Point { x: x as f32, y: y as f32 });
    for p in 0..np {
        let step = run.roster.start(p, target);
        run.wiring.apply(p, step, 0)?;
    }
    if n > 0 {
        run.wiring.queue.push_frame_start(clocks.frame_start(0), 0);
    }
    loop {
        let until = run.wiring.queue.peek().unwrap_or(u64::MAX);
        if let Some(win) = run.wiring.units.next_window(until, source)? {
            run.on_window(win)?;
            continue;
        }
        let Some((c, event)) = run.wiring.queue.pop() else { break };
        match event {
            Event::FrameStart(k) => {
                if k + 1 < n {
                    run.wiring.queue.push_frame_start(clocks.frame_start(k + 1), k + 1);
                }
                run.on_frame_start(k, c, progress, on_record)
            }
            Event::MessageArrives { to, from } => run.on_message(to, from, c)?,
        }
    }
    if n > 0 {
        on_record(run.recorder.end_frame(n - 1, run.roster.mode()));
    }
    let mut log = run.recorder.finish();
    log.requests = run.wiring.writes.written;
    log.refused = run.wiring.writes.refused;
    Ok(log)
}

/// The `side` x `side` template around `at` in frame `k`.
fn template_at(source: &mut dyn FrameSource, k: usize, (x, y): (f64, f64), side: u16) -> Result<Template, SimError> {
    let (w, h) = source.size();
    let f = source.frame(k)?;
    let view = WindowView::packed(f, w, h).map_err(|error| SimError::FrameView { frame: k, error })?;
    let p = Point { x: x as f32, y: y as f32 };
    Template::capture(&view, p, side as usize).ok_or(SimError::TemplateDoesNotFit { side, at: (x, y) })
}

/// Where a step's effects go: coordinate writes to the units, messages over the links.
struct Wiring<'a> {
    units: &'a mut dyn WindowUnits,
    writes: CoordinateWrites<'a>,
    links: Links,
    queue: EventQueue,
    roles: Roles,
}

impl Wiring<'_> {
    /// Carries out processor `p`'s step finished on clock `at`: its request is written to its
    /// unit, its messages go over the links.
    fn apply(&mut self, p: usize, step: Step, at: u64) -> Result<(), SimError> {
        if let Some(req) = step.request {
            self.writes.request(p, req, at, self.units);
        }
        for (d, m) in step.sends {
            if let Some(to) = self.roles.to(d) {
                let arrives = self.links.send(p, to, &m, at)?;
                self.queue.push(arrives, Event::MessageArrives { to, from: p });
            }
        }
        Ok(())
    }
}

/// A run in progress.
struct Run<'a, 'b> {
    roster: Roster<'b>,
    wiring: Wiring<'a>,
    recorder: Recorder,
    timing: Timing,
    /// The clock each processor is free from.
    free_at: Vec<u64>,
    /// The frame of the last window each processor received.
    window_frame: Vec<usize>,
    /// Fault injection: the index of the delivered window the processor does not read.
    drop_window: Option<usize>,
    /// Whether each delivered window's pixels are fingerprinted in the log.
    fingerprint_windows: bool,
    /// A decimated window spread back onto its full-resolution grid.
    scratch: Vec<u8>,
}

impl Run<'_, '_> {
    /// A window delivered: its processor takes it once free.
    fn on_window(&mut self, win: Delivered) -> Result<(), SimError> {
        let p = win.unit;
        let log = &mut self.recorder.log;
        let dropped = self.drop_window == Some(log.deliveries.len());
        log.deliveries.push((p, win.frame, win.clock, self.fingerprint_windows.then(|| fingerprint(&win.pixels))));
        log.windows_delivered.push((p, win.frame, win.req));
        if dropped {
            // Not read: the processor still waits, and its watchdog will ask again.
            log.dropped.push((p, win.frame));
            return Ok(());
        }
        self.wiring.writes.delivered(p);
        let view = delivered_view(&win, &mut self.scratch)?;
        let begin = win.clock.max(self.free_at[p]);
        self.recorder.log.windows[p] += 1;
        let step = self.roster.on_window(p, &view, self.timing.seconds(begin));
        self.window_frame[p] = win.frame;
        self.finish_step(p, step, begin, win.frame)
    }

    /// A message arrived on clock `c`: its processor takes it once free.
    fn on_message(&mut self, to: usize, from: usize, c: u64) -> Result<(), SimError> {
        let msg = self.wiring.links.receive(from, to)?;
        let begin = c.max(self.free_at[to]);
        let Some(step) = self.roster.on_message(to, &msg, self.timing.seconds(begin)) else { return Ok(()) };
        // A report on a message (COOP's decision once the partner's result is in) measures the
        // processor's last window.
        self.finish_step(to, step, begin, self.window_frame[to])
    }

    /// Processor `p`'s step, begun on clock `begin`, ends after its work: its report (measured
    /// in `frame`) is published and its effects carried out.
    fn finish_step(&mut self, p: usize, step: Step, begin: u64, frame: usize) -> Result<(), SimError> {
        let end = begin + self.timing.busy(&step.work);
        self.free_at[p] = end;
        self.recorder.publish(&step, self.timing.seconds(end), frame)?;
        self.wiring.apply(p, step, end)
    }

    /// Frame `k`'s FVAL rises on clock `c`: the last frame's record, and the watchdog.
    fn on_frame_start(&mut self, k: usize, c: u64, progress: &mut dyn FnMut(usize), on_record: &mut dyn FnMut(&FrameRecord)) {
        if k > 0 {
            on_record(self.recorder.end_frame(k - 1, self.roster.mode()));
        }
        progress(k);
        let rewrites = self.wiring.writes.watchdog(k, c, self.wiring.units);
        self.recorder.log.watchdog.extend(rewrites);
    }
}

/// The processor's view of a delivered window. A 25% window arrives packed; it is spread back
/// onto its full-resolution grid in `scratch` so the view carries the 2-pixel step and the
/// kernels report frame positions.
fn delivered_view<'s>(win: &'s Delivered, scratch: &'s mut Vec<u8>) -> Result<WindowView<'s>, SimError> {
    let req = &win.req;
    let (x0, y0) = (u32::from(req.x0), u32::from(req.y0));
    let bad = |error| SimError::Window { req: *req, error };
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
