//! The waveform audit on a real rust-hdl run: the VCD of a window unit is read back (with the
//! `vcd` crate) and checked against the coordinate sets its processor wrote. A clean run passes;
//! a tampered request list and a tampered waveform are caught (the audit can fail).
use coopwin_firmware::types::Decimation;
use coopwin_testbench::analysis::audit::{audit, read_vcd, requests, Sample, Set};
use coopwin_testbench::frames::scene::{PathKind, Scene, SceneConfig, SceneFrames};
use coopwin_testbench::system::cost::CostModel;
use coopwin_testbench::system::{simulate_traced, Strategy, SystemConfig};
use coopwin_testbench::units::clocked::Trace;
use coopwin_testbench::units::UnitBackend;

/// TPDF's three units on a 64x64 camera (a small trace): the Watch's full frames, the
/// Peripheral's 25% windows and the Foveal's 24x24 windows, all in one VCD of `frames`.
/// Returns every unit's samples and requests as the audit reads them.
/// A unit's trace and the requests its processor wrote, as the audit reads them.
type UnitTrace = (Vec<Sample>, Vec<(usize, Set)>);

fn traced_tpdf(name: &str, frames: std::ops::Range<usize>) -> Vec<UnitTrace> {
    let scene = SceneConfig { path: PathKind::Triangle, width: 64, height: 64, frames: 10, speed: 60.0, seed: 3, ..SceneConfig::default() };
    let target = Scene::new(scene.clone()).truth(0).corner;
    let mut cfg = SystemConfig::thesis(Strategy::Tpdf, CostModel::NATIVE, Some(target));
    cfg.backend = UnitBackend::RustHdl;
    let path = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let out = Box::new(std::io::BufWriter::new(std::fs::File::create(&path).unwrap()));
    let log = simulate_traced(&cfg, &mut SceneFrames::new(scene), &mut |_| {}, &mut |_| {}, Some(Trace { out, frames })).unwrap();
    assert!(log.requests.iter().any(|r| r.2.decimation == Decimation::Quarter));
    let csv = requests::to_csv(&log);
    let read = |unit| read_vcd(std::io::BufReader::new(std::fs::File::open(&path).unwrap()), unit).unwrap();
    (0..3).map(|unit| (read(unit), requests::read(&csv, unit).unwrap())).collect()
}

#[test]
fn a_traced_run_passes_the_audit_and_tampering_is_caught() {
    let units = traced_tpdf("audit_run.vcd", 0..10);
    for (unit, (samples, sets)) in units.iter().enumerate() {
        let a = audit(samples, sets);
        assert!(a.violations.is_empty(), "unit {unit}: {:?}", a.violations);
        assert!(a.windows >= 5, "unit {unit}: {a:?}");
        assert_eq!(a.frames, 10);
    }
    let (samples, sets) = units[2].clone();

    // A set the processor never wrote.
    let mut wrong = sets.clone();
    wrong[1].1.window.xmin += 1;
    assert!(audit(&samples, &wrong).violations.iter().any(|v| v.contains("the processor wrote")));
    // A strobe the unit never made.
    let mut forged = samples.clone();
    let quiet = forged.iter().position(|s| !s.strben && !s.pixel_strobe && s.fval).unwrap();
    forged[quiet + 1].pixel_strobe = true;
    assert!(!audit(&forged, &sets).violations.is_empty());
}

#[test]
fn a_trace_of_chosen_frames_is_audited_from_the_units_state_at_its_start() {
    // Frames 4..7 only: the trace starts in the blanking before frame 4 with each unit's
    // pending set in its registers, and the requests CSV leaves out the sets taken before.
    // Reference: the same frames of the whole-run trace, audited the same way.
    let part = traced_tpdf("audit_part.vcd", 4..7);
    let whole = traced_tpdf("audit_whole.vcd", 0..10);
    for (unit, ((samples, sets), (all, _))) in part.iter().zip(&whole).enumerate() {
        let a = audit(samples, sets);
        assert!(a.violations.is_empty(), "unit {unit}: {:?}", a.violations);
        assert_eq!(a.frames, 3, "unit {unit}");
        // The partial trace is the whole trace's clocks, sample for sample.
        let first = samples[0].clock as usize;
        let differ = samples.iter().zip(&all[first..]).position(|(a, b)| a != b);
        assert_eq!(differ, None, "unit {unit}: {:?}", differ.map(|i| (samples[i], all[first + i])));
        assert!(all.len() >= first + samples.len());
        // Each frame's window verified: as many as the whole trace delivers in frames 4..7.
        let frame_starts: Vec<usize> = (1..all.len()).filter(|&t| all[t].fval && !all[t - 1].fval).collect();
        let (from, to) = (frame_starts[4], frame_starts[7]);
        let strobed_frames = frame_starts[4..7]
            .iter()
            .filter(|&&f| all[f..frame_starts.iter().find(|&&g| g > f).copied().unwrap_or(to)].iter().any(|s| s.pixel_strobe))
            .count();
        assert!(from > first && samples.len() >= to - first);
        assert_eq!(a.windows, strobed_frames, "unit {unit}");
    }
    // The set pending at the trace start counts: with it hidden, its window is flagged.
    let (mut samples, sets) = part[2].clone();
    assert!(samples[0].start, "the Foveal unit has a set pending before frame 4");
    samples[0].start = false;
    assert!(audit(&samples, &sets).violations.iter().any(|v| v.contains("no set armed")));
}
