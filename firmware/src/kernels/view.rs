//! Borrowed views of window pixels (thesis 2.2-2.3: Watch, Peripheral and Foveal windows).
//!
//! A [`WindowView`] is a rectangle of 8-bit grey pixels inside a row-major buffer,
//! together with the frame coordinates of its top-left pixel. The view pixel `(x, y)`
//! lives at `data[(y * step) * stride + x * step]`; `step` is 1 for a full-resolution
//! view and 2 for the 25 %-resolution view of the Peripheral window (every other pixel
//! of every other row), whose pixel `(x, y)` sits at frame position
//! `(x0 + 2x, y0 + 2y)`.

/// Why a [`WindowView`] could not be built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ViewError {
    /// `stride < width` (rows would overlap).
    StrideTooSmall,
    /// The buffer is shorter than `(height - 1) * stride + width`.
    BufferTooShort,
    /// The dimensions overflow `usize` or the frame coordinates overflow `u32`.
    Overflow,
}

error_messages!(ViewError {
    StrideTooSmall => "the row stride is smaller than the width (rows would overlap)",
    BufferTooShort => "the pixel buffer is shorter than the view needs",
    Overflow => "the view's dimensions or frame coordinates overflow",
});

/// A borrowed, possibly decimated, view of window pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WindowView<'a> {
    data: &'a [u8],
    width: usize,
    height: usize,
    stride: usize,
    step: usize,
    x0: u32,
    y0: u32,
}

impl<'a> WindowView<'a> {
    /// A full-resolution view of `width x height` pixels with row pitch `stride`, whose
    /// top-left pixel is at frame position `(x0, y0)`.
    ///
    /// Empty views (`width == 0` or `height == 0`) are valid; every kernel treats them
    /// as "nothing to see" instead of failing.
    pub fn new(
        data: &'a [u8],
        width: usize,
        height: usize,
        stride: usize,
        x0: u32,
        y0: u32,
    ) -> Result<Self, ViewError> {
        if stride < width {
            return Err(ViewError::StrideTooSmall);
        }
        if width > 0 && height > 0 {
            let need = (height - 1)
                .checked_mul(stride)
                .and_then(|v| v.checked_add(width))
                .ok_or(ViewError::Overflow)?;
            if data.len() < need {
                return Err(ViewError::BufferTooShort);
            }
        }
        // Frame coordinates of the far corner must be representable.
        let w = u32::try_from(width).map_err(|_| ViewError::Overflow)?;
        let h = u32::try_from(height).map_err(|_| ViewError::Overflow)?;
        x0.checked_add(w).ok_or(ViewError::Overflow)?;
        y0.checked_add(h).ok_or(ViewError::Overflow)?;
        Ok(Self {
            data,
            width,
            height,
            stride,
            step: 1,
            x0,
            y0,
        })
    }

    /// A tightly packed (`stride == width`) view with its origin at frame `(0, 0)`.
    pub fn packed(data: &'a [u8], width: usize, height: usize) -> Result<Self, ViewError> {
        Self::new(data, width, height, width, 0, 0)
    }

    /// Width in (view) pixels.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Height in (view) pixels.
    pub fn height(&self) -> usize {
        self.height
    }

    /// Row pitch of the underlying buffer, in buffer bytes.
    pub fn stride(&self) -> usize {
        self.stride
    }

    /// Sampling step in buffer pixels: 1 at full resolution, 2 for the 25 % view.
    pub fn step(&self) -> usize {
        self.step
    }

    /// Frame coordinates of view pixel `(0, 0)`.
    pub fn origin(&self) -> (u32, u32) {
        (self.x0, self.y0)
    }

    /// True when the view has no pixel.
    pub fn is_empty(&self) -> bool {
        self.width == 0 || self.height == 0
    }

