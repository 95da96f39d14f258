//! The host's side of the Cortex-M4 parity check (thesis 2.6: the same tracking code on the
//! processors as in the simulation): the suite's lines computed here must equal
//! `fixtures/board/expected.txt`, which `scripts/board.sh` diffs against the QEMU run.
//! `COOPWIN_BLESS=1` rewrites the file instead. The kernel lines are also checked against
//! OpenCV's answers on the same inputs (`fixtures/bench/README.md`).
use coopwin_parity::suite::{self, NoMeter, Replay};
use coopwin_parity::stream::{Stream, StreamError};
use coopwin_firmware::kernels::motion::detect_motion;
use coopwin_firmware::kernels::view::WindowView;
use coopwin_firmware::processors::{watch, Params, Template};
use coopwin_firmware::types::{Decimation, Point, WindowRequest};

fn lines() -> String {
    let mut s = String::new();
    suite::run(&mut s, &mut NoMeter).expect("the suite runs on the committed inputs");
    s
}

fn field<'a>(text: &'a str, id: &str, key: &str) -> &'a str {
    let line = text.lines().find(|l| l.split(' ').next() == Some(id)).unwrap_or_else(|| panic!("no line {id}"));
    line.split(' ').find_map(|f| f.strip_prefix(key).and_then(|r| r.strip_prefix('='))).unwrap_or_else(|| panic!("{id}: no {key}"))
}

#[test]
fn expected_txt_is_what_the_host_computes() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/board/expected.txt");
    let got = lines();
    if std::env::var_os("COOPWIN_BLESS").is_some() {
        std::fs::write(path, &got).unwrap();
    }
    let want = std::fs::read_to_string(path).unwrap_or_default();
    assert_eq!(got, want, "{path} is stale: rerun with COOPWIN_BLESS=1 (and scripts/board.sh)");
}

#[test]
fn the_blocks_line_is_the_zero_mean_ncc_formula_block_by_block() {
    // Reference: each 5x5 block of the 20x20 template against the 24x24 window's pixels
    // under it at (2, 2), zero-mean NCC summed in f64 here.
    let w = coopwin_parity::pgm::parse(suite::inputs::FOVEAL_WINDOW).unwrap();
    let t = coopwin_parity::pgm::parse(suite::inputs::FOVEAL_TEMPLATE).unwrap();
    let (mut matching, mut textured) = (0, 0);
    for b in 0..16 {
        let (bx, by) = (b % 4 * 5, b / 4 * 5);
        let px = |y: usize, x: usize| (f64::from(t.pixels[(by + y) * 20 + bx + x]), f64::from(w.pixels[(2 + by + y) * 24 + 2 + bx + x]));
        let pairs: Vec<(f64, f64)> = (0..25).map(|i| px(i / 5, i % 5)).collect();
        let (mt, mw) = (pairs.iter().map(|p| p.0).sum::<f64>() / 25.0, pairs.iter().map(|p| p.1).sum::<f64>() / 25.0);
        let cov: f64 = pairs.iter().map(|(a, b)| (a - mt) * (b - mw)).sum();
        let (vt, vw): (f64, f64) = (pairs.iter().map(|p| (p.0 - mt).powi(2)).sum(), pairs.iter().map(|p| (p.1 - mw).powi(2)).sum());
        if vt > 0.0 {
            textured += 1;
            matching += usize::from(vw > 0.0 && cov / (vt * vw).sqrt() >= 0.9);
        }
    }
    let t = lines();
    assert_eq!((field(&t, "foveal_blocks_20in24", "matching"), field(&t, "foveal_blocks_20in24", "textured")), (matching.to_string().as_str(), textured.to_string().as_str()));
}

