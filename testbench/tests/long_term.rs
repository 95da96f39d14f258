//! The long-term evaluation (issue 38) against its independent references: the renderer's
//! exact truth of where the target is and whether it can be seen (`frames/scene/longterm.rs`),
//! and the hand labels of `fixtures/longterm/` (visible, hidden or gone, every 5th frame).
//!
//! `ok` 1 is a promise: the bounds are the figures measured by `coopwin experiment long-term`
//! (docs/results/long-term.csv, long-term-clips.csv). No more wrong `ok` 1 rows than measured,
//! full silence where the target is hidden or gone, and recall at least 90 % of the measured.
mod common;

use coopwin_testbench::analysis::longterm;
use coopwin_testbench::experiments::long_term::clips::{labelled, opencv_set_scores, opencv_sets_folder, score_object, CLIPS, OPENCV};
use coopwin_testbench::experiments::long_term::{present, rows, run};
use coopwin_testbench::experiments::real_footage::{Clip, DEFAULT_CLIPS};
use coopwin_testbench::frames::scene::longterm::sets;
use coopwin_testbench::system::RunLog;
use coopwin_firmware::ports::{frame::FrameDecoder, position::PositionUpdate};
use std::path::Path;

/// (set, measured recall) of the default tracker; every set measured with no wrong `ok` 1 row
/// and, where the target is ever hidden or gone, a TNR of 1.
const SYNTHETIC: [(&str, f64); 10] = [
    ("lookalike-front", 0.9893),
    ("lookalike-behind", 1.0),
    ("turned-front", 0.9786),
    ("identical-behind", 1.0),
    ("leaves", 1.0),
    ("leaves-identical", 1.0),
    ("crowd", 0.9183),
    ("panel", 0.9124),
    ("partial", 1.0),
    ("clutter", 1.0),
];

/// (clip, object, measured wrong `ok` 1 rows, measured recall) of the default tracker. Most of
/// vtest's people are tracked as 32x32 patches of clothing, vouched for on a few frames only;
/// the coat and the redcoat binned 2x2, their template spanning more of them (issue 38, item 4).
const CLIPS_MEASURED: [(&str, &str, usize, f64); 15] = [
    ("vtest", "coat", 0, 0.5373),
    ("vtest", "jeans", 0, 0.0345),
    ("vtest", "red", 0, 0.0745),
    ("vtest", "blond", 0, 0.1232),
    ("vtest", "hoodie", 0, 0.1772),
    ("vtest", "redcoat", 0, 0.2188),
    ("vtest", "stripes", 0, 0.0),
    ("Megamind", "eye", 0, 0.1690),
    ("Megamind", "earring", 0, 0.7581),
    ("Megamind", "hinge", 0, 1.0),
    ("Megamind_bugy", "eye", 0, 0.1702),
    ("Megamind_bugy", "candle", 0, 0.6667),
    ("Megamind_bugy", "bridge", 0, 0.4400),
    ("tree", "gap", 0, 0.2667),
    ("tree", "frame", 0, 1.0),
];

/// The robot link's updates, decoded with the firmware's own frame decoder.
fn link_updates(log: &RunLog) -> Vec<PositionUpdate> {
    let mut dec = FrameDecoder::new();
    log.robot_link.iter().filter_map(|&b| dec.feed(b)).map(|f| PositionUpdate::decode(&f.expect("valid frame")).expect("valid payload")).collect()
}