    /// Frame coordinates of view pixel `(x, y)`: `(x0 + step*x, y0 + step*y)`.
    ///
    /// Saturates instead of overflowing for positions far outside the view.
    pub fn to_frame(&self, x: usize, y: usize) -> (u32, u32) {
        let conv = |o: u32, v: usize| {
            let v = u32::try_from(v.saturating_mul(self.step)).unwrap_or(u32::MAX);
            o.saturating_add(v)
        };
        (conv(self.x0, x), conv(self.y0, y))
    }

    /// The pixel at view position `(x, y)`, or `None` outside the view.
    #[inline]
    pub fn get(&self, x: usize, y: usize) -> Option<u8> {
        if x >= self.width || y >= self.height {
            return None;
        }
        // In range by the constructor's length check: (y*step)*stride + x*step is a
        // position inside the original full-resolution rectangle.
        self.data
            .get(y * self.step * self.stride + x * self.step)
            .copied()
    }

    /// Row `y` as a contiguous slice, available only for full-resolution views.
    #[inline]
    pub fn row(&self, y: usize) -> Option<&'a [u8]> {
        if self.step != 1 || y >= self.height {
            return None;
        }
        let start = y * self.stride;
        self.data.get(start..start + self.width)
    }

    /// The underlying buffer (starting at view pixel `(0, 0)`) and its stride, for
    /// kernels that walk rows by offset; only for full-resolution views.
    pub(crate) fn raw(&self) -> Option<(&'a [u8], usize)> {
        (self.step == 1).then_some((self.data, self.stride))
    }

    /// The pixels of row `y` in order, for any step (empty outside the view).
    pub fn row_iter(&self, y: usize) -> impl Iterator<Item = u8> + 'a {
        let (start, len) = if y < self.height && self.width > 0 {
            (
                y * self.step * self.stride,
                (self.width - 1) * self.step + 1,
            )
        } else {
            (0, 0)
        };
        self.data
            .get(start..start + len)
            .unwrap_or(&[])
            .iter()
            .step_by(self.step)
            .copied()
    }

    /// The 25 %-resolution view (thesis 2.3, Peripheral window): every other pixel of
    /// every other row, `ceil(w/2) x ceil(h/2)` pixels, same frame origin.
    pub fn decimated(&self) -> WindowView<'a> {
        WindowView {
            width: self.width.div_ceil(2),
            height: self.height.div_ceil(2),
            step: self.step * 2,
            ..*self
        }
    }

    /// A sub-rectangle of this view (in view coordinates), or `None` if it does not fit.
    pub fn sub(&self, x: usize, y: usize, width: usize, height: usize) -> Option<WindowView<'a>> {
        if x.checked_add(width)? > self.width || y.checked_add(height)? > self.height {
            return None;
        }
        let offset = y * self.step * self.stride + x * self.step;
        let (x0, y0) = self.to_frame(x, y);
        Some(WindowView {
            data: self.data.get(offset..).unwrap_or(&[]),
            width,
            height,
            x0,
            y0,
            ..*self
        })
    }

    /// Copies the view into `buf` tightly packed (`stride == width`, step 1) and returns
    /// the packed view with the same frame origin, or `None` if `buf` is too small.
    ///
    /// The packed view keeps the *frame origin* but not the step: matching a packed
    /// decimated view yields positions in decimated pixels, which callers scale by 2.
    pub fn pack_into<'b>(&self, buf: &'b mut [u8]) -> Option<WindowView<'b>> {
        let n = self.width.checked_mul(self.height)?;
        let out = buf.get_mut(..n)?;
        if self.width > 0 {
            for (y, dst) in out.chunks_exact_mut(self.width).enumerate() {
                match self.row(y) {
                    // Full resolution: a row is a slice (the Watch copies whole frames).
                    Some(src) => dst.copy_from_slice(src),
                    // Strided: every `step`-th byte of the row's span, a chunk of `step` at a
                    // time (a stepped iterator costs several times more per pixel).
                    None => {
                        let start = y * self.step * self.stride;
                        match self.data.get(start..start + self.width * 2) {
                            // The 25 % views: pairs of known size, which LLVM gathers in vectors.
                            Some(span) if self.step == 2 => {
                                #[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
                                evens(dst, span);
                                #[cfg(not(all(target_arch = "x86_64", target_feature = "sse2")))]
                                for (d, c) in dst.iter_mut().zip(span.chunks_exact(2)) {
                                    *d = c.first().copied().unwrap_or(0);
                                }
                            }
                            _ => {
                                let span = self.data.get(start..start + (self.width - 1) * self.step + 1).unwrap_or(&[]);
                                for (d, c) in dst.iter_mut().zip(span.chunks(self.step)) {
                                    *d = c.first().copied().unwrap_or(0);
                                }
                            }
                        }
                    }
                }
            }
        }
        Some(WindowView {
            data: out,
            width: self.width,
            height: self.height,
            stride: self.width,
            step: 1,
            x0: self.x0,
            y0: self.y0,
        })
    }
}

