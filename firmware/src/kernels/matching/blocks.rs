//! How much of a template still matches at one placement (issue 38, item 1): a cover over
//! part of the object drops the whole template's score, while the parts it leaves uncovered
//! score as they did. The template is cut into a `g x g` grid of blocks, each scored on its
//! own by zero-mean NCC against the window's pixels under it,
//! `(nΣRI - ΣRΣI) / sqrt((nΣR² - (ΣR)²)(nΣI² - (ΣI)²))` over its `n` pixels (as
//! [`super::Method::Zncc`]), from integer sums and one `f32` square root a block: a
//! search's exact scores cost a 64-bit floating-point library call a block on the M4F.
use crate::kernels::fmath::sqrtf;
use crate::kernels::view::WindowView;

/// Largest block side: `n` times a sum of `n` products of pixels stays within `i32`
/// (169² x 255² < 2³¹), so the M4F converts the terms to `f32` in hardware.
const MAX_BLOCK: usize = 13;

/// Of the `g x g` blocks of `tpl` (each `side / g` pixels square, at most 13; rows and columns
/// past the last whole block are left out) placed with its top-left pixel at `(px, py)` in
/// `win`, how many have texture (a block with no variance has no score), and how many of those
/// score at least `bar` by zero-mean NCC (a flat patch of the window under one scores 0, as a
/// search scores it): `(matching, textured)`. `(0, 0)` where the template does not fit there,
/// a view is strided, or the blocks would be over 13 pixels a side (a block of a pixel has no
/// variance, so none has texture).
pub fn blocks_matching(win: &WindowView<'_>, tpl: &WindowView<'_>, (px, py): (usize, usize), g: usize, bar: f32) -> (u8, u8) {
    let b = tpl.width().min(tpl.height()).checked_div(g).unwrap_or(0);
    let (Some((t, ts)), Some((w, ws))) = (tpl.raw(), win.raw()) else { return (0, 0) };
    let fits = |p: usize, len: usize| p.checked_add(g * b).is_some_and(|end| end <= len);
    if b > MAX_BLOCK || !fits(px, win.width()) || !fits(py, win.height()) {
        return (0, 0);
    }
    let n = (b * b) as i32;
    let (mut matching, mut textured) = (0u8, 0u8);
    for j in 0..g {
        for i in 0..g {
            let (mut st, mut stt, mut sw, mut sww, mut stw) = (0i32, 0i32, 0i32, 0i32, 0i32);
            for v in j * b..(j + 1) * b {
                let t = t.get(v * ts + i * b..).and_then(|r| r.get(..b));
                let w = w.get((py + v) * ws + px + i * b..).and_then(|r| r.get(..b));
                let (Some(t), Some(w)) = (t, w) else { return (0, 0) };
                for (&t, &w) in t.iter().zip(w) {
                    let (t, w) = (i32::from(t), i32::from(w));
                    (st, stt, sw, sww, stw) = (st + t, stt + t * t, sw + w, sww + w * w, stw + t * w);
                }
            }
            let (vt, vw) = (n * stt - st * st, n * sww - sw * sw);
            if vt == 0 {
                continue;
            }
            textured = textured.saturating_add(1);
            let cov = (n * stw - st * sw) as f32;
            let score_at_least = if vw == 0 { 0.0 >= bar } else { cov >= bar * sqrtf(vt as f32 * vw as f32) };
            matching = matching.saturating_add(u8::from(score_at_least));
        }
    }
    (matching, textured)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An 8x8 template of four 4x4 blocks, each a ramp (textured), as 8 rows of 8.
    fn ramps() -> std::vec::Vec<u8> {
        (0..64).map(|i| (100 + (i % 8) * 5 + (i / 8) * 3) as u8).collect()
    }

    #[test]
    fn each_block_is_scored_on_its_own() {
        let t = ramps();
        let tpl = WindowView::packed(&t, 8, 8).unwrap();
        // The window: the template at (1, 2) of a 10x11 patch of 0s. Hand scores: the top-left
        // block as it is (ZNCC 1), the top-right one negated (236 - v: -1), the
        // bottom-left flat (no variance: 0, as a search scores it), the bottom-right one
        // brighter by 40 (ZNCC is blind to an offset: 1).
        let mut w = std::vec![0u8; 10 * 11];
        for y in 0..8 {
            for x in 0..8 {
                let v = t[y * 8 + x];
                w[(y + 2) * 10 + x + 1] = match (x / 4, y / 4) {
                    (0, 0) => v,
                    (1, 0) => 236 - v,
                    (0, 1) => 90,
                    _ => v + 40,
                };
            }
        }
        let win = WindowView::packed(&w, 10, 11).unwrap();
        assert_eq!(blocks_matching(&win, &tpl, (1, 2), 2, 0.9), (2, 4));
        assert_eq!(blocks_matching(&win, &tpl, (1, 2), 2, -1.0), (4, 4), "every block scores at least -1, a flat patch 0");
        assert_eq!(blocks_matching(&win, &tpl, (1, 2), 2, 0.0), (3, 4), "the negated block scores -1");
        // A flat template block has no score and is not counted.
        let mut flat = t.clone();
        for y in 0..4 {
            flat[y * 8..y * 8 + 4].fill(7);
        }
        assert_eq!(blocks_matching(&win, &WindowView::packed(&flat, 8, 8).unwrap(), (1, 2), 2, 0.9), (1, 3));
        // Nowhere to place it, or no grid: nothing.
        assert_eq!(blocks_matching(&win, &tpl, (3, 2), 2, 0.9), (0, 0));
        assert_eq!(blocks_matching(&win, &tpl, (1, 2), 0, 0.9), (0, 0));
        assert_eq!(blocks_matching(&win, &tpl, (usize::MAX, 2), 2, 0.9), (0, 0), "a placement past any window");
        // 26x26 of texture: 13x13 blocks are scored, 14x14 ones (28x28) would overflow the sums.
        let ramp = |side: usize| -> std::vec::Vec<u8> { (0..side * side).map(|i| (i % side * 7 + i / side * 3) as u8).collect() };
        let (r26, r28) = (ramp(26), ramp(28));
        let (r26, r28) = (WindowView::packed(&r26, 26, 26).unwrap(), WindowView::packed(&r28, 28, 28).unwrap());
        assert_eq!(blocks_matching(&r26, &r26, (0, 0), 2, 0.9), (4, 4));
        assert_eq!(blocks_matching(&r28, &r28, (0, 0), 2, 0.9), (0, 0), "blocks over 13 pixels a side are refused");
        // A decimated view of a 16x16 ramp (8x8, every other pixel) has no rows of its own.
        let wide: std::vec::Vec<u8> = (0..256).map(|i| (i % 16 * 3 + i / 16 * 5) as u8).collect();
        let decimated = WindowView::packed(&wide, 16, 16).unwrap().decimated();
        assert_eq!(blocks_matching(&win, &decimated, (1, 2), 2, -1.0), (0, 0), "a strided view is refused");
    }
}
