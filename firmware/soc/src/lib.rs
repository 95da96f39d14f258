//! The tracking firmware of the soft-CPU SoC (issue 40): the thesis's Foveal processor (2.3,
//! NCC on a fixed 20x20 template, Table 2.2's 24x24 window) on one window unit, the positions
//! it vouches for sent to the robot controller on the UART
//! ([`coopwin_firmware::ports::position`]).
//! [`Tracker`] is the loop's pure part, the same on the SoC and in the host's reference
//! replay (`soc-replay`); [`mmio`] is the SoC's hardware, reached through the `ports` traits.
#![no_std]

#[cfg(target_arch = "riscv32")]
pub mod mmio;

use coopwin_firmware::kernels::view::WindowView;
use coopwin_firmware::ports::position::PositionUpdate;
use coopwin_firmware::processors::foveal::{Foveal, FovealKind};
use coopwin_firmware::processors::step::{Step, Work};
use coopwin_firmware::processors::template::Template;
use coopwin_firmware::processors::Params;
use coopwin_firmware::types::{Decimation, Point, WindowRequest};

/// The camera's frame rate the time stamps count in (the thesis's camera, 2.6).
pub const FPS: u32 = 114;

/// A frame's time stamp in microseconds: frame `k` at `k / FPS` s.
pub fn frame_us(k: u32) -> u32 {
    (u64::from(k) * 1_000_000 / u64::from(FPS)) as u32
}

/// The frame a time stamp is of ([`frame_us`]'s inverse).
pub fn us_frame(t_us: u32) -> u32 {
    ((u64::from(t_us) * u64::from(FPS) + 999_999) / 1_000_000) as u32
}

/// The Foveal processor's side the board builds it with (Table 2.2: a 24x24 window), and its
/// Lucas-Kanade template's pixels (18x18, a 20x20 template's interior).
pub type Processor = Foveal<24, 324>;

/// Why tracking stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TrackError {
    /// The lock-on window does not hold the template around the target.
    NoTemplate,
    /// The Foveal processor asked for a first window other than the lock-on window (its
    /// parameters size it otherwise).
    StartWindow,
}

/// The loop's pure part: the lock-on window, the template, then one step a window.
pub struct Tracker {
    params: Params,
    target: Point,
    step: Step,
    /// The Foveal processor, once locked on.
    fov: Option<Processor>,
}

impl Tracker {
    /// A tracker for the point `target` of the first frame, the thesis's parameters.
    pub fn new(target: Point) -> Self {
        Tracker { params: Params::default(), target, step: Step::new(Work::None), fov: None }
    }

    /// The first window: a Foveal window around the target, to cut the template from (the
    /// template's own side would lose a column to rounding at a half-pixel centre).
    pub fn lock_on_window(&self) -> WindowRequest {
        self.params.window(self.target, self.params.foveal, Decimation::Full)
    }

    /// A window arrived from frame `frame`: the position update to send and the next window
    /// to ask for (none when tracking was lost).
    pub fn on_window(&mut self, win: &WindowView<'_>, frame: u32) -> Result<(Option<PositionUpdate>, Option<WindowRequest>), TrackError> {
        let (t_us, lock_on) = (frame_us(frame), self.lock_on_window());
        let fov = match &mut self.fov {
            Some(fov) => fov,
            empty @ None => {
                let tpl = Template::capture(win, self.target, usize::from(self.params.template)).ok_or(TrackError::NoTemplate)?;
                let mut fov = Processor::sized(FovealKind::Ncc, self.params);
                fov.set_template(tpl);
                fov.start_at_into(self.target, &mut self.step);
                // The lock-on window is the Foveal window `start_at` asks for on the target, so
                // it is measured at once, as `coopwin track` measures the first frame.
                if self.step.request != Some(lock_on) {
                    return Err(TrackError::StartWindow);
                }
                empty.insert(fov)
            }
        };
        fov.on_window_into(win, f64::from(t_us) * 1e-6, &mut self.step);
        let update = self.step.outcome.vouched().map(|f| PositionUpdate { t_us, x: f.at.x, y: f.at.y, source: f.source });
        Ok((update, self.step.request))
    }
}
