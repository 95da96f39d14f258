//! Faults on the loop: nothing panics, the loss is logged, tracking recovers. Run with the
//! behavioural window units and with the rust-hdl units.
use coopwin_firmware::processors::Mode;
use coopwin_hdl::sim::camera::Jitter;
use coopwin_testbench::analysis::metrics::summarise;
use coopwin_testbench::experiments::setup::{run_scene, triangle, watch_config};
use coopwin_testbench::frames::scene::{PathKind, Scene, SceneConfig, SceneFrames};
use coopwin_testbench::system::cost::CostModel;
use coopwin_testbench::system::{simulate, Strategy, SystemConfig};
use coopwin_testbench::units::UnitBackend;

mod common;
use common::Dropout;

#[test]
fn all_zero_frames_lose_the_target_then_tracking_recovers() {
    for strategy in [Strategy::Spmf, Strategy::Tpdf, Strategy::Coop] {
        for hdl in [UnitBackend::BehaviouralModel, UnitBackend::RustHdl] {
            // 48 frames: a coasting COOP resumes from a 36x36 window, about 15 C40 frames.
            let scene = SceneConfig { frames: 48, ..triangle(40.0, 8) };
            let target = Scene::new(scene.clone()).truth(0).corner;
            let mut cfg = SystemConfig::thesis(strategy, CostModel::C40, Some(target));
            cfg.backend = hdl;
            let mut src = Dropout { inner: SceneFrames::new(scene), dark: 8..10, zeros: vec![0; 65536] };
            let log = simulate(&cfg, &mut src, &mut |_| {}).unwrap();
            let period = log.frame_period;
            let what = format!("{strategy:?} on {hdl:?}");
            // COOP coasts through a short dropout on its prediction (no loss, no position);
            // the others lose the target at the dropout and the Peripheral searches.
            let coasts = strategy == Strategy::Coop;
            if coasts {
                assert!(log.losses.is_empty(), "{what}: {:?}", log.losses);
                assert_eq!(log.frames[9].mode, Mode::Track, "{what}: coasting is tracking");
            } else {
                assert_eq!(log.losses.len(), 1, "{what}: {:?}", log.losses);
                assert!(log.losses[0] > 8.0 * period && log.losses[0] < 11.0 * period, "{what}: lost at {}", log.losses[0]);
                assert_eq!(log.frames[9].mode, Mode::Detect, "{what}: the Peripheral searches after the loss");
            }
            assert!(log.reports.iter().any(|r| r.frame >= 12), "{what}: tracking never recovered");
            // No stale position: a frame counts as tracked only on a measurement at most two
            // frames old (the C40's NCC updates every other frame), never across the dropout;
            // a track resuming from coasting measured a 36x36 window, which takes the C40
            // about 15 frame periods.
            for f in &log.frames {
                if let Some(m) = f.measured_frame {
                    let resumed = coasts && m > 0 && log.frames[m - 1].point.is_none();
                    let latency = if resumed { 20 } else { 2 };
                    assert!(m + latency >= f.frame && !(8..10).contains(&m), "{what}: frame {} tracked from frame {m}", f.frame);
                }
            }
            assert!(log.frames[9].point.is_none(), "{what}: a dark frame reported as tracked");
        }
    }
}

#[test]
fn a_long_dropout_falls_back_to_watch_then_relocks() {
    // Thesis 2.3: a lost target is searched for by the Peripheral (Detection); when that fails
    // the system watches the whole frame again, and locks on anew once the part moves. 60
    // dark frames (0.53 s) make the Peripheral give up, and outlast COOP's coasting (0.35 s).
    for strategy in [Strategy::Spmf, Strategy::Tpdf, Strategy::Coop] {
        let scene = SceneConfig { frames: 150, ..triangle(40.0, 8) };
        let target = Scene::new(scene.clone()).truth(0).corner;
        let cfg = SystemConfig::thesis(strategy, CostModel::C40, Some(target));
        let mut src = Dropout { inner: SceneFrames::new(scene), dark: 8..68, zeros: vec![0; 65536] };
        let log = simulate(&cfg, &mut src, &mut |_| {}).unwrap();
        assert_eq!(log.losses.len(), 1, "{strategy:?}");
        let modes: Vec<Mode> = log.frames.iter().map(|f| f.mode).collect();
        let detect = modes[8..].iter().position(|&m| m == Mode::Detect).map(|i| i + 8);
        let watch = detect.and_then(|d| modes[d..].iter().position(|&m| m == Mode::Watch).map(|i| i + d));
        let track = watch.and_then(|w| modes[w..].iter().position(|&m| m == Mode::Track).map(|i| i + w));
        assert!(track.is_some(), "{strategy:?}: Detect {detect:?}, Watch {watch:?}, Track {track:?}");
        assert!(log.reports.iter().any(|r| r.frame > 68), "{strategy:?}: no report after the camera came back");
    }
}

