use super::bounds::bounding_points_bits;
use super::labelling::{largest_component_bits, Runs};
use super::morphology::open_cross_bits;
use super::sobel::reflect;
use super::*;

/// Parses a picture of `#` (edge) and `.` into a binary map.
fn map(rows: &[&str]) -> ([u8; 64], usize, usize) {
    let mut m = [0u8; 64];
    let w = rows[0].len();
    for (y, r) in rows.iter().enumerate() {
        for (x, c) in r.bytes().enumerate() {
            m[y * w + x] = u8::from(c == b'#');
        }
    }
    (m, w, rows.len())
}

const LIT: CornerParams = CornerParams { threshold: 0, distinct_tol: 0, refine: false };

#[test]
fn reflect_101() {
    assert_eq!([reflect(-1, 5), reflect(5, 5), reflect(2, 5)], [1, 3, 2]);
    assert_eq!([reflect(-1, 1), reflect(1, 1)], [0, 0]);
}

#[test]
fn sobel_hand_values() {
    // Step edge 0 | 100 between columns 1 and 2 of a 4x3 window.
    let d = [0, 0, 100, 100, 0, 0, 100, 100, 0, 0, 100, 100];
    let v = WindowView::packed(&d, 4, 3).unwrap();
    // gx at (1,1) = (100-0)*(1+2+1) = 400; gy = 0.
    assert_eq!(sobel_at(&v, 1, 1), Some((400, 0)));
    // Column 0 reflects column 1 onto -1: gx = 4*(0-0) = 0.
    assert_eq!(sobel_at(&v, 0, 0), Some((0, 0)));
    // Column 3: neighbour 4 reflects to 2: gx = 4*(100-100) = 0.
    assert_eq!(sobel_at(&v, 3, 2), Some((0, 0)));
    assert_eq!(sobel_at(&v, 4, 0), None);
    // The fast edge map agrees with sobel_at + threshold (400² > 399², not > 400²).
    let mut det = CornerDetector::new();
    det.w = 4;
    det.h = 3;
    assert_eq!(det.threshold_edges(&v, 400), 0);
    assert_eq!(det.threshold_edges(&v, 399), 6);
    assert_eq!(&det.bits[..3], &[0b0110, 0b0110, 0b0110]);
}

/// A xorshift64 generator for the random-map tests.
fn xorshift(mut seed: u64) -> impl FnMut() -> u64 {
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        seed
    }
}

/// The bit-row pipeline of `detect` (run labelling, opening, bounding points) gives
/// exactly the byte-map functions' results on random maps of every density.
#[test]
fn bit_pipeline_matches_byte_functions() {
    let mut rnd = xorshift(0x1234_5678_9abc_def0);
    let mut runs = Runs::<MAX_DIM>::new();
    for case in 0..3000 {
        let w = 1 + (rnd() % 64) as usize;
        let h = 1 + (rnd() % 64) as usize;
        let density = rnd() % 100;
        let mut m = std::vec![0u8; w * h];
        for v in m.iter_mut() {
            *v = u8::from(rnd() % 100 < density);
        }
        let mut bits = [0u64; MAX_DIM];
        for (y, b) in bits.iter_mut().take(h).enumerate() {
            for x in 0..w {
                *b |= u64::from(m[y * w + x]) << x;
            }
        }
        let pn = (w + 2) * (h + 2);
        let (mut l, mut st) = (std::vec![0u16; pn], std::vec![0u16; pn]);
        let c = keep_largest_component(&mut m, w, h, &mut l, &mut st).unwrap();
        let area = largest_component_bits(&mut bits[..h], &mut runs);
        assert_eq!(area, c.largest_area, "case {case}");
        let mut tmp = std::vec![0u8; w * h];
        let n = open_cross(&mut m, w, h, &mut tmp).unwrap();
        let mut t = [0u64; MAX_DIM];
        assert_eq!(open_cross_bits(&mut bits[..h], w, &mut t), n, "case {case}");
        for y in 0..h {
            for x in 0..w {
                assert_eq!(u8::from(bits[y] >> x & 1 != 0), m[y * w + x], "case {case} ({x},{y})");
            }
        }
        assert_eq!(bounding_points_bits(&bits[..h]), bounding_points(&m, w, h), "case {case}");
    }
}

