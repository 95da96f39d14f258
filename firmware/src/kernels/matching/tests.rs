#[cfg(target_arch = "x86_64")]
use super::dot::dot_products_on;
use super::dot::{dot_row_bytes, dot_row_pairs, row_dot_products, strip_dot_products};
#[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
use super::dot::patch_dots;
use super::subpixel::parabola;
use super::*;

/// Pixels from a fixed LCG (Numerical Recipes' constants) seeded with `seed`.
fn lcg(seed: u32) -> impl FnMut() -> u8 {
    let mut x = seed;
    move || {
        x = x.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (x >> 24) as u8
    }
}

/// `n` pixels from `px`.
fn pixels(px: &mut impl FnMut() -> u8, n: usize) -> std::vec::Vec<u8> {
    (0..n).map(|_| px()).collect()
}

/// The Cortex-M4's paired row dot product against the byte-at-a-time one, and a hand sum.
#[test]
fn the_arm_row_dot_product_is_the_bytewise_one() {
    let mut px = lcg(987);
    for (la, lb) in [(0, 0), (1, 1), (3, 3), (4, 4), (7, 7), (24, 24), (255, 255), (9, 6), (6, 9), (40, 41)] {
        let a = pixels(&mut px, la);
        let b = pixels(&mut px, lb);
        let want: u64 = a.iter().zip(&b).map(|(&p, &q)| u64::from(p) * u64::from(q)).sum();
        assert_eq!((dot_row_pairs(&a, &b), dot_row_bytes(&a, &b)), (want, want), "{la} {lb}");
    }
    let full = [255u8; 256];
    assert_eq!(dot_row_pairs(&full, &full), 256 * 65025);
}

/// A placement's SSE2 sums (`Σ R·I`, `Σ I²` in lanes kept across rows) against the same sums
/// taken pixel by pixel here: widths 8 and multiples of 16 (one and several vectors a row,
/// the 8-pixel rest), odd heights, placements off the window's origin in a window with a
/// stride, all-255 pixels at the largest patch taken (16,384 pixels: the lanes' limit), and
/// the widths and sizes it leaves to the per-row path (`None`).
#[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
#[test]
fn patch_sums_are_the_pixel_sums() {
    let mut px = lcg(2024);
    for (tw, th, px0, py0) in [(8, 8, 0, 0), (8, 5, 3, 7), (16, 16, 9, 2), (24, 3, 1, 1), (32, 7, 0, 5), (40, 9, 2, 0), (48, 1, 4, 4)] {
        let (stride, ww, wh) = (70, 64, 20);
        let (t, w) = (pixels(&mut px, tw * th), pixels(&mut px, stride * wh));
        let (tv, wv) = (WindowView::new(&t, tw, th, tw, 0, 0).unwrap(), WindowView::new(&w, ww, wh, stride, 0, 0).unwrap());
        let at = |i: usize| u64::from(w[(py0 + i / tw) * stride + px0 + i % tw]);
        let want = ((0..tw * th).map(|i| u64::from(t[i]) * at(i)).sum(), (0..tw * th).map(|i| at(i) * at(i)).sum());
        assert_eq!(patch_dots(&tv, &wv, px0, py0), Some(want), "{tw}x{th} at ({px0}, {py0})");
    }
    let full = [255u8; 128 * 128];
    let v = WindowView::new(&full, 128, 128, 128, 0, 0).unwrap();
    assert_eq!(patch_dots(&v, &v, 0, 0), Some((16384 * 65025, 16384 * 65025)));
    let big = [255u8; 128 * 136];
    let wide = WindowView::new(&big, 128, 136, 128, 0, 0).unwrap();
    let (t12, t16) = (WindowView::new(&full, 12, 4, 12, 0, 0).unwrap(), WindowView::new(&full, 16, 4, 16, 0, 0).unwrap());
    assert_eq!(patch_dots(&wide, &wide, 0, 0), None, "over 16,384 pixels");
    assert_eq!(patch_dots(&t12, &v, 0, 0), None, "12 pixels wide");
    assert_eq!(patch_dots(&t16, &v, 113, 0), None, "outside the window");
    assert!(patch_dots(&t16, &v, 112, 124).is_some(), "at the window's corner");
}

