//! The long-term evaluation on real clips with ground truth by hand (issue 38 item 6): the
//! people of `vtest.avi` and the footage objects, labelled every 5th frame as visible, hidden
//! or gone (`fixtures/longterm/`, whose README gives the procedure), tracked from their start
//! box and scored as `scripts/opencv_longterm.py` scores OpenCV's trackers on them.
use super::{rows, TRACKERS};
use crate::analysis::longterm::{self, Bin, LongTermScore, Truth};
use crate::experiments::real_footage::{Clip, Object};
use crate::experiments::ExperimentError;
use coopwin_firmware::processors::Params;
use std::path::{Path, PathBuf};

/// The labelled clips, in the order of the tables.
pub const CLIPS: [&str; 4] = ["vtest", "Megamind", "Megamind_bugy", "tree"];

/// OpenCV's trackers in `fixtures/longterm/opencv/`: (label, file name part).
pub const OPENCV: [(&str, &str); 4] = [("CSRT", "csrt"), ("KCF", "kcf"), ("MOSSE", "mosse"), ("TLD", "tld")];

/// An object labelled by hand: the object (clip, name, frames, start box) and its truth on
/// every frame from its first.
#[derive(Clone, Debug, PartialEq)]
pub struct Labelled {
    /// The clip, the object's name, its first and last labelled frame and its start box.
    pub object: Object,
    /// The truth of its frames, first to last.
    pub truth: Vec<Truth>,
}

/// `fixtures/longterm/`.
fn folder() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join("fixtures").join("longterm")
}

/// A CSV file's data lines split at commas, with their line numbers.
fn lines(path: &Path) -> Result<Vec<(usize, Vec<String>)>, ExperimentError> {
    let text = std::fs::read_to_string(path).map_err(|source| ExperimentError::Io { action: "read", path: path.into(), source })?;
    Ok(text.lines().enumerate().skip(1).filter(|(_, l)| !l.trim().is_empty()).map(|(i, l)| (i + 1, l.split(',').map(|f| f.trim().to_string()).collect())).collect())
}

/// A keyframe: frame, box (none for `gone`, or where a hidden object cannot be seen), visible.
type Keyframe = (usize, Option<(f64, f64, f64, f64)>, bool);

fn keyframes(path: &Path) -> Result<Vec<Keyframe>, ExperimentError> {
    let bad = |line| ExperimentError::Fixture { path: path.into(), line };
    let mut keys = Vec::new();
    for (line, f) in lines(path)? {
        let frame = f.first().and_then(|v| v.parse::<usize>().ok()).ok_or_else(|| bad(line))?;
        let num = |k: usize| f.get(k).and_then(|v| v.parse::<f64>().ok());
        let bbox = match (num(1), num(2), num(3), num(4)) {
            (Some(x), Some(y), Some(w), Some(h)) => Some((x, y, w, h)),
            _ => None,
        };
        let (bbox, visible) = match f.get(5).map(String::as_str) {
            Some("visible") if bbox.is_some() => (bbox, true),
            Some("hidden") => (bbox, false),
            Some("gone") => (None, false),
            _ => return Err(bad(line)),
        };
        if keys.last().is_some_and(|k: &Keyframe| k.0 >= frame) {
            return Err(bad(line));
        }
        keys.push((frame, bbox, visible));
    }
    Ok(keys)
}

/// Each frame's truth from the first keyframe to the last, as the fixtures' README defines
/// it: between keyframes `k0 < f < k1` the state is `k0`'s and the box the linear
/// interpolation of theirs (`k0`'s when `k1` has none, none when `k0` has none).
pub fn interpolate(keys: &[Keyframe]) -> Vec<Truth> {
    let mut truth = Vec::new();
    for pair in keys.windows(2) {
        let ((k0, b0, visible), (k1, b1, _)) = (pair[0], pair[1]);
        for f in k0..k1 {
            let t = (f - k0) as f64 / (k1 - k0) as f64;
            let lerp = |a: f64, b: f64| a + (b - a) * t;
            let bbox = b0.map(|a| b1.map_or(a, |b| (lerp(a.0, b.0), lerp(a.1, b.1), lerp(a.2, b.2), lerp(a.3, b.3))));
            truth.push(Truth::labelled(visible, bbox));
        }
    }
    if let Some(&(_, bbox, visible)) = keys.last() {
        truth.push(Truth::labelled(visible, bbox));
    }
    truth
}

/// The objects labelled in `clip` (`fixtures/longterm/<clip>/objects.csv` and their keyframes).
pub fn labelled(clip: &'static str) -> Result<Vec<Labelled>, ExperimentError> {
    let dir = folder().join(clip);
    let path = dir.join("objects.csv");
    let mut objects = Vec::new();
    for (line, f) in lines(&path)? {
        let bad = || ExperimentError::Fixture { path: path.clone(), line };
        let num = |k: usize| f.get(k).and_then(|v| v.parse::<u32>().ok()).ok_or_else(bad);
        if f.len() != 7 {
            return Err(bad());
        }
        let (first, last) = (num(1)? as usize, num(2)? as usize);
        let keys = keyframes(&dir.join(format!("{}.csv", f[0])))?;
        if keys.first().map(|k| k.0) != Some(first) || keys.last().map(|k| k.0) != Some(last) {
            return Err(bad());
        }
        let object = Object { clip: clip.into(), name: f[0].clone(), frames: (first, last), bbox: (num(3)?, num(4)?, num(5)?, num(6)?) };
        objects.push(Labelled { object, truth: interpolate(&keys) });
    }
    Ok(objects)
}

