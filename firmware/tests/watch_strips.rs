//! A Watch split into strips, each its own processor (thesis 2.3.3, MPDF's Watch windows; issue
//! 22: a 256x256 previous frame does not fit one processor's 64 KiB): the strips' motion areas,
//! merged, must equal the whole-frame detector's (thesis 2.4) on any frame and any split. The
//! reference is `detect_motion` over the whole region, as the single Watch runs it today.
use coopwin_firmware::kernels::motion::detect_motion;
use coopwin_firmware::kernels::view::WindowView;
use coopwin_firmware::processors::watch::{merge, strip};
use coopwin_firmware::types::{Decimation, WindowRequest};
use proptest::prelude::*;

/// A frame pair `w x h`: `prev` random, `next` equal to it but for `changes` pixels moved by a
/// random amount (so some areas are small, some empty, some the whole frame).
fn pair() -> impl Strategy<Value = (usize, usize, Vec<u8>, Vec<u8>)> {
    (1usize..=48, 1usize..=48).prop_flat_map(|(w, h)| {
        let n = w * h;
        (
            Just(w),
            Just(h),
            proptest::collection::vec(any::<u8>(), n),
            proptest::collection::vec((0..n, any::<u8>()), 0..=n.min(40)),
        )
            .prop_map(|(w, h, prev, changes)| {
                let mut next = prev.clone();
                for (i, v) in changes {
                    next[i] = v;
                }
                (w, h, prev, next)
            })
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(600))]

    #[test]
    fn strips_merge_into_the_whole_frames_motion(
        (w, h, prev, next) in pair(),
        (x0, y0) in (0u16..200, 0u16..200),
        n in 1u16..=12,
        threshold in any::<u8>(),
    ) {
        let view = |d| WindowView::new(d, w, h, w, u32::from(x0), u32::from(y0)).unwrap();
        let (p, q) = (view(&prev), view(&next));
        let whole = detect_motion(&p, &q, threshold).unwrap();
        let region = WindowRequest { x0, y0, width: w as u16, height: h as u16, decimation: Decimation::Full };
        let mut merged = None;
        let mut rows = 0;
        for k in 0..n {
            let s = strip(region, k, n).unwrap();
            // Contiguous, in order, each row once.
            prop_assert_eq!(s.y0, y0 + rows);
            prop_assert_eq!((s.x0, s.width), (x0, region.width));
            rows += s.height;
            let (dy, sh) = (usize::from(s.y0 - y0), usize::from(s.height));
            let (a, b) = (p.sub(0, dy, w, sh).unwrap(), q.sub(0, dy, w, sh).unwrap());
            merged = merge(merged, detect_motion(&a, &b, threshold).unwrap());
        }
        prop_assert_eq!(rows, region.height);
        prop_assert_eq!(strip(region, n, n), None);
        prop_assert_eq!(merged, whole);
    }
}

#[test]
fn strips_split_the_rows_as_evenly_as_they_go() {
    // 256 rows in 4 (the board's Watch image): 64 each; 10 rows in 4: 3, 3, 2, 2.
    let frame = WindowRequest { x0: 0, y0: 0, width: 256, height: 256, decimation: Decimation::Full };
    let got: Vec<_> = (0..4).map(|k| strip(frame, k, 4).map(|s| (s.y0, s.height))).collect();
    assert_eq!(got, [Some((0, 64)), Some((64, 64)), Some((128, 64)), Some((192, 64))]);
    let small = WindowRequest { y0: 5, height: 10, ..frame };
    let got: Vec<_> = (0..4).map(|k| strip(small, k, 4).map(|s| (s.y0, s.height))).collect();
    assert_eq!(got, [Some((5, 3)), Some((8, 3)), Some((11, 2)), Some((13, 2))]);
}
