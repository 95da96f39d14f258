//! Hardware in the loop: the same runs with the behavioural window model, with the rust-hdl
//! `WindowUnit`s stepped clock by clock, and with the exported Verilog in Verilator deliver the
//! same windows, on the same clocks, with the same pixels, and give the same tracking record.
//! The units (two independent simulations of one design) are the reference for the model.
use coopwin_testbench::experiments::setup::{run_scene, triangle, watch_config};
use coopwin_testbench::frames::scene::{PathKind, Scene, SceneConfig};
use coopwin_testbench::system::cost::CostModel;
use coopwin_testbench::system::{Strategy, SystemConfig};
use coopwin_testbench::units::UnitBackend;

mod common;
use common::have_verilator as verilator;

fn both(cfg: &SystemConfig, scene: &SceneConfig) {
    let backends = if verilator() { vec![UnitBackend::RustHdl, UnitBackend::Verilator] } else { vec![UnitBackend::RustHdl] };
    for backend in backends {
        let mut hdl = cfg.clone();
        hdl.backend = backend;
        same(cfg, &hdl, scene);
    }
}

fn same(cfg: &SystemConfig, hdl: &SystemConfig, scene: &SceneConfig) {
    let fingerprinted = |c: &SystemConfig| SystemConfig { fingerprint_windows: true, ..c.clone() };
    let (a, _) = run_scene(&fingerprinted(cfg), scene.clone()).unwrap();
    let (b, _) = run_scene(&fingerprinted(hdl), scene.clone()).unwrap();
    assert!(!a.deliveries.is_empty());
    assert!(a.deliveries.iter().chain(&b.deliveries).all(|d| d.3.is_some()), "every window fingerprinted");
    assert_eq!(a.deliveries.len(), b.deliveries.len(), "{:?}", cfg.strategy);
    for (x, y) in a.deliveries.iter().zip(&b.deliveries) {
        assert_eq!(x, y, "{:?}: (processor, frame, clock, pixel hash) model vs {:?}", cfg.strategy, hdl.backend);
    }
    assert_eq!(a.frames, b.frames, "{:?}: tracking records differ", cfg.strategy);
    assert_eq!(a.reports, b.reports);
    // Every unit delivered windows: the run exercised all of them.
    for p in 0..a.windows.len() {
        assert!(a.deliveries.iter().any(|d| d.0 == p), "{:?}: unit {p} idle", cfg.strategy);
    }
}

#[test]
fn coop_all_four_units_busy_model_equals_rust_hdl() {
    let scene = SceneConfig { frames: 12, ..triangle(60.0, 21) };
    let target = Scene::new(scene.clone()).truth(0).corner;
    both(&SystemConfig::thesis(Strategy::Coop, CostModel::C40, Some(target)), &scene);
}

#[test]
fn watch_lock_on_with_full_frames_strips_and_quarter_windows_model_equals_rust_hdl() {
    // The part enters through the top strip: MPDF's strips, the Peripheral's 25% windows and
    // the Foveal windows all run; native timing makes every unit busy every frame.
    let scene = SceneConfig { path: PathKind::Pendulum, frames: 24, speed: 400.0, noise: 1.0, seed: 5, ..SceneConfig::default() };
    // The template (the stored model of the part) comes from later in the swing.
    let cfg = watch_config(Strategy::Mpdf, CostModel::NATIVE, &SceneConfig { frames: 200, ..scene.clone() });
    both(&cfg, &scene);
}

#[test]
fn coop_on_a_jittered_raster_model_equals_rust_hdl_and_verilator() {
    // Random camera blanking (up to 24 extra clocks before each line, 4 000 after each frame):
    // the Verilated network and the rust-hdl units see the same jittered bus, the model places
    // every window on it from `FrameRaster::pixel_clock`.
    let scene = SceneConfig { frames: 12, ..triangle(60.0, 22) };
    let target = Scene::new(scene.clone()).truth(0).corner;
    let mut cfg = SystemConfig::thesis(Strategy::Coop, CostModel::C40, Some(target));
    cfg.jitter = Some(coopwin_hdl::sim::camera::Jitter { seed: 4, line_max: 24, frame_max: 4_000 });
    both(&cfg, &scene);
}