#[test]
fn kernel_lines_agree_with_opencv() {
    let t = lines();
    // TM_CCORR_NORMED maxLoc (2,2), maxVal 0.99964.
    assert_eq!((field(&t, "foveal_ncc_20in24", "x"), field(&t, "foveal_ncc_20in24", "y")), ("2", "2"));
    let score = f64::from_bits(u64::from_str_radix(field(&t, "foveal_ncc_20in24", "score"), 16).unwrap());
    assert!((score - 0.99964).abs() < 5e-6, "{score}");
    // TM_SQDIFF minLoc (15,11); its minVal 2159 is float32 arithmetic, so the exact value
    // is summed here by brute force.
    assert_eq!((field(&t, "peripheral_ssd_16in40", "x"), field(&t, "peripheral_ssd_16in40", "y")), ("15", "11"));
    let ssd = f64::from_bits(u64::from_str_radix(field(&t, "peripheral_ssd_16in40", "score"), 16).unwrap());
    let w = coopwin_parity::pgm::parse(suite::inputs::PERIPHERAL_WINDOW).unwrap();
    let p = coopwin_parity::pgm::parse(suite::inputs::PERIPHERAL_TEMPLATE).unwrap();
    let brute: i64 = (0..16 * 16)
        .map(|i| (i64::from(p.pixels[i]) - i64::from(w.pixels[(11 + i / 16) * 40 + 15 + i % 16])).pow(2))
        .sum();
    assert_eq!(ssd, brute as f64);
    assert!((ssd - 2159.0).abs() <= 1.0, "{ssd}");
    // Decimated minLoc (8,6) at 25 %, i.e. (16,12) in full-resolution pixels.
    assert_eq!((field(&t, "peripheral_ssd_16in40_dec", "x"), field(&t, "peripheral_ssd_16in40_dec", "y")), ("16", "12"));
    // absdiff > 30: 224 pixels, boundingRect (117, 98, 24, 19).
    assert_eq!(field(&t, "watch_motion_256", "bbox"), "117,140,98,116");
    assert_eq!(field(&t, "watch_motion_256", "count"), "224");
    // Edge maps: 119 and 129 pixels above TH; 94 and 108 after labelling and opening.
    assert_eq!((field(&t, "corner_20", "edge"), field(&t, "corner_20", "clean")), ("119", "94"));
    assert_eq!((field(&t, "corner_24", "edge"), field(&t, "corner_24", "clean")), ("129", "108"));
    // The three number formats pick the same placement as the f64 kernel (x=2, y=2 of 5x5).
    for id in ["ncc_norm25_f64", "ncc_norm25_f32", "ncc_norm25_q15"] {
        assert_eq!(field(&t, id, "best"), "12", "{id}");
    }
    // The replay followed every recorded window.
    let count = Stream::parse(suite::inputs::WINDOWS).unwrap().count;
    assert_eq!(field(&t, "tracker_total", "frames"), count.to_string());
}

#[test]
fn a_damaged_stream_is_an_error_not_a_panic() {
    let mut w = suite::inputs::WINDOWS.to_vec();
    let last = w.len() - 1;
    assert_eq!(suite::tracker(&mut String::new(), &mut NoMeter, &Replay { windows: &w[..last], ..Replay::THESIS }), Err(suite::SuiteError::Stream(StreamError::Truncated)));
    // A different recorded window position: the replay notices it has left the recording.
    let header = 4 + 1 + 8 + 400 + 8 + 2;
    w[header + 8] ^= 1;
    assert_eq!(suite::tracker(&mut String::new(), &mut NoMeter, &Replay { windows: &w, ..Replay::THESIS }), Err(suite::SuiteError::Diverged(0)));
}

/// The lines of `text` whose first word is one of `ids`: what a processor's image prints of
/// `expected.txt` (`scripts/board.sh` selects them alike).
fn lines_of(text: &str, ids: &[&str]) -> String {
    text.lines().filter(|l| ids.contains(&l.split(' ').next().unwrap_or(""))).map(|l| format!("{l}\n")).collect()
}

/// The COOP partner image's lines: the corner kernels and the partner's corner each frame.
const PARTNER_IDS: [&str; 6] = ["corner_20", "corner_24", "corner_24_literal", "info", "tracker_cd", "adaptive_cd"];
/// The Peripheral image's lines: its kernels and its processor's scenarios.
const PERIPHERAL_IDS: [&str; 6] = [
    "peripheral_ssd_16in40",
    "peripheral_sad_16in40",
    "peripheral_ssd_16in40_dec",
    "peripheral_lockon",
    "peripheral_lost",
    "peripheral_sweep",
];
/// The COOP master image's lines: the pair's decisions each frame and their totals.
const MASTER_IDS: [&str; 4] = ["tracker", "tracker_total", "adaptive", "adaptive_total"];
/// The Watch image's lines: each strip's area and the merged whole frame's.
const WATCH_IDS: [&str; 2] = ["watch_strip", "watch_motion_256"];

#[test]
fn the_partner_alone_answers_as_in_the_pair() {
    // The partner's image replays the master's recorded windows without the master, cutting
    // its own window where the master's Follow puts it: its lines must be the pair's own.
    let mut alone = String::new();
    suite::run_partner(&mut alone, &mut NoMeter).unwrap();
    let want = lines_of(&lines(), &PARTNER_IDS);
    assert_eq!(alone, want);
    // Both replays, every frame: one line each.
    let frames = |b: &[u8]| usize::from(Stream::parse(b).unwrap().count);
    assert_eq!(alone.lines().filter(|l| l.contains("_cd ")).count(), frames(suite::inputs::WINDOWS) + frames(suite::inputs::WINDOWS_ADAPTIVE));
}