#[test]
fn leaving_and_reentering_the_field_of_view_relocks() {
    let scene = SceneConfig { path: PathKind::Pendulum, frames: 900, speed: 150.0, noise: 1.0, seed: 9, ..SceneConfig::default() };
    let (log, m) = run_scene(&watch_config(Strategy::Tpdf, CostModel::C40, &scene), scene.clone()).unwrap();
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
    for hdl in [UnitBackend::BehaviouralModel, UnitBackend::RustHdl] {
        let mut cfg = SystemConfig::thesis(Strategy::Spmf, CostModel::C40, Some(target));
        cfg.corrupt_request = Some(3);
        cfg.backend = hdl;
        cfg.fingerprint_windows = true;
        let log = simulate(&cfg, &mut SceneFrames::new(scene.clone()), &mut |_| {}).unwrap();
        assert_eq!(log.requests[3].2.width, 1, "{hdl:?}: the fault was injected");
        assert_eq!(log.watchdog.len(), 1, "{hdl:?}: {:?}", log.watchdog);
        let (_, at) = log.watchdog[0];
        let resumed = log.deliveries.iter().any(|d| d.2 > at);
        assert!(resumed, "{hdl:?}: no window after the watchdog");
        assert!(log.reports.iter().any(|r| r.frame > 12), "{hdl:?}: tracking did not carry on");
        logs.push(log);
    }
    assert!(logs.iter().all(|l| l.deliveries.iter().all(|d| d.3.is_some())), "every window fingerprinted");
    assert_eq!(logs[0].deliveries, logs[1].deliveries);
    assert_eq!(logs[0].frames, logs[1].frames);
}

#[test]
fn a_processor_that_misses_a_window_is_woken_by_the_watchdog() {
    // The Foveal processor does not read one window (say it was busy elsewhere): no result,
    // no new request; three frames on, the watchdog asks again and tracking carries on.
    for hdl in [UnitBackend::BehaviouralModel, UnitBackend::RustHdl] {
        let scene = SceneConfig { frames: 24, ..triangle(40.0, 13) };
        let target = Scene::new(scene.clone()).truth(0).corner;
        let mut cfg = SystemConfig::thesis(Strategy::Spmf, CostModel::C40, Some(target));
        cfg.drop_window = Some(2);
        cfg.backend = hdl;
        let log = simulate(&cfg, &mut SceneFrames::new(scene), &mut |_| {}).unwrap();
        assert_eq!(log.dropped.len(), 1, "{hdl:?}");
        assert_eq!(log.watchdog.len(), 1, "{hdl:?}: {:?}", log.watchdog);
        let (p, frame) = log.dropped[0];
        assert!(log.reports.iter().all(|r| r.frame != frame), "{hdl:?}: a report from the dropped window");
        assert!(log.reports.iter().any(|r| r.frame > frame + 3), "{hdl:?}: tracking did not carry on");
        assert_eq!(log.watchdog[0].0, p);
    }
}

/// COOP (all four units) on a target the triangle scene keeps in view, the windows from `hdl`.
fn coop(hdl: UnitBackend, scene: &SceneConfig) -> coopwin_testbench::system::SystemConfig {
    let target = Scene::new(scene.clone()).truth(0).corner;
    let mut cfg = SystemConfig::thesis(Strategy::Coop, CostModel::C40, Some(target));
    cfg.backend = hdl;
    cfg
}

#[test]
fn random_camera_blanking_changes_no_window_and_tracking_holds() {
    // Blanking drawn at random: up to 40 extra clocks before each line (the nominal gap is
    // 16) and up to 6 000 after each frame. The window logic needs only FVAL and LVAL, so:
    // the rust-hdl units deliver exactly what the behavioural model cuts from each frame (the
    // model places every pixel on the jittered raster by `FrameRaster::pixel_clock`, the units
    // find them by counting LVAL pulses), and tracking is as good as on the fixed raster.
    let scene = SceneConfig { frames: 20, ..triangle(40.0, 3) };
    let truth = SceneFrames::new(scene.clone()).truth();
    let steady = simulate(&coop(UnitBackend::BehaviouralModel, &scene), &mut SceneFrames::new(scene.clone()), &mut |_| {}).unwrap();
    let mut logs = Vec::new();
    for hdl in [UnitBackend::BehaviouralModel, UnitBackend::RustHdl] {
        let mut cfg = coop(hdl, &scene);
        cfg.jitter = Some(Jitter { seed: 11, line_max: 40, frame_max: 6_000 });
        cfg.fingerprint_windows = true;
        let log = simulate(&cfg, &mut SceneFrames::new(scene.clone()), &mut |_| {}).unwrap();
        let m = summarise(&log, &truth);
        assert!(log.windows.iter().all(|&n| n > 0), "{hdl:?}: every unit delivers: {:?}", log.windows);
        assert!(log.losses.is_empty(), "{hdl:?}: lost at {:?}", log.losses);
        let fixed = summarise(&steady, &truth);
        assert!(m.rms < fixed.rms + 0.1, "{hdl:?}: RMS {} px jittered, {} px fixed", m.rms, fixed.rms);
        // The frames did stretch: the mean period is longer than the CA-D1's 70 192 clocks.
        assert!(log.frame_period > steady.frame_period * 1.02, "{} vs {}", log.frame_period, steady.frame_period);
        logs.push(log);
    }
    assert!(logs.iter().all(|l| l.deliveries.iter().all(|d| d.3.is_some())), "every window fingerprinted");
    assert_eq!(logs[0].deliveries, logs[1].deliveries, "model and rust-hdl: same windows, clocks, pixels");
    assert_eq!(logs[0].frames, logs[1].frames);
}

