//! Pixel labelling (thesis 3.2.1): keep the most populous 8-connected component.

/// Result of [`keep_largest_component`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Components {
    /// Number of labels including the background, as `cv::connectedComponents`.
    pub num_labels: u32,
    /// Pixels in the largest foreground component (0 if none).
    pub largest_area: u32,
}

/// Pixel labelling (thesis 3.2.1): labels the non-zero pixels of the `w x h` binary
/// `map` by 8-connectivity and clears every pixel not in the most populous component
/// (ties: first in raster order). `labels` and `stack` are scratch of at least
/// `(w+2)·(h+2)` entries (a padded frame); `None` if they or `map` are too short, or
/// `(w+2)·(h+2) > 65535`.
pub fn keep_largest_component(
    map: &mut [u8],
    w: usize,
    h: usize,
    labels: &mut [u16],
    stack: &mut [u16],
) -> Option<Components> {
    // Labels live in a frame padded by one background pixel on every side, so the eight
    // neighbours of any pixel are at fixed offsets and need no border tests.
    let pw = w.checked_add(2)?;
    let pn = pw.checked_mul(h.checked_add(2)?)?;
    if pn > usize::from(u16::MAX) {
        return None;
    }
    let map = map.get_mut(..w * h)?;
    let labels = labels.get_mut(..pn)?;
    let stack = stack.get_mut(..pn)?;
    // Background 0, unvisited foreground UNSEEN, then component labels 1, 2, ...
    const UNSEEN: u16 = u16::MAX;
    labels.iter_mut().for_each(|l| *l = 0);
    if w > 0 {
        for (src, dst) in map.chunks_exact(w).zip(labels.chunks_exact_mut(pw).skip(1)) {
            for (d, &v) in dst.iter_mut().skip(1).zip(src) {
                *d = if v != 0 { UNSEEN } else { 0 };
            }
        }
    }
    let offsets = [pw + 1, pw, pw - 1, 1];
    let (mut next, mut best, mut best_area) = (0u16, 0u16, 0u32);
    for start in pw..pn - pw {
        if labels.get(start) != Some(&UNSEEN) {
            continue;
        }
        // At most (w·h + 1) / 2 components, so labels stay below UNSEEN.
        next += 1;
        labels[start] = next;
        stack[0] = start as u16;
        let (mut sp, mut area) = (1usize, 0u32);
        while sp > 0 {
            sp -= 1;
            let i = usize::from(stack[sp]);
            area += 1;
            // i is an interior pixel of the padded frame: i ± (pw + 1) is inside it.
            for j in offsets.iter().flat_map(|&o| [i - o, i + o]) {
                if let Some(l) = labels.get_mut(j) {
                    if *l == UNSEEN {
                        *l = next;
                        // Each pixel is pushed once, so sp < pn always.
                        if let Some(s) = stack.get_mut(sp) {
                            *s = j as u16;
                            sp += 1;
                        }
                    }
                }
            }
        }
        if area > best_area {
            best = next;
            best_area = area;
        }
    }
    if w > 0 {
        for (dst, src) in map.chunks_exact_mut(w).zip(labels.chunks_exact(pw).skip(1)) {
            for (m, &l) in dst.iter_mut().zip(src.iter().skip(1)) {
                *m = u8::from(l != 0 && l == best);
            }
        }
    }
    Some(Components { num_labels: u32::from(next) + 1, largest_area: best_area })
}

/// Scratch of the run-based labelling ([`largest_component_bits`]) for maps of up to
/// `N x N` pixels: a row of `w` pixels has at most `w / 2` runs (rounded up; `N` is even), so
/// `N² / 2` runs, each two columns, a row, a parent and an area. Pairs share an `N x N` array.
pub(super) struct Runs<const N: usize> {
    /// First then last columns: `N² / 2` of each.
    cols: [[u8; N]; N],
    /// Rows (the first `N² / 2`).
    rows: [[u8; N]; N],
    /// Parents then areas: `N² / 2` of each.
    tree: [[u16; N]; N],
}

/// [`Runs`]'s arrays, `(x0, x1, y, parent, area)`.
type RunArrays<'a> = (&'a mut [u8], &'a mut [u8], &'a mut [u8], &'a mut [u16], &'a mut [u16]);

