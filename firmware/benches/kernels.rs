//! Criterion benchmarks of the kernels at the thesis' sizes, on the inputs in
//! `fixtures/bench/` (see its README): Foveal NCC 20x20 in 24x24, Peripheral SSD 16x16 in
//! 40x40 at 100 % and 25 %, Watch motion on 256x256, an adapting Peripheral's sweep tile
//! (zero-mean NCC of a 20x20 template in a 128x128 tile at 25 %, every placement and by
//! candidates), the corner detector on 20x20 and 24x24, and the COOP decision.
//!
//! On x86-64 the kernels take the widest path the host runs (AVX-512, AVX2, portable);
//! `COOPWIN_ISA=avx2` (or `portable`) makes them take no wider one, so a narrower host's path
//! can be measured here: `COOPWIN_ISA=avx2 cargo bench -p coopwin-firmware --bench kernels`.
use coopwin_firmware::kernels::confidence::{ConfidencePolicy, SseCoop};
use coopwin_firmware::types::Source;
use coopwin_firmware::kernels::corner::{CornerDetector, CornerParams};
use coopwin_firmware::kernels::matching::{best_match, best_match_candidates, best_match_decimated, Method};
use coopwin_firmware::kernels::motion::detect_motion;
use coopwin_firmware::kernels::view::WindowView;
use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;

#[path = "../tests/support/pgm.rs"]
mod pgm;
use pgm::read_pgm;

/// The path `COOPWIN_ISA` names, if any, as the widest the kernels take.
#[cfg(target_arch = "x86_64")]
fn isa_from_env() {
    use coopwin_firmware::kernels::x86::{detected, path, use_at_most, Isa};
    let Ok(name) = std::env::var("COOPWIN_ISA") else { return };
    match name.as_str() {
        "portable" => use_at_most(Isa::Portable),
        "avx2" => use_at_most(Isa::Avx2),
        "avx512" => use_at_most(Isa::Avx512),
        other => panic!("COOPWIN_ISA={other}: expected portable, avx2 or avx512"),
    }
    eprintln!("kernels' path: {:?} (COOPWIN_ISA={name}; the host runs {:?})", path(), detected());
}

fn kernels(c: &mut Criterion) {
    #[cfg(target_arch = "x86_64")]
    isa_from_env();
    let (ww, wh, fw) = read_pgm("foveal_window.pgm");
    let (tw, th, ft) = read_pgm("foveal_template.pgm");
    let win = WindowView::packed(&fw, ww, wh).unwrap();
    let tpl = WindowView::packed(&ft, tw, th).unwrap();
    c.bench_function("foveal_ncc_20in24", |b| {
        b.iter(|| best_match(Method::Ncc, black_box(&win), black_box(&tpl)))
    });

    let (ww, wh, pw) = read_pgm("peripheral_window.pgm");
    let (tw, th, pt) = read_pgm("peripheral_template.pgm");
    let win = WindowView::packed(&pw, ww, wh).unwrap();
    let tpl = WindowView::packed(&pt, tw, th).unwrap();
    c.bench_function("peripheral_ssd_16in40", |b| {
        b.iter(|| best_match(Method::Ssd, black_box(&win), black_box(&tpl)))
    });
    c.bench_function("peripheral_ssd_16in40_dec", |b| {
        b.iter(|| best_match_decimated(Method::Ssd, black_box(&win), black_box(&tpl)))
    });

    let (w, h, prev) = read_pgm("watch_prev.pgm");
    let (_, _, next) = read_pgm("watch_next.pgm");
    let p = WindowView::packed(&prev, w, h).unwrap();
    let n = WindowView::packed(&next, w, h).unwrap();
    c.bench_function("watch_motion_256", |b| {
        b.iter(|| detect_motion(black_box(&p), black_box(&n), black_box(30)))
    });

    // The tile of the board suite's sweep that holds the moving object, its template cut on it.
    let tile = n.sub(108, 0, 128, 128).unwrap().decimated();
    let object = n.sub(118, 97, 20, 20).unwrap().decimated();
    c.bench_function("peripheral_zncc_tile_full", |b| {
        b.iter(|| best_match(Method::Zncc, black_box(&tile), black_box(&object)))
    });
    c.bench_function("peripheral_zncc_tile_candidates", |b| {
        b.iter(|| best_match_candidates(black_box(&tile), black_box(&object)))
    });

    let mut det = Box::new(CornerDetector::new());
    for (id, file) in [("corner_20", "corner_20.pgm"), ("corner_24", "corner_24.pgm")] {
        let (w, h, d) = read_pgm(file);
        let v = WindowView::packed(&d, w, h).unwrap();
        let params = CornerParams::new(50);
        c.bench_function(id, |b| b.iter(|| det.detect(black_box(&v), black_box(&params))));
    }

    // One COOP step: both Foveal results of a frame go in, the decision comes out.
    let mut coop = SseCoop::new(4).unwrap();
    let mut t = 0.0f64;
    c.bench_function("coop_decision", |b| {
        b.iter(|| {
            t += 0.0088;
            let _ = coop.push(Source::Ncc, t, black_box(100.0 + t), black_box(50.0));
            let _ = coop.push(Source::Cd, t, black_box(100.5 + t), black_box(50.2));
            coop.choose()
        })
    });
}

criterion_group!(benches, kernels);
criterion_main!(benches);