#[test]
fn coordinate_writes_at_every_raster_phase_agree_with_the_model() {
    // Every set held until one phase of the raster (clocks from FVAL rising, 256x256 frame of
    // 70 192 clocks, set latency 13, a set arms a frame if it completes 1 clock before FVAL
    // rises): on the FVAL rising edge; inside the Foveal windows' rows; on the FVAL falling
    // edge (16 + 256 * 272 = 69 648); in vertical blanking; and either side of the arming
    // margin (70 192 - 14 arms the next frame, 70 192 - 13 misses it). The units and the model
    // must agree window for window, and tracking must carry on at every phase.
    let scene = SceneConfig { frames: 16, ..triangle(40.0, 5) };
    let truth = SceneFrames::new(scene.clone()).truth();
    let mut first_frames = Vec::new();
    for phase in [0, 30_000, 69_648, 69_900, 70_178, 70_179] {
        let mut logs = Vec::new();
        for hdl in [UnitBackend::BehaviouralModel, UnitBackend::RustHdl] {
            let mut cfg = coop(hdl, &scene);
            cfg.write_phase = Some(phase);
            let log = simulate(&cfg, &mut SceneFrames::new(scene.clone()), &mut |_| {}).unwrap();
            let period = 70_192;
            assert!(log.requests.iter().all(|r| (r.1 - 544) % period == phase), "{hdl:?} at {phase}: a write off its phase: {:?}", log.requests.iter().map(|r| r.1).collect::<Vec<_>>());
            assert!(log.reports.len() >= 3, "{hdl:?} at {phase}: {} reports", log.reports.len());
            assert!(summarise(&log, &truth).rms < 1.0, "{hdl:?} at {phase}");
            logs.push(log);
        }
        assert_eq!(logs[0].deliveries, logs[1].deliveries, "phase {phase}: model and rust-hdl differ");
        first_frames.push((phase, logs[1].deliveries[0].1));
    }
    // The first sets are written at clock 0, so held to `phase` of frame 0: by hand, a set
    // written at 70 178 completes at 70 191 and arms frame 1; at 70 179 it is too late and
    // arms frame 2. At phase 0 it arms frame 1 too (frame 0's FVAL has already risen).
    assert_eq!(first_frames, vec![(0, 1), (30_000, 1), (69_648, 1), (69_900, 1), (70_178, 1), (70_179, 2)]);
}

#[test]
fn a_window_the_port_cannot_carry_is_refused_and_nothing_is_written() {
    // An empty window has no bounds to write, and the units' coordinates are 8-bit: both are
    // refused with a reason before anything reaches the port, and no window comes of them.
    use coopwin_firmware::types::{Decimation, WindowRequest};
    use coopwin_hdl::sim::camera::RasterTiming;
    use coopwin_testbench::units::clocked::ClockedUnits;
    use coopwin_testbench::units::clocks::Clocks;
    use coopwin_testbench::units::model::BehaviouralUnits;
    use coopwin_testbench::units::WindowUnits;
    let scene = SceneConfig { frames: 3, ..triangle(40.0, 1) };
    let clocks = Clocks::new(RasterTiming { width: 256, height: 256, h_blank: 16, v_blank_lines: 2 }, 3, None);
    let empty = WindowRequest { x0: 0, y0: 0, width: 0, height: 8, decimation: Decimation::Full };
    let wide = WindowRequest { x0: 250, y0: 0, width: 10, height: 8, decimation: Decimation::Full };
    let mut model = BehaviouralUnits::new(clocks.clone(), 1);
    let mut hdl = ClockedUnits::rust_hdl(clocks.clone(), 8, 1, None).unwrap();
    for backend in [&mut model as &mut dyn WindowUnits, &mut hdl] {
        let why = backend.request(0, empty, 0).unwrap_err().to_string();
        assert!(why.contains("window"), "{why}");
        assert!(backend.next_window(clocks.frame_start(3), &mut SceneFrames::new(scene.clone())).unwrap().is_none());
    }
    assert!(hdl.request(0, wide, 0).unwrap_err().to_string().contains("reaches past the sensor's last column or row"));
    assert!(hdl.next_window(clocks.frame_start(3), &mut SceneFrames::new(scene)).unwrap().is_none());
    assert_eq!(hdl.finish().unwrap().clocks, clocks.frame_start(3) + 1, "the units ran the run through");
}
