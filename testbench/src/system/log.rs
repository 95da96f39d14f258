//! What a run records: a record per frame, the position reports (also framed onto the robot
//! controller's link, thesis 2.6), losses, windows, writes, faults and the units' timings.
use super::SimError;
use crate::frames::binned;
use crate::units::RequestRefused;
use coopwin_firmware::ports::position::{FramedPositionSink, PositionSink, PositionUpdate};
use coopwin_firmware::types::{Point, Shape, Source, WindowRequest};
use coopwin_firmware::processors::{Mode, Msg, Outcome, Step};
use std::collections::VecDeque;

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
    /// The NCC score behind `point`, when NCC measured it.
    pub score: Option<f32>,
    /// The object's turn and scale behind `point`, when an adapting track measured them.
    pub shape: Option<Shape>,
    /// The object's last turn and scale measured since lock-on, kept through frames that
    /// measure none: the size of the box drawn around the position.
    pub box_shape: Option<Shape>,
    /// What the track is doing at the end of the frame period.
    pub state: TrackState,
    /// Without a current `point`: where the target is expected (a coasting track's prediction)
    /// or was last measured (while it is searched for, or lost).
    pub estimate: Option<(f64, f64)>,
}

/// Oldest report, in frames, that still counts as a frame's position (the pipeline's
/// latency: a COOP decision waits for the partner's message).
pub const MAX_AGE: usize = 2;

impl FrameRecord {
    /// The frame's position and the frame it was measured in: the last one reported, when it
    /// was measured at most [`MAX_AGE`] frames before.
    pub fn fresh(&self) -> Option<((f64, f64), usize)> {
        self.point.zip(self.measured_frame).filter(|(_, m)| *m <= self.frame && self.frame - m <= MAX_AGE)
    }

    /// Whether a robot may follow the frame's position (`coopwin track`'s `ok`): a fresh one
    /// the firmware vouched for ([`Outcome::Measured`]).
    pub fn vouched(&self) -> bool {
        self.fresh().is_some() && self.state == TrackState::Tracking
    }

    /// The record of a run over frames binned `k` x `k`, its positions in the sensor's pixels.
    pub fn to_sensor(&self, k: usize) -> FrameRecord {
        let sensor = |p| binned::to_sensor(p, k);
        FrameRecord { point: self.point.map(sensor), estimate: self.estimate.map(sensor), ..*self }
    }
}

/// What a track is doing in a frame, as a user reads it: the firmware's last [`Outcome`] of
/// it, held until the next.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TrackState {
    /// A position measured in a recent window, confirmed to be the target's.
    Tracking,
    /// A position measured in a recent window that nothing confirms to be the target's (a
    /// look-alike, an occluder or a changed look may be under the window): `ok` 0.
    Unconfirmed,
    /// No measurement (an occluder, a blurred or changed look): the position is predicted
    /// from the motion, and the Foveal window looks there.
    Predicted,
    /// The Foveal window gave the target up: the Peripheral window searches for it (or has
    /// found it, and the Foveal window has yet to measure it).
    Searching,
    /// No window on the target: waiting for motion.
    Lost,
}

impl TrackState {
    /// Whether the row's position was measured in a recent window (vouched for or not).
    pub fn measured(self) -> bool {
        matches!(self, TrackState::Tracking | TrackState::Unconfirmed)
    }

    /// The name in the CSV.
    pub fn name(self) -> &'static str {
        match self {
            TrackState::Tracking => "tracking",
            TrackState::Unconfirmed => "unconfirmed",
            TrackState::Predicted => "predicted",
            TrackState::Searching => "searching",
            TrackState::Lost => "lost",
        }
    }
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
    /// The NCC score behind the point, when NCC measured it.
    pub score: Option<f32>,
    /// The object's turn and scale, when an adapting track measured them.
    pub shape: Option<Shape>,
    /// Whether the firmware vouched for the point ([`Outcome::Measured`]).
    pub vouched: bool,
}

