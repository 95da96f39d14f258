//! Which processors a strategy runs (thesis 2.3, 3.5, 4.2), how each is started, and which
//! processor plays each role messages are addressed to. A new strategy is a [`Strategy`]
//! variant (`config.rs`) and its arms in this file.
use super::config::{CoopPolicy, MpdfWatch, Strategy, SystemConfig};
use super::log::Role;
use super::SimError;
use coopwin_firmware::kernels::confidence::{KalmanCoop, SseCoop};
use coopwin_firmware::processors::coop::guard::{Guard, GuardParams};
use coopwin_firmware::types::{Decimation, WindowRequest};
use coopwin_firmware::processors::{CornerPartner, Dest, Foveal, FovealKind, Mode, Msg, Params, Peripheral, Policy, Spmf, Step, Template, Watch, Work};
use coopwin_firmware::types::Point;
use coopwin_firmware::kernels::view::WindowView;

/// One processor of a run, lent its Watch buffer (if any) for the run.
// A run holds one to four processors, so their sizes (a Foveal carries the corner
// detector's 45 KB of buffers) cost nothing worth an indirection.
#[allow(clippy::large_enum_variant)]
pub(super) enum Processor<'b> {
    Watch(Watch<'b>),
    Peripheral(Peripheral),
    Foveal(Foveal),
    Partner(CornerPartner),
    Spmf(Spmf<'b>),
}

/// Which processor plays each role messages are addressed to.
#[derive(Clone, Copy, Debug)]
pub(super) struct Roles {
    peripheral: Option<usize>,
    foveal: Option<usize>,
    partner: Option<usize>,
}

impl Roles {
    /// The processor a message for `d` goes to, if the strategy has one.
    pub(super) fn to(&self, d: Dest) -> Option<usize> {
        match d {
            Dest::Peripheral => self.peripheral,
            Dest::Foveal => self.foveal,
            Dest::FovealCd => self.partner,
        }
    }
}

/// A run's processors, in unit order, and their roles.
pub(super) struct Roster<'b> {
    processors: Vec<Processor<'b>>,
    /// Which processor plays each role.
    pub(super) roles: Roles,
}

/// The COOP master's policy for `cfg`.
fn coop_policy(cfg: &SystemConfig) -> Result<Policy, SimError> {
    Ok(match cfg.policy {
        CoopPolicy::Guarded => Policy::Guarded(Guard::new(GuardParams::for_track(&cfg.params))),
        CoopPolicy::Sse => Policy::Sse(SseCoop::new(cfg.coop_n).map_err(|error| SimError::CoopSize { n: cfg.coop_n, error })?),
        // Process noise for a part that turns corners at up to ~100 px/s each frame;
        // measurement noise of half a pixel; newest innovation 30%.
        CoopPolicy::Kalman => Policy::Kalman(KalmanCoop::new(1.0e4, 0.25, 0.3).map_err(SimError::Kalman)?),
    })
}

