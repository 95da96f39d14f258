//! The appearance-change evaluation (issue 21) against its independent references: the
//! renderer's exact ground truth and OpenCV's trackers run by `scripts/opencv_real.py` on the
//! same sequences (`fixtures/opencv/real/centre-{rotate,...}.*.csv`, checked fresh by
//! `real_images.rs`).
//!
//! The bounds are the figures measured with the first template aligned under a similarity
//! warp (`coopwin experiment appearance`, docs/results.md), with at most 2x margin on RMS and
//! one point plus 2x on loss, and never above issue 21's targets (0.3 px, 2 %): a change that
//! loses the object more often, or drifts further, fails.
use coopwin_firmware::processors::Params;
use coopwin_testbench::analysis::metrics::auroc;
use coopwin_testbench::experiments::appearance::{conditions, judge, run};
use coopwin_testbench::experiments::real_images::{opencv_score, simulate_configured, OPENCV};
use coopwin_testbench::system::{CoopPolicy, Strategy};
mod common;
use common::assert_rows_are_honest;

/// (condition, measured RMS px, measured loss %) of COOP with the adapting template.
const MEASURED: [(&str, f64, f64); 7] = [
    ("centre-rotate", 0.060, 0.0),
    ("centre-scale", 0.034, 0.0),
    ("centre-tilt", 0.066, 0.0),
    ("centre-shadow", 0.156, 0.0),
    ("centre-blur", 0.216, 0.0),
    ("centre-cover", 0.067, 1.5),
    ("centre-combined", 0.284, 0.0),
];

/// Issue 21's targets on every appearance set: RMS px and loss %.
const TARGET: (f64, f64) = (0.3, 2.0);

#[test]
fn the_adapting_template_holds_the_object_where_the_fixed_one_loses_it() {
    for c in conditions() {
        let (_, rms, loss) = MEASURED.iter().copied().find(|m| m.0 == c.name).expect("a measured figure");
        let mut frames = c.render();
        let adapting = run(&c, &mut frames, true).expect("runs");
        let fixed = run(&c, &mut frames, false).expect("runs");
        let r = adapting.rms.unwrap_or(f64::INFINITY);
        assert!(r <= (2.0 * rms).min(TARGET.0), "{}: RMS {r:.3} px, measured {rms}", c.name);
        assert!(adapting.loss <= (2.0 * loss + 1.0).min(TARGET.1), "{}: loss {:.1}%, measured {loss}", c.name, adapting.loss);
        // The thesis's fixed template loses over half of every one of these sets.
        assert!(fixed.loss > 50.0 && adapting.loss < fixed.loss, "{}: {adapting:?} against fixed {fixed:?}", c.name);
    }
}

#[test]
fn where_the_object_turns_scales_or_is_covered_no_opencv_tracker_keeps_it_as_often() {
    for name in ["centre-rotate", "centre-scale", "centre-cover", "centre-combined"] {
        let c = conditions().into_iter().find(|c| c.name == name).expect("condition");
        let mut frames = c.render();
        let ours = run(&c, &mut frames, true).expect("runs");
        for (label, file) in OPENCV {
            let theirs = opencv_score(&c, &frames.truth, file).expect("readable").expect("fixture present");
            assert!(ours.loss <= theirs.loss, "{name}: COOP loss {:.1}% vs {label} {:.1}%", ours.loss, theirs.loss);
        }
    }
}

#[test]
fn the_adapting_track_reports_the_objects_turn_and_scale() {
    // Independent reference: the renderer's pose of the object in the frame each report
    // measured, against its pose at lock-on (frame 0). Bounds: 2x the worst errors measured
    // (rotate: 0.48 degrees, scale 0.0068; scale: 1.03 degrees, 0.0115).
    for (name, angle_max, scale_max) in [("centre-rotate", 1.0, 0.014), ("centre-scale", 2.0, 0.023)] {
        let c = conditions().into_iter().find(|c| c.name == name).expect("condition");
        let mut frames = c.render();
        let log = simulate_configured(&c, &mut frames, Strategy::Coop, CoopPolicy::Guarded, true).expect("runs");
        assert_rows_are_honest(name, &log);
        let look = &c.scene.appearance;
        let at = |k: usize| look.pose(k as f64 / c.scene.frames as f64).angle_scale();
        let (angle0, scale0) = at(0);
        let (mut shaped, mut worst_angle, mut worst_scale) = (0, 0.0f64, 0.0f64);
        for r in &log.frames {
            if let (Some(s), Some(m)) = (r.shape, r.measured_frame) {
                let (angle, scale) = at(m);
                worst_angle = worst_angle.max((f64::from(s.angle_deg) - (angle - angle0)).abs());
                worst_scale = worst_scale.max((f64::from(s.scale) - scale / scale0).abs());
                shaped += 1;
            }
        }
        eprintln!("{name}: {shaped} frames with a shape, worst angle error {worst_angle:.3} deg, worst scale error {worst_scale:.4}");
        assert!(shaped >= 270, "{name}: {shaped} of 300 frames report a shape");
        assert!(worst_angle <= angle_max && worst_scale <= scale_max, "{name}: angle {worst_angle:.3} deg, scale {worst_scale:.4}");
    }
}

#[test]
fn confidence_tells_the_bad_frames_better_than_the_psr_baseline() {
    // Issue 21 aims at an AUROC of 0.9 for "over 2 px". The adapting track has bad frames on
    // the cover set only (measured 1.000), so the measure is judged where the thesis's fixed
    // template loses the object on most frames (measured 0.977-1.000 a set, PSR 0.696-0.969,
    // pooled 0.960 against 0.871): at least 0.9 on each set and ahead of the PSR pooled.
    let (mut conf, mut psr) = (Vec::new(), Vec::new());
    for c in conditions() {
        let mut frames = c.render();
        let log = simulate_configured(&c, &mut frames, Strategy::Coop, CoopPolicy::Guarded, false).expect("runs");
        // The fixed template loses and re-finds the object many times: every kind of row.
        assert_rows_are_honest(&c.name, &log);
        let j = judge(&c, &log, &mut frames, Params::default().correlation(false).1);
        let area = auroc(&j.confidence).expect("good and bad frames");
        eprintln!("{}: confidence {area:.3}, PSR {:?}", c.name, auroc(&j.psr));
        assert!(area >= 0.9, "{}: AUROC {area:.3}", c.name);
        conf.extend(j.confidence);
        psr.extend(j.psr);
    }
    let (a, p) = (auroc(&conf).unwrap(), auroc(&psr).unwrap());
    assert!(a > p, "pooled: confidence {a:.3}, PSR {p:.3}");
}
