//! Corner detector on arbitrary windows: never panics; a corner lies inside the window.
#![no_main]
use coopwin_firmware::kernels::corner::{CornerDetector, CornerParams};
use coopwin_firmware::kernels::view::WindowView;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    // Header: width, height (0..=70, so some exceed the 64x64 capacity), threshold, tol.
    let [w, h, th, tol, pixels @ ..] = data else { return };
    let (w, h) = (usize::from(*w % 71), usize::from(*h % 71));
    let Ok(view) = WindowView::new(pixels, w, h, w, 7, 9) else { return };
    let mut det = CornerDetector::new();
    let params = CornerParams { threshold: u16::from(*th) * 4, distinct_tol: *tol % 6, refine: *tol > 127 };
    if let Ok(c) = det.detect(&view, &params) {
        assert!(c.x.is_finite() && c.y.is_finite());
        assert!(c.x >= 7.0 && c.x < 7.0 + w as f32 && c.y >= 9.0 && c.y < 9.0 + h as f32);
    }
    if let Ok(c) = det.detect(&view.decimated(), &params) {
        assert!(c.x.is_finite() && c.y.is_finite());
    }
});