#[test]
fn the_ids_the_images_print_are_those_board_sh_selects() {
    // scripts/board.sh greps expected.txt for each image's lines by these first words.
    let script = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../scripts/board.sh")).unwrap();
    for ids in [&PARTNER_IDS[..], &PERIPHERAL_IDS, &WATCH_IDS, &MASTER_IDS] {
        assert!(script.contains(&format!(" '{}'", ids.join("|"))), "board.sh does not select {ids:?}");
    }
}

/// A 256x256 benchmark frame's pixels.
fn frame(bytes: &[u8]) -> Vec<u8> {
    let p = coopwin_parity::pgm::parse(bytes).unwrap();
    assert_eq!((p.width, p.height), (256, 256));
    p.pixels.to_vec()
}

/// Brute force: the best placement `(u, v)` of the 25 % template `t` (`n x n` samples) in the
/// 25 % window of `f` at `(x0, y0)`, `w x h` samples: least SSD, or highest zero-mean NCC in f64;
/// the first in raster order on a tie.
fn brute(f: &[u8], (x0, y0, w, h): (usize, usize, usize, usize), t: &[f64], n: usize, zncc: bool) -> (usize, usize) {
    let px = |u: usize, v: usize| f64::from(f[(y0 + 2 * v) * 256 + x0 + 2 * u]);
    let tm = t.iter().sum::<f64>() / t.len() as f64;
    let mut best = (f64::INFINITY, (0, 0));
    for v in 0..=h - n {
        for u in 0..=w - n {
            let score = if zncc {
                let wm = (0..n * n).map(|i| px(u + i % n, v + i / n)).sum::<f64>() / (n * n) as f64;
                let (mut p, mut et, mut ew) = (0.0, 0.0, 0.0);
                for (i, &ti) in t.iter().enumerate().take(n * n) {
                    let (a, b) = (ti - tm, px(u + i % n, v + i / n) - wm);
                    p += a * b;
                    et += a * a;
                    ew += b * b;
                }
                -p / (et * ew).sqrt()
            } else {
                (0..n * n).map(|i| (t[i] - px(u + i % n, v + i / n)).powi(2)).sum()
            };
            if score < best.0 {
                best = (score, (u, v));
            }
        }
    }
    best.1
}

#[test]
fn the_peripheral_alone_answers_as_in_the_suite_and_finds_the_object() {
    let mut alone = String::new();
    suite::run_peripheral(&mut alone, &mut NoMeter).unwrap();
    assert_eq!(alone, lines_of(&lines(), &PERIPHERAL_IDS));
    // Each location it hands over is the brute-force best placement of the decimated template
    // (the Watch's, 20x20 at the motion's centre) plus its anchor, within the parabola's
    // sub-pixel step (one full-resolution pixel), and on the object: inside the motion area
    // that OpenCV's absdiff > 30 gives (kernel_lines_agree_with_opencv: 117..=140, 98..=116).
    let (prev, next) = (frame(suite::inputs::WATCH_PREV), frame(suite::inputs::WATCH_NEXT));
    let view = |d| WindowView::packed(d, 256, 256).unwrap();
    let params = Params::default();
    let a = detect_motion(&view(&prev), &view(&next), params.motion_threshold).unwrap().unwrap();
    let centre = Point { x: (a.xmin + a.xmax) as f32 / 2.0, y: (a.ymin + a.ymax) as f32 / 2.0 };
    let tpl = Template::capture(&view(&next), centre, 20).unwrap();
    let t: Vec<f64> = (0..100).map(|i| f64::from(tpl.pixels()[(i / 10) * 40 + (i % 10) * 2])).collect();
    let mut found = Vec::new();
    for l in alone.lines().filter(|l| l.contains(" approx=")) {
        let f: Vec<&str> = l.split(' ').collect();
        let win: Vec<usize> = f[2].strip_prefix("win=").unwrap().split([',', 'x']).map(|v| v.parse().unwrap()).collect();
        let Some(xy) = f.last().unwrap().strip_prefix("approx=").unwrap().split_once(',') else { continue };
        let bits = |v: &str| f32::from_bits(u32::from_str_radix(v, 16).unwrap());
        let (ax, ay) = (bits(xy.0), bits(xy.1));
        let (x0, y0, w, h) = (win[0], win[1], win[2].div_ceil(2), win[3].div_ceil(2));
        let (u, v) = brute(&next, (x0, y0, w, h), &t, 10, f[0] == "peripheral_sweep");
        let at = Point { x: (x0 + 2 * u) as f32 + tpl.anchor().x, y: (y0 + 2 * v) as f32 + tpl.anchor().y };
        assert!((ax - at.x).abs() <= 1.0 && (ay - at.y).abs() <= 1.0, "{l}: brute force {at:?}");
        assert!((117.0..=140.0).contains(&ax) && (98.0..=116.0).contains(&ay), "{l}: off the object");
        found.push(f[0]);
    }
    // The lock-on and the sweep find it; the thesis's search far from it gives up after its
    // two sizes (40x40, 64x64: 20x20 and 32x32 samples), back to waiting for motion.
    assert_eq!(found, ["peripheral_lockon", "peripheral_sweep"]);
    let lost: Vec<&str> = alone.lines().filter(|l| l.starts_with("peripheral_lost ")).collect();
    assert_eq!(lost.len(), 2, "{lost:?}");
    assert!(lost[0].contains(",40x40 ") && lost[1].contains(",64x64 "), "{lost:?}");
    // The sweep reaches its 128x128 tiles (64x64 samples, the largest window it matches).
    assert!(alone.lines().any(|l| l.starts_with("peripheral_sweep ") && l.contains(",128x128 ")));
}

