//! Checks every kernel against the OpenCV reference fixtures in `fixtures/opencv/*.json`
//! (format in that folder's README). Fails if the folder holds no fixture, so it can
//! never pass vacuously.
#[path = "support/pgm.rs"]
mod pgm;

use coopwin_firmware::kernels::corner::{keep_largest_component, open_cross, sobel_at};
use coopwin_firmware::kernels::matching::{best_match, score_map, MatchError, Method};
use coopwin_firmware::kernels::motion::{detect_motion, motion_mask};
use coopwin_firmware::kernels::view::WindowView;
use serde_json::Value;
use std::path::PathBuf;

struct Img {
    w: usize,
    h: usize,
    data: Vec<u8>,
}

fn img(v: &Value) -> Img {
    let w = v["width"].as_u64().unwrap() as usize;
    let h = v["height"].as_u64().unwrap() as usize;
    let data: Vec<u8> = v["data"].as_array().unwrap().iter().map(|x| x.as_u64().unwrap() as u8).collect();
    assert_eq!(data.len(), w * h);
    Img { w, h, data }
}

fn nums(v: &Value) -> Vec<f64> {
    v["data"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect()
}

impl Img {
    fn view(&self) -> WindowView<'_> {
        WindowView::packed(&self.data, self.w, self.h).unwrap()
    }
}

fn check_match(name: &str, case: &Value, method: Method) {
    let (im, tp) = (img(&case["image"]), img(&case["template"]));
    let res = &case["result"];
    let (rw, rh) = (res["width"].as_u64().unwrap() as usize, res["height"].as_u64().unwrap() as usize);
    let want = nums(res);
    let mut got = vec![0f64; rw * rh];
    match score_map(method, &im.view(), &tp.view(), &mut got) {
        Ok(dims) => assert_eq!(dims, (rw, rh), "{name}"),
        // Zero-energy NCC template: a typed "no match" where OpenCV writes zeros.
        Err(MatchError::ZeroEnergy) => {
            assert!(method == Method::Ncc && want.iter().all(|&v| v == 0.0), "{name}");
            return;
        }
        Err(e) => panic!("{name}: {e:?}"),
    }
    let max = want.iter().fold(0f64, |m, v| m.max(v.abs()));
    for (i, (g, w)) in got.iter().zip(&want).enumerate() {
        // OpenCV works in float32 (README gotcha 1): SSD within max(4, 1e-5·max),
        // NCC within 1e-5 absolute.
        let tol = if method == Method::Ssd { (1e-5 * max).max(4.0) } else { 1e-5 };
        assert!((g - w).abs() <= tol, "{name}: placement {i}: ours {g} opencv {w}");
    }
    let best = &res["best"];
    let (bx, by) = (best["x"].as_u64().unwrap() as usize, best["y"].as_u64().unwrap() as usize);
    match best_match(method, &im.view(), &tp.view()) {
        Ok(m) => assert_eq!((m.x, m.y), (bx, by), "{name}: best placement"),
        // A zero template or all-zero patches: OpenCV reports 0 at (0,0), we say "no match".
        Err(e) => {
            assert_eq!(method, Method::Ncc, "{name}: {e:?}");
            assert!(want.iter().all(|&v| v == 0.0), "{name}: {e:?} but OpenCV has a non-zero map");
        }
    }
}

fn check_sobel(name: &str, case: &Value) {
    let im = img(&case["image"]);
    let (gx, gy) = (nums(&case["result"]["gx"]), nums(&case["result"]["gy"]));
    let v = im.view();
    // Interior and border alike: both use BORDER_REFLECT_101.
    for y in 0..im.h {
        for x in 0..im.w {
            let (a, b) = sobel_at(&v, x, y).unwrap();
            let i = y * im.w + x;
            assert_eq!((a as f64, b as f64), (gx[i], gy[i]), "{name}: ({x},{y})");
        }
    }
}

fn check_components(name: &str, case: &Value) {
    let mut im = img(&case["image"]);
    let res = &case["result"];
    let n = (im.w + 2) * (im.h + 2);
    let (mut labels, mut stack) = (vec![0u16; n], vec![0u16; n]);
    let c = keep_largest_component(&mut im.data, im.w, im.h, &mut labels, &mut stack).unwrap();
    assert_eq!(u64::from(c.num_labels), res["num_labels"].as_u64().unwrap(), "{name}");
    assert_eq!(u64::from(c.largest_area), res["largest_area"].as_u64().unwrap(), "{name}");
    assert_eq!(im.data, img(&res["largest_mask"]).data, "{name}: mask");
}

fn check_open(name: &str, case: &Value) {
    let mut im = img(&case["image"]);
    let mut tmp = vec![0u8; im.w * im.h];
    open_cross(&mut im.data, im.w, im.h, &mut tmp).unwrap();
    assert_eq!(im.data, img(&case["result"]["mask"]).data, "{name}");
}