#[test]
fn the_arm_row_dot_products_equal_the_strip_ones() {
    // Pixels from a fixed LCG; the Foveal and Peripheral sizes (and the Peripheral's 10x10 and
    // 5x5 decimated and halved templates), a remainder of placement rows (ny % 4), widths not a
    // multiple of 4 and under 4: every unrolled row width of `dot4` and the general one.
    let mut px = lcg(12345);
    let sizes = [(20, 20, 24, 24), (16, 16, 40, 40), (8, 8, 20, 20), (7, 5, 13, 11), (20, 20, 20, 20), (33, 3, 40, 9), (3, 6, 9, 9), (64, 64, 64, 64), (10, 10, 32, 32), (5, 5, 32, 32), (12, 9, 17, 30)];
    for (tw, th, ww, wh) in sizes {
        let t = pixels(&mut px, tw * th);
        let w = pixels(&mut px, ww * wh);
        let (tv, wv) = (v(&t, tw, th), v(&w, ww, wh));
        let (mut rows, mut strips) = (Vec::new(), Vec::new());
        let (r, s) = (row_dot_products(&wv, &tv, &mut rows), strip_dot_products(&wv, &tv, &mut strips));
        assert_eq!((r, s), (Some(()), Some(())), "{tw}x{th} in {ww}x{wh}");
        let want: std::vec::Vec<u32> = (0..(ww - tw + 1) * (wh - th + 1))
            .map(|k| {
                let (ox, oy) = (k % (ww - tw + 1), k / (ww - tw + 1));
                (0..tw * th).map(|i| u32::from(t[i]) * u32::from(w[(oy + i / tw) * ww + ox + i % tw])).sum()
            })
            .collect();
        assert_eq!((&rows[..], &strips[..]), (&want[..], &want[..]), "{tw}x{th} in {ww}x{wh}");
    }
}

/// The dot products of every path the host runs (AVX-512, AVX2, the strips) against the hand
/// formula, as the Arm ones above: templates up to 32x32 (the largest the vector paths take;
/// 33 wide or high goes to the strips), 1 to 16 and 17 to 32 wide (one or two AVX2 registers a
/// row), placement rows a multiple of 4 and not, one-pixel and one-row templates, a sub-view
/// whose rows are `stride` apart, in a frame that ends with the window (the last rows' pixels
/// read from a padded copy) and one that goes on past it. Elsewhere (aarch64: the portable code,
/// in NEON) the one path the build has.
#[test]
fn every_paths_dot_products_equal_the_formula() {
    let mut px = lcg(4242);
    let sizes = [(20, 20, 24, 24), (16, 16, 40, 40), (8, 8, 20, 20), (7, 5, 13, 11), (32, 32, 56, 56), (32, 1, 40, 9), (1, 32, 9, 40), (1, 1, 5, 6), (3, 6, 9, 9), (10, 10, 32, 32), (12, 9, 17, 30), (17, 4, 19, 7), (33, 3, 40, 9), (3, 33, 9, 40)];
    let mut checked = 0;
    for (tw, th, ww, wh) in sizes {
        for below in [0, 2] {
            let t = pixels(&mut px, tw * th);
            // The window a sub-view of a wider frame: 3 columns and 2 rows in, rows `ww + 5`
            // apart, `below` rows after it.
            let stride = ww + 5;
            let frame = pixels(&mut px, stride * (wh + 2 + below));
            let wv = WindowView::new(&frame, stride, wh + 2 + below, stride, 0, 0).unwrap().sub(3, 2, ww, wh).unwrap();
            let want: std::vec::Vec<u32> = (0..(ww - tw + 1) * (wh - th + 1))
                .map(|k| {
                    let (ox, oy) = (k % (ww - tw + 1), k / (ww - tw + 1));
                    (0..tw * th).map(|i| u32::from(t[i]) * u32::from(frame[(2 + oy + i / tw) * stride + 3 + ox + i % tw])).sum()
                })
                .collect();
            #[cfg(target_arch = "x86_64")]
            let paths = crate::kernels::x86::runnable();
            #[cfg(not(target_arch = "x86_64"))]
            let paths = ["built"].into_iter();
            for isa in paths {
                let mut dots = Vec::new();
                #[cfg(target_arch = "x86_64")]
                let got = dot_products_on(isa, &wv, &v(&t, tw, th), &mut dots);
                #[cfg(not(target_arch = "x86_64"))]
                let got = super::dot::dot_products(&wv, &v(&t, tw, th), &mut dots);
                assert_eq!(got, Some(()), "{isa:?}, {tw}x{th} in {ww}x{wh}");
                assert_eq!(&dots[..], &want[..], "{isa:?}, {tw}x{th} in {ww}x{wh}");
                checked += 1;
            }
        }
    }
    assert!(checked >= 2 * sizes.len(), "{checked}");
}