impl<'b> Roster<'b> {
    /// `cfg`'s processors for frames of `params`' size, with the template if known; the Watch
    /// processors take `buffers` (one frame or strip each).
    pub(super) fn build(
        cfg: &SystemConfig,
        params: Params,
        template: Option<Template>,
        buffers: [&'b mut Vec<u8>; 2],
    ) -> Result<Self, SimError> {
        let [b0, b1] = buffers;
        let (w, h) = (params.frame_w, params.frame_h);
        let full = WindowRequest { x0: 0, y0: 0, width: w, height: h, decimation: Decimation::Full };
        // The top window's rows, and the bottom window's (to the last row).
        let (top_rows, bottom_rows) = match cfg.mpdf_watch {
            MpdfWatch::Strips => (20.min(h / 2), 20.min(h / 2)),
            MpdfWatch::Halves => (h / 2, h - h / 2),
        };
        let top = WindowRequest { height: top_rows, ..full };
        let bottom = WindowRequest { y0: h - bottom_rows, height: bottom_rows, ..full };
        let known = template.is_some();
        let foveal = |kind| Foveal::new(kind, params, template.clone());
        let processors = match cfg.strategy {
            Strategy::Spmf => vec![Processor::Spmf(Spmf::new(params, b0, template.clone()))],
            Strategy::Tpdf | Strategy::TpdfCd | Strategy::Coop => {
                let kind = match cfg.strategy {
                    Strategy::Coop => FovealKind::CoopMaster,
                    Strategy::TpdfCd => FovealKind::Cd,
                    _ => FovealKind::Ncc,
                };
                let mut v = vec![
                    Processor::Watch(Watch::new(full, b0, params, known)),
                    Processor::Peripheral(Peripheral::new(params, template.clone())),
                    Processor::Foveal(foveal(kind).with_policy(coop_policy(cfg)?)),
                ];
                if cfg.strategy == Strategy::Coop {
                    v.push(Processor::Partner(CornerPartner::new(params)));
                }
                v
            }
            Strategy::SingleCd => vec![Processor::Foveal(foveal(FovealKind::Cd))],
            Strategy::Mpdf => vec![
                Processor::Watch(Watch::new(top, b0, params, known)),
                Processor::Watch(Watch::new(bottom, b1, params, known)),
                Processor::Peripheral(Peripheral::new(params, template.clone())),
                Processor::Foveal(foveal(FovealKind::Ncc)),
            ],
        };
        if processors.len() != cfg.strategy.units() {
            return Err(SimError::Roster { processors: processors.len(), units: cfg.strategy.units() });
        }
        let roles = Roles {
            peripheral: processors.iter().position(|p| matches!(p, Processor::Peripheral(_))),
            foveal: processors.iter().position(|p| matches!(p, Processor::Foveal(_))),
            partner: processors.iter().position(|p| matches!(p, Processor::Partner(_))),
        };
        Ok(Roster { processors, roles })
    }

    /// What each processor does, in processor order.
    pub(super) fn processor_roles(&self) -> Vec<Role> {
        self.processors
            .iter()
            .map(|p| match p {
                Processor::Watch(_) => Role::Watch,
                Processor::Peripheral(_) => Role::Peripheral,
                Processor::Partner(_) => Role::FovealCd,
                Processor::Foveal(_) => Role::Foveal,
                Processor::Spmf(_) => Role::Single,
            })
            .collect()
    }

    /// Processors in the run.
    pub(super) fn len(&self) -> usize {
        self.processors.len()
    }

    /// Processor `p`'s first step, at the start of the blanking before frame 0: the Watch
    /// windows look for motion; with a target, the Peripheral and Foveal windows start on it.
    pub(super) fn start(&mut self, p: usize, target: Option<Point>) -> Step {
        let foveal = self.roles.foveal;
        match (&mut self.processors[p], target) {
            (Processor::Watch(wp), _) => wp.start(),
            (Processor::Spmf(s), t) => s.start(t),
            (Processor::Peripheral(pp), Some(t)) => pp.start_at(t),
            (Processor::Foveal(f), Some(t)) if Some(p) == foveal => f.start_at(t),
            _ => Step::new(Work::None),
        }
    }

    /// Processor `p` takes its window, processing from `t` seconds.
    pub(super) fn on_window(&mut self, p: usize, view: &WindowView, t: f64) -> Step {
        match &mut self.processors[p] {
            Processor::Watch(x) => x.on_window(view),
            Processor::Peripheral(x) => x.on_window(view),
            Processor::Foveal(x) => x.on_window(view, t),
            Processor::Partner(x) => x.on_window(view),
            Processor::Spmf(x) => x.on_window(view, t),
        }
    }

    /// Processor `p` takes a message, processing from `t` seconds; `None` for a processor
    /// that takes no messages.
    pub(super) fn on_message(&mut self, p: usize, msg: &Msg, t: f64) -> Option<Step> {
        match &mut self.processors[p] {
            Processor::Peripheral(x) => Some(x.on_message(msg)),
            Processor::Foveal(x) => Some(x.on_message(msg, t)),
            Processor::Partner(x) => Some(x.on_message(msg)),
            _ => None,
        }
    }

    /// The system's mode: tracking if any processor tracks, else detecting if any detects.
    pub(super) fn mode(&self) -> Mode {
        let mut mode = Mode::Watch;
        for p in &self.processors {
            let m = match p {
                Processor::Spmf(s) => s.mode(),
                Processor::Foveal(f) => f.mode(),
                Processor::Partner(f) => f.mode(),
                Processor::Peripheral(x) => x.mode(),
                Processor::Watch(_) => Mode::Watch,
            };
            mode = match (mode, m) {
                (Mode::Track, _) | (_, Mode::Track) => Mode::Track,
                (Mode::Detect, _) | (_, Mode::Detect) => Mode::Detect,
                _ => Mode::Watch,
            };
        }
        mode
    }
}
