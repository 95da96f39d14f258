use super::*;

#[test]
fn hand_computed_area() {
    // 4x3 frame at (10, 100); differences: (1,0)=40, (3,1)=31, (2,2)=30 (not > 30).
    let prev = [0u8; 12];
    let mut next = [0u8; 12];
    next[1] = 40;
    next[4 + 3] = 31;
    next[8 + 2] = 30;
    let p = WindowView::new(&prev, 4, 3, 4, 10, 100).unwrap();
    let n = WindowView::new(&next, 4, 3, 4, 10, 100).unwrap();
    let a = detect_motion(&p, &n, 30).unwrap().unwrap();
    assert_eq!(
        a,
        MotionArea {
            xmin: 11,
            xmax: 13,
            ymin: 100,
            ymax: 101,
            count: 2
        }
    );
    // Differencing is symmetric.
    assert_eq!(detect_motion(&n, &p, 30).unwrap(), Some(a));
    assert_eq!(detect_motion(&p, &n, 40).unwrap(), None);
    let mut m = [9u8; 12];
    assert_eq!(motion_mask(&p, &n, 30, &mut m), Some(2));
    assert_eq!(m, [0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0]);
}

#[test]
fn long_rows_and_strips() {
    // 600-wide rows exercise the 255-byte chunking; every pixel moves.
    let prev = [0u8; 600 * 2];
    let next = [255u8; 600 * 2];
    let p = WindowView::packed(&prev, 600, 2).unwrap();
    let n = WindowView::packed(&next, 600, 2).unwrap();
    let a = detect_motion(&p, &n, 0).unwrap().unwrap();
    assert_eq!(
        (a.xmin, a.xmax, a.ymin, a.ymax, a.count),
        (0, 599, 0, 1, 1200)
    );
}

/// Moving pixels in whole blocks, across a block boundary and in the tail after the
/// blocks, on 200-wide rows (3 blocks of 64 and 8 more); reference: a direct per-pixel
/// scan written here.
#[test]
fn blocks_and_tail_match_a_pixel_scan() {
    const W: usize = 200;
    const H: usize = 6;
    let prev = [100u8; W * H];
    let mut next = [100u8; W * H];
    let moves: [(usize, usize, u8); 7] = [(70, 0, 131), (63, 1, 0), (64, 1, 255), (195, 2, 140), (199, 3, 60), (0, 5, 69), (128, 5, 131)];
    for &(x, y, v) in &moves {
        next[y * W + x] = v;
    }
    let p = WindowView::new(&prev, W, H, W, 7, 3).unwrap();
    let n = WindowView::new(&next, W, H, W, 7, 3).unwrap();
    // Reference: every pixel tested once.
    let mut want: Option<MotionArea> = None;
    for y in 0..H {
        for x in 0..W {
            if prev[y * W + x].abs_diff(next[y * W + x]) > 30 {
                let (fx, fy) = (7 + x as u32, 3 + y as u32);
                want = Some(match want {
                    None => MotionArea { xmin: fx, xmax: fx, ymin: fy, ymax: fy, count: 1 },
                    Some(a) => MotionArea { xmin: a.xmin.min(fx), xmax: a.xmax.max(fx), ymin: a.ymin, ymax: fy, count: a.count + 1 },
                });
            }
        }
    }
    // All seven differ by more than 30 (the closest by 31).
    assert_eq!(want.map(|a| (a.xmin, a.xmax, a.ymin, a.ymax, a.count)), Some((7, 206, 3, 8, 7)));
    assert_eq!(detect_motion(&p, &n, 30).unwrap(), want);
    // Rows whose only motion is in the tail, or in one block: first and last columns.
    assert_eq!(scan_row_blocks(&prev[3 * W..4 * W], &next[3 * W..4 * W], 30), Some((1, 199, 199)));
    assert_eq!(scan_row_blocks(&prev[W..2 * W], &next[W..2 * W], 30), Some((2, 63, 64)));
    assert_eq!(scan_row_blocks(&prev[4 * W..5 * W], &next[4 * W..5 * W], 30), None);
}

