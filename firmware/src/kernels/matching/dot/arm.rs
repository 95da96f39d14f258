//! [`super::dot_products`] and [`super::dot_row`] on 32-bit Arm (the Cortex-M4): its DSP
//! extension's `SMLAD` multiplies pairs of 16-bit halves, fed straight from the pixel rows.
use super::{DOT_CHUNK, SCORE_CACHE, STRIP_CAP};
use crate::kernels::dsp::{pair, smlad};
use crate::kernels::view::WindowView;
use heapless::Vec;

/// [`super::dot_row`] four pixels at a time on the Cortex-M4: each word's pixels spread over two
/// words of 16-bit halves and multiplied in pairs by `SMLAD` (see [`group`]).
#[inline(always)]
pub(in super::super) fn dot_row_pairs(a: &[u8], b: &[u8]) -> u64 {
    let n = a.len().min(b.len());
    let (Some(a), Some(b)) = (a.get(..n), b.get(..n)) else { return 0 };
    let mut s = 0u64;
    for (ca, cb) in a.chunks(DOT_CHUNK).zip(b.chunks(DOT_CHUNK)) {
        let (qa, qb) = (ca.chunks_exact(4), cb.chunks_exact(4));
        let tail = qa.remainder().iter().zip(qb.remainder()).fold(0u32, |acc, (&x, &y)| acc + u32::from(x) * u32::from(y));
        // At most DOT_CHUNK·255² < 2³¹: the `i32` sum does not wrap.
        let d = qa.zip(qb).fold(0i32, |acc, (x, y)| match <&[u8; 4]>::try_from(x) {
            Ok(&x) => {
                let x = u32::from_le_bytes(x);
                group(acc, x & 0x00ff_00ff, (x >> 8) & 0x00ff_00ff, y)
            }
            Err(_) => acc,
        });
        s += u64::from(d as u32) + u64::from(tail);
    }
    s
}

/// [`super::dot_products`] for 32-bit Arm (Cortex-M4, thesis 2.6's processors on a
/// microcontroller). `SMLAD` ([`crate::kernels::dsp`]) adds the products of two pairs of
/// 16-bit halves, and `UXTB16` (LLVM's for `w & 0x00ff_00ff`) spreads a word of four window
/// pixels `(w0, w1, w2, w3)` over two such pairs, `(w0, w2)` and `(w1, w3)`; so the template
/// is rearranged once into those halves, `(t0, t2)` and `(t1, t3)` per group of four
/// pixels, and four neighbouring placements of a row share each template word (their window
/// words are one row's bytes from four offsets in a row, loads at fixed offsets from one
/// pointer). A row's last `tw % 4` pixels make a last group padded with zero pixels,
/// multiplied with the window's four pixels from there wherever they are in the window's
/// memory (the pixels past the patch count zero times); where they are not (the last
/// placements of the window's last rows), those pixels are summed one at a time. A row's last
/// `nx % 4` placements go one at a time. The sums stay under `4096·255² < 2³¹`.
pub(in super::super) fn row_dot_products(win: &WindowView<'_>, tpl: &WindowView<'_>, dots: &mut Vec<u32, SCORE_CACHE>) -> Option<()> {
    let (tw, th, ww, wh) = (tpl.width(), tpl.height(), win.width(), win.height());
    let nx = ww.checked_sub(tw)? + 1;
    let ny = wh.checked_sub(th)? + 1;
    // The template's words (two a group of four pixels, padded) must fit too: pushes past
    // their capacity end the function with `None`.
    if nx * ny > SCORE_CACHE || tw.checked_mul(wh)? > STRIP_CAP || tw == 0 || th == 0 {
        return None;
    }
    let body = tw - tw % 4;
    // Pixels a row's groups cover, the last padded.
    let padded = tw.div_ceil(4) * 4;
    let mut words: Vec<u32, { STRIP_CAP / 2 }> = Vec::new();
    for v in 0..th {
        let (groups, rest) = tpl.row(v)?.split_at_checked(body)?;
        for g in groups.chunks_exact(4) {
            if let &[t0, t1, t2, t3] = g {
                words.push(pair(i16::from(t0), i16::from(t2))).ok()?;
                words.push(pair(i16::from(t1), i16::from(t3))).ok()?;
            }
        }
        if !rest.is_empty() {
            let px = |i: usize| rest.get(i).map_or(0, |&p| i16::from(p));
            words.push(pair(px(0), px(2))).ok()?;
            words.push(pair(px(1), px(3))).ok()?;
        }
    }
    let rows = Rows { words: &words, per_row: padded / 2, th, one_last: tw % 4 == 1 };
    let (data, stride) = win.raw()?;
    // Patch pixels each call multiplies: the padded groups where the last of the calls' `span`
    // patches (at `at + span`) has them in `data`, else the groups of four only.
    let len = |at: usize, span: usize| if at + span + (th - 1) * stride + padded <= data.len() { padded } else { body };
    // Placement `(px, py)`'s dot product from the sum of its rows' groups, adding its last
    // `tw % 4` pixels one at a time unless `len` covered them.
    let product = |px: usize, py: usize, sum: i32, len: usize| -> Option<u32> {
        let mut tail = 0u32;
        if len < tw {
            for v in 0..th {
                let start = (py + v) * stride + px;
                let (t, w) = (tpl.row(v)?.get(len..)?, data.get(start + len..start + tw)?);
                tail = t.iter().zip(w).fold(tail, |s, (&t, &w)| s.wrapping_add(u32::from(t) * u32::from(w)));
            }
        }
        Some((sum as u32).wrapping_add(tail))
    };
    // In raster order: four placements of a row at a time, then one at a time.
    dots.clear();
    for py in 0..ny {
        let mut px = 0;
        while px + 4 <= nx {
            let at = py * stride + px;
            let n = len(at, 3);
            for (j, &sum) in rows.dot4(data, stride, at, n)?.iter().enumerate() {
                dots.push(if n >= tw { sum as u32 } else { product(px + j, py, sum, n)? }).ok()?;
            }
            px += 4;
        }
        while px < nx {
            let at = py * stride + px;
            let n = len(at, 0);
            dots.push(product(px, py, rows.dot(data, stride, at, n)?, n)?).ok()?;
            px += 1;
        }
    }
    Some(())
}