impl<const N: usize> Runs<N> {
    pub(super) const fn new() -> Self {
        Self { cols: [[0; N]; N], rows: [[0; N]; N], tree: [[0; N]; N] }
    }

    /// The arrays as `(x0, x1, y, parent, area)`, `N² / 2` entries each.
    fn split(&mut self) -> RunArrays<'_> {
        let cap = N * N / 2;
        let (x0, x1) = self.cols.as_flattened_mut().split_at_mut(cap);
        let (parent, area) = self.tree.as_flattened_mut().split_at_mut(cap);
        let y = self.rows.as_flattened_mut();
        (x0, x1, y.get_mut(..cap).unwrap_or(&mut []), parent, area)
    }
}

/// Root of run `i` (path halving). Parents always point to smaller indices, so the root
/// is the component's first run in raster order.
#[inline]
fn find(parent: &mut [u16], mut i: usize) -> usize {
    loop {
        let p = usize::from(parent.get(i).copied().unwrap_or(0));
        if p == i {
            return i;
        }
        let gp = parent.get(p).copied().unwrap_or(0);
        if let Some(slot) = parent.get_mut(i) {
            *slot = gp;
        }
        i = p;
    }
}

/// [`keep_largest_component`] on bit rows: union-find over horizontal runs. Two runs of
/// consecutive rows are 8-connected iff their column ranges, each widened by one pixel,
/// overlap. The root of a component is its first run in raster order, so the largest
/// component with ties to the smallest root is the one `keep_largest_component` keeps.
/// Returns the number of pixels kept.
pub(super) fn largest_component_bits<const N: usize>(rows: &mut [u64], runs: &mut Runs<N>) -> u32 {
    let (x0, x1, ry, parent, area) = runs.split();
    let max_runs = x0.len();
    let mut n = 0usize;
    let mut prev = (0usize, 0usize);
    for (y, row) in rows.iter().enumerate() {
        let start = n;
        let mut b = *row;
        while b != 0 && n < max_runs {
            let a = b.trailing_zeros();
            let len = (b >> a).trailing_ones();
            let end = a + len; // exclusive, <= 64
            b = if end >= 64 { 0 } else { b & (u64::MAX << end) };
            x0[n] = a as u8;
            x1[n] = (end - 1) as u8;
            ry[n] = y as u8;
            parent[n] = n as u16;
            area[n] = 0;
            n += 1;
        }
        // Merge with the runs of the previous row (two pointers, both sorted by x).
        let (mut i, mut j) = prev;
        while i < prev.1 && j < n {
            let (pa, pb, ca, cb) = (x0[i], x1[i], x0[j], x1[j]);
            if u16::from(pb) + 1 < u16::from(ca) {
                i += 1;
            } else if u16::from(cb) + 1 < u16::from(pa) {
                j += 1;
            } else {
                let (ri, rj) = (find(parent, i), find(parent, j));
                if ri < rj {
                    parent[rj] = ri as u16;
                } else if rj < ri {
                    parent[ri] = rj as u16;
                }
                if pb < cb {
                    i += 1;
                } else {
                    j += 1;
                }
            }
        }
        prev = (start, n);
    }
    let (mut best, mut best_area) = (usize::MAX, 0u32);
    for r in 0..n {
        let root = find(parent, r);
        parent[r] = root as u16;
        let len = u16::from(x1[r]) - u16::from(x0[r]) + 1;
        area[root] += len;
    }
    for r in 0..n {
        if usize::from(parent[r]) == r && u32::from(area[r]) > best_area {
            best = r;
            best_area = u32::from(area[r]);
        }
    }
    rows.iter_mut().for_each(|r| *r = 0);
    for r in 0..n {
        if usize::from(parent[r]) == best {
            let (a, e) = (u32::from(x0[r]), u32::from(x1[r]));
            let m = (u64::MAX >> (63 - e)) & (u64::MAX << a);
            if let Some(row) = rows.get_mut(usize::from(ry[r])) {
                *row |= m;
            }
        }
    }
    best_area
}