fn check_absdiff(name: &str, case: &Value) {
    let (a, b) = (img(&case["image"]), img(&case["image2"]));
    let t = case["params"]["threshold"].as_u64().unwrap() as u8;
    let res = &case["result"];
    let area = detect_motion(&a.view(), &b.view(), t).unwrap();
    let mut mask = vec![0u8; a.w * a.h];
    let count = motion_mask(&a.view(), &b.view(), t, &mut mask).unwrap();
    assert_eq!(mask, img(&res["mask"]).data, "{name}: mask");
    assert_eq!(u64::from(count), res["count"].as_u64().unwrap(), "{name}: count");
    match (&res["bbox"], area) {
        (Value::Null, None) => {}
        (Value::Array(bb), Some(m)) => {
            let bb: Vec<u64> = bb.iter().map(|v| v.as_u64().unwrap()).collect();
            assert_eq!(vec![m.xmin as u64, m.xmax as u64, m.ymin as u64, m.ymax as u64], bb, "{name}");
            assert_eq!(u64::from(m.count), res["count"].as_u64().unwrap(), "{name}");
        }
        (want, got) => panic!("{name}: bbox {want} vs {got:?}"),
    }
}

#[test]
fn every_opencv_fixture_matches() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/opencv");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no fixture in {}", dir.display());
    let mut kinds = std::collections::BTreeMap::<String, usize>::new();
    for f in &files {
        let case: Value = serde_json::from_slice(&std::fs::read(f).unwrap()).unwrap();
        let kind = case["kind"].as_str().unwrap().to_owned();
        let name = case["name"].as_str().unwrap_or("?").to_owned();
        match kind.as_str() {
            "match_sqdiff" => check_match(&name, &case, Method::Ssd),
            "match_ccorr_normed" => check_match(&name, &case, Method::Ncc),
            "sobel" => check_sobel(&name, &case),
            "components" => check_components(&name, &case),
            "open_cross" => check_open(&name, &case),
            "absdiff_threshold" => check_absdiff(&name, &case),
            other => panic!("{}: unknown kind {other}", f.display()),
        }
        *kinds.entry(kind).or_default() += 1;
    }
    eprintln!("checked {} OpenCV fixtures: {kinds:?}", files.len());
}

/// The benchmark inputs, read by the benchmark's own PGM reader.
fn read_pgm(name: &str) -> Img {
    let (w, h, data) = pgm::read_pgm(name);
    Img { w, h, data }
}

/// The benchmark inputs give the answers OpenCV gives (fixtures/bench/README.md), so the
/// benchmarks time the same work.
#[test]
fn bench_inputs_agree_with_opencv() {
    use coopwin_firmware::kernels::corner::{CornerDetector, CornerParams};
    use coopwin_firmware::kernels::matching::best_match_decimated;
    let (fw, ft) = (read_pgm("foveal_window.pgm"), read_pgm("foveal_template.pgm"));
    let m = best_match(Method::Ncc, &fw.view(), &ft.view()).unwrap();
    assert_eq!((m.x, m.y), (2, 2));
    assert!((m.score - 0.99964).abs() < 1e-5);
    let (pw, pt) = (read_pgm("peripheral_window.pgm"), read_pgm("peripheral_template.pgm"));
    let m = best_match(Method::Ssd, &pw.view(), &pt.view()).unwrap();
    // OpenCV's float32 minVal is 2159; the exact integer SSD (checked with numpy int64) is
    // 2158.
    assert_eq!((m.x, m.y, m.score), (15, 11, 2158.0));
    let m = best_match_decimated(Method::Ssd, &pw.view(), &pt.view()).unwrap();
    assert_eq!((m.x, m.y), (16, 12)); // decimated (8, 6)
    let (a, b) = (read_pgm("watch_prev.pgm"), read_pgm("watch_next.pgm"));
    let area = detect_motion(&a.view(), &b.view(), 30).unwrap().unwrap();
    assert_eq!((area.xmin, area.xmax, area.ymin, area.ymax, area.count), (117, 140, 98, 116, 224));
    let mut det = Box::new(CornerDetector::new());
    // Edge pixels, pixels left after labelling + opening (OpenCV's numbers), and the
    // rendered apex.
    for (file, edges, clean, apex) in [("corner_20.pgm", 119, 94, (8.3, 9.1)), ("corner_24.pgm", 129, 108, (10.6, 11.4))] {
        let im = read_pgm(file);
        let c = det.detect(&im.view(), &CornerParams::new(50)).unwrap();
        assert_eq!((c.edge_pixels, c.clean_pixels), (edges, clean), "{file}: {c:?}");
        let err = (c.x - apex.0).hypot(c.y - apex.1);
        assert!(err <= 1.0, "{file}: {c:?} error {err}");
    }
}