/// The template words of [`row_dot_products`] (halves `(t0, t2)`, `(t1, t3)` per group of
/// four pixels, each row's last group padded with zeros): `per_row` words a row, `th` rows.
struct Rows<'w> {
    words: &'w [u32],
    per_row: usize,
    th: usize,
    /// Whether each row's last group holds one pixel (its odd word and the even word's high
    /// half are zeros).
    one_last: bool,
}

impl Rows<'_> {
    /// The products with the patches at `at`, `at + 1`, `at + 2` and `at + 3` of the window
    /// pixels `data` (rows `stride` apart), over each row's first `len` pixels (whole groups):
    /// four neighbouring placements of a row sharing each template word. Rows of the common
    /// widths (the padded template's whole row, 8, 12, 16 or 20 pixels) go to
    /// [`Rows::fixed`].
    #[inline(never)]
    fn dot4(&self, data: &[u8], stride: usize, at: usize, len: usize) -> Option<[i32; 4]> {
        if len == 2 * self.per_row {
            match (len, self.one_last) {
                (8, true) => return self.fixed::<4, 8, 4, 11, true>(data, stride, at),
                (8, false) => return self.fixed::<4, 8, 4, 11, false>(data, stride, at),
                (12, _) => return self.fixed::<4, 12, 6, 15, false>(data, stride, at),
                (16, _) => return self.fixed::<4, 16, 8, 19, false>(data, stride, at),
                (20, _) => return self.fixed::<4, 20, 10, 23, false>(data, stride, at),
                _ => {}
            }
        }
        let mut a = [0i32; 4];
        for (v, t) in self.words.chunks(self.per_row.max(1)).take(self.th).enumerate() {
            let row = data.get(at + v * stride..)?.get(..len + 3)?;
            for (g, t) in t.chunks_exact(2).enumerate() {
                if let &[even, odd] = t {
                    for (k, acc) in a.iter_mut().enumerate() {
                        *acc = group(*acc, even, odd, row.get(k + 4 * g..k + 4 * g + 4).unwrap_or(&[]));
                    }
                }
            }
        }
        Some(a)
    }

    /// The products with the `K` patches from `at` (neighbours in a row, [`Rows::dot4`]'s four or
    /// [`Rows::dot`]'s one) over rows of `P` pixels (`W = P / 2` template words), unrolled: the
    /// patches' row is one array of `R = P + K - 1` pixels (one bounds check a row), from which
    /// every group is read at a fixed offset. A narrow template's rows (the Peripheral's
    /// 5-pixel half-resolution one, 2 groups) spent more on checks and pointers than on their
    /// products. With `ONE` (rows of `P - 3` pixels, as that one's) the last group is its one
    /// pixel's product, not two `SMLAD`s of mostly zeros.
    #[inline(always)]
    fn fixed<const K: usize, const P: usize, const W: usize, const R: usize, const ONE: bool>(&self, data: &[u8], stride: usize, at: usize) -> Option<[i32; K]> {
        let mut a = [0i32; K];
        for (v, t) in self.words.chunks_exact(W).take(self.th).enumerate() {
            let t = <&[u32; W]>::try_from(t).ok()?;
            let row = <&[u8; R]>::try_from(data.get(at + v * stride..)?.get(..R)?).ok()?;
            for (g, pair) in t.chunks_exact(2).enumerate() {
                if let &[even, odd] = pair {
                    for (k, acc) in a.iter_mut().enumerate() {
                        *acc = if ONE && g == W / 2 - 1 {
                            // The even word's low half is the pixel (at most 255).
                            acc.wrapping_add((even & 0xffff) as i32 * i32::from(row.get(k + 4 * g).copied().unwrap_or(0)))
                        } else {
                            group(*acc, even, odd, row.get(k + 4 * g..k + 4 * g + 4).unwrap_or(&[]))
                        };
                    }
                }
            }
        }
        Some(a)
    }

    /// [`Rows::dot4`] for the one placement at `at` (a row's last `nx % 4`).
    #[inline(never)]
    fn dot(&self, data: &[u8], stride: usize, at: usize, len: usize) -> Option<i32> {
        let one = match (len == 2 * self.per_row, len, self.one_last) {
            (true, 8, true) => self.fixed::<1, 8, 4, 8, true>(data, stride, at),
            (true, 8, false) => self.fixed::<1, 8, 4, 8, false>(data, stride, at),
            (true, 12, _) => self.fixed::<1, 12, 6, 12, false>(data, stride, at),
            (true, 16, _) => self.fixed::<1, 16, 8, 16, false>(data, stride, at),
            (true, 20, _) => self.fixed::<1, 20, 10, 20, false>(data, stride, at),
            _ => return self.dot_any(data, stride, at, len),
        };
        one.map(|[a]| a)
    }

    /// [`Rows::dot`] over rows of any length.
    fn dot_any(&self, data: &[u8], stride: usize, at: usize, len: usize) -> Option<i32> {
        let mut a = 0i32;
        for (v, t) in self.words.chunks(self.per_row.max(1)).take(self.th).enumerate() {
            let row = data.get(at + v * stride..at + v * stride + len)?;
            a = t.chunks_exact(2).zip(row.chunks_exact(4)).fold(a, |s, (t, c)| match t {
                &[even, odd] => group(s, even, odd, c),
                _ => s,
            });
        }
        Some(a)
    }
}

/// `acc` plus the products of one group: the window word's pixels `(w0, w1, w2, w3)` spread
/// over the halves `(w0, w2)` and `(w1, w3)` (`UXTB16`), each pair multiplied and added by
/// one `SMLAD`.
#[inline(always)]
fn group(acc: i32, even: u32, odd: u32, w: &[u8]) -> i32 {
    // The four bytes as one array (one load), not four (which LLVM would mask apart).
    match <&[u8; 4]>::try_from(w) {
        Ok(&bytes) => {
            let w = u32::from_le_bytes(bytes);
            smlad(smlad(acc, even, w & 0x00ff_00ff), odd, (w >> 8) & 0x00ff_00ff)
        }
        Err(_) => acc,
    }
}