/// One OpenCV tracker's score on one object or set: (tracker file part, object, precision
/// (`None`: no `ok` row), F).
pub type OpencvScore = (String, String, Option<f64>, f64);

/// OpenCV's scores on `clip`'s objects from the fixtures' `summary.csv`.
pub fn opencv_scores(clip: &str) -> Result<Vec<OpencvScore>, ExperimentError> {
    let dir = if clip == "vtest" { folder().join("opencv") } else { folder().join("opencv").join(clip) };
    summary_scores(&dir.join("summary.csv"))
}

/// Where `scripts/opencv_longterm.py --sets` keeps OpenCV's runs on the long-term sets.
pub fn opencv_sets_folder() -> PathBuf {
    folder().join("opencv").join("sets")
}

/// OpenCV's scores on the long-term sets, as [`opencv_scores`] (the object is the set).
pub fn opencv_set_scores() -> Result<Vec<OpencvScore>, ExperimentError> {
    summary_scores(&opencv_sets_folder().join("summary.csv"))
}

/// The rows of a `summary.csv` that `scripts/opencv_longterm.py` writes.
fn summary_scores(path: &Path) -> Result<Vec<OpencvScore>, ExperimentError> {
    lines(path)?
        .into_iter()
        .map(|(line, f)| {
            let bad = || ExperimentError::Fixture { path: path.into(), line };
            let f_score = f.get(10).and_then(|v| v.parse::<f64>().ok()).ok_or_else(bad)?;
            let precision = f.get(8).and_then(|v| v.parse::<f64>().ok());
            Ok((f.first().cloned().ok_or_else(bad)?, f.get(1).cloned().ok_or_else(bad)?, precision, f_score))
        })
        .collect()
}

/// Each tracker of [`TRACKERS`] on `o` in `clip`, scored from the frame after the start box
/// (the start frame is given, not tracked), as `scripts/opencv_longterm.py` scores, with the
/// reliability diagram's bins of its rows.
pub fn score_object(clip: &Clip, labelled: &Labelled) -> Result<Vec<(LongTermScore, [Bin; 10])>, ExperimentError> {
    let o = &labelled.object;
    let (first, last) = o.frames;
    TRACKERS
        .iter()
        .map(|&(_, adapt)| {
            let log = clip.simulate(first..=last, o.centre(), o, adapt)?;
            let rows = rows(&log, Params::default().correlation(adapt).1);
            let (rows, truth) = (rows.get(1..).unwrap_or(&[]), labelled.truth.get(1..).unwrap_or(&[]));
            Ok((longterm::score(rows, truth), longterm::reliability(rows, truth)))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolation_follows_the_fixtures_readme() {
        // Keyframes 0 (box 0,0,10,10 visible), 4 (box 8,4,10,14 hidden), 6 (gone), 8 (visible).
        let keys = [(0, Some((0.0, 0.0, 10.0, 10.0)), true), (4, Some((8.0, 4.0, 10.0, 14.0)), false), (6, None, false), (8, Some((0.0, 0.0, 4.0, 4.0)), true)];
        let t = interpolate(&keys);
        assert_eq!(t.len(), 9);
        // Frame 2, halfway: box 4,2,10,12, centre (8.5, 7.5), half-sides (4.5, 5.5); visible.
        assert_eq!(t[2], Truth { visible: true, on: Some(((8.5, 7.5), (4.5, 5.5))) });
        // Frame 5: hidden, k1 (gone) has no box, so k0's box; frame 7: gone, no box.
        assert_eq!(t[5], Truth::labelled(false, Some((8.0, 4.0, 10.0, 14.0))));
        assert_eq!(t[7], Truth { visible: false, on: None });
        assert_eq!(t[8], Truth::labelled(true, Some((0.0, 0.0, 4.0, 4.0))));
    }

    #[test]
    fn every_labelled_object_reads_and_covers_its_frames() {
        // The fixtures' README counts the frames of each object (its table "frames" column).
        let counts: Vec<(String, usize)> = CLIPS.iter().flat_map(|c| labelled(c).expect("fixtures read")).map(|o| (o.object.name, o.truth.len())).collect();
        assert_eq!(counts.len(), 15);
        assert!(counts.contains(&("coat".into(), 301)) && counts.contains(&("red".into(), 646)) && counts.contains(&("hinge".into(), 70)));
        for clip in CLIPS {
            assert_eq!(opencv_scores(clip).expect("summary reads").len(), 4 * labelled(clip).unwrap().len(), "{clip}");
        }
    }
}
