//! The waveform audit on a real rust-hdl run: the VCD of a window unit is read back (with the
//! `vcd` crate) and checked against the coordinate sets its processor wrote. A clean run passes;
//! a tampered request list and a tampered waveform are caught (the audit can fail).
use coopwin_firmware::ports::Decimation;
use coopwin_testbench::audit::{audit, read_requests, read_vcd};
use coopwin_testbench::commands::track::requests_csv;
use coopwin_testbench::cost::CostModel;
use coopwin_testbench::experiments::{system, SceneFrames};
use coopwin_testbench::scene::{PathKind, Scene, SceneConfig};
use coopwin_testbench::system::{run_traced, HdlChoice, Strategy};

#[test]
fn a_traced_run_passes_the_audit_and_tampering_is_caught() {
    // A 64x64 camera keeps the trace small. TPDF's three units: the Watch's full frames, the
    // Peripheral's 25% windows and the Foveal's 24x24 windows, all in one VCD.
    let scene = SceneConfig { path: PathKind::Triangle, width: 64, height: 64, frames: 10, speed: 60.0, seed: 3, ..SceneConfig::default() };
    let target = Scene::new(scene.clone()).truth(0).corner;
    let mut cfg = system(Strategy::Tpdf, CostModel::NATIVE, Some(target));
    cfg.hdl = HdlChoice::RustHdl;
    let path = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("audit_run.vcd");
    let file = std::io::BufWriter::new(std::fs::File::create(&path).unwrap());
    let log = run_traced(&cfg, &mut SceneFrames::new(scene), &mut |_| {}, Some(Box::new(file))).unwrap();
    assert!(log.requests.iter().any(|r| r.2.decimation == Decimation::Quarter));
    let csv = requests_csv(&log);
    let read = |unit| read_vcd(std::io::BufReader::new(std::fs::File::open(&path).unwrap()), unit).unwrap();
    for unit in 0..3 {
        let a = audit(&read(unit), &read_requests(&csv, unit).unwrap());
        assert!(a.violations.is_empty(), "unit {unit}: {:?}", a.violations);
        assert!(a.windows >= 5, "unit {unit}: {a:?}");
        assert_eq!(a.frames, 10);
    }
    let (samples, sets) = (read(2), read_requests(&csv, 2).unwrap());

    // A set the processor never wrote.
    let mut wrong = sets.clone();
    wrong[1].1 .0 += 1;
    assert!(audit(&samples, &wrong).violations.iter().any(|v| v.contains("the processor wrote")));
    // A strobe the unit never made.
    let mut forged = samples.clone();
    let quiet = forged.iter().position(|s| !s.strben && !s.pixel_strobe && s.fval).unwrap();
    forged[quiet + 1].pixel_strobe = true;
    assert!(!audit(&forged, &sets).violations.is_empty());
}
