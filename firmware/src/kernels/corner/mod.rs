//! Window-based corner detector (thesis chapter 3).
//!
//! Pipeline (thesis Figure 3.1), each step a public function so it can be checked
//! against OpenCV:
//!
//! 1. **Sobel edges** ([`sobel_at`]): `gx`, `gy` with the 3x3 kernels of OpenCV
//!    `Sobel(ksize=3)` (`gx = [-1 0 1; -2 0 2; -1 0 1]`, `gy` its transpose) and
//!    OpenCV's default border `BORDER_REFLECT_101`, so edges reach the window border.
//!    The magnitude is the Euclidean norm, compared without a square root: a pixel is
//!    an edge iff `gx² + gy² > TH²` (exact in integers; the same edge map as
//!    `sqrt(gx² + gy²) > TH` and as the OpenCV benchmark script).
//! 2. **Pixel labelling** (3.2.1, [`keep_largest_component`]): 8-neighbour connected
//!    components (`|xi-xj| <= 1 ∧ |yi-yj| <= 1`); only the most populous label is kept
//!    (ties: the label met first in raster order).
//! 3. **Morphological opening** (3.2.2, [`open_cross`]): erosion then dilation with the
//!    3x3 plus-shaped element, OpenCV border semantics (outside = foreground for the
//!    erosion, background for the dilation).
//! 4. **Corner location**, one of two modes ([`CornerParams::refine`]):
//!    - the thesis' rules (3.2.3, 3.3, [`corner_from_edges`]): bounding points, Q1,
//!      Q2, Q3, MidNum logic, or the Golden Section Search when Q3 is undefined
//!      ([`CornerParams::literal`]);
//!    - beyond the thesis, the default ([`CornerParams::new`]): sub-pixel edge points
//!      split into the two sides by gradient orientation, one line fitted per side
//!      away from the apex, and their intersection (`lines.rs`). The rules pick one
//!      pixel of a 3-4 px wide band by its bounding box, so their error depends on the
//!      orientation (several pixels at some); the fit is sub-pixel at any orientation
//!      and either polarity.
//!
//! Windows up to `N x N` are handled with fixed buffers held by a [`CornerDetector<N>`]
//! (`N` a multiple of 8, at most [`MAX_DIM`]; 28 bytes a pixel: 16 KiB for the 24x24
//! Foveal window, 44 KiB for 40x40, 113 KiB for [`MAX_DIM`] = 64), so a processor holds the
//! detector its largest window needs. On an x86-64 host, the vector Sobel pass (`x86.rs`)
//! adds 264 bytes a row.

mod bounds;
mod labelling;
mod lines;
mod morphology;
mod sobel;
#[cfg(test)]
mod tests;
#[cfg(target_arch = "x86_64")]
mod x86;

pub use bounds::{bounding_points, corner_from_edges, BoundingPoints, Pixel, Q3Source};
pub use labelling::{keep_largest_component, Components};
pub use morphology::open_cross;
pub use sobel::sobel_at;

use bounds::{bounding_points_bits, corner_from_bounds};
use labelling::{largest_component_bits, Runs};
use lines::{apex_from_points, collect_points, EdgePoints};
use morphology::open_cross_bits;
use crate::kernels::view::WindowView;
use sobel::{sobel_rows, BYTES};

/// `TH²` as the Sobel passes compare it: `|g| <= 4·255` per axis, so
/// `gx² + gy² <= 2.1e6 < i32::MAX`, and clamping `TH²` to `i32::MAX` changes no comparison.
fn th2(th: u16) -> i32 {
    i32::try_from(u32::from(th) * u32::from(th)).unwrap_or(i32::MAX)
}

/// Largest window side a [`CornerDetector`] can be built for (a bit row is a `u64`); the
/// default detector's.
pub const MAX_DIM: usize = 64;

/// Parameters of the corner detector.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CornerParams {
    /// Edge threshold TH on `sqrt(gx² + gy²)` (thesis 3.4: good for 30 < TH < 70).
    pub threshold: u16,
    /// Thesis rules only: two bounding points count as "the same point" in the
    /// Q1/Q2/Q3 rules when their Chebyshev distance is at most this many pixels. 0 is
    /// the thesis' literal `≠`; 2, the width of a Sobel edge band, makes the rules
    /// hold on bands the thesis' thin-edge reasoning takes to be 1 px wide.
    pub distinct_tol: u8,
    /// Beyond the thesis: locate the corner as the intersection of the two edge lines
    /// fitted to sub-pixel edge points (see `lines.rs`) instead of by the bounding-point
    /// rules (3.2.3, 3.3), which pick one pixel of the band and depend on the
    /// orientation.
    pub refine: bool,
}

impl CornerParams {
    /// The default, beyond the thesis: threshold `th`, then the line fit
    /// (`refine = true`).
    pub fn new(threshold: u16) -> Self {
        Self { threshold, distinct_tol: 2, refine: true }
    }