/// The fixed-width Sobel rows agree with `sobel_at` + threshold on random windows,
/// including strided (decimated) views and a detector reused across sizes.
#[test]
fn sobel_rows_match_sobel_at() {
    let mut rnd = xorshift(0x0ddb_a11c_afe5_eed5);
    let mut det = CornerDetector::new();
    for case in 0..600 {
        let (w, h) = (1 + (rnd() % 64) as usize, 1 + (rnd() % 64) as usize);
        let step = if case % 3 == 0 { 2 } else { 1 };
        let (fw, fh) = (w * step, h * step);
        let d: std::vec::Vec<u8> = (0..fw * fh).map(|_| rnd() as u8).collect();
        let mut v = WindowView::packed(&d, fw, fh).unwrap();
        if step == 2 {
            v = v.decimated();
        }
        let th = (rnd() % 1200) as u16;
        let n = det.threshold_edges(&v, th);
        let mut expect = 0;
        for y in 0..h {
            for x in 0..w {
                let (gx, gy) = sobel_at(&v, x, y).unwrap();
                let e = i64::from(gx * gx + gy * gy) > i64::from(th) * i64::from(th);
                expect += u32::from(e);
                assert_eq!(det.bits[y] >> x & 1 != 0, e, "case {case} ({x},{y})");
            }
            assert_eq!(det.bits[y] >> w.min(63) >> u32::from(w == 64), 0);
        }
        assert_eq!(n, expect);
    }
}

#[test]
fn largest_component_8_connected() {
    let (mut m, w, h) = map(&["#..##", ".#..#", "....#", "##..."]);
    let (mut l, mut s) = ([0u16; 64], [0u16; 64]); // (5+2)·(4+2) = 42 entries
    let c = keep_largest_component(&mut m, w, h, &mut l, &mut s).unwrap();
    // Components: {(0,0),(1,1)} (diagonal), {(3,0),(4,0),(4,1),(4,2)}, {(0,3),(1,3)}.
    assert_eq!(
        c,
        Components {
            num_labels: 4,
            largest_area: 4
        }
    );
    assert_eq!(map(&["...##", "....#", "....#", "....."]).0, m);
}

#[test]
fn opening_keeps_border_touching_plus() {
    // A 3-wide bar along the left border survives (outside counts as set for the
    // erosion); an isolated 2x2 block vanishes.
    let (mut m, w, h) = map(&["###...", "###.##", "###.##", "###..."]);
    let mut t = [0u8; 64];
    let n = open_cross(&mut m, w, h, &mut t).unwrap();
    assert_eq!(map(&["###...", "###...", "###...", "###..."]).0, m);
    assert_eq!(n, 12);
}

#[test]
fn q3_is_bar_p00_diamond_tip() {
    // Tip at (3,0); edges down-left and down-right to the border.
    let (m, w, h) = map(&["...#...", "..#.#..", ".#...#.", "#.....#"]);
    let b = bounding_points(&m, w, h).unwrap();
    assert_eq!((b.p00, b.p10, b.bar_p00), ((0, 3), (6, 3), (3, 0)));
    // M12 = (3,3): no edge around (3,2..4) -> corner Q3.
    assert_eq!(
        corner_from_edges(&m, w, h, &LIT),
        Ok((3.0, 0.0, CornerCase::Q3(Q3Source::BarP00)))
    );
}

#[test]
fn q1_corner_of_an_l() {
    // Corner at (0,0) of an L: Q1 = (0,0), Q2 = (4,0), Q3 = P̄10 = (0,3).
    let (m, w, h) = map(&["#####", "#....", "#....", "#...."]);
    assert_eq!(
        corner_from_edges(&m, w, h, &LIT),
        Ok((0.0, 0.0, CornerCase::Q1(Q3Source::BarP10)))
    );
}