/// What a processor of the run does (thesis 2.3), for drawing its windows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// A Watch processor (motion detection).
    Watch,
    /// The Peripheral processor (detection at 25 %).
    Peripheral,
    /// The Foveal processor (NCC, or the corner detector alone).
    Foveal,
    /// COOP's second Foveal processor (the corner detector).
    FovealCd,
    /// SPMF's single processor, in every mode.
    Single,
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
    /// The robot controller's link: every position report the firmware vouched for, as its
    /// `FramedPositionSink` sends it (thesis 2.6: position updates to the robot controller).
    pub robot_link: Vec<u8>,
    /// With clock-by-clock window units: pixel clocks simulated, for the speed report.
    pub hdl_clocks: u64,
    /// Seconds inside the HDL simulator (rust-hdl or Verilator).
    pub hdl_seconds: f64,
    /// Windows delivered but not read (fault injection): (processor, frame).
    pub dropped: Vec<(usize, usize)>,
    /// Watchdog re-requests: (processor, clock), when a request brought no window for three
    /// frame periods (a set refused by the unit, or lost).
    pub watchdog: Vec<(usize, u64)>,
    /// Every window delivered: (processor, frame, clock, fingerprint of its pixels where
    /// [`super::SystemConfig::fingerprint_windows`] asks), so backends can be compared window
    /// for window.
    pub deliveries: Vec<(usize, usize, u64, Option<u64>)>,
    /// Every window delivered: (processor, frame, the request it answers).
    pub windows_delivered: Vec<(usize, usize, WindowRequest)>,
    /// What each processor does, in processor order.
    pub roles: Vec<Role>,
    /// The frame and point the template was cut at, if known before the run: the tracked
    /// point is that point of the part.
    pub reference: Option<(usize, (f64, f64))>,
    /// Without a target: the frame and point at which a Watch processor cut the template, the
    /// centre of the first motion it saw; the point tracked from then on.
    pub locked_on: Option<(usize, (f64, f64))>,
    /// Requests the coordinate port refused: (processor, clock, why).
    pub refused: Vec<(usize, u64, RequestRefused)>,
    /// With a VCD of chosen frames: per unit, the sets taken before the trace began.
    pub sets_before_trace: Vec<usize>,
}

impl RunLog {
    /// The log of a run over frames binned `k` x `k`, its positions (frames, reports, the
    /// reference, the lock-on) mapped to the sensor's pixels, and the robot link framed anew
    /// from the reports so mapped, as a robot needs them (the firmware itself does not know
    /// the binning); the requests and the windows stay as the units had them, binned.
    pub fn to_sensor(&mut self, k: usize) -> Result<(), SimError> {
        let sensor = |p| binned::to_sensor(p, k);
        for r in &mut self.frames {
            *r = r.to_sensor(k);
        }
        let mut robot = FramedPositionSink::new(VecDeque::new());
        for r in &mut self.reports {
            let (x, y) = sensor((f64::from(r.point.x), f64::from(r.point.y)));
            r.point = Point { x: x as f32, y: y as f32 };
            if r.vouched {
                emit(&mut robot, r)?;
            }
        }
        self.robot_link = robot.into_inner().into();
        for (_, p) in self.reference.iter_mut().chain(self.locked_on.iter_mut()) {
            *p = sensor(*p);
        }
        Ok(())
    }
}

/// Sends a report to the robot controller through the firmware's position sink.
fn emit(robot: &mut FramedPositionSink<VecDeque<u8>>, r: &Report) -> Result<(), SimError> {
    let source = if r.algo == Source::Cd { Source::Cd } else { Source::Ncc };
    let update = PositionUpdate { t_us: (r.t.max(0.0) * 1e6) as u32, x: r.point.x, y: r.point.y, source };
    robot.emit(&update).map_err(SimError::RobotLink)
}

/// Where a track stands between the firmware's outcomes.
#[derive(Clone, Copy, Debug)]
enum Track {
    /// No position since the start, a loss or a re-detection.
    Searching,
    /// The last position measured.
    Reported(Report),
    /// Coasting: where the motion predicts the point.
    Predicted(Point),
}