#[test]
fn the_default_never_vouches_for_a_look_alike_an_occluder_or_an_empty_place() {
    let mut unvouched = 0;
    let opencv = opencv_set_scores().expect("fixtures/longterm/opencv/sets/summary.csv reads");
    for set in sets() {
        let (_, recall) = SYNTHETIC.iter().copied().find(|m| m.0 == set.name).expect("a measured figure");
        let mut frames = set.render_all();
        // OpenCV's runs in the fixtures were made from these very frames.
        let stored = std::fs::read_to_string(opencv_sets_folder().join(format!("{}.fingerprint", set.name))).unwrap_or_default();
        assert_eq!(
            stored.trim(),
            frames.fingerprint(),
            "{}: OpenCV's fixtures are missing or stale: python3 scripts/opencv_longterm.py --sets (a new set goes into its SETS first)",
            set.name
        );
        let truth = present(&frames);
        let (log, acceptance) = run(&set, &mut frames, true).expect("runs");
        common::assert_rows_are_honest(set.name, &log);
        // A robot follows the link: it carries the reports vouched for, and no other.
        let vouched: Vec<_> = log.reports.iter().filter(|r| r.vouched).map(|r| (r.point.x, r.point.y)).collect();
        let sent: Vec<_> = link_updates(&log).iter().map(|u| (u.x, u.y)).collect();
        assert_eq!(sent.len(), vouched.len(), "{}: updates on the robot link against vouched reports", set.name);
        assert_eq!(sent, vouched, "{}: the robot link", set.name);
        unvouched += log.reports.len() - vouched.len();
        let s = longterm::score(&rows(&log, acceptance), &truth);
        eprintln!("{}: {s:?}", set.name);
        assert_eq!(s.wrong, 0, "{}: {} of {} ok rows wrong", set.name, s.wrong, s.vouched);
        assert!(s.tnr.is_none_or(|t| t == 1.0), "{}: TNR {:?}", set.name, s.tnr);
        assert!(s.recall >= 0.9 * recall, "{}: recall {:.4}, measured {recall}", set.name, s.recall);
        assert_eq!(opencv.iter().filter(|r| r.1 == set.name).count(), OPENCV.len(), "{}: OpenCV's trackers in the fixtures", set.name);
    }
    assert!(unvouched > 0, "the sets have reports the firmware did not vouch for, which the link leaves out");
}

#[test]
fn on_the_hand_labelled_clips_no_more_wrong_ok_rows_than_measured() {
    let dir = Path::new(DEFAULT_CLIPS);
    if !dir.join("vtest.avi").exists() {
        common::missing_tool("opencv-doc's clips", "apt-get install -y opencv-doc");
        return;
    }
    let mut binned = 0;
    for clip_name in CLIPS {
        let clip = Clip::decode(&dir.join(format!("{clip_name}.avi"))).expect("decodes");
        for o in labelled(clip_name).expect("fixtures read") {
            let name = o.object.name.clone();
            let (.., wrong, recall) = CLIPS_MEASURED.iter().copied().find(|m| m.0 == clip_name && m.1 == name).expect("a measured figure");
            let (s, _) = score_object(&clip, &o).expect("runs").remove(0);
            eprintln!("{clip_name} {name}: {s:?}");
            assert!(s.wrong <= wrong, "{clip_name} {name}: {} wrong ok rows of {}, measured {wrong}", s.wrong, s.vouched);
            assert!(s.recall >= 0.9 * recall, "{clip_name} {name}: recall {:.4}, measured {recall}", s.recall);
            // The bar: the binned coat and redcoat are vouched for on a few frames
            // labelled hidden, partly behind another person (0.98); every other object 1.
            assert!(s.tnr.is_none_or(|t| t >= 0.95), "{clip_name} {name}: TNR {:?}", s.tnr);
            if o.object.binned_template(clip.size()).0 > 1 {
                // A binned run's robot link carries its reports vouched for, in the clip's pixels.
                let log = clip.forward_log(&o.object).expect("runs");
                let vouched: Vec<_> = log.reports.iter().filter(|r| r.vouched).map(|r| (r.point.x, r.point.y)).collect();
                let sent: Vec<_> = link_updates(&log).iter().map(|u| (u.x, u.y)).collect();
                assert!(!sent.is_empty() && sent == vouched, "{clip_name} {name}: the robot link of a binned run");
                binned += 1;
            }
        }
    }
    // The coat (44x80) and the redcoat (48x96), binned 2x2.
    assert_eq!(binned, 2);
}
