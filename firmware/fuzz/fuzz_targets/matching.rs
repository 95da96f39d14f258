//! Template matching on arbitrary windows and templates: never panics, never NaN.
#![no_main]
use coopwin_firmware::kernels::matching::{best_match, best_match_decimated, score_map, Method};
use coopwin_firmware::kernels::motion::detect_motion;
use coopwin_firmware::kernels::view::WindowView;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let [ww, wh, tw, th, split, rest @ ..] = data else { return };
    let (ww, wh, tw, th) = (usize::from(*ww % 48), usize::from(*wh % 48), usize::from(*tw % 24), usize::from(*th % 24));
    let cut = usize::from(*split).min(rest.len());
    let (a, b) = rest.split_at(cut);
    let (Ok(win), Ok(tpl)) = (WindowView::packed(b, ww, wh), WindowView::packed(a, tw, th)) else { return };
    let mut map = [0f64; 48 * 48];
    for m in [Method::Ssd, Method::Sad, Method::Ncc, Method::Zncc] {
        if let Ok(r) = best_match(m, &win, &tpl) {
            assert!(r.score.is_finite() && r.sub_x.is_finite() && r.sub_y.is_finite());
            assert!(r.x + tpl.width() <= win.width() && r.y + tpl.height() <= win.height());
            if matches!(m, Method::Ncc) {
                assert!((0.0..=1.0).contains(&r.score));
            }
        }
        if let Ok((nx, ny)) = score_map(m, &win, &tpl, &mut map) {
            assert!(map[..nx * ny].iter().all(|v| v.is_finite()));
        }
        if let Ok(r) = best_match_decimated(m, &win, &tpl) {
            assert!(r.score.is_finite());
        }
    }
    if let Ok(t) = WindowView::packed(a, ww, wh) {
        let _ = detect_motion(&win, &t, *split);
    }
});