/// The run's log as it is written, with the robot link and where the track stands.
pub(super) struct Recorder {
    pub(super) log: RunLog,
    robot: FramedPositionSink<VecDeque<u8>>,
    track: Track,
    /// The last position reported, kept through a loss, or where the Peripheral last found
    /// the target for the Foveal window.
    last_seen: Option<Point>,
    /// The last shape reported since lock-on.
    last_shape: Option<Shape>,
}

impl Recorder {
    /// An empty log.
    pub(super) fn new(log: RunLog) -> Self {
        Recorder { log, robot: FramedPositionSink::new(VecDeque::new()), track: Track::Searching, last_seen: None, last_shape: None }
    }

    /// What a step finished at `t` seconds tells the outside: its outcome; a position, measured
    /// in `frame`, goes to the robot controller and the log; a loss of track is logged.
    pub(super) fn publish(&mut self, step: &Step, t: f64, frame: usize) -> Result<(), SimError> {
        let template_cut = step.sends.iter().any(|(_, m)| matches!(m, Msg::Template(_)));
        if let Some(Msg::Motion { xmin, xmax, ymin, ymax }) = step.sends.iter().map(|(_, m)| m).find(|m| matches!(m, Msg::Motion { .. })) {
            if template_cut {
                // A lock-on (motion and a template cut there): shapes are measured against
                // this look from now on.
                self.last_shape = None;
            }
            if template_cut && self.log.locked_on.is_none() {
                let centre = |a: u16, b: u16| f64::from(f32::from(a + b) / 2.0);
                self.log.locked_on = Some((frame, (centre(*xmin, *xmax), centre(*ymin, *ymax))));
            }
        }
        if let Some(Msg::Approx(p)) = step.sends.iter().map(|(_, m)| m).find(|m| matches!(m, Msg::Approx(_))) {
            self.last_seen = Some(*p);
        }
        match step.outcome {
            Outcome::Measured(fix) | Outcome::Unconfirmed(fix) => {
                let vouched = step.outcome.vouched().is_some();
                let r = Report { t, frame, point: fix.at, algo: fix.source, score: fix.score, shape: fix.shape, vouched };
                // A robot follows what the link carries: only what the firmware vouched for.
                if vouched {
                    emit(&mut self.robot, &r)?;
                }
                self.log.reports.push(r);
                self.track = Track::Reported(r);
                self.last_seen = Some(fix.at);
                self.last_shape = r.shape.or(self.last_shape);
            }
            Outcome::Predicted(q) => self.track = Track::Predicted(q),
            Outcome::Redetected(_) => self.track = Track::Searching,
            Outcome::Lost(_) => {
                self.log.losses.push(t);
                self.track = Track::Searching;
            }
            Outcome::Silent => {}
        }
        Ok(())
    }

    /// The record of `frame`, at the end of its period, the system in `mode`.
    pub(super) fn end_frame(&mut self, frame: usize, mode: Mode) -> &FrameRecord {
        let (tracked, state, estimate) = match (mode, self.track) {
            (Mode::Track, Track::Reported(r)) if r.vouched => (Some(r), TrackState::Tracking, None),
            (Mode::Track, Track::Reported(r)) => (Some(r), TrackState::Unconfirmed, None),
            (Mode::Track, Track::Predicted(q)) => (None, TrackState::Predicted, Some(q)),
            // Re-found, with its first Foveal window still to come: still searching.
            (Mode::Track | Mode::Detect, _) => (None, TrackState::Searching, self.last_seen),
            (Mode::Watch, _) => (None, TrackState::Lost, self.last_seen),
        };
        let xy = |p: Point| (f64::from(p.x), f64::from(p.y));
        self.log.frames.push(FrameRecord {
            frame,
            point: tracked.map(|r| xy(r.point)),
            measured_frame: tracked.map(|r| r.frame),
            mode,
            source: tracked.map(|r| r.algo),
            score: tracked.and_then(|r| r.score),
            shape: tracked.and_then(|r| r.shape),
            box_shape: self.last_shape,
            state,
            estimate: estimate.map(xy),
        });
        &self.log.frames[self.log.frames.len() - 1]
    }

    /// The finished log, with the robot link's bytes.
    pub(super) fn finish(self) -> RunLog {
        RunLog { robot_link: self.robot.into_inner().into(), ..self.log }
    }
}