/// A pyramid level, two pixels a word: against the rounded mean of each 2x2 block (a hand
/// formula), for even and odd widths and heights, a sub-view of a frame (rows `stride` apart)
/// and all-255 blocks (the largest sums).
#[test]
fn halving_takes_the_rounded_mean_of_each_block() {
    let mut px = lcg(77);
    let mut frame: std::vec::Vec<u8> = (0..40 * 30).map(|_| px()).collect();
    frame[..80].fill(255);
    let full = v(&frame, 40, 30);
    // One buffer for all, holding the last one's pixels (and junk at first).
    let mut buf = heapless::Vec::<u8, 1024>::from_slice(&[0xa5; 1024]).unwrap();
    for (x, y, w, h) in [(0, 0, 40, 30), (0, 0, 2, 2), (1, 0, 3, 3), (3, 5, 9, 7), (5, 2, 10, 4), (7, 1, 11, 8), (0, 0, 32, 2)] {
        let view = full.sub(x, y, w, h).unwrap();
        let half = halve(&view, &mut buf).unwrap();
        assert_eq!((half.width(), half.height()), (w / 2, h / 2));
        for j in 0..h / 2 {
            let want: std::vec::Vec<u8> = (0..w / 2)
                .map(|i| {
                    let p = |dx: usize, dy: usize| u16::from(frame[(y + 2 * j + dy) * 40 + x + 2 * i + dx]);
                    ((p(0, 0) + p(1, 0) + p(0, 1) + p(1, 1) + 2) / 4) as u8
                })
                .collect();
            assert_eq!(half.row(j).unwrap(), &want[..], "{w}x{h} at ({x}, {y}), row {j}");
        }
    }
}

/// The row dot products over sub-views of a larger frame (a band of a map over the score
/// cache, a window cut from the frame: the row pitch is the frame's), where a row's last
/// `tw % 4` pixels are read as one padded group while the frame's memory holds them and one
/// at a time at its very end: against the direct sums.
#[test]
fn the_arm_row_dot_products_of_sub_views_are_the_direct_sums() {
    let mut px = lcg(2024);
    let frame: std::vec::Vec<u8> = (0..64 * 48).map(|_| px()).collect();
    let full = v(&frame, 64, 48);
    // (x, y, w, h) of the sub-view, template side: inside the frame, and at its bottom-right
    // corner (the last placements' padded reads would pass the frame's end).
    for ((x, y, w, h), (tw, th)) in [((30, 20, 20, 24), (10, 10)), ((44, 24, 20, 24), (10, 10)), ((57, 41, 7, 7), (5, 3)), ((0, 0, 40, 30), (13, 7))] {
        let t = pixels(&mut px, tw * th);
        let sub = full.sub(x, y, w, h).unwrap();
        let mut dots = Vec::new();
        assert_eq!(row_dot_products(&sub, &v(&t, tw, th), &mut dots), Some(()), "{w}x{h} at ({x}, {y})");
        let (nx, ny) = (w - tw + 1, h - th + 1);
        let want: std::vec::Vec<u32> = (0..nx * ny)
            .map(|k| (0..tw * th).map(|i| u32::from(t[i]) * u32::from(frame[(y + k / nx + i / tw) * 64 + x + k % nx + i % tw])).sum())
            .collect();
        assert_eq!(&dots[..], &want[..], "{w}x{h} at ({x}, {y})");
    }
}

fn v<'a>(d: &'a [u8], w: usize, h: usize) -> WindowView<'a> {
    WindowView::packed(d, w, h).unwrap()
}

// Window 3x2 = [1 2 3; 4 5 6], template 2x1 = [1 2]. Placements 2x2.
const W: [u8; 6] = [1, 2, 3, 4, 5, 6];
const T: [u8; 2] = [1, 2];

