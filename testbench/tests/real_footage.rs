//! The real-footage evaluation (issue 21) against its independent reference: OpenCV's trackers
//! run by `scripts/opencv_footage.py` on the same objects of Debian's opencv-doc clips
//! (`fixtures/opencv/footage/`, objects in `fixtures/footage/objects.csv`).
//!
//! The bounds are the figures last measured (`coopwin experiment real-footage`,
//! docs/results.md): positions at least 90 % of the measured count (the tracker is
//! deterministic: the margin is for a legitimate change's frame or two), and on the
//! objects COOP holds as CSRT does, issue 21's 95 % of the frames CSRT reports, with at least
//! 97.5 % of the reports within 5 px of CSRT's (measured 98.9-100: 2x margin on the rest), or
//! where CSRT's point drifts off the object, a forward-backward error no larger than CSRT's;
//! on every object, reports within 10 px of CSRT's on average (no false re-lock).
mod common;

use coopwin_testbench::experiments::real_footage::{figures, objects, opencv_runs, Clip, DEFAULT_CLIPS};
use std::path::Path;

/// (object, measured positions of its frames).
const MEASURED: [(&str, usize); 8] = [
    ("Megamind-eye", 26),
    ("Megamind-earring", 95),
    ("Megamind-hinge", 70),
    ("Megamind_bugy-eye", 26),
    ("Megamind_bugy-candle", 94),
    ("Megamind_bugy-bridge", 56),
    ("tree-gap", 42),
    ("tree-frame", 68),
];

/// Largest mean distance, px, of an object's reports from CSRT's.
const STRAY_PX: f64 = 10.0;

/// Objects COOP holds as CSRT does (rigid, or nearly, and the earring through the head's
/// whip), and whether CSRT's point stays on the object's: on the earring it sits about 6 px
/// off the stud from frame 20 (crops with both points, docs/results.md), so there the
/// forward-backward error is held to CSRT's instead. The gap between the leaves was held (52
/// of 54 frames) until issue 38: its first view aligns at 0.5-0.8 and never confirms, so the
/// track was taken to be astray after 8 windows; since stop 53 an alignment from 0.6 where the
/// motion aims the window vouches for it (an object coming out from behind a cover): 42 of 54,
/// under the 95 % asked here.
const HELD: [(&str, bool); 4] = [("Megamind-earring", false), ("Megamind_bugy-candle", true), ("Megamind_bugy-bridge", true), ("tree-frame", true)];

/// The SHA-256 of a clip, by `sha256sum`.
fn sha256(path: &Path) -> String {
    let out = std::process::Command::new("sha256sum").arg(path).output().expect("sha256sum runs");
    String::from_utf8_lossy(&out.stdout).split_whitespace().next().unwrap_or_default().to_string()
}

#[test]
fn coop_on_the_opencv_doc_clips_holds_the_rigid_objects_as_csrt_does() {
    let clips = Path::new(DEFAULT_CLIPS);
    if !clips.join("Megamind.avi").exists() {
        common::missing_tool("opencv-doc's clips", "apt-get install -y opencv-doc");
        return;
    }
    let readme = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/opencv/footage/README.md")).expect("fixture README");
    let mut decoded: Option<(String, Clip)> = None;
    for o in objects().expect("objects.csv") {
        let path = clips.join(format!("{}.avi", o.clip));
        // The fixtures were made from these very files: otherwise they are stale.
        assert!(readme.contains(&sha256(&path)), "{}: not the clip the OpenCV fixtures were made from (rerun scripts/opencv_footage.py)", path.display());
        if decoded.as_ref().is_none_or(|(c, _)| c != &o.clip) {
            decoded = Some((o.clip.clone(), Clip::decode(&path).expect("decodes")));
        }
        let (_, clip) = decoded.as_ref().expect("decoded");
        let csrt_runs = opencv_runs(&o, "csrt").expect("CSRT fixture");
        let csrt = &csrt_runs.forward;
        let forward = clip.forward_log(&o).expect("runs");
        // The earring is lost in a fast pan and found again at once: a re-found frame's row.
        if o.id() == "Megamind-earring" {
            common::assert_rows_are_honest(&o.id(), &forward);
        }
        let f = figures(&o, &clip.runs_from(&o, &forward).expect("runs"), csrt);
        let (_, measured) = MEASURED.iter().copied().find(|m| m.0 == o.id()).expect("a measured figure");
        eprintln!("{}: {f:?}", o.id());
        assert!(f.positions * 10 >= measured * 9, "{}: {} positions of {}, measured {measured}", o.id(), f.positions, f.frames);
        // Never lying: a report is on the object CSRT follows, give or take a face's drift
        // (measured at most 6.9 px on average; a false re-lock measured 21.5 and 44.8).
        if let Some((mean, _)) = f.to_csrt {
            assert!(mean <= STRAY_PX, "{}: reports {mean:.1} px from CSRT's on average", o.id());
        }
        if let Some(&(_, on_point)) = HELD.iter().find(|h| h.0 == o.id()) {
            assert!(f.where_csrt * 100 >= 95 * f.csrt_frames, "{}: {} of CSRT's {} frames", o.id(), f.where_csrt, f.csrt_frames);
            if on_point {
                let (_, within) = f.to_csrt.expect("reports beside CSRT's");
                assert!(within >= 97.5, "{}: {within:.1} % within 5 px of CSRT", o.id());
            } else {
                let theirs = figures(&o, &csrt_runs, csrt).fb_mean.expect("CSRT's backward run");
                let ours = f.fb_mean.expect("a backward run");
                assert!(ours <= theirs, "{}: forward-backward {ours:.3} px, CSRT's {theirs:.3}", o.id());
            }
        }
    }
}