/// Every row scan the host runs (AVX-512, AVX2, the portable one) against a per-pixel scan
/// written here: rows of every length around the 32- and 64-pixel vectors, motion sparse and
/// dense, thresholds at both ends and at the pixels' edge.
#[test]
fn row_scans_match_a_pixel_scan() {
    let mut x = 7u32;
    let mut next = || {
        x = x.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (x >> 24) as u8
    };
    for len in [0, 1, 31, 32, 33, 63, 64, 65, 127, 128, 200, 256, 600] {
        for density in [0u8, 4, 128, 255] {
            let a: std::vec::Vec<u8> = (0..len).map(|_| next()).collect();
            let b: std::vec::Vec<u8> = a.iter().map(|&p| if next() < density { next() } else { p.saturating_add(30) }).collect();
            let want = {
                let hits: std::vec::Vec<usize> = (0..len).filter(|&i| a[i].abs_diff(b[i]) > 30).collect();
                hits.first().map(|&f| (hits.len() as u32, f, *hits.last().unwrap_or(&f)))
            };
            assert_eq!(scan_row_blocks(&a, &b, 30), want, "blocks, {len} px, density {density}");
            #[cfg(target_arch = "x86_64")]
            for isa in crate::kernels::x86::runnable() {
                for t in [0, 30, 254, 255] {
                    let hits: std::vec::Vec<usize> = (0..len).filter(|&i| a[i].abs_diff(b[i]) > t).collect();
                    let want = hits.first().map(|&f| (hits.len() as u32, f, *hits.last().unwrap_or(&f)));
                    assert_eq!(scan_on(isa, &a, &b, t), want, "{isa:?}, {len} px, density {density}, threshold {t}");
                }
            }
        }
    }
}

/// The row scan of path `isa` (narrowed to what the host runs).
#[cfg(target_arch = "x86_64")]
fn scan_on(isa: crate::kernels::x86::Isa, a: &[u8], b: &[u8], t: u8) -> Option<(u32, usize, usize)> {
    use crate::kernels::x86::{detected, Isa};
    // SAFETY: the host runs the path (narrowed by `detected`), the functions' only requirement.
    #[allow(unsafe_code)]
    match isa.min(detected()) {
        Isa::Avx512 => unsafe { super::avx512::scan_row(a, b, t) },
        Isa::Avx2 => unsafe { super::avx2::scan_row(a, b, t) },
        Isa::Portable => scan_row_blocks(a, b, t),
    }
}

/// The motion area of two views a pixel at a time through `get`, the reference below.
fn area_by_pixels(prev: &WindowView<'_>, next: &WindowView<'_>, t: u8) -> Option<MotionArea> {
    let mut area: Option<MotionArea> = None;
    for y in 0..next.height() {
        for x in 0..next.width() {
            if prev.get(x, y).unwrap().abs_diff(next.get(x, y).unwrap()) > t {
                let (fx, fy) = next.to_frame(x, y);
                area = Some(match area {
                    None => MotionArea { xmin: fx, xmax: fx, ymin: fy, ymax: fy, count: 1 },
                    Some(a) => MotionArea { xmin: a.xmin.min(fx), xmax: a.xmax.max(fx), ymin: a.ymin.min(fy), ymax: a.ymax.max(fy), count: a.count + 1 },
                });
            }
        }
    }
    area
}