#[test]
fn hand_computed_maps() {
    let (w, t) = (v(&W, 3, 2), v(&T, 2, 1));
    let mut m = [0f64; 4];
    // SSD: (0,0): 0; (1,0): (1-2)²+(2-3)²=2; (0,1): 9+9=18; (1,1): 16+16=32.
    assert_eq!(score_map(Method::Ssd, &w, &t, &mut m), Ok((2, 2)));
    assert_eq!(m, [0.0, 2.0, 18.0, 32.0]);
    // SAD: 0, 2, 6, 8.
    score_map(Method::Sad, &w, &t, &mut m).unwrap();
    assert_eq!(m, [0.0, 2.0, 6.0, 8.0]);
    // NCC (0,1): P = 4+10 = 14, Q = sqrt(5 * 41).
    score_map(Method::Ncc, &w, &t, &mut m).unwrap();
    assert!((m[0] - 1.0).abs() < 1e-12);
    assert!((m[1] - 8.0 / (5.0f64 * 13.0).sqrt()).abs() < 1e-12);
    assert!((m[2] - 14.0 / (5.0f64 * 41.0).sqrt()).abs() < 1e-12);
    // ZNCC of two increasing pairs is exactly 1 everywhere.
    score_map(Method::Zncc, &w, &t, &mut m).unwrap();
    assert!(m.iter().all(|s| (s - 1.0).abs() < 1e-12));
    let b = best_match(Method::Ssd, &w, &t).unwrap();
    assert_eq!((b.x, b.y, b.score), (0, 0, 0.0));
}

#[test]
fn zero_energy_is_typed() {
    let z = [0u8; 6];
    let (w, t) = (v(&W, 3, 2), v(&T, 2, 1));
    assert_eq!(
        best_match(Method::Ncc, &w, &v(&z, 2, 1)),
        Err(MatchError::ZeroEnergy)
    );
    assert_eq!(
        best_match(Method::Ncc, &v(&z, 3, 2), &t),
        Err(MatchError::NoMatch)
    );
    let flat = [7u8; 2];
    assert_eq!(
        best_match(Method::Zncc, &w, &v(&flat, 2, 1)),
        Err(MatchError::ZeroEnergy)
    );
    // A zero window is still fine for difference measures.
    assert_eq!(
        best_match(Method::Ssd, &v(&z, 3, 2), &t).unwrap().score,
        5.0
    );
    assert_eq!(
        best_match(Method::Ssd, &t, &w),
        Err(MatchError::TemplateLarger)
    );
    assert_eq!(
        best_match(Method::Ssd, &v(&[], 0, 0), &t),
        Err(MatchError::Empty)
    );
}

#[test]
fn errors_read_as_sentences() {
    use std::string::ToString;
    // Every variant has its own message (a copied line would repeat one).
    let all = [
        MatchError::Empty,
        MatchError::TemplateLarger,
        MatchError::TooLarge,
        MatchError::ZeroEnergy,
        MatchError::NoMatch,
        MatchError::MapTooSmall,
        MatchError::Strided,
    ];
    let texts: std::vec::Vec<_> = all.iter().map(ToString::to_string).collect();
    assert!(texts.iter().all(|t| !t.is_empty() && !t.contains("Error")));
    let distinct: std::collections::BTreeSet<_> = texts.iter().collect();
    assert_eq!(distinct.len(), all.len());
    assert_eq!(MatchError::ZeroEnergy.to_string(), "the template is flat (no energy for NCC, no variance for ZNCC)");
}

#[test]
fn parabola_vertex() {
    // Scores 1, 3, 2 along x: vertex at (1-2)/(2(1-6+2)) = 1/6.
    assert!((parabola(Some(1.0), 3.0, Some(2.0), true) - 1.0 / 6.0).abs() < 1e-12);
    assert_eq!(parabola(Some(1.0), 3.0, Some(2.0), false), 0.0);
    assert_eq!(parabola(None, 3.0, Some(2.0), true), 0.0);
    assert_eq!(parabola(Some(3.0), 3.0, Some(3.0), true), 0.0);
}

