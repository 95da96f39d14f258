//! Records the COOP Foveal pair's window streams (thesis 4.2) for the Cortex-M4 replay
//! (`firmware/board`): the testbench's scene is rendered frame by frame, the pair's
//! requested window is cut from it, and the pair runs on it to choose the next window.
//! The files are `fixtures/board/windows.bin` (the thesis's pair, [`thesis`]),
//! `windows_adaptive.bin` (the adapting pair, [`adaptive`]) and `windows_covered.bin` (the
//! adapting pair with a cover over part of the object, [`covered`]); `tests/board_windows.rs`
//! checks they are current.
use crate::experiments::appearance;
use crate::frames::scene::{PathKind, Scene, SceneConfig};
use crate::units::window_of;
use coopwin_firmware::types::WindowRequest;
use coopwin_firmware::types::Point;
use coopwin_firmware::processors::{Params, Template};
use coopwin_firmware::kernels::view::{ViewError, WindowView};
use coopwin_parity::stream::{encode, Frame};
use coopwin_parity::suite::{CoopPair, NoMeter};

/// A recorded run: the scene, the point tracked, the pair's parameters and how many frames.
#[derive(Clone, Debug)]
pub struct Recording {
    /// The scene rendered.
    pub scene: SceneConfig,
    /// The object's centre (a textured template) rather than its corner.
    pub centre: bool,
    /// The pair adapts its template ([`Params::adaptive`]).
    pub adapt: bool,
    /// Frames recorded (from the first).
    pub frames: usize,
    /// A cover over part of the object for some of the frames.
    pub cover: Option<Cover>,
}

/// A flat gray cover over the left of the tracked point, 80 px tall, from 40 px left of it
/// to `right` px left of it (issue 38: an object partly covered), over `frames`.
#[derive(Clone, Debug)]
pub struct Cover {
    /// The frames covered.
    pub frames: std::ops::Range<usize>,
    /// How far left of the tracked point the cover's right edge stands, in pixels.
    pub right: f64,
}

/// The cover's gray level (the appearance sets' full cover's).
const COVER_GRAY: u8 = 90;

impl Recording {
    /// The tracked point's truth in frame `k`.
    pub fn truth(&self, scene: &Scene, k: usize) -> (f64, f64) {
        let t = scene.truth(k);
        if self.centre {
            t.centre
        } else {
            t.corner
        }
    }
}

/// `windows.bin`: the thesis's pair on the triangle path at 150 px/s under the lamp change,
/// with noise, tracking the corner, so both the NCC and the corner detector are chosen (the
/// lamp's middle third) within 48 frames.
pub fn thesis() -> Recording {
    let scene = SceneConfig { path: PathKind::Triangle, speed: 150.0, frames: 48, lighting_ramp: true, noise: 2.0, seed: 7, ..SceneConfig::default() };
    Recording { scene, centre: false, adapt: false, frames: 48, cover: None }
}

/// `windows_adaptive.bin`: the adapting pair (`track`'s default) on the first 60 frames of the
/// appearance evaluation's combined condition (the object's centre on a photograph turning,
/// scaling, tilting, blurring and under a shadow, 30 frames/s; `coopwin experiment
/// appearance`), so its template is replaced and its window grows with the motion.
pub fn adaptive() -> Recording {
    let scene = appearance::conditions().into_iter().find(|c| c.name == "centre-combined").map(|c| c.scene).unwrap_or_default();
    Recording { scene, centre: true, adapt: true, frames: 60, cover: None }
}

/// `windows_covered.bin`: the adapting pair as [`adaptive`], a flat cover over its object's
/// left part (the 20x20 template's first 3 columns, and 37 px beyond) over frames 30-44, so
/// its chain of vouched rows breaks and the partly covered check runs (issue 38): the frames
/// of an object in doubt, measured on the board.
pub fn covered() -> Recording {
    Recording { frames: 45, cover: Some(Cover { frames: 30..45, right: 7.0 }), ..adaptive() }
}

