//! Morphological opening (thesis 3.2.2) with the plus-shaped element.

use super::sobel::row_mask;

/// Morphological opening (thesis 3.2.2) of the `w x h` binary `map` with the 3x3
/// plus-shaped element: erosion (a pixel survives iff it and its 4 neighbours are set;
/// outside the map counts as set) then dilation (a pixel is set iff it or a 4-neighbour
/// is set; outside counts as clear). These are OpenCV's `morphologyEx(MORPH_OPEN,
/// MORPH_CROSS 3x3)` default borders. `tmp` is scratch of `w*h` bytes. Returns the
/// number of set pixels, or `None` if a slice is too short.
pub fn open_cross(map: &mut [u8], w: usize, h: usize, tmp: &mut [u8]) -> Option<u32> {
    let n = w.checked_mul(h)?;
    let map = map.get_mut(..n)?;
    let tmp = tmp.get_mut(..n)?;
    if n == 0 {
        return Some(0);
    }
    map.iter_mut().for_each(|v| *v = u8::from(*v != 0));
    // Whole-row passes (zipped slices, so they vectorise): the centre row combined with
    // the rows above and below and with itself shifted one pixel left and right. Rows
    // or columns outside the map are simply skipped: skipping an AND is "outside = 1",
    // skipping an OR is "outside = 0".
    cross_pass(map, tmp, w, |a, b| a & b);
    cross_pass(tmp, map, w, |a, b| a | b);
    Some(map.iter().map(|&v| u32::from(v)).sum())
}

/// `dst[p] = op` over `src[p]` and its 4-neighbours that lie inside the map.
fn cross_pass(src: &[u8], dst: &mut [u8], w: usize, op: impl Fn(u8, u8) -> u8 + Copy) {
    dst.copy_from_slice(src);
    for (y, out) in dst.chunks_exact_mut(w).enumerate() {
        let row = |r: usize| src.get(r * w..(r + 1) * w);
        for nb in [y.checked_sub(1).and_then(row), row(y + 1)].into_iter().flatten() {
            out.iter_mut().zip(nb).for_each(|(o, &v)| *o = op(*o, v));
        }
        if let Some(cur) = row(y) {
            out.iter_mut().skip(1).zip(cur).for_each(|(o, &v)| *o = op(*o, v));
            out.iter_mut().zip(cur.iter().skip(1)).for_each(|(o, &v)| *o = op(*o, v));
        }
    }
}

/// [`open_cross`] on bit rows of width `w`; returns the number of set pixels.
pub(super) fn open_cross_bits(rows: &mut [u64], w: usize, tmp: &mut [u64]) -> u32 {
    let mask = row_mask(w);
    let left_out = 1u64; // pixel 0's left neighbour is outside
    let right_out = 1u64 << (w - 1).min(63);
    let h = rows.len().min(tmp.len());
    for y in 0..h {
        let c = rows[y];
        let up = if y > 0 { rows[y - 1] } else { u64::MAX };
        let dn = if y + 1 < h { rows[y + 1] } else { u64::MAX };
        tmp[y] = c & up & dn & ((c << 1) | left_out) & ((c >> 1) | right_out) & mask;
    }
    let mut count = 0;
    for y in 0..h {
        let e = tmp[y];
        let up = if y > 0 { tmp[y - 1] } else { 0 };
        let dn = if y + 1 < h { tmp[y + 1] } else { 0 };
        let d = (e | up | dn | (e << 1) | (e >> 1)) & mask;
        rows[y] = d;
        count += d.count_ones();
    }
    count
}
