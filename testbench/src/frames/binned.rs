//! A binning camera (issue 38 item 4): each K x K block of the sensor's pixels read out as
//! their mean, as a sensor bins, so that the firmware's template (32x32 at most) covers more
//! of an object larger than it, at a coarser scale. Targets, positions and the frame rate stay
//! the sensor's; the window units and the processors see the binned frames.
use super::{FrameError, FrameSource};

/// The largest binning `track` chooses or takes.
pub const MAX_BIN: usize = 8;

/// The binned box's shorter side, at least (px): vtest's man in jeans was vouched for on the
/// woman in black who walks in front of him where his box was binned to 17 px across (45
/// wrong rows, stop 55: his 17x17 template, a patch of dark cloth, matched her legs at 0.83)
/// and, upscaled to 1080p (85x146), to 21 (3 wrong rows at 4x4, none at 3x3: 28 across); the
/// coat's and the redcoat's 22 and 24 gave none (stop 56).
pub const BINNED_SHORT_SIDE: u32 = 22;

/// The binned box's longer side, at least (px): the largest template, so that a box under
/// twice its side along is not binned (the footage's 32x32 boxes, the long-term sets' 48x48).
pub const BINNED_LONG_SIDE: u32 = 32;

/// The smallest binned frame side: the least the input and the window units take.
pub const MIN_SIDE: usize = *super::folder::SIDES.start();

/// The binning for a target box `w` x `h` on frames of `size`: the largest K at which the
/// box binned is still [`BINNED_SHORT_SIDE`] across and [`BINNED_LONG_SIDE`] along, and the
/// frame [`MIN_SIDE`] a side; 1 where the box is too small to bin.
pub fn factor_for_box((w, h): (u32, u32), size: (usize, usize)) -> usize {
    let k = (w.min(h) / BINNED_SHORT_SIDE).min(w.max(h) / BINNED_LONG_SIDE) as usize;
    let fits = |k: usize| size.0 / k >= MIN_SIDE && size.1 / k >= MIN_SIDE;
    (1..=k.clamp(1, MAX_BIN)).rev().find(|&k| fits(k)).unwrap_or(1)
}

/// The template side `--target-box` takes for a `w` x `h` box on frames binned `k` x `k`: the
/// box's shorter side binned, up to the firmware's 32.
pub fn box_template((w, h): (u32, u32), k: usize) -> u16 {
    (w.min(h) / k.max(1) as u32).min(32) as u16
}

/// The binning and the template side `--target-box` takes for a `w` x `h` box on frames of
/// `size`: [`factor_for_box`] and [`box_template`] at it.
pub fn for_box(wh: (u32, u32), size: (usize, usize)) -> (usize, u16) {
    let k = factor_for_box(wh, size);
    (k, box_template(wh, k))
}

/// Frames of `size` binned `k` x `k`: the right and bottom remainders are dropped.
pub fn binned_size((w, h): (usize, usize), k: usize) -> (usize, usize) {
    (w / k.max(1), h / k.max(1))
}

/// A sensor point (pixel centres at integers) in the frames binned `k` x `k`.
pub fn to_binned((x, y): (f64, f64), k: usize) -> (f64, f64) {
    let k = k as f64;
    ((x + 0.5) / k - 0.5, (y + 0.5) / k - 0.5)
}

/// A point of the frames binned `k` x `k` in the sensor's pixels.
pub fn to_sensor((x, y): (f64, f64), k: usize) -> (f64, f64) {
    let k = k as f64;
    ((x + 0.5) * k - 0.5, (y + 0.5) * k - 0.5)
}

/// `source`'s frames binned `k` x `k`: each pixel the rounded mean of its block.
pub struct Binned<'a> {
    source: &'a mut dyn FrameSource,
    k: usize,
    size: (usize, usize),
    px: Vec<u8>,
    held: Option<usize>,
}