/// Why the stream cannot be recorded.
#[derive(Debug)]
pub enum RecordError {
    /// A frame or a window cannot be viewed.
    View {
        /// The frame.
        frame: usize,
        /// The reason.
        error: ViewError,
    },
    /// The template does not fit in frame 0.
    TemplateDoesNotFit,
    /// The pair asked for a window that leaves the frame (or has no pixel).
    WindowOutside {
        /// The frame.
        frame: usize,
        /// The window.
        req: WindowRequest,
    },
    /// The pair's partner sent no result (or its window is not in the master's).
    NoResult(usize),
    /// The template's side does not fit the stream's byte.
    TemplateTooLarge,
}

impl std::fmt::Display for RecordError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RecordError::View { frame, error } => write!(f, "frame {frame}: {error}"),
            RecordError::TemplateDoesNotFit => f.write_str("the template does not fit in frame 0"),
            RecordError::WindowOutside { frame, req } => write!(f, "frame {frame}: window {req:?} leaves the frame"),
            RecordError::NoResult(k) => write!(f, "frame {k}: the partner sent no result"),
            RecordError::TemplateTooLarge => f.write_str("template side over 255"),
        }
    }
}

impl std::error::Error for RecordError {}

/// The stream's bytes; it ends early if the pair loses the target.
pub fn record(rec: &Recording) -> Result<Vec<u8>, RecordError> {
    let cfg = &rec.scene;
    let scene = Scene::new(cfg.clone());
    let (w, h) = (cfg.width, cfg.height);
    let (frame0, _) = scene.render(0);
    let at = rec.truth(&scene, 0);
    let start = Point { x: at.0 as f32, y: at.1 as f32 };
    let view = WindowView::packed(&frame0, w, h).map_err(|error| RecordError::View { frame: 0, error })?;
    let tpl = Template::capture(&view, start, 20).ok_or(RecordError::TemplateDoesNotFit)?;
    let params = if rec.adapt { Params::default().adaptive() } else { Params::default() };
    let mut pair = CoopPair::new(params);
    pair.start(tpl.clone(), start);
    let mut windows: Vec<(f64, WindowRequest, Vec<u8>)> = Vec::new();
    for k in 0..rec.frames.min(cfg.frames) {
        let Some(r) = pair.want() else { break };
        let mut img = if k == 0 { frame0.clone() } else { scene.render(k).0 };
        if let Some(c) = rec.cover.as_ref().filter(|c| c.frames.contains(&k)) {
            let (x, y) = rec.truth(&scene, k);
            let clamp = |v: f64, hi: usize| (v.round().max(0.0) as usize).min(hi);
            for row in clamp(y - 40.0, h)..clamp(y + 40.0, h) {
                img[row * w + clamp(x - 40.0, w)..row * w + clamp(x - c.right, w)].fill(COVER_GRAY);
            }
        }
        let (x0, y0, ww, wh) = (usize::from(r.x0), usize::from(r.y0), usize::from(r.width), usize::from(r.height));
        if ww == 0 || wh == 0 || x0 + ww > w || y0 + wh > h {
            return Err(RecordError::WindowOutside { frame: k, req: r });
        }
        let px = window_of(&r).crop(&img, w, false);
        let t = k as f64 / cfg.fps;
        let v = WindowView::new(&px, ww, wh, ww, r.x0.into(), r.y0.into()).map_err(|error| RecordError::View { frame: k, error })?;
        pair.frame(&mut NoMeter, "", &v, t).ok_or(RecordError::NoResult(k))?;
        windows.push((t, r, px));
    }
    let frames: Vec<Frame<'_>> =
        windows.iter().map(|(t, r, px)| Frame { t: *t, x0: r.x0, y0: r.y0, w: r.width, h: r.height, pixels: px }).collect();
    let side = u8::try_from(tpl.side()).map_err(|_| RecordError::TemplateTooLarge)?;
    let mut bytes = Vec::new();
    let a = tpl.anchor();
    encode(side, (a.x, a.y), tpl.pixels(), (start.x, start.y), &frames, &mut |b| bytes.extend_from_slice(b));
    Ok(bytes)
}