#[test]
fn the_watch_strips_merge_into_the_whole_frames_motion() {
    let mut alone = String::new();
    suite::run_watch(&mut alone, &mut NoMeter).unwrap();
    // Its lines are the suite's, and its merged line the whole frame's (one Watch, as today).
    assert_eq!(alone, lines_of(&lines(), &WATCH_IDS));
    assert_eq!(alone.lines().filter(|l| l.starts_with("watch_strip ")).count(), usize::from(suite::WATCH_STRIPS));
    // Any number of strips gives the whole frame's area on the benchmark pair, and at the
    // Watch processor's own threshold too (the reference: detect_motion over the whole frame).
    let (prev, next) = (frame(suite::inputs::WATCH_PREV), frame(suite::inputs::WATCH_NEXT));
    let (p, q) = (WindowView::packed(&prev, 256, 256).unwrap(), WindowView::packed(&next, 256, 256).unwrap());
    let region = WindowRequest { x0: 0, y0: 0, width: 256, height: 256, decimation: Decimation::Full };
    for threshold in [Params::default().motion_threshold, 30] {
        let whole = detect_motion(&p, &q, threshold).unwrap();
        assert!(whole.is_some());
        for n in 1..=20 {
            let merged = (0..n).fold(None, |m, k| {
                let s = watch::strip(region, k, n).unwrap();
                let (y, h) = (usize::from(s.y0), usize::from(s.height));
                let (a, b) = (p.sub(0, y, 256, h).unwrap(), q.sub(0, y, 256, h).unwrap());
                watch::merge(m, detect_motion(&a, &b, threshold).unwrap())
            });
            assert_eq!(merged, whole, "{n} strips at threshold {threshold}");
        }
    }
}

#[test]
fn the_master_alone_decides_as_in_the_pair() {
    // The master's image replays the recorded windows without its partner, taking the
    // partner's corners from the partner's own lines: its decisions must be the pair's.
    let mut alone = String::new();
    suite::run_master(&mut alone, &mut NoMeter).unwrap();
    assert_eq!(alone, lines_of(&lines(), &MASTER_IDS));
    let frames = |b: &[u8]| usize::from(Stream::parse(b).unwrap().count);
    let n = frames(suite::inputs::WINDOWS) + frames(suite::inputs::WINDOWS_ADAPTIVE);
    assert_eq!(alone.lines().filter(|l| l.contains(" win=")).count(), n);
    // The partner's results decide: without them (every corner `none`) the master never picks
    // the corner, which the pair does.
    assert!(alone.lines().any(|l| l.starts_with("tracker ") && l.ends_with("algo=Cd")));
    let blind: String = suite::PARTNER_RESULTS
        .lines()
        .map(|l| match l.strip_prefix("tracker_cd ") {
            Some(r) => format!("tracker_cd {} none\n", r.split(' ').take(2).collect::<Vec<_>>().join(" ")),
            None => format!("{l}\n"),
        })
        .collect();
    let mut without = String::new();
    let r = suite::master(&mut without, &mut NoMeter, &Replay::THESIS, &blind);
    assert!(!without.lines().any(|l| l.ends_with("algo=Cd")), "{without}");
    // It no longer follows the recorded run: its window leaves the recording.
    assert!(matches!(r, Err(suite::SuiteError::Diverged(_))), "{r:?}");
    // A missing result is an error, not a guess.
    let cut: String = suite::PARTNER_RESULTS.lines().filter(|l| !l.starts_with("tracker_cd 5 ")).map(|l| format!("{l}\n")).collect();
    assert!(suite::master(&mut String::new(), &mut NoMeter, &Replay::THESIS, &cut).is_err());
}