    /// The thesis' rules literally (3.2.3, 3.3): exact `≠` and the edge pixel itself.
    pub fn literal(threshold: u16) -> Self {
        Self { threshold, distinct_tol: 0, refine: false }
    }
}

/// Why no corner was located.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NoCorner {
    /// The window has no pixel.
    Empty,
    /// The window is larger than the detector's `N x N`.
    TooLarge,
    /// No pixel exceeds the edge threshold.
    NoEdges,
    /// The opening removed every edge pixel (edges thinner than the plus element).
    FilteredOut,
    /// Q1 and Q2 coincide: the edges form a vertical line.
    VerticalLine,
    /// Q1 and Q2 are on one row (GSS case): a horizontal line.
    HorizontalLine,
    /// A straight edge: Q3 undefined and no edge pixel off the line Q1-Q2 (thesis
    /// rules), or one edge orientation only, or two within 30° of parallel (line fit).
    StraightLine,
    /// Line fit: a side keeps fewer than 2 sub-pixel edge points away from the apex.
    TooFewPoints,
    /// Line fit: the lines meet outside the window's pixel centres.
    OutsideWindow,
}

error_messages!(NoCorner {
    Empty => "the window has no pixel",
    TooLarge => "the window is larger than the detector's buffers",
    NoEdges => "no pixel exceeds the edge threshold",
    FilteredOut => "the opening removed every edge pixel",
    VerticalLine => "the edges form a vertical line",
    HorizontalLine => "the edges form a horizontal line",
    StraightLine => "the edges form a straight line, not a corner",
    TooFewPoints => "a side of the corner has too few edge points",
    OutsideWindow => "the edge lines meet outside the window",
});

/// How the corner was found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CornerCase {
    /// Corner = Q1 (`MidNum(M12) > 0 ∧ MidNum(M13) > 0`), with Q3's source.
    Q1(Q3Source),
    /// Corner = Q2 (`MidNum(M12) > 0 ∧ MidNum(M13) = 0`).
    Q2(Q3Source),
    /// Corner = Q3 (`MidNum(M12) = 0`).
    Q3(Q3Source),
    /// Q3 undefined: farthest edge pixel from the line Q1-Q2 by Golden Section Search.
    Gss,
    /// Beyond the thesis: intersection of the two fitted edge lines.
    Lines,
}

/// A located corner.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Corner {
    /// Column in frame coordinates.
    pub x: f32,
    /// Row in frame coordinates.
    pub y: f32,
    /// The rule that produced it.
    pub case: CornerCase,
    /// Edge pixels above the threshold (before filtering), for the information measures.
    pub edge_pixels: u32,
    /// Edge pixels left after labelling and opening.
    pub clean_pixels: u32,
    /// Unit directions of the two edges away from the corner (the line fit only; the
    /// thesis's rules find no edge directions).
    pub rays: Option<[(f32, f32); 2]>,
}

/// The corner detector with its fixed working buffers (window, edge maps, labelling
/// runs, sub-pixel edge points) for windows up to `N x N` (`N` a multiple of 8, at most
/// [`MAX_DIM`]: [`CornerDetector::sized`] refuses others at compile time).
pub struct CornerDetector<const N: usize = MAX_DIM> {
    /// The clean edge map a byte per pixel (row-major, `w x h`), for the thesis's rules.
    edges: [[u8; N]; N],
    /// Bit-packed edge rows (bit `x` of row `y` = pixel `(x, y)`).
    bits: [u64; N],
    /// The window widened to `i16`, one `N` row per window row (Sobel input).
    wide: [[i16; N]; N],
    runs: Runs<N>,
    points: EdgePoints<N>,
    /// The vector Sobel pass's gradients and peaks (x86.rs).
    #[cfg(target_arch = "x86_64")]
    grads: x86::Gradients<N>,
    w: usize,
    h: usize,
    edge_pixels: u32,
}

impl Default for CornerDetector {
    fn default() -> Self {
        Self::new()
    }
}

impl CornerDetector {
    /// A detector for windows up to [`MAX_DIM`] x [`MAX_DIM`] (`const`, so it can be a
    /// `static`); [`CornerDetector::sized`] builds a smaller one.
    pub const fn new() -> Self {
        Self::sized()
    }
}

impl<const N: usize> CornerDetector<N> {
    /// A detector for windows up to `N x N`, with zeroed buffers (`const`, so it can be a
    /// `static`).
    pub const fn sized() -> Self {
        // Whole 8-pixel chunks per row (Sobel) and 64-bit rows (the bit maps).
        const { assert!(N > 0 && N.is_multiple_of(8) && N <= MAX_DIM, "the detector's side is a multiple of 8 up to 64") };
        Self {
            edges: [[0; N]; N],
            bits: [0; N],
            wide: [[0; N]; N],
            runs: Runs::new(),
            points: EdgePoints::new(),
            #[cfg(target_arch = "x86_64")]
            grads: x86::Gradients::new(),
            w: 0,
            h: 0,
            edge_pixels: 0,
        }
    }