impl<'a> Binned<'a> {
    /// Bins `source`'s frames `k` x `k` (`k` from 1 to the frames' shorter side).
    pub fn new(source: &'a mut dyn FrameSource, k: usize) -> Self {
        let (w, h) = source.size();
        let k = k.clamp(1, w.min(h).max(1));
        let size = binned_size(source.size(), k);
        Binned { source, k, size, px: vec![0; size.0 * size.1], held: None }
    }
}

impl FrameSource for Binned<'_> {
    fn size(&self) -> (usize, usize) {
        self.size
    }
    fn len(&self) -> usize {
        self.source.len()
    }
    fn frame(&mut self, f: usize) -> Result<&[u8], FrameError> {
        if self.held != Some(f) {
            self.held = None;
            let (k, sensor_w, (w, h)) = (self.k, self.source.size().0, self.size);
            let full = self.source.frame(f)?;
            let half = (k * k / 2) as u32;
            for (y, row) in self.px.chunks_exact_mut(w).take(h).enumerate() {
                for (x, out) in row.iter_mut().enumerate() {
                    let sum: u32 = (0..k).flat_map(|dy| full[(y * k + dy) * sensor_w + x * k..][..k].iter()).map(|&p| u32::from(p)).sum();
                    *out = ((sum + half) / (k * k) as u32) as u8;
                }
            }
            self.held = Some(f);
        }
        Ok(&self.px)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct One(Vec<u8>, (usize, usize));
    impl FrameSource for One {
        fn size(&self) -> (usize, usize) {
            self.1
        }
        fn len(&self) -> usize {
            1
        }
        fn frame(&mut self, k: usize) -> Result<&[u8], FrameError> {
            if k == 0 {
                Ok(&self.0)
            } else {
                Err(FrameError::Missing(k))
            }
        }
    }

    #[test]
    fn each_pixel_is_its_blocks_rounded_mean_and_the_remainders_are_dropped() {
        // A 5x3 sensor binned 2x2: 2x1 pixels. Reference: the means by hand.
        let mut sensor = One(vec![0, 1, 10, 20, 99, 2, 3, 30, 41, 99, 99, 99, 99, 99, 99], (5, 3));
        let mut b = Binned::new(&mut sensor, 2);
        assert_eq!(b.size(), (2, 1));
        // (0+1+2+3)/4 = 1.5 rounds to 2; (10+20+30+41)/4 = 25.25 to 25.
        assert_eq!(b.frame(0).unwrap(), &[2, 25]);
        assert!(matches!(b.frame(1), Err(FrameError::Missing(1))));
    }

    #[test]
    fn points_map_to_the_binned_pixel_that_covers_them_and_back() {
        // Sensor pixels 0 and 1 make binned pixel 0, whose centre is the sensor's 0.5.
        assert_eq!(to_binned((0.5, 2.5), 2), (0.0, 1.0));
        assert_eq!(to_sensor((0.0, 1.0), 2), (0.5, 2.5));
        assert_eq!(to_sensor(to_binned((123.25, 7.0), 3), 3), (123.25, 7.0));
    }

    #[test]
    fn a_box_is_binned_while_it_stays_22_across_and_32_along() {
        let vga = (768, 576);
        // vtest's coat (44x80) and redcoat (48x96): 2; its jeans (34x78): 17 across binned, 1.
        assert_eq!(factor_for_box((44, 80), vga), 2);
        assert_eq!(factor_for_box((48, 96), vga), 2);
        assert_eq!(factor_for_box((34, 78), vga), 1);
        // The boxes the template spans: the footage's 32x32, the sets' 48x48.
        assert_eq!(factor_for_box((32, 32), vga), 1);
        assert_eq!(factor_for_box((48, 48), vga), 1);
        // The 1080p jeans (85x146): 3 (28x48). A box over a small frame: the frame
        // binned stays 64 a side (100 / 2 = 50 would not).
        assert_eq!(factor_for_box((85, 146), (1920, 1080)), 3);
        assert_eq!(factor_for_box((64, 96), (100, 100)), 1);
        assert_eq!(factor_for_box((400, 800), (4096, 4096)), MAX_BIN);
    }
}
