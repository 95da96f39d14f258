//! Property tests: no panic and no NaN for any size and content; NCC self-match is 1;
//! translating the scene translates the match.
use coopwin_firmware::kernels::confidence::{ConfidencePolicy, KalmanCoop, LsqTrack, SseCoop};
use coopwin_firmware::types::Source;
use coopwin_firmware::kernels::corner::{CornerDetector, CornerParams};
use coopwin_firmware::kernels::info::edge_information;
use coopwin_firmware::kernels::matching::{best_match, best_match_decimated, score_map, MatchError, Method};
use coopwin_firmware::ports::window::{coordinate_bytes, WriteError};
use coopwin_firmware::kernels::motion::{detect_motion, motion_mask};
use coopwin_firmware::ports::link::MessageDecoder;
use coopwin_firmware::types::{Decimation, WindowRequest};
use coopwin_firmware::processors::Msg;
use coopwin_firmware::kernels::refine::refine_translation;
use coopwin_firmware::kernels::view::WindowView;
use proptest::prelude::*;

const METHODS: [Method; 4] = [Method::Ssd, Method::Sad, Method::Ncc, Method::Zncc];

/// An image of `w x h` pixels: all 0, all 255, or random.
fn image(max: usize) -> impl Strategy<Value = (usize, usize, Vec<u8>)> {
    (0..=max, 0..=max, 0u8..3).prop_flat_map(|(w, h, mode)| {
        let n = w * h;
        let data = match mode {
            0 => Just(vec![0u8; n]).boxed(),
            1 => Just(vec![255u8; n]).boxed(),
            _ => proptest::collection::vec(any::<u8>(), n).boxed(),
        };
        (Just(w), Just(h), data)
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn matching_never_panics_or_nans((ww, wh, wd) in image(24), (tw, th, td) in image(12)) {
        let win = WindowView::packed(&wd, ww, wh).unwrap();
        let tpl = WindowView::packed(&td, tw, th).unwrap();
        let mut map = vec![0f64; 25 * 25];
        for m in METHODS {
            for r in [best_match(m, &win, &tpl), best_match_decimated(m, &win, &tpl)] {
                match r {
                    Ok(r) => {
                        prop_assert!(r.score.is_finite() && r.sub_x.is_finite() && r.sub_y.is_finite());
                        prop_assert!((r.sub_x - r.x as f32).abs() <= 1.0 && (r.sub_y - r.y as f32).abs() <= 1.0);
                    }
                    Err(e) => {
                        let expected_fail = ww == 0 || wh == 0 || tw == 0 || th == 0 || tw > ww || th > wh
                            || matches!(e, MatchError::ZeroEnergy | MatchError::NoMatch);
                        prop_assert!(expected_fail, "{:?} {:?}", m, e);
                    }
                }
            }
            if let Ok((nx, ny)) = score_map(m, &win, &tpl, &mut map) {
                prop_assert!(map[..nx * ny].iter().all(|v| v.is_finite()));
                if m == Method::Ncc {
                    prop_assert!(map[..nx * ny].iter().all(|v| (0.0..=1.0).contains(v)));
                }
            }
        }
    }

    /// `best_match` ranks placements by their integer sums; the independent reference is the
    /// `f64` score map: the placement chosen has the map's best score (the first in raster
    /// order when the map ties, unless the map's `f64` rounding ties what the sums tell apart).
    #[test]
    fn the_best_placement_has_the_best_score((ww, wh, wd) in image(24), (tw, th, td) in image(12)) {
        let win = WindowView::packed(&wd, ww, wh).unwrap();
        let tpl = WindowView::packed(&td, tw, th).unwrap();
        let mut map = vec![0f64; 25 * 25];
        for m in METHODS {
            let (Ok(best), Ok((nx, ny))) = (best_match(m, &win, &tpl), score_map(m, &win, &tpl, &mut map)) else { continue };
            let map = &map[..nx * ny];
            let top = if m == Method::Ssd || m == Method::Sad { map.iter().copied().fold(f64::INFINITY, f64::min) } else { map.iter().copied().fold(f64::NEG_INFINITY, f64::max) };
            prop_assert_eq!(best.score, top, "{:?}", m);
            prop_assert_eq!(map[best.y * nx + best.x], top, "{:?}", m);
            let first = map.iter().position(|&v| v == top).unwrap();
            if map.iter().filter(|&&v| v == top).count() == 1 {
                prop_assert_eq!((best.x, best.y), (first % nx, first / nx), "{:?}", m);
            }
        }
    }

    #[test]
    fn ncc_of_a_crop_is_one_at_its_placement(
        (w, h, d) in (8usize..30, 8usize..30).prop_flat_map(|(w, h)| (Just(w), Just(h), proptest::collection::vec(1u8..=255, w * h))),
        fx in 0.0f64..1.0, fy in 0.0f64..1.0, fw in 0.2f64..1.0, fh in 0.2f64..1.0,
    ) {
        let img = WindowView::packed(&d, w, h).unwrap();
        let tw = ((w as f64 * fw) as usize).max(1);
        let th = ((h as f64 * fh) as usize).max(1);
        let px = ((w - tw) as f64 * fx) as usize;
        let py = ((h - th) as f64 * fy) as usize;
        let mut crop = Vec::new();
        for y in py..py + th {
            crop.extend_from_slice(&img.row(y).unwrap()[px..px + tw]);
        }
        let tpl = WindowView::packed(&crop, tw, th).unwrap();
        let mut map = vec![0f64; (w - tw + 1) * (h - th + 1)];
        let (nx, _) = score_map(Method::Ncc, &img, &tpl, &mut map).unwrap();
        prop_assert!((map[py * nx + px] - 1.0).abs() < 1e-12);
        let best = best_match(Method::Ncc, &img, &tpl).unwrap();
        prop_assert!((best.score - 1.0).abs() < 1e-12);
        // The window with itself: one placement, score 1.
        let me = best_match(Method::Ncc, &img, &img).unwrap();
        prop_assert_eq!((me.x, me.y), (0, 0));
        prop_assert!((me.score - 1.0).abs() < 1e-12);
        // SSD finds the crop exactly (score 0) at a placement whose patch equals it.
        let s = best_match(Method::Ssd, &img, &tpl).unwrap();
        prop_assert_eq!(s.score, 0.0);
    }

    #[test]
    fn translation_moves_the_match(
        scene in proptest::collection::vec(any::<u8>(), 48 * 48),
        px in 0usize..20, py in 0usize..20, dx in 0usize..8, dy in 0usize..8,
    ) {
        let img = WindowView::packed(&scene, 48, 48).unwrap();
        let tpl_view = img.sub(px + 8, py + 8, 10, 10).unwrap();
        let mut tbuf = [0u8; 100];
        let tpl = tpl_view.pack_into(&mut tbuf).unwrap();
        let a = img.sub(8, 8, 36, 36).unwrap();
        let b = img.sub(8 - dx, 8 - dy, 36, 36).unwrap();
        for m in [Method::Ssd, Method::Ncc, Method::Zncc, Method::Sad] {
            let ma = best_match(m, &a, &tpl).unwrap();
            let mb = best_match(m, &b, &tpl).unwrap();
            prop_assert_eq!((ma.x, ma.y), (px, py));
            prop_assert_eq!((mb.x, mb.y), (px + dx, py + dy));
            // In frame coordinates the match does not move at all (the sub-pixel offset
            // may differ where a window border hides a neighbour of the peak).
            let (ax, ay) = a.to_frame(ma.x, ma.y);
            let (bx, by) = b.to_frame(mb.x, mb.y);
            prop_assert_eq!((ax, ay), (bx, by));
            prop_assert!((ma.frame_x - ax as f32).abs() <= 0.5 && (mb.frame_y - by as f32).abs() <= 0.5);
        }
    }

    #[test]
    fn refinement_never_panics_and_never_walks_far(
        (ww, wh, wd) in image(40), (tw, th, td) in image(34), x in -3.0f32..40.0, y in -3.0f32..40.0,
    ) {
        let (Ok(win), Ok(tpl)) = (WindowView::packed(&wd, ww, wh), WindowView::packed(&td, tw, th)) else { return Ok(()) };
        if let Some((rx, ry)) = refine_translation(&win, &tpl, x, y) {
            prop_assert!(rx.is_finite() && ry.is_finite());
            prop_assert!((rx - x).hypot(ry - y) <= 1.0 + 1e-4, "walked from ({x}, {y}) to ({rx}, {ry})");
        }
    }

    #[test]
    fn corner_detector_never_panics((w, h, d) in image(70), th in 0u16..600, tol in 0u8..5) {
        let v = WindowView::packed(&d, w, h).unwrap();
        let mut det = Box::new(CornerDetector::new());
        for view in [v, v.decimated()] {
            if let Ok(c) = det.detect(&view, &CornerParams { threshold: th, distinct_tol: tol, refine: tol % 2 == 0 }) {
                prop_assert!(c.x >= 0.0 && c.y >= 0.0 && c.x < w as f32 && c.y < h as f32);
                prop_assert!(c.clean_pixels <= c.edge_pixels && c.edge_pixels as usize <= w * h);
                prop_assert!(edge_information(c.edge_pixels, (w * h) as u32).is_finite());
            }
        }
    }

    #[test]
    fn motion_area_bounds_the_mask((w, h, a) in image(40), noise in proptest::collection::vec(any::<u8>(), 1600), t in any::<u8>()) {
        let b: Vec<u8> = a.iter().zip(&noise).map(|(x, n)| x.wrapping_add(*n)).collect();
        let (pa, pb) = (WindowView::new(&a, w, h, w, 3, 5).unwrap(), WindowView::new(&b, w, h, w, 3, 5).unwrap());
        let mut mask = vec![0u8; w * h];
        let count = motion_mask(&pa, &pb, t, &mut mask).unwrap();
        match detect_motion(&pa, &pb, t).unwrap() {
            None => prop_assert_eq!(count, 0),
            Some(m) => {
                prop_assert_eq!(m.count, count);
                for (i, &v) in mask.iter().enumerate() {
                    let (x, y) = ((i % w) as u32 + 3, (i / w) as u32 + 5);
                    if v == 1 {
                        prop_assert!(x >= m.xmin && x <= m.xmax && y >= m.ymin && y <= m.ymax);
                    }
                }
            }
        }
    }

    #[test]
    fn confidence_never_nans(samples in proptest::collection::vec((any::<f64>(), any::<f64>(), any::<f64>(), any::<bool>()), 0..40), n in 3usize..=8) {
        let mut lsq = SseCoop::new(n).unwrap();
        let mut kal = KalmanCoop::new(10.0, 0.5, 0.3).unwrap();
        let mut track = LsqTrack::new(n).unwrap();
        for (t, x, y, which) in samples {
            let src = if which { Source::Ncc } else { Source::Cd };
            let _ = lsq.push(src, t, x, y);
            let _ = kal.push(src, t, x, y);
            let _ = track.push(t, x, y);
            let _ = (lsq.choose(), kal.choose());
            if let Some(f) = track.fit() {
                prop_assert!(f.a.is_finite() && f.b.is_finite() && f.sse.is_finite() && f.sse >= 0.0);
            }
            for s in [Source::Ncc, Source::Cd] {
                if let Some(v) = kal.score(s) {
                    prop_assert!(v.is_finite());
                }
            }
        }
    }

    #[test]
    fn link_decoding_never_panics(payloads in proptest::collection::vec(proptest::collection::vec(any::<u8>(), 0..40), 0..80)) {
        // Arbitrary payloads, template chunks among them (tags 8 and 9 are common here): the
        // decoder answers each with a message, an error or nothing, and never panics.
        let mut dec = MessageDecoder::new();
        for p in &payloads {
            let biased: Vec<u8> = p.iter().enumerate().map(|(i, &b)| if i == 0 { b % 11 } else { b }).collect();
            if let Some(Ok(Msg::Template(t))) = dec.feed(&biased) {
                prop_assert_eq!(t.pixels().len(), t.side() * t.side());
            }
        }
    }

    #[test]
    fn coordinate_bytes_are_the_window_or_refused(x0 in any::<u16>(), y0 in any::<u16>(), w in any::<u16>(), h in any::<u16>()) {
        // Reference: the inclusive bounds by plain arithmetic in u32, which fit 8 bits or not.
        let req = WindowRequest { x0, y0, width: w, height: h, decimation: Decimation::Full };
        let bounds = |a: u16, n: u16| (n > 0 && u32::from(a) + u32::from(n) <= 256).then(|| (u32::from(a), u32::from(a) + u32::from(n) - 1));
        match (bounds(x0, w), bounds(y0, h), coordinate_bytes(&req)) {
            (Some(x), Some(y), Ok(b)) => prop_assert_eq!(b.map(u32::from), [x.0, x.1, y.0, y.1]),
            (None, _, Err(e)) | (_, None, Err(e)) => prop_assert_eq!(e, WriteError::OutOfRange),
            (x, y, got) => prop_assert!(false, "{x:?} {y:?} {got:?}"),
        }
    }
}

#[test]
fn one_by_n_and_template_larger() {
    let row = [5u8, 9, 200, 9, 5];
    let w = WindowView::packed(&row, 5, 1).unwrap();
    let t = WindowView::packed(&row[1..4], 3, 1).unwrap();
    let m = best_match(Method::Ncc, &w, &t).unwrap();
    assert_eq!((m.x, m.y), (1, 0));
    assert_eq!(best_match(Method::Ssd, &t, &w), Err(MatchError::TemplateLarger));
    let col = WindowView::packed(&row, 1, 5).unwrap();
    assert_eq!(best_match(Method::Sad, &col, &WindowView::packed(&row[2..3], 1, 1).unwrap()).unwrap().y, 2);
}