    /// Edge pixels above the threshold in the last [`detect`](Self::detect) call (before
    /// labelling and opening), for the information content measure (3.4.1).
    pub fn edge_pixels(&self) -> u32 {
        self.edge_pixels
    }

    /// The clean edge map of the last call, one row of bits per window row (bit `x` of row
    /// `y` = pixel `(x, y)`), with the window's width and height.
    pub fn clean_rows(&self) -> (&[u64], usize, usize) {
        (self.bits.get(..self.h).unwrap_or(&[]), self.w, self.h)
    }

    /// Thresholded Sobel edge map `gx² + gy² > TH²` of `view` into the bit rows;
    /// returns the number of edge pixels.
    fn threshold_edges(&mut self, view: &WindowView<'_>, th: u16) -> u32 {
        let (w, h) = (view.width(), view.height());
        if w == 0 || h == 0 || w > N || h > N {
            return 0;
        }
        for (y, r) in self.wide.iter_mut().take(h).enumerate() {
            match view.row(y) {
                Some(src) => {
                    for (d, &s) in r.iter_mut().zip(src) {
                        *d = i16::from(s);
                    }
                }
                None => {
                    for (d, s) in r.iter_mut().zip(view.row_iter(y)) {
                        *d = i16::from(s);
                    }
                }
            }
        }
        let th2 = th2(th);
        // Rows of 32 when they do (shorter fixed loops), of `N` otherwise.
        if w <= 32 && N >= 32 {
            sobel_rows::<N, 32>(&self.wide, &mut self.bits, w, h, th2)
        } else {
            sobel_rows::<N, N>(&self.wide, &mut self.bits, w, h, th2)
        }
    }

    /// The edge map of `view` into the bit rows and its count into `edge_pixels`: by the x86
    /// vector pass where it runs (then `true`: it kept the peaks for `collect_points`), else
    /// by [`threshold_edges`](Self::threshold_edges).
    fn edges(&mut self, view: &WindowView<'_>, th: u16) -> bool {
        #[cfg(target_arch = "x86_64")]
        if let Some(n) = self.grads.sobel(crate::kernels::x86::path(), view, &mut self.bits, th2(th)) {
            self.edge_pixels = n;
            return true;
        }
        self.edge_pixels = self.threshold_edges(view, th);
        false
    }

    /// Runs the whole chapter-3 pipeline on `view` and returns the corner in frame
    /// coordinates, or why there is none.
    pub fn detect(
        &mut self,
        view: &WindowView<'_>,
        params: &CornerParams,
    ) -> Result<Corner, NoCorner> {
        self.w = 0;
        self.h = 0;
        self.edge_pixels = 0;
        if view.is_empty() {
            return Err(NoCorner::Empty);
        }
        let (w, h) = (view.width(), view.height());
        if w > N || h > N {
            return Err(NoCorner::TooLarge);
        }
        self.w = w;
        self.h = h;
        let vectors = self.edges(view, params.threshold);
        if self.edge_pixels == 0 {
            return Err(NoCorner::NoEdges);
        }
        let rows = self.bits.get_mut(..h).ok_or(NoCorner::TooLarge)?;
        largest_component_bits(rows, &mut self.runs);
        let mut tmp = [0u64; N];
        let clean = open_cross_bits(rows, w, &mut tmp);
        if clean == 0 {
            return Err(NoCorner::FilteredOut);
        }
        let (x, y, case, rays) = if params.refine {
            if vectors {
                #[cfg(target_arch = "x86_64")]
                self.grads.collect_points(rows, &mut self.points);
            } else {
                collect_points(&self.wide, rows, w, h, &mut self.points);
            }
            let ((x, y), rays) = apex_from_points(&mut self.points, w, h)?;
            (x, y, CornerCase::Lines, Some(rays))
        } else {
            // The rules read the map a byte per pixel.
            for (dst, &r) in self.edges.as_flattened_mut().chunks_exact_mut(w).zip(rows.iter()) {
                for (k, d) in dst.chunks_mut(8).enumerate() {
                    let bytes = BYTES[((r >> (8 * k)) & 0xff) as usize].to_le_bytes();
                    // Whole chunks as one store (a copy of under 8 bytes is a library call).
                    match <&mut [u8; 8]>::try_from(&mut *d) {
                        Ok(d) => *d = bytes,
                        Err(_) => d.iter_mut().zip(bytes).for_each(|(d, b)| *d = b),
                    }
                }
            }
            let b = bounding_points_bits(rows).ok_or(NoCorner::FilteredOut)?;
            let (x, y, case) = corner_from_bounds(self.edges.as_flattened(), w, h, &b, params)?;
            (x, y, case, None)
        };
        let (ox, oy) = view.origin();
        let step = view.step() as f32;
        Ok(Corner {
            x: ox as f32 + x * step,
            y: oy as f32 + y * step,
            case,
            edge_pixels: self.edge_pixels,
            clean_pixels: clean,
            rays,
        })
    }
}