#[test]
fn q2_tip_pointing_right() {
    // ">" with the tip at (4,4): Q1 = (0,0), Q2 = (4,4), Q3 = P̄10 = (0,8);
    // M12 = (2,2) is on the upper edge, M13 = (0,4) has no edge within 3x3.
    let (m, w, h) = map(&[
        "#......", ".#.....", "..#....", "...#...", "....#..", "...#...", "..#....", ".#.....",
        "#......",
    ]);
    let mut big = [0u8; 64];
    big[..w * h].copy_from_slice(&m[..w * h]);
    let r = corner_from_edges(&big, w, h, &LIT);
    assert_eq!(r, Ok((4.0, 4.0, CornerCase::Q2(Q3Source::BarP10))));
}

#[test]
fn gss_on_thin_v() {
    // Q3 undefined: edges from (0,0) to the corner (6,2) and on to (9,9); every
    // bounding point is Q1 = (0,0) or Q2 = (9,9).
    let mut m = [0u8; 100];
    let pts = [
        (0, 0),
        (1, 1),
        (2, 1),
        (3, 1),
        (4, 2),
        (5, 2),
        (6, 2),
        (7, 3),
        (7, 4),
        (7, 5),
        (8, 6),
        (8, 7),
        (8, 8),
        (9, 9),
    ];
    for (x, y) in pts {
        m[y * 10 + x] = 1;
    }
    let r = corner_from_edges(&m, 10, 10, &LIT).unwrap();
    assert_eq!(r.2, CornerCase::Gss);
    // Farthest pixels from y = x: (6,2) and (7,3), both at 4/√2 ≈ 2.83 px.
    assert!(
        (r.0 - 6.0).abs() <= 1.0 && (r.1 - 2.0).abs() <= 1.0,
        "{r:?}"
    );
}

/// Like `map` for larger pictures.
fn big(rows: &[&str]) -> (std::vec::Vec<u8>, usize, usize) {
    let w = rows[0].len();
    let m = rows.iter().flat_map(|r| r.bytes().map(|c| u8::from(c == b'#'))).collect();
    (m, w, rows.len())
}

#[test]
fn remaining_q3_cases() {
    // P̄01: a run along the top row, then a diagonal to the bottom-right.
    let top_run = [
        "#######......", ".......#.....", "........#....", ".........#...", "..........#..", "...........#.", "............#",
    ];
    let (m, w, h) = big(&top_run);
    assert_eq!(corner_from_edges(&m, w, h, &LIT), Ok((6.0, 0.0, CornerCase::Q3(Q3Source::BarP01))));
    // P̄11: the same upside down.
    let rev: std::vec::Vec<&str> = top_run.iter().rev().copied().collect();
    let (m, w, h) = big(&rev);
    assert_eq!(corner_from_edges(&m, w, h, &LIT), Ok((6.0, 6.0, CornerCase::Q3(Q3Source::BarP11))));
    // P01: a run down the left column, then a diagonal to the bottom-right.
    let rows: std::vec::Vec<std::string::String> = (0..13)
        .map(|y| (0..7).map(|x| if (x == 0 && y <= 6) || (y > 6 && x == y - 6) { '#' } else { '.' }).collect())
        .collect();
    let refs: std::vec::Vec<&str> = rows.iter().map(|r| r.as_str()).collect();
    let (m, w, h) = big(&refs);
    assert_eq!(corner_from_edges(&m, w, h, &LIT), Ok((0.0, 6.0, CornerCase::Q3(Q3Source::P01))));
    // P11: a diagonal from the bottom-left up to (6,6), then up the right column.
    let rows: std::vec::Vec<std::string::String> = (0..13)
        .map(|y| (0..7).map(|x| if (x == 6 && y <= 6) || (y > 6 && x == 12 - y) { '#' } else { '.' }).collect())
        .collect();
    let refs: std::vec::Vec<&str> = rows.iter().map(|r| r.as_str()).collect();
    let (m, w, h) = big(&refs);
    assert_eq!(corner_from_edges(&m, w, h, &LIT), Ok((6.0, 6.0, CornerCase::Q3(Q3Source::P11))));
}

