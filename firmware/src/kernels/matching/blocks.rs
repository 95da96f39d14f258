//! How much of a template still matches at one placement (issue 38, item 1): a cover over
//! part of the object drops the whole template's score, while the parts it leaves uncovered
//! score as they did. The template is cut into a `g x g` grid of blocks, each scored on its
//! own by zero-mean NCC against the window's pixels under it.
use super::{score_at, Method};
use crate::kernels::view::WindowView;

/// Of the `g x g` blocks of `tpl` (each `side / g` pixels square; rows and columns past the
/// last whole block are left out) placed with its top-left pixel at `(px, py)` in `win`,
/// how many have texture (a block with no variance has no score), and how many of those
/// score at least `bar` by zero-mean NCC on their own: `(matching, textured)`. `(0, 0)`
/// where the template does not fit there or `g` is 0.
pub fn blocks_matching(win: &WindowView<'_>, tpl: &WindowView<'_>, (px, py): (usize, usize), g: usize, bar: f32) -> (u8, u8) {
    let b = if g == 0 { 0 } else { tpl.width().min(tpl.height()) / g };
    let (mut matching, mut textured) = (0u8, 0u8);
    if b < 2 || px + tpl.width() > win.width() || py + tpl.height() > win.height() {
        return (0, 0);
    }
    for j in 0..g {
        for i in 0..g {
            let (Some(t), Some(w)) = (tpl.sub(i * b, j * b, b, b), win.sub(px + i * b, py + j * b, b, b)) else { continue };
            match score_at(Method::Zncc, &w, &t, (0, 0)) {
                Ok(s) => {
                    textured = textured.saturating_add(1);
                    matching = matching.saturating_add(u8::from(s as f32 >= bar));
                }
                // A flat window patch under a textured block scores 0, as a search scores it.
                Err(super::MatchError::NoMatch) => textured = textured.saturating_add(1),
                Err(_) => {}
            }
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
        assert_eq!(blocks_matching(&win, &tpl, (1, 2), 2, -1.0), (3, 4), "a flat patch matches at no bar");
        // A flat template block has no score and is not counted.
        let mut flat = t.clone();
        for y in 0..4 {
            flat[y * 8..y * 8 + 4].fill(7);
        }
        assert_eq!(blocks_matching(&win, &WindowView::packed(&flat, 8, 8).unwrap(), (1, 2), 2, 0.9), (1, 3));
        // Nowhere to place it, or no grid: nothing.
        assert_eq!(blocks_matching(&win, &tpl, (3, 2), 2, 0.9), (0, 0));
        assert_eq!(blocks_matching(&win, &tpl, (1, 2), 0, 0.9), (0, 0));
        assert_eq!(blocks_matching(&win, &tpl, (1, 2), 5, 0.9), (0, 0), "blocks of a pixel have no score");
    }
}
