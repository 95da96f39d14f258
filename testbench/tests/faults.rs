//! Faults on the loop: nothing panics, the loss is logged, tracking recovers. Run with the
//! behavioural window units and with the rust-hdl units.
use coopwin_testbench::cost::CostModel;
use coopwin_testbench::experiments::{run_scene, system, triangle, watch_system, SceneFrames};
use coopwin_testbench::scene::{PathKind, Scene, SceneConfig};
use coopwin_testbench::system::{run, FrameSource, HdlChoice, Strategy};

/// The scene with frames `dark` replaced by all zeros (a camera dropout).
struct Dropout {
    inner: SceneFrames,
    dark: std::ops::Range<usize>,
    zeros: Vec<u8>,
}

impl FrameSource for Dropout {
    fn size(&self) -> (usize, usize) {
        self.inner.size()
    }
    fn len(&self) -> usize {
        self.inner.len()
    }
    fn frame(&mut self, k: usize) -> Result<&[u8], String> {
        if self.dark.contains(&k) {
            return Ok(&self.zeros);
        }
        self.inner.frame(k)
    }
}

#[test]
fn all_zero_frames_lose_the_target_then_tracking_recovers() {
    for hdl in [HdlChoice::Model, HdlChoice::RustHdl] {
        let scene = SceneConfig { frames: 24, ..triangle(40.0, 8) };
        let target = Scene::new(scene.clone()).truth(0).corner;
        let mut cfg = system(Strategy::Tpdf, CostModel::C40, Some(target));
        cfg.hdl = hdl;
        let mut src = Dropout { inner: SceneFrames::new(scene), dark: 8..10, zeros: vec![0; 65536] };
        let log = run(&cfg, &mut src, &mut |_| {}).unwrap();
        let period = log.frame_period;
        let lost = log.losses.first().copied().unwrap_or_else(|| panic!("{hdl:?}: no loss logged"));
        assert!(lost > 8.0 * period && lost < 12.0 * period, "{hdl:?}: lost at {lost}");
        assert!(log.reports.iter().any(|r| r.frame >= 12), "{hdl:?}: tracking never recovered");
        assert!(log.frames[9].point.is_none(), "{hdl:?}: a dark frame reported as tracked");
    }
}

#[test]
fn leaving_and_reentering_the_field_of_view_relocks() {
    let scene = SceneConfig { path: PathKind::Pendulum, frames: 900, speed: 150.0, noise: 1.0, seed: 9, ..SceneConfig::default() };
    let (log, m) = run_scene(&watch_system(Strategy::Tpdf, CostModel::C40, &scene), scene.clone()).unwrap();
    let truth: Vec<_> = (0..scene.frames).map(|k| Scene::new(scene.clone()).truth(k)).collect();
    let entries = (1..truth.len()).filter(|&k| truth[k].visible && !truth[k - 1].visible).count();
    assert!(entries >= 2, "the scene re-enters: {entries}");
    // A report after every re-entry.
    for k in (1..truth.len()).filter(|&k| truth[k].visible && !truth[k - 1].visible) {
        assert!(log.reports.iter().any(|r| r.frame >= k && r.frame < k + 60), "no lock-on after entry at {k}");
    }
    assert!(m.lock_on.is_some());
}

#[test]
fn a_set_corrupted_on_the_link_is_refused_and_the_watchdog_recovers() {
    // The Foveal processor's fourth request arrives as a one-column window: the unit refuses
    // it (coord_error), no window comes, and three frames later the watchdog writes it again.
    // The behavioural model and the rust-hdl units must agree on all of it.
    let scene = SceneConfig { frames: 24, ..triangle(40.0, 12) };
    let target = Scene::new(scene.clone()).truth(0).corner;
    let mut logs = Vec::new();
    for hdl in [HdlChoice::Model, HdlChoice::RustHdl] {
        let mut cfg = system(Strategy::Spmf, CostModel::C40, Some(target));
        cfg.corrupt_request = Some(3);
        cfg.hdl = hdl;
        let log = run(&cfg, &mut SceneFrames::new(scene.clone()), &mut |_| {}).unwrap();
        assert_eq!(log.requests[3].2.width, 1, "{hdl:?}: the fault was injected");
        assert_eq!(log.watchdog.len(), 1, "{hdl:?}: {:?}", log.watchdog);
        let (_, at) = log.watchdog[0];
        let resumed = log.deliveries.iter().any(|d| d.2 > at);
        assert!(resumed, "{hdl:?}: no window after the watchdog");
        assert!(log.reports.iter().any(|r| r.frame > 12), "{hdl:?}: tracking did not carry on");
        logs.push(log);
    }
    assert_eq!(logs[0].deliveries, logs[1].deliveries);
    assert_eq!(logs[0].frames, logs[1].frames);
}

#[test]
fn a_processor_that_misses_a_window_is_woken_by_the_watchdog() {
    // The Foveal processor does not read one window (say it was busy elsewhere): no result,
    // no new request; three frames on, the watchdog asks again and tracking carries on.
    for hdl in [HdlChoice::Model, HdlChoice::RustHdl] {
        let scene = SceneConfig { frames: 24, ..triangle(40.0, 13) };
        let target = Scene::new(scene.clone()).truth(0).corner;
        let mut cfg = system(Strategy::Spmf, CostModel::C40, Some(target));
        cfg.drop_window = Some(2);
        cfg.hdl = hdl;
        let log = run(&cfg, &mut SceneFrames::new(scene), &mut |_| {}).unwrap();
        assert_eq!(log.dropped.len(), 1, "{hdl:?}");
        assert_eq!(log.watchdog.len(), 1, "{hdl:?}: {:?}", log.watchdog);
        let (p, frame) = log.dropped[0];
        assert!(log.reports.iter().all(|r| r.frame != frame), "{hdl:?}: a report from the dropped window");
        assert!(log.reports.iter().any(|r| r.frame > frame + 3), "{hdl:?}: tracking did not carry on");
        assert_eq!(log.watchdog[0].0, p);
    }
}