#[test]
fn lines_are_typed() {
    let (m, w, h) = map(&["..#..", "..#..", "..#.."]);
    assert_eq!(
        corner_from_edges(&m, w, h, &LIT),
        Err(NoCorner::VerticalLine)
    );
    let (m, w, h) = map(&[".....", "#####", "....."]);
    assert_eq!(
        corner_from_edges(&m, w, h, &LIT),
        Err(NoCorner::HorizontalLine)
    );
    let (m, w, h) = map(&["#....", ".#...", "..#..", "...#."]);
    assert_eq!(
        corner_from_edges(&m, w, h, &LIT),
        Err(NoCorner::StraightLine)
    );
    assert_eq!(
        corner_from_edges(&[0; 4], 2, 2, &LIT),
        Err(NoCorner::NoEdges)
    );
}

#[test]
fn detector_is_sized_by_its_window() {
    // The module documentation's figures: 28 bytes a pixel of the N x N window (edges 1,
    // widened window 2, runs 4, edge points 20 and their flags 1) and a 64-bit row each;
    // on x86-64, the vector pass's 32-pixel rows of gradients and magnitudes (8 bytes a pixel)
    // and peak bits too.
    let host = |n: usize| if cfg!(target_arch = "x86_64") { (8 * 32 + 8) * n } else { 0 };
    for (size, n) in [
        (core::mem::size_of::<CornerDetector<24>>(), 24),
        (core::mem::size_of::<CornerDetector<40>>(), 40),
        (core::mem::size_of::<CornerDetector>(), 64),
    ] {
        let least = 28 * n * n + 8 * n + host(n);
        assert!((least..least + 64).contains(&size), "{n}: {size}");
    }
}

/// Detectors of sides 24 and 40 find exactly what the 64 detector finds on every window they
/// hold (the same code on smaller buffers, whose capacities no window reaches), and refuse a
/// larger one: random wedges of either polarity with noise, both modes.
#[test]
fn smaller_detectors_agree_with_the_largest() {
    let mut rnd = xorshift(0x5eed_c0de_1234_5678);
    let (mut d24, mut d40, mut d64) = (CornerDetector::<24>::sized(), CornerDetector::<40>::sized(), CornerDetector::new());
    let mut found = 0;
    for case in 0..400 {
        let (w, h) = (4 + (rnd() % 37) as usize, 4 + (rnd() % 37) as usize);
        let (ax, ay) = ((rnd() % w as u64) as f32, (rnd() % h as u64) as f32);
        let (a, b) = ((rnd() % 628) as f32 / 100.0, 0.6 + (rnd() % 200) as f32 / 100.0);
        let (lo, hi) = if case % 2 == 0 { (40, 200) } else { (200, 40) };
        let d: std::vec::Vec<u8> = (0..w * h)
            .map(|i| {
                let (x, y) = ((i % w) as f32 - ax, (i / w) as f32 - ay);
                let t = libm::atan2f(y, x) - a;
                let t = t - libm::floorf(t / core::f32::consts::TAU) * core::f32::consts::TAU;
                (if t < b { hi } else { lo }) as u8 ^ (rnd() % 8) as u8
            })
            .collect();
        let v = WindowView::packed(&d, w, h).unwrap();
        let params = if case % 3 == 0 { CornerParams::new(50) } else { CornerParams::literal(50) };
        let want = d64.detect(&v, &params);
        found += u32::from(want.is_ok());
        for (got, rows, n) in [(d24.detect(&v, &params), d24.clean_rows(), 24), (d40.detect(&v, &params), d40.clean_rows(), 40)] {
            if w <= n && h <= n {
                assert_eq!(got, want, "case {case}: {w}x{h} on {n}");
                assert_eq!(rows, d64.clean_rows(), "case {case}");
            } else {
                assert_eq!(got, Err(NoCorner::TooLarge), "case {case}: {w}x{h} on {n}");
            }
        }
    }
    assert!(found > 100, "{found}");
}

#[test]
fn detector_rejects_large_and_flat() {
    let big = [0u8; 65 * 2];
    let mut d = CornerDetector::new();
    let v = WindowView::packed(&big, 65, 2).unwrap();
    assert_eq!(
        d.detect(&v, &CornerParams::new(50)),
        Err(NoCorner::TooLarge)
    );
    let flat = [9u8; 20 * 20];
    let v = WindowView::packed(&flat, 20, 20).unwrap();
    assert_eq!(d.detect(&v, &CornerParams::new(50)), Err(NoCorner::NoEdges));
    assert_eq!(d.edge_pixels(), 0);
}

