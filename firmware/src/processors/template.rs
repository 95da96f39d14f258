//! The target template (thesis 2.3.2, 2.4): the N x N block captured at lock-on, matched by
//! the Peripheral (SSD at 25 %) and Foveal (NCC) processors and sent between them.
use crate::kernels::view::WindowView;
use crate::types::Point;

/// Largest template side.
pub const MAX_TEMPLATE: usize = 32;


/// The target template: an N x N block and the offset of the tracked point from its
/// top-left pixel (N/2 - 0.5 when the point was the block's centre).
#[derive(Clone, Debug)]
pub struct Template {
    px: [u8; MAX_TEMPLATE * MAX_TEMPLATE],
    n: usize,
    anchor: Point,
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