/// Whole frames, every path the host runs (AVX-512, AVX2, the portable one), against
/// [`area_by_pixels`]: widths around the 32- and 64-pixel vectors, heights around the row groups,
/// strides past the width, sub-views with origins, their decimated views and empty ones;
/// no motion, one moving pixel anywhere, sparse, random and all-moving pixels; thresholds
/// 0, 30, 254 and 255.
#[test]
fn frames_match_a_pixel_scan() {
    let mut x = 11u32;
    let mut rand = || {
        x = x.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        x >> 8
    };
    /// The view of `d` at `(x0, 0)`, its decimated view and two sub-views.
    fn views(d: &[u8], x0: usize, w: usize, h: usize, stride: usize, fx: u32) -> std::vec::Vec<WindowView<'_>> {
        let Ok(v) = WindowView::new(&d[x0..], w, h, stride, fx, 3) else { return std::vec::Vec::new() };
        let mut views = std::vec![v, v.decimated()];
        views.extend(v.sub(w.min(3), h.min(1), w - w.min(3), h - h.min(1)));
        views.extend(v.sub(0, 0, w / 2, h));
        views
    }
    let mut checked = 0;
    for w in [0usize, 1, 5, 33, 63, 64, 65, 127, 128, 129, 200, 256, 300] {
        for h in [0usize, 1, 2, 3, 4, 5, 7, 9] {
            for pad in [0usize, 1, 37, 64] {
                let (x0, stride) = (pad % 13, w + pad);
                let len = (stride * h + x0).max(1);
                for kind in 0..5 {
                    let prev: std::vec::Vec<u8> = (0..len).map(|_| if kind == 4 { 255 * (rand() % 2) as u8 } else { rand() as u8 }).collect();
                    let mut next = prev.clone();
                    match kind {
                        // One pixel (maybe outside the view: then none) by 255 or more than 30.
                        1 => {
                            let i = rand() as usize % len;
                            next[i] = if rand() % 2 == 0 { 255 - prev[i] } else { prev[i].wrapping_add(31 + rand() as u8 % 200) };
                        }
                        2 => {
                            for q in next.iter_mut() {
                                if rand() % 64 == 0 {
                                    *q = rand() as u8;
                                }
                            }
                        }
                        3 => next.iter_mut().for_each(|q| *q = rand() as u8),
                        4 => next.iter_mut().for_each(|q| *q = 255 - *q),
                        _ => {}
                    }
                    let fx = 5 + pad as u32;
                    for (p, n) in views(&prev, x0, w, h, stride, fx).iter().zip(&views(&next, x0, w, h, stride, fx)) {
                        for t in [0, 30, 254, 255] {
                            let want = area_by_pixels(p, n, t);
                            let at = (w, h, stride, kind, p.width(), p.height(), p.step(), t);
                            assert_eq!(motion_rows(p, n, t, scan_row_blocks), want, "portable, {at:?}");
                            assert_eq!(detect_motion(p, n, t).unwrap(), want, "{at:?}");
                            #[cfg(target_arch = "x86_64")]
                            for isa in crate::kernels::x86::runnable() {
                                assert_eq!(motion_on(isa, p, n, t), want, "{isa:?}, {at:?}");
                            }
                            checked += usize::from(want.is_some());
                        }
                    }
                }
            }
        }
    }
    // Most cases move somewhere.
    assert!(checked > 5000, "{checked}");
}

#[test]
fn decimated_and_mismatch() {
    let prev = [0u8; 16];
    let mut next = [0u8; 16];
    next[2 * 4 + 2] = 200; // frame (2,2) = decimated (1,1)
    next[3] = 200; // odd column: invisible at 25 %
    let p = WindowView::packed(&prev, 4, 4).unwrap();
    let n = WindowView::packed(&next, 4, 4).unwrap();
    let a = detect_motion(&p.decimated(), &n.decimated(), 10)
        .unwrap()
        .unwrap();
    assert_eq!(
        a,
        MotionArea {
            xmin: 2,
            xmax: 2,
            ymin: 2,
            ymax: 2,
            count: 1
        }
    );
    let small = WindowView::packed(&prev, 2, 2).unwrap();
    assert_eq!(detect_motion(&small, &n, 1), Err(MotionError::SizeMismatch));
}