/// Every x86 vector pass the host runs (x86/: AVX-512, AVX2) gives the portable one's edge map
/// and count, and its peaks give exactly `collect_points`' sub-pixel points, of every pixel and
/// of the edge pixels, on windows 1 to 32 wide and 1 to 64 high: random pixels, noisy wedges
/// and step edges of every orientation, saturated checkerboards (the largest gradients),
/// packed, strided and decimated views, thresholds from 0 to past the largest magnitude.
#[cfg(target_arch = "x86_64")]
#[test]
fn vector_pass_matches_portable() {
    use super::sobel::row_mask;
    use crate::kernels::x86::{runnable, Isa};
    let mut rnd = xorshift(0x5eed_c0ff_ee15_900d);
    let mut det = CornerDetector::new();
    let mut grads = super::x86::Gradients::<MAX_DIM>::new();
    let (mut points, mut other) = (std::collections::BTreeMap::new(), EdgePoints::<MAX_DIM>::new());
    for case in 0..4000 {
        let (w, h) = (1 + (rnd() % 32) as usize, 1 + (rnd() % 64) as usize);
        let (step, pad) = (if case % 4 == 0 { 2 } else { 1 }, (rnd() % 3) as usize);
        let stride = w * step + pad;
        let (a, b, c) = ((rnd() % 200) as i64 - 100, (rnd() % 200) as i64 - 100, (rnd() % 4000) as i64);
        let (lo, hi, noise) = ((rnd() % 256) as i64, (rnd() % 256) as i64, 1 + (rnd() % 24) as i64);
        let kind = case % 3;
        let d: std::vec::Vec<u8> = (0..stride * h * step)
            .map(|i| {
                let (x, y) = ((i % stride) as i64, (i / stride) as i64);
                match kind {
                    0 => rnd() as u8,
                    // A wedge (two half-planes) or a step edge, with noise.
                    1 => {
                        let inside = a * x + b * y > c - 2000 && (case % 2 == 0 || b * x - a * y > c - 2000);
                        (if inside { hi } else { lo } + (rnd() as i64 % noise) - noise / 2).clamp(0, 255) as u8
                    }
                    _ => 255 * ((x + y / (1 + case as i64 % 3)) % 2) as u8,
                }
            })
            .collect();
        let mut v = WindowView::new(&d, w * step, h * step, stride, 0, 0).unwrap();
        if step == 2 {
            v = v.decimated();
        }
        let th = [0, 1, 30, 50, 70, 300, 1020, 1021, 1500][case % 9];
        let n = det.threshold_edges(&v, th);
        for isa in runnable().filter(|&i| i > Isa::Portable) {
            let mut bits = [0u64; MAX_DIM];
            // The AVX2 pass takes windows from 2 pixels wide.
            let Some(m) = grads.sobel(isa, &v, &mut bits[..h], th2(th)) else {
                assert!(isa == Isa::Avx2 && w == 1, "{isa:?}, case {case}: {w}x{h} not taken");
                continue;
            };
            assert_eq!((m, &bits[..h]), (n, &det.bits[..h]), "{isa:?}, case {case}: {w}x{h}");
            // Every pixel (the peak test everywhere), then the edge pixels.
            let every = [row_mask(w); MAX_DIM];
            for rows in [&every[..h], &bits[..h]] {
                collect_points(&det.wide, rows, w, h, &mut det.points);
                grads.collect_points(rows, &mut other);
                assert!(det.points.bits().eq(other.bits()), "{isa:?}, case {case}: {w}x{h}");
                *points.entry(isa).or_insert(0) += other.bits().count();
            }
        }
    }
    // Each vector path the host runs found many points (none where it runs neither).
    for isa in runnable().filter(|&i| i > Isa::Portable) {
        assert!(points.get(&isa).copied().unwrap_or(0) > 20_000, "{isa:?}: {points:?}");
    }
}