#[test]
fn subpixel_of_symmetric_peak_is_between_placements() {
    // A bright bar at columns 2 and 3 and a template that is one column of the bar:
    // placements 1 and 2 tie (first wins), SSD at 0, 1, 2 is 2c, c, c, so the
    // parabola vertex is at (2c - c) / (2 (2c - 2c + c)) = +0.5: exactly between.
    let mut d = [10u8; 6 * 3];
    for y in 0..3 {
        d[y * 6 + 2] = 200;
        d[y * 6 + 3] = 200;
    }
    let t = [10u8, 200, 10, 10, 200, 10, 10, 200, 10];
    let m = best_match(Method::Ssd, &v(&d, 6, 3), &v(&t, 3, 3)).unwrap();
    assert_eq!((m.x, m.y), (1, 0));
    assert_eq!(m.sub_x, 1.5);
}

#[test]
fn the_full_resolution_match_is_best_match_and_refuses_strided_views() {
    // Reference: `best_match` (which packs strided views first).
    let w = smooth_noise(30, 30, 3);
    let t: std::vec::Vec<u8> = (0..100).map(|k| w[(7 + k / 10) * 30 + 11 + k % 10]).collect();
    for m in [Method::Ncc, Method::Zncc, Method::Ssd, Method::Sad] {
        assert_eq!(best_match_full(m, &v(&w, 30, 30), &v(&t, 10, 10)), best_match(m, &v(&w, 30, 30), &v(&t, 10, 10)));
    }
    let strided = v(&w, 30, 30).decimated();
    assert_eq!(best_match_full(Method::Ncc, &strided, &v(&t[..25], 5, 5)), Err(MatchError::Strided));
    assert!(best_match(Method::Ncc, &strided, &v(&t[..25], 5, 5)).is_ok());
}

#[test]
fn decimated_scales_back() {
    // 8x8 window with a single bright 2x2 block at (4,4); template 4x4 with the block
    // at (2,2): at 25 % the match is at decimated (1,1) = full (2,2).
    let mut w = [0u8; 64];
    let mut t = [0u8; 16];
    for (y, x) in [(4, 4), (4, 5), (5, 4), (5, 5)] {
        w[y * 8 + x] = 255;
    }
    for (y, x) in [(2, 2), (2, 3), (3, 2), (3, 3)] {
        t[y * 4 + x] = 255;
    }
    let m = best_match_decimated(Method::Ssd, &v(&w, 8, 8), &v(&t, 4, 4)).unwrap();
    assert_eq!((m.x, m.y, m.score), (2, 2, 0.0));
    let full = best_match(Method::Ncc, &v(&w, 8, 8), &v(&t, 4, 4)).unwrap();
    assert_eq!((full.x, full.y), (2, 2));
    assert!((full.score - 1.0).abs() < 1e-12);
}

/// A `w x h` texture smooth over a few pixels, as a camera sees an object: LCG noise,
/// box-blurred twice over 3x3.
fn smooth_noise(w: usize, h: usize, seed: u32) -> std::vec::Vec<u8> {
    let mut px = lcg(seed);
    let mut img: std::vec::Vec<u32> = (0..w * h).map(|_| u32::from(px())).collect();
    for _ in 0..2 {
        img = (0..w * h)
            .map(|k| {
                let (x, y) = (k % w, k / w);
                let (xs, ys) = (x.saturating_sub(1)..=(x + 1).min(w - 1), y.saturating_sub(1)..=(y + 1).min(h - 1));
                let n = (xs.clone().count() * ys.clone().count()) as u32;
                ys.flat_map(|yy| xs.clone().map(move |xx| (xx, yy))).map(|(xx, yy)| img[yy * w + xx]).sum::<u32>() / n
            })
            .collect();
    }
    img.into_iter().map(|v| v as u8).collect()
}