/// `dst[i] = span[2i]` (`span` at least twice as long as `dst`), on x86-64 16 or 8 pixels a
/// vector: the pairs' high bytes masked off and the words packed back to bytes (a pixel at a
/// time, LLVM gathered them a byte at a time, 15 % of the 25 % match). A row whose width is
/// not a multiple of the vector's ends with one more vector overlapping the one before.
#[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
fn evens(dst: &mut [u8], span: &[u8]) {
    // SAFETY: the only requirement of a `target_feature` function is that the CPU has the
    // feature, and this is compiled only where SSE2 is part of the build's target.
    #[allow(unsafe_code)]
    unsafe {
        evens_sse2(dst, span);
    }
}

/// [`evens`] itself (the intrinsics are safe to call inside).
#[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
#[target_feature(enable = "sse2")]
fn evens_sse2(dst: &mut [u8], span: &[u8]) {
    use core::arch::x86_64::{_mm_and_si128, _mm_cvtsi128_si64, _mm_packus_epi16, _mm_set1_epi16, _mm_set_epi64x, _mm_unpackhi_epi64};
    let n = dst.len().min(span.len() / 2);
    let low = _mm_set1_epi16(0x00ff);
    // Eight pixels as a 64-bit word (0 past the end).
    let word = |p: &[u8], at: usize| p.get(at..at + 8).and_then(|w| <[u8; 8]>::try_from(w).ok()).map_or(0, i64::from_le_bytes);
    // The even pixels of `span[2·at..2·(at + len)]` into `dst[at..at + len]`, `len` 16 or 8.
    let mut put = |at: usize, len: usize| -> Option<()> {
        let src = span.get(2 * at..2 * (at + len))?;
        let (a, b) = (_mm_set_epi64x(word(src, 8), word(src, 0)), _mm_set_epi64x(word(src, 24), word(src, 16)));
        // Words of at most 255: the saturating pack keeps them exactly.
        let v = _mm_packus_epi16(_mm_and_si128(a, low), _mm_and_si128(b, low));
        let (lo, hi) = (_mm_cvtsi128_si64(v).to_le_bytes(), _mm_cvtsi128_si64(_mm_unpackhi_epi64(v, v)).to_le_bytes());
        dst.get_mut(at..at + 8)?.copy_from_slice(&lo);
        if len == 16 {
            dst.get_mut(at + 8..at + 16)?.copy_from_slice(&hi);
        }
        Some(())
    };
    let len = if n >= 16 { 16 } else { 8 };
    if n < 8 {
        for (d, c) in dst.iter_mut().zip(span.chunks_exact(2)) {
            *d = c.first().copied().unwrap_or(0);
        }
        return;
    }
    let mut at = 0;
    while at + len <= n {
        put(at, len);
        at += len;
    }
    if at < n {
        put(n - len, len);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The vector gather of a row's even pixels against a pixel at a time, for every width up
    /// to 40 (under one vector, one or two of 8, whole and overlapping 16s), from spans just
    /// long enough and longer, with 255s (the pack saturates nothing) and zeros.
    #[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
    #[test]
    fn the_even_pixels_are_every_other_one() {
        let span: std::vec::Vec<u8> = (0..96u32).map(|i| match i % 7 {
            0 => 255,
            3 => 0,
            _ => (i * 37 % 251) as u8,
        }).collect();
        for width in 0..=40 {
            for extra in [0, 1, 9] {
                let src = &span[..2 * width + extra];
                let mut dst = std::vec![0xa5u8; width];
                evens(&mut dst, src);
                let want: std::vec::Vec<u8> = (0..width).map(|i| src[2 * i]).collect();
                assert_eq!(dst, want, "width {width}, span {}", src.len());
            }
        }
    }

    #[test]
    fn rejects_inconsistent_dims() {
        let d = [0u8; 10];
        assert_eq!(
            WindowView::new(&d, 4, 2, 3, 0, 0),
            Err(ViewError::StrideTooSmall)
        );
        assert_eq!(
            WindowView::new(&d, 4, 3, 4, 0, 0),
            Err(ViewError::BufferTooShort)
        );
        // (3-1)*4 + 2 = 10 bytes: exactly enough.
        assert!(WindowView::new(&d, 2, 3, 4, 0, 0).is_ok());
        assert_eq!(
            WindowView::new(&d, 1, 1, 1, u32::MAX, 0),
            Err(ViewError::Overflow)
        );
        assert!(WindowView::new(&[], 0, 5, 0, 0, 0).unwrap().is_empty());
    }

    #[test]
    fn get_row_and_frame_coords() {
        // 3x2 view at column 1 of a 5-wide buffer.
        let d: [u8; 10] = [0, 1, 2, 3, 4, 5, 6, 7, 8, 9];
        let v = WindowView::new(&d[1..], 3, 2, 5, 100, 50).unwrap();
        assert_eq!(v.get(0, 0), Some(1));
        assert_eq!(v.get(2, 1), Some(8));
        assert_eq!(v.get(3, 0), None);
        assert_eq!(v.row(1), Some(&[6u8, 7, 8][..]));
        assert_eq!(v.to_frame(2, 1), (102, 51));
    }

    #[test]
    fn decimated_takes_every_other_pixel_of_every_other_row() {
        let d: [u8; 25] = core::array::from_fn(|i| i as u8);
        let v = WindowView::new(&d, 5, 5, 5, 10, 20).unwrap();
        let q = v.decimated();
        assert_eq!((q.width(), q.height(), q.step()), (3, 3, 2));
        assert_eq!(q.get(0, 0), Some(0));
        assert_eq!(q.get(1, 0), Some(2));
        assert_eq!(q.get(2, 2), Some(24));
        assert_eq!(q.row(0), None);
        let r: [u8; 3] = {
            let mut it = q.row_iter(1);
            core::array::from_fn(|_| it.next().unwrap_or(0))
        };
        assert_eq!(r, [10, 12, 14]);
        assert_eq!(q.to_frame(2, 1), (14, 22));
        let mut buf = [0u8; 9];
        let p = q.pack_into(&mut buf).unwrap();
        assert_eq!(p.row(2), Some(&[20u8, 22, 24][..]));
        assert_eq!(p.origin(), (10, 20));
    }

    #[test]
    fn sub_view() {
        let d: [u8; 16] = core::array::from_fn(|i| i as u8);
        let v = WindowView::new(&d, 4, 4, 4, 3, 3).unwrap();
        let s = v.sub(1, 2, 3, 2).unwrap();
        assert_eq!(s.get(0, 0), Some(9));
        assert_eq!(s.origin(), (4, 5));
        assert!(v.sub(2, 0, 3, 1).is_none());
    }
}

