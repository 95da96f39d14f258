//! The CSV files of a tracking run: the per-frame record (`coopwin track --out`, the main
//! job's `coop.csv`) and the frame listing (`coopwin track --list`).
use crate::system::FrameRecord;
use coopwin_firmware::types::Source;
use coopwin_firmware::processors::Mode;
use std::fmt::Write as _;

/// The CSV of a run: frame,x,y,mode,source,measured_frame,file (the frame's file name, empty
/// for frames that come from no file).
pub fn track_csv(frames: &[FrameRecord], files: Option<&[String]>) -> String {
    let mut s = String::from("frame,x,y,mode,source,measured_frame,file\n");
    for r in frames {
        let (x, y) = r.point.map(|(x, y)| (format!("{x:.3}"), format!("{y:.3}"))).unwrap_or_default();
        let file = files.and_then(|f| f.get(r.frame)).map(|n| csv_field(n)).unwrap_or_default();
        let _ = writeln!(
            s,
            "{},{x},{y},{},{},{},{file}",
            r.frame,
            mode_name(r.mode),
            r.source.map(algo_name).unwrap_or("none"),
            r.measured_frame.map(|f| f.to_string()).unwrap_or_default()
        );
    }
    s
}

/// `frame,file` lines: the order frames with these names are tracked in.
pub fn frame_listing(names: &[String]) -> String {
    let mut s = String::from("frame,file\n");
    for (k, n) in names.iter().enumerate() {
        let _ = writeln!(s, "{k},{}", csv_field(n));
    }
    s
}

/// A CSV field: quoted when it holds a comma, a quote or a line break.
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// `watch`, `detect` or `track`.
fn mode_name(m: Mode) -> &'static str {
    match m {
        Mode::Watch => "watch",
        Mode::Detect => "detect",
        Mode::Track => "track",
    }
}

/// `ncc`, `cd` or `ssd`.
fn algo_name(a: Source) -> &'static str {
    match a {
        Source::Ncc => "ncc",
        Source::Cd => "cd",
    }
}
