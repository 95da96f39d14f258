//! The host's side of the Cortex-M4 parity check (thesis 2.6: the same tracking code on the
//! processors as in the simulation): the suite's lines computed here must equal
//! `fixtures/board/expected.txt`, which `scripts/board.sh` diffs against the QEMU run.
//! `COOPWIN_BLESS=1` rewrites the file instead. The kernel lines are also checked against
//! OpenCV's answers on the same inputs (`fixtures/bench/README.md`).
use coopwin_parity::suite::{self, NoMeter, Replay};
use coopwin_parity::stream::{Stream, StreamError};

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

/// The lines of `expected.txt` the COOP partner's image prints (`scripts/board.sh` compares
/// them alike): the corner kernels and the partner's corner in each replayed frame.
fn partner_lines(text: &str) -> String {
    let ids = ["corner_20", "corner_24", "corner_24_literal", "info", "tracker_cd", "adaptive_cd"];
    text.lines().filter(|l| ids.contains(&l.split(' ').next().unwrap_or(""))).map(|l| format!("{l}\n")).collect()
}

#[test]
fn the_partner_alone_answers_as_in_the_pair() {
    // The partner's image replays the master's recorded windows without the master, cutting
    // its own window where the master's Follow puts it: its lines must be the pair's own.
    let mut alone = String::new();
    suite::run_partner(&mut alone, &mut NoMeter).unwrap();
    let want = partner_lines(&lines());
    assert_eq!(alone, want);
    // Both replays, every frame: one line each.
    let frames = |b: &[u8]| usize::from(Stream::parse(b).unwrap().count);
    assert_eq!(alone.lines().filter(|l| l.contains("_cd ")).count(), frames(suite::inputs::WINDOWS) + frames(suite::inputs::WINDOWS_ADAPTIVE));
}