#[test]
fn the_pyramid_finds_what_the_full_search_finds() {
    // Reference: the full search (`best_match`). A 20x20 template cut at even and odd
    // offsets of a 52x52 window (the adapting Foveal's widest, 1,089 placements) of smooth
    // texture: the result is the full search's (the sub-pixel position to float rounding: the
    // fine search adds its sub-window's offset). At (22, 16) and (16, 10) the coarse match lies
    // 6 px beside the centre's placement (16, 16): the two fine ranges are searched as one.
    let same = |a: Match, b: Match| {
        (a.x, a.y, a.score) == (b.x, b.y, b.score) && (a.sub_x - b.sub_x).abs() < 1e-4 && (a.sub_y - b.sub_y).abs() < 1e-4
            && (a.frame_x - b.frame_x).abs() < 1e-4 && (a.frame_y - b.frame_y).abs() < 1e-4
    };
    let cut = |w: &[u8], tx: usize, ty: usize| -> std::vec::Vec<u8> { (0..400).map(|k| w[(ty + k / 20) * 52 + tx + k % 20]).collect() };
    let w = smooth_noise(52, 52, 7);
    for (tx, ty) in [(0, 0), (1, 0), (13, 9), (32, 32), (31, 17), (7, 30), (16, 16), (22, 16), (16, 10)] {
        let t = cut(&w, tx, ty);
        let full = best_match(Method::Zncc, &v(&w, 52, 52), &v(&t, 20, 20)).unwrap();
        let pyramid = best_match_pyramid(Method::Zncc, &v(&w, 52, 52), &v(&t, 20, 20)).unwrap();
        assert_eq!((full.x, full.y), (tx, ty));
        assert!(same(pyramid, full), "template at ({tx}, {ty}): {pyramid:?} {full:?}");
    }
    // A near-periodic texture, where a near-copy 21 px down wins the half-resolution search
    // for a template at an odd offset: near the window's centre (placement (16, 16)) the
    // centre's fine search still finds it.
    let periodic = |x: usize, y: usize| {
        let (x, y) = (x as f64, y as f64);
        (128.0 + 50.0 * (0.37 * x).sin() * (0.29 * y).cos() + 40.0 * (0.23 * x - 0.31 * y).sin()) as u8
    };
    let w: std::vec::Vec<u8> = (0..52 * 52).map(|k| periodic(k % 52, k / 52)).collect();
    for (tx, ty) in [(15, 15), (17, 18), (18, 16)] {
        let t = cut(&w, tx, ty);
        let m = best_match_pyramid(Method::Zncc, &v(&w, 52, 52), &v(&t, 20, 20)).unwrap();
        let full = best_match(Method::Zncc, &v(&w, 52, 52), &v(&t, 20, 20)).unwrap();
        assert!(same(m, full), "template at ({tx}, {ty}): {m:?} {full:?}");
    }
    // A window of at most PYRAMID_FROM placements (8x8 = 64 in 27x27) is searched in full.
    let t = cut(&w, 5, 5);
    let w27 = WindowView::new(&w, 27, 27, 52, 0, 0).unwrap();
    assert_eq!(best_match_pyramid(Method::Zncc, &w27, &v(&t, 20, 20)), best_match(Method::Zncc, &w27, &v(&t, 20, 20)));
}

