//! The experiments' scenes and systems: the thesis's paths, the configurations that must find
//! the part by themselves, and a run scored against its scene's ground truth.
use crate::analysis::metrics::{self, Summary};
use crate::frames::groundtruth::Truth;
use crate::frames::scene::{PathKind, Scene, SceneConfig, SceneFrames};
use crate::system::cost::CostModel;
use crate::system::{self, RunLog, SimError, Strategy, SystemConfig};

/// The pendulum scene of Fig. 2.8 at `speed` px/s: long enough for several passes.
pub fn pendulum(speed: f64, seed: u64) -> SceneConfig {
    let frames = ((4.0 * 400.0 / speed.max(10.0)) * 114.0).clamp(300.0, 3000.0) as usize;
    SceneConfig { path: PathKind::Pendulum, speed, frames, noise: 1.0, seed, ..SceneConfig::default() }
}

/// The triangular path of Fig. 3.4 (300 frames, the thesis's 300-point path).
pub fn triangle(speed: f64, seed: u64) -> SceneConfig {
    SceneConfig { path: PathKind::Triangle, speed, frames: 300, noise: 1.0, seed, ..SceneConfig::default() }
}

/// The part's corner in frame 0 of `scene`: the target given to a run.
pub fn corner0(scene: &SceneConfig) -> (f64, f64) {
    Scene::new(scene.clone()).truth(0).corner
}

/// A system that must find the part with its Watch window(s), knowing only its template: a
/// model of the part cut at its corner (the part's centre is featureless) from the frame where
/// it is nearest the image centre.
pub fn watch_config(strategy: Strategy, cost: CostModel, scene: &SceneConfig) -> SystemConfig {
    let s = Scene::new(scene.clone());
    let best = (0..scene.frames).map(|k| s.truth(k)).min_by(|a, b| {
        let d = |t: &Truth| (t.centre.0 - 128.0).hypot(t.centre.1 - 128.0);
        d(a).total_cmp(&d(b))
    });
    let mut cfg = SystemConfig::thesis(strategy, cost, None);
    cfg.model = best.map(|t| (t.frame, t.corner));
    cfg
}

/// Runs `cfg` on `scene` and summarises it against the truth.
pub fn run_scene(cfg: &SystemConfig, scene: SceneConfig) -> Result<(RunLog, Summary), SimError> {
    let mut frames = SceneFrames::new(scene);
    let truth = frames.truth();
    let log = system::simulate(cfg, &mut frames, &mut |_| {})?;
    let s = metrics::summarise(&log, &truth);
    Ok((log, s))
}

/// The strategies of chapter 2, which lock on from the Watch mode.
pub const WATCH_STRATEGIES: [Strategy; 3] = [Strategy::Spmf, Strategy::Tpdf, Strategy::Mpdf];
