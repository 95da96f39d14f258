//! The target template (thesis 2.3.2, 2.4): the N x N block captured at lock-on, matched by
//! the Peripheral (SSD at 25 %) and Foveal (NCC) processors and sent between them.
use crate::kernels::view::WindowView;
use crate::types::Point;

/// Largest template side.
pub const MAX_TEMPLATE: usize = 32;


/// The target template: an N x N block and the offset of the tracked point from its
/// top-left pixel (N/2 - 0.5 when the point was the block's centre).
#[derive(Debug)]
pub struct Template {
    px: [u8; MAX_TEMPLATE * MAX_TEMPLATE],
    n: usize,
    anchor: Point,
}

impl Clone for Template {
    fn clone(&self) -> Self {
        Template { px: self.px, n: self.n, anchor: self.anchor }
    }

    /// Copies the N x N pixels in use, not the whole block, zeroing those the copy leaves
    /// past them (every template keeps its unused bytes zero): an adapting track keeps the
    /// look of each window vouched for, 400 bytes of a 20x20 template where the block is
    /// 1,024 (on the Cortex-M4, 1,300 instructions a vouched window for the block).
    fn clone_from(&mut self, source: &Self) {
        let (used, was) = (source.n * source.n, self.n * self.n);
        if let (Some(to), Some(from)) = (self.px.get_mut(..used), source.px.get(..used)) {
            to.copy_from_slice(from);
        }
        if let Some(rest) = self.px.get_mut(used..was) {
            rest.fill(0);
        }
        (self.n, self.anchor) = (source.n, source.anchor);
    }
}

/// Equal sides, anchors and N x N pixels: every constructor zeroes the bytes past them, so
/// only the used ones are compared (an adapting track compares its template with its first
/// every frame), a word at a time: the M4's `memcmp` a slice comparison becomes takes a byte
/// at a time, 2,400 instructions for a 20x20 template.
impl PartialEq for Template {
    fn eq(&self, other: &Self) -> bool {
        let (a, b) = (self.pixels(), other.pixels());
        let word = |c: &[u8]| <[u8; 4]>::try_from(c).map_or(0, u32::from_le_bytes);
        let (wa, wb) = (a.chunks_exact(4), b.chunks_exact(4));
        self.n == other.n
            && self.anchor == other.anchor
            && wa.remainder() == wb.remainder()
            && wa.zip(wb).all(|(x, y)| word(x) == word(y))
    }
}

impl Template {
    /// The N x N block of `frame` whose centre is nearest `p`, or `None` if it does not fit
    /// in the view or N is 0 or over [`MAX_TEMPLATE`].
    pub fn capture(frame: &WindowView<'_>, p: Point, n: usize) -> Option<Template> {
        if n == 0 || n > MAX_TEMPLATE {
            return None;
        }
        let half = (n as f32 - 1.0) / 2.0;
        let (ox, oy) = frame.origin();
        let x0 = libm::roundf(p.x - half - ox as f32);
        let y0 = libm::roundf(p.y - half - oy as f32);
        if x0 < 0.0 || y0 < 0.0 {
            return None;
        }
        let sub = frame.sub(x0 as usize, y0 as usize, n, n)?;
        let mut px = [0u8; MAX_TEMPLATE * MAX_TEMPLATE];
        for y in 0..n {
            for (x, v) in sub.row_iter(y).enumerate() {
                if let Some(slot) = px.get_mut(y * n + x) {
                    *slot = v;
                }
            }
        }
        let top_left = Point { x: x0 + ox as f32, y: y0 + oy as f32 };
        Some(Template { px, n, anchor: Point { x: p.x - top_left.x, y: p.y - top_left.y } })
    }

    /// The template's pixels as a view.
    pub fn view(&self) -> Option<WindowView<'_>> {
        WindowView::packed(self.px.get(..self.n * self.n)?, self.n, self.n).ok()
    }

    /// Side N.
    pub fn side(&self) -> usize {
        self.n
    }

    /// The N x N pixels, row by row.
    pub fn pixels(&self) -> &[u8] {
        self.px.get(..self.n * self.n).unwrap_or(&[])
    }

    /// Offset of the tracked point from the top-left pixel.
    pub fn anchor(&self) -> Point {
        self.anchor
    }

    /// A template from its side, anchor and N x N pixels (as a link carries it), or `None`
    /// if N is 0 or over [`MAX_TEMPLATE`] or the pixels are not N x N.
    pub fn from_parts(n: usize, anchor: Point, pixels: &[u8]) -> Option<Template> {
        if n == 0 || n > MAX_TEMPLATE || pixels.len() != n * n {
            return None;
        }
        let mut px = [0u8; MAX_TEMPLATE * MAX_TEMPLATE];
        px[..n * n].copy_from_slice(pixels);
        Some(Template { px, n, anchor })
    }

    /// The tracked point for a template placed with its top-left at `(x, y)`.
    pub(super) fn point_at(&self, x: f32, y: f32) -> Point {
        Point { x: x + self.anchor.x, y: y + self.anchor.y }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A copy into a template in place equals a fresh clone, byte for byte (reference: a clone's
    /// fields), from a larger template into a smaller one and back.
    #[test]
    fn a_copy_in_place_equals_a_clone_byte_for_byte() {
        let frame: [u8; 64] = core::array::from_fn(|k| (k * 37 % 251) as u8 + 1);
        let view = WindowView::packed(&frame, 8, 8).unwrap();
        let (small, large) = (Template::capture(&view, Point { x: 2.5, y: 2.5 }, 3).unwrap(), Template::capture(&view, Point { x: 3.5, y: 3.5 }, 6).unwrap());
        let mut t = large.clone();
        t.clone_from(&small);
        assert_eq!((t.px, t.n, t.anchor), (small.px, small.n, small.anchor));
        t.clone_from(&large);
        assert_eq!((t.px, t.n, t.anchor), (large.px, large.n, large.anchor));
    }

    /// Equality as the derived one would have it over every byte (reference: the fields
    /// compared by hand): a captured template equals the same side, anchor and pixels sent
    /// over a link, and differs in any one of them.
    #[test]
    fn equal_templates_have_equal_sides_anchors_and_pixels() {
        let frame: [u8; 64] = core::array::from_fn(|k| (k * 37 % 251) as u8);
        let view = WindowView::packed(&frame, 8, 8).unwrap();
        let t = Template::capture(&view, Point { x: 3.5, y: 3.5 }, 4).unwrap();
        let same = Template::from_parts(4, t.anchor(), t.pixels()).unwrap();
        assert_eq!(t, same);
        assert_eq!((t.px, t.n, t.anchor), (same.px, same.n, same.anchor));
        let mut pixels = [0u8; 16];
        pixels.copy_from_slice(t.pixels());
        pixels[15] ^= 1;
        assert_ne!(t, Template::from_parts(4, t.anchor(), &pixels).unwrap());
        assert_ne!(t, Template::from_parts(4, Point { x: 1.0, ..t.anchor() }, t.pixels()).unwrap());
        let (small, large) = (Template::from_parts(1, t.anchor(), &[0]).unwrap(), Template::from_parts(2, t.anchor(), &[0; 4]).unwrap());
        assert_ne!(small, large);
    }
}