/// SSD's successive elimination finds what scoring every placement finds: the first minimum
/// in raster order, its score and its sub-pixel position. Reference: SSD summed pixel by pixel
/// here, on LCG pixels (a noise window with the template cut out of it, or a noise template),
/// repeated tiles (ties between equal minima), a flat window (nothing eliminated) and a map of
/// 1,089 placements (over the elimination's capacity: every placement scored).
#[test]
fn ssd_elimination_is_exact() {
    let mut px = lcg(4242);
    for (case, (tw, th, ww, wh)) in [(16, 16, 40, 40), (8, 8, 20, 20), (12, 9, 30, 21), (16, 16, 40, 40), (8, 8, 20, 20), (16, 16, 40, 40), (8, 8, 20, 20), (16, 16, 40, 40), (16, 16, 48, 48)].into_iter().enumerate() {
        let mut w = pixels(&mut px, ww * wh);
        match case {
            // Repeated 4x4 tiles: many placements tie with the minimum.
            3 => w.iter_mut().enumerate().for_each(|(i, p)| *p = ((i % ww) % 4 * 60 + (i / ww) % 4 * 3) as u8),
            // Flat: every placement ties.
            4 => w.iter_mut().for_each(|p| *p = 77),
            // Flat 8x8 tiles (the bound's blocks for 16x16): the bound is the SSD at aligned
            // placements, so an overestimate would skip the minimum.
            7 => {
                let tiles: std::vec::Vec<u8> = (0..25).map(|_| px() / 2).collect();
                w.iter_mut().enumerate().for_each(|(i, p)| *p = tiles[(i / ww) / 8 * 5 + (i % ww) / 8]);
            }
            _ => {}
        }
        // The template: the window's patch at (5, 3), one pixel changed.
        let mut t: std::vec::Vec<u8> = (0..tw * th).map(|i| w[(3 + i / tw) * ww + 5 + i % tw]).collect();
        t[0] = t[0].wrapping_add(9);
        // Cases 5 and 6: a noise template, not in the window (the minimum's bound is close to
        // its SSD, so a bound that overestimated would skip it).
        if case == 5 || case == 6 {
            t.iter_mut().for_each(|p| *p = px() / 2 + 64);
        }
        // Case 7: the aligned tiles at (8, 8), each pixel 5 brighter.
        if case == 7 {
            t.iter_mut().enumerate().for_each(|(i, p)| *p = w[(8 + i / tw) * ww + 8 + i % tw] + 5);
        }
        let (wv, tv) = (v(&w, ww, wh), v(&t, tw, th));
        let (nx, ny) = (ww - tw + 1, wh - th + 1);
        let ssd = |ox: usize, oy: usize| -> u64 {
            (0..tw * th).map(|i| (i64::from(t[i]) - i64::from(w[(oy + i / tw) * ww + ox + i % tw])).pow(2) as u64).sum()
        };
        let all: std::vec::Vec<u64> = (0..nx * ny).map(|k| ssd(k % nx, k / nx)).collect();
        let min = *all.iter().min().unwrap();
        let first = all.iter().position(|&s| s == min).unwrap();
        let m = best_match(Method::Ssd, &wv, &tv).unwrap();
        assert_eq!((m.x, m.y, m.score), (first % nx, first / nx, min as f64), "case {case}");
        // The sub-pixel fit from the reference's neighbours.
        let s = |x: usize, y: usize| (x < nx && y < ny).then(|| all[y * nx + x] as f64);
        let (bx, by) = (first % nx, first / nx);
        let dx = parabola(bx.checked_sub(1).and_then(|x| s(x, by)), min as f64, s(bx + 1, by), false);
        let dy = parabola(by.checked_sub(1).and_then(|y| s(bx, y)), min as f64, s(bx, by + 1), false);
        assert_eq!((m.sub_x, m.sub_y), ((bx as f64 + dx) as f32, (by as f64 + dy) as f32), "case {case}");
    }
}

/// A map over the score cache (a Peripheral sweep's 64x64 window at 25 % with a 10x10
/// template: 3,025 placements, the cache 1,024) is summed a band of placement rows at a time:
/// every placement's NCC and ZNCC against a direct computation from the formulas in the
/// module docs, in `f64` from exact integer sums.
#[test]
fn a_map_larger_than_the_score_cache_is_scored_in_bands_exactly() {
    let mut px = lcg(777);
    let (tw, th, ww, wh) = (10, 10, 64, 64);
    let w = pixels(&mut px, ww * wh);
    let t = pixels(&mut px, tw * th);
    let (nx, ny) = (ww - tw + 1, wh - th + 1);
    assert!(nx * ny > SCORE_CACHE);
    for method in [Method::Ncc, Method::Zncc] {
        let mut map = std::vec![0.0f64; nx * ny];
        assert_eq!(score_map(method, &v(&w, ww, wh), &v(&t, tw, th), &mut map), Ok((nx, ny)));
        let n = (tw * th) as f64;
        for (k, &got) in map.iter().enumerate() {
            let (ox, oy) = (k % nx, k / nx);
            let patch = |i: usize| f64::from(w[(oy + i / tw) * ww + ox + i % tw]);
            let (mut ri, mut ii, mut i1) = (0.0, 0.0, 0.0);
            for (i, &r) in t.iter().enumerate() {
                ri += f64::from(r) * patch(i);
                ii += patch(i) * patch(i);
                i1 += patch(i);
            }
            let (rr, r1) = (t.iter().map(|&r| f64::from(r) * f64::from(r)).sum::<f64>(), t.iter().map(|&r| f64::from(r)).sum::<f64>());
            let want = match method {
                Method::Ncc => ri / (rr * ii).sqrt(),
                _ => (n * ri - r1 * i1) / ((n * rr - r1 * r1) * (n * ii - i1 * i1)).sqrt(),
            };
            assert!((got - want).abs() < 1e-9, "{method:?} placement ({ox}, {oy}): {got} against {want}");
        }
    }
}

