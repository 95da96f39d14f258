//! The appearance-change evaluation (issue 21) against its independent references: the
//! renderer's exact ground truth and OpenCV's trackers run by `scripts/opencv_real.py` on the
//! same sequences (`fixtures/opencv/real/centre-{rotate,...}.*.csv`, checked fresh by
//! `real_images.rs`).
//!
//! The bounds are the figures measured when the adapting template was introduced
//! (`coopwin experiment appearance`, docs/results.md), with at most 2x margin on RMS and one
//! point plus 2x on loss: a change that loses the object more often, or drifts further, fails.
use coopwin_testbench::experiments::appearance::{conditions, run};
use coopwin_testbench::experiments::real_images::{opencv_score, OPENCV};

/// (condition, measured RMS px, measured loss %) of COOP with the adapting template.
const MEASURED: [(&str, f64, f64); 7] = [
    ("centre-rotate", 0.775, 0.0),
    ("centre-scale", 0.526, 0.0),
    ("centre-tilt", 0.066, 0.0),
    ("centre-shadow", 0.261, 0.0),
    ("centre-blur", 0.210, 0.0),
    ("centre-cover", 0.066, 0.8),
    ("centre-combined", 1.084, 0.0),
];

#[test]
fn the_adapting_template_holds_the_object_where_the_fixed_one_loses_it() {
    for c in conditions() {
        let (_, rms, loss) = MEASURED.iter().copied().find(|m| m.0 == c.name).expect("a measured figure");
        let mut frames = c.render();
        let adapting = run(&c, &mut frames, true).expect("runs");
        let fixed = run(&c, &mut frames, false).expect("runs");
        let r = adapting.rms.unwrap_or(f64::INFINITY);
        assert!(r <= 2.0 * rms, "{}: RMS {r:.3} px, measured {rms}", c.name);
        assert!(adapting.loss <= 2.0 * loss + 1.0, "{}: loss {:.1}%, measured {loss}", c.name, adapting.loss);
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
