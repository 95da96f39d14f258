//! Hand-made inputs for the processors' unit tests: a 64x64 frame of grey 50 with a 4x4 block
//! of 200 whose top-left pixel is chosen by the test, the windows a request cuts from it, and
//! random texture.
use super::params::Params;
use super::template::Template;
use crate::kernels::view::WindowView;
use crate::types::{Decimation, Point, WindowRequest};
use std::vec::Vec;

/// Frame side.
pub const SIDE: usize = 64;

/// Small windows for a 64x64 frame: 8x8 template, 16x16 Foveal, 16x16 then 24x24 Peripheral.
pub fn params() -> Params {
    Params { frame_w: 64, frame_h: 64, template: 8, foveal: 16, peripheral: [16, 24], ..Params::default() }
}

/// The frame with the block's top-left pixel at `at` (no block for `None`).
pub fn frame(at: Option<(usize, usize)>) -> Vec<u8> {
    let mut f = std::vec![50u8; SIDE * SIDE];
    if let Some((x0, y0)) = at {
        for y in y0..y0 + 4 {
            for x in x0..x0 + 4 {
                f[y * SIDE + x] = 200;
            }
        }
    }
    f
}

/// The pixels the window unit delivers for `req` (every other pixel of every other row at 25 %).
pub fn cut<'a>(frame: &'a [u8], req: &WindowRequest) -> WindowView<'a> {
    let full = WindowView::packed(frame, SIDE, SIDE).unwrap();
    let sub = full.sub(req.x0.into(), req.y0.into(), req.width.into(), req.height.into()).unwrap();
    match req.decimation {
        Decimation::Full => sub,
        Decimation::Quarter => sub.decimated(),
    }
}

/// The block of `frame(Some((30, 20)))` is centred on this point.
pub const TARGET: Point = Point { x: 31.5, y: 21.5 };

/// The 8x8 template around [`TARGET`]: columns 28..=35, rows 18..=25, the block in its middle.
pub fn template() -> Template {
    let f = frame(Some((30, 20)));
    Template::capture(&WindowView::packed(&f, SIDE, SIDE).unwrap(), TARGET, 8).unwrap()
}

/// A `side`x`side` window with its top-left pixel at `(x0, y0)`.
pub fn square(x0: u16, y0: u16, side: u16, decimation: Decimation) -> WindowRequest {
    WindowRequest { x0, y0, width: side, height: side, decimation }
}

/// `len` pixels of random texture, grey `base` to `base + 127` (a linear congruential
/// generator's high byte, halved), drawn from `state`.
pub fn texture(state: &mut u32, len: usize, base: u8) -> Vec<u8> {
    (0..len)
        .map(|_| {
            *state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            base + (*state >> 24) as u8 / 2
        })
        .collect()
}