/// One placement's score is the map's at that placement, for every measure, and `best_match`'s
/// at the best one; a placement past the last is refused.
#[test]
fn one_placement_scores_as_the_map_does() {
    let mut px = lcg(31);
    let (tw, th, ww, wh) = (7, 5, 16, 12);
    let w = pixels(&mut px, ww * wh);
    let t = pixels(&mut px, tw * th);
    let (wv, tv) = (v(&w, ww, wh), v(&t, tw, th));
    for method in [Method::Ssd, Method::Sad, Method::Ncc, Method::Zncc] {
        let mut map = std::vec![0.0; 100];
        let (nx, ny) = score_map(method, &wv, &tv, &mut map).unwrap();
        for (k, &want) in map.iter().take(nx * ny).enumerate() {
            assert_eq!(score_at(method, &wv, &tv, (k % nx, k / nx)), Ok(want), "{method:?} placement {k}");
        }
        let m = best_match(method, &wv, &tv).unwrap();
        assert_eq!(score_at(method, &wv, &tv, (m.x, m.y)), Ok(m.score));
        assert_eq!(score_at(method, &wv, &tv, (nx, 0)), Err(MatchError::TemplateLarger));
    }
}

/// The candidates' search finds what the full search finds. Reference: `best_match` over
/// every placement. A 128x128 tile of smooth texture at 25 % (64x64 samples, 3,025 placements
/// of a 10x10 template, as an adapting Peripheral's sweep), the template cut at even and odd
/// sample offsets; then with three fainter copies of it elsewhere (look-alikes, each the
/// template mixed 3:1 with other texture), which must not displace it. A window of at most
/// `CANDIDATES_FROM` placements is the full search itself, and a flat template the same error.
#[test]
fn the_candidates_find_what_the_full_search_finds() {
    let same = |a: Match, b: Match| {
        (a.x, a.y, a.score) == (b.x, b.y, b.score) && (a.frame_x - b.frame_x).abs() < 1e-3 && (a.frame_y - b.frame_y).abs() < 1e-3
    };
    fn tile(w: &[u8]) -> WindowView<'_> {
        WindowView::new(w, 128, 128, 128, 108, 128).unwrap().decimated()
    }
    let cut = |w: &[u8], tx: usize, ty: usize| -> std::vec::Vec<u8> { (0..400).map(|k| w[(ty + k / 20) * 128 + tx + k % 20]).collect() };
    let mut w = smooth_noise(128, 128, 11);
    for (sx, sy) in [(0, 0), (1, 0), (27, 9), (54, 54), (31, 17), (7, 40), (44, 3)] {
        let t = cut(&w, 2 * sx, 2 * sy);
        let tv = v(&t, 20, 20).decimated();
        let full = best_match(Method::Zncc, &tile(&w), &tv).unwrap();
        let found = best_match_candidates(&tile(&w), &tv).unwrap();
        assert_eq!((full.x, full.y), (2 * sx, 2 * sy));
        assert!(same(found, full), "template at samples ({sx}, {sy}): {found:?} {full:?}");
    }
    let t = cut(&w, 60, 30);
    let other = smooth_noise(20, 20, 5);
    for (x0, y0) in [(4, 80), (90, 90), (100, 6)] {
        for k in 0..400 {
            let p = &mut w[(y0 + k / 20) * 128 + x0 + k % 20];
            *p = ((3 * u16::from(t[k]) + u16::from(other[k])) / 4) as u8;
        }
    }
    let tv = v(&t, 20, 20).decimated();
    let (full, found) = (best_match(Method::Zncc, &tile(&w), &tv).unwrap(), best_match_candidates(&tile(&w), &tv).unwrap());
    assert_eq!((full.x, full.y), (60, 30));
    assert!(same(found, full), "with look-alikes: {found:?} {full:?}");
    // 40x40 at 25 %: 11x11 placements, fewer than CANDIDATES_FROM.
    let small = WindowView::new(&w, 40, 40, 128, 0, 0).unwrap().decimated();
    assert_eq!(best_match_candidates(&small, &tv), best_match(Method::Zncc, &small, &tv));
    let flat = [9u8; 400];
    assert_eq!(best_match_candidates(&tile(&w), &v(&flat, 20, 20).decimated()), Err(MatchError::ZeroEnergy));
}
