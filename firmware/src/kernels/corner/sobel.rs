//! Sobel edges (thesis 3.2, Figure 3.1): the per-pixel derivatives and the fast
//! thresholded edge map.

use super::MAX_DIM;
use crate::kernels::view::WindowView;

/// BORDER_REFLECT_101 index: `-1 -> 1`, `n -> n-2` (`0` for a single pixel).
#[inline]
pub(super) fn reflect(i: isize, n: usize) -> usize {
    let n = n as isize;
    let r = if i < 0 {
        -i
    } else if i >= n {
        2 * n - 2 - i
    } else {
        i
    };
    r.clamp(0, (n - 1).max(0)) as usize
}

/// Sobel derivatives `(gx, gy)` at view pixel `(x, y)` with 3x3 kernels and
/// `BORDER_REFLECT_101`, identical to OpenCV `Sobel(src, CV_32S, 1, 0, 3)` /
/// `(0, 1, 3)`. `None` outside the view.
pub fn sobel_at(view: &WindowView<'_>, x: usize, y: usize) -> Option<(i32, i32)> {
    let (w, h) = (view.width(), view.height());
    if x >= w || y >= h {
        return None;
    }
    let p = |dx: isize, dy: isize| -> i32 {
        let xx = reflect(x as isize + dx, w);
        let yy = reflect(y as isize + dy, h);
        i32::from(view.get(xx, yy).unwrap_or(0))
    };
    let gx = (p(1, -1) - p(-1, -1)) + 2 * (p(1, 0) - p(-1, 0)) + (p(1, 1) - p(-1, 1));
    let gy = (p(-1, 1) + 2 * p(0, 1) + p(1, 1)) - (p(-1, -1) + 2 * p(0, -1) + p(1, -1));
    Some((gx, gy))
}

/// Sobel + threshold of the `w x h` window in `wide` (rows of `D` pixels) into bit rows
/// `bits`, reading the first `N` pixels of a row at most (`w <= N <= D`, `N` a multiple of
/// 8), each row computed over `w` rounded up to a multiple of 8 so every loop is whole SIMD
/// vectors (the Cortex-M4 has none: there the rounding up costs little, a row of `N` would).
/// Pixels beyond `w` are computed from whatever the rows and the buffers hold there and
/// masked off. Returns the number of edge pixels.
pub(super) fn sobel_rows<const D: usize, const N: usize>(
    wide: &[[i16; D]],
    bits: &mut [u64],
    w: usize,
    h: usize,
    th2: i32,
) -> u32 {
    let fixed = |y: usize| -> &[i16; N] {
        let r = wide.get(y).map_or(&[][..], |r| r.get(..N).unwrap_or(&[]));
        <&[i16; N]>::try_from(r).unwrap_or(&[0; N])
    };
    let mask = row_mask(w);
    let (l, r) = (reflect(-1, w), reflect(w as isize, w));
    let len = w.next_multiple_of(8).min(N);
    let mut count = 0;
    // Column sums at index x + 1 with the margins at 0 and w + 1.
    let (mut smooth, mut diff) = ([0i16; MAX_DIM + 2], [0i16; MAX_DIM + 2]);
    for (y, out) in bits.iter_mut().enumerate().take(h) {
        let (up, mid, dn) = (
            fixed(reflect(y as isize - 1, h)),
            fixed(y),
            fixed(reflect(y as isize + 1, h)),
        );
        // Vertical pass: smooth = up + 2 mid + down, diff = down - up, at index x + 1,
        // then the reflect-101 margins at 0 and w + 1.
        let column = up.iter().zip(mid).zip(dn).take(len);
        for ((s, d), ((&u, &m), &v)) in smooth.iter_mut().skip(1).zip(diff.iter_mut().skip(1)).zip(column) {
            *s = u + 2 * m + v;
            *d = v - u;
        }
        smooth[0] = smooth[l + 1];
        diff[0] = diff[l + 1];
        smooth[w + 1] = smooth[r + 1];
        diff[w + 1] = diff[r + 1];
        let mut edge = [0u8; N];
        for (e, (s, d)) in edge.iter_mut().zip(smooth.windows(3).zip(diff.windows(3))).take(len) {
            if let ([s0, _, s2], [d0, d1, d2]) = (s, d) {
                let (gx, gy) = (i32::from(s2 - s0), i32::from(d0 + 2 * d1 + d2));
                *e = u8::from(gx * gx + gy * gy > th2);
            }
        }
        let mut b = 0u64;
        for (k, c) in edge.chunks_exact(8).take(len / 8).enumerate() {
            if let Ok(c) = <&[u8; 8]>::try_from(c) {
                b |= pack8(c) << (8 * k);
            }
        }
        *out = b & mask;
        count += out.count_ones();
    }
    count
}

/// Row mask of a `w`-pixel row (`1 <= w <= 64`).
#[inline]
pub(super) fn row_mask(w: usize) -> u64 {
    if w >= 64 {
        u64::MAX
    } else {
        (1u64 << w) - 1
    }
}

/// `BYTES[b]`: the 8 bits of `b` as 8 bytes of 0/1, little-endian (bit 0 = byte 0).
pub(super) const BYTES: [u64; 256] = {
    let mut t = [0u64; 256];
    let mut b = 0;
    while b < 256 {
        let mut k = 0;
        while k < 8 {
            if b & (1 << k) != 0 {
                t[b] |= 1u64 << (8 * k);
            }
            k += 1;
        }
        b += 1;
    }
    t
};

/// Packs 8 bytes of 0/1 (byte `k` = bit `k`) into a byte: `b_k` moves from bit `8k`
/// to bit `56 + k` of the product, and no two partial products collide.
#[inline(always)]
fn pack8(bytes: &[u8; 8]) -> u64 {
    u64::from_le_bytes(*bytes).wrapping_mul(0x0102_0408_1020_4080) >> 56
}
