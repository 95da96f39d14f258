//! Camera raster generator (testbench side): the synchronisation signals and pixel stream of
//! the Dalsa CA-D1 (thesis 2.2.1: 256x256, 8-bit, up to 200 frames/s, run at 114 frames/s with
//! an ~8 MHz pixel clock, 2.5), clock by clock.
//!
//! One frame is `fval` high around `height` lines of `width` clocks with `lval` high, separated
//! by `h_blank` clocks of `lval` low; `fval` falls `h_blank` clocks after the last line and stays
//! low for `v_blank_lines` blanking lines, during which `lval` still pulses (thesis B1.1 step 3:
//! "the end of a line of invalid pixel data").

/// The camera's outputs on one pixel clock.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CameraBus {
    /// Frame valid (FVAL).
    pub fval: bool,
    /// Line valid (LVAL).
    pub lval: bool,
    /// Pixel value (OD0-OD7, up to 16 bits); meaningful while `fval & lval & pixel_valid`.
    pub pixel: u16,
    /// A pixel is on the bus this clock (with `fval & lval`); the CA-D1 holds it high.
    pub pixel_valid: bool,
}

/// Geometry and blanking of the raster.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RasterTiming {
    /// Pixels per line.
    pub width: usize,
    /// Lines per frame.
    pub height: usize,
    /// Clocks with `lval` low between lines (at least 2).
    pub h_blank: usize,
    /// Blanking lines between frames, each with its `lval` pulse while `fval` is low.
    pub v_blank_lines: usize,
}

/// Pixel clock of the CA-D1 as modelled here: 8 MHz.
pub const CA_D1_PIXEL_CLOCK_HZ: f64 = 8.0e6;

impl RasterTiming {
    /// The CA-D1 at 114 frames/s: 256x256, 16 clocks of line blanking and 2 blanking lines give
    /// 70 192 clocks a frame (16 + 258 lines of 272), i.e. 113.97 frames/s at 8 MHz.
    pub const CA_D1: RasterTiming = RasterTiming {
        width: 256,
        height: 256,
        h_blank: 16,
        v_blank_lines: 2,
    };

    /// Clocks from one line start to the next.
    pub fn line_clocks(&self) -> usize {
        self.width + self.h_blank
    }

    /// Clocks in one frame period, blanking included.
    pub fn frame_clocks(&self) -> usize {
        // A leading gap, the active lines, then the blanking lines.
        self.h_blank + (self.height + self.v_blank_lines) * self.line_clocks()
    }

    /// Frames per second at the given pixel clock.
    pub fn frame_rate(&self, pixel_clock_hz: f64) -> f64 {
        pixel_clock_hz / self.frame_clocks() as f64
    }

    /// The camera bus on clock `t` (0-based) of a frame, with `image(x, y)` the pixel values.
    ///
    /// Clock 0 is the rising edge of `fval`, with `lval` low; `h_blank` clocks later the first
    /// line starts. After the last line `fval` falls `h_blank` clocks after `lval`, then each
    /// blanking line has `lval` high for `width` clocks starting `h_blank` clocks into it.
    pub fn bus_at<T: Into<u16>>(&self, t: usize, image: impl Fn(usize, usize) -> T) -> CameraBus {
        let line = self.line_clocks();
        let active_end = self.h_blank + self.height * line;
        if t < self.h_blank {
            CameraBus {
                fval: true,
                lval: false,
                pixel: 0,
                pixel_valid: true,
            }
        } else if t < active_end {
            let (y, in_line) = ((t - self.h_blank) / line, (t - self.h_blank) % line);
            let lval = in_line < self.width;
            let pixel = if lval { image(in_line, y).into() } else { 0 };
            CameraBus {
                fval: true,
                lval,
                pixel,
                pixel_valid: true,
            }
        } else {
            // Blanking: lval pulses for `width` clocks after `h_blank` clocks of each line slot.
            let in_line = (t - active_end) % line;
            let lval = in_line >= self.h_blank;
            CameraBus {
                fval: false,
                lval,
                pixel: 0,
                pixel_valid: true,
            }
        }
    }
}

impl RasterTiming {
    /// One frame period clock by clock, as [`bus_at`](Self::bus_at) gives it, but with
    /// `gaps(x, y)` clocks of `pixel_valid` low (LVAL held high) before pixel (x, y): a sensor
    /// that sends a pixel over several clocks (RGB565 on a byte-wide bus) or stalls mid-line.
    pub fn frame_with_gaps<T: Into<u16>>(
        &self,
        image: impl Fn(usize, usize) -> T,
        mut gaps: impl FnMut(usize, usize) -> usize,
    ) -> Vec<CameraBus> {
        let bus = |fval, lval, pixel, pixel_valid| CameraBus { fval, lval, pixel, pixel_valid };
        let mut out = vec![bus(true, false, 0, true); self.h_blank];
        for y in 0..self.height {
            for x in 0..self.width {
                out.extend(std::iter::repeat_n(bus(true, true, 0, false), gaps(x, y)));
                out.push(bus(true, true, image(x, y).into(), true));
            }
            out.extend(std::iter::repeat_n(bus(true, false, 0, true), self.h_blank));
        }
        for _ in 0..self.v_blank_lines {
            out.extend(std::iter::repeat_n(bus(false, false, 0, true), self.h_blank));
            out.extend(std::iter::repeat_n(bus(false, true, 0, true), self.width));
        }
        out
    }
}

/// Blanking that varies from line to line and frame to frame (the fault campaign's "random
/// camera blanking"): extra clocks of line blanking before each line, and of frame blanking
/// after each frame's blanking lines, drawn from a seed. The window logic needs only FVAL and
/// LVAL, so it must deliver the same pixels whatever the blanking.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Jitter {
    /// Seed of the draw.
    pub seed: u64,
    /// Most extra clocks of line blanking before a line.
    pub line_max: u32,
    /// Most extra clocks of frame blanking after a frame.
    pub frame_max: u32,
}

/// SplitMix64's finaliser: 64 well-mixed bits from `z` (Steele, Lea and Flood 2014), for the
/// jitter draws here and the testbench's scene generator.
pub fn splitmix64(z: u64) -> u64 {
    let z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    let z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

impl Jitter {
    /// Extra clocks for slot `slot` of frame `k` (a line, or `usize::MAX` for the frame's end).
    fn draw(&self, k: usize, slot: usize, max: u32) -> u32 {
        let z = splitmix64(self.seed ^ (k as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15) ^ (slot as u64).wrapping_mul(0xc2b2_ae3d_27d4_eb4f));
        (z % (u64::from(max) + 1)) as u32
    }
}

/// One frame of the raster with its extra blanking, if any: the nominal frame of
/// [`RasterTiming::bus_at`] with idle clocks (LVAL low) inserted before each line and after the
/// frame's blanking lines.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FrameRaster {
    timing: RasterTiming,
    /// Per line y: the clock its inserted blanking starts, and the clocks inserted up to and
    /// including it. Empty without jitter.
    lines: Vec<(usize, usize)>,
    /// Clocks inserted after the blanking lines.
    tail: usize,
}

impl FrameRaster {
    /// Frame `k` of `timing`, with `jitter`'s extra blanking.
    pub fn new(timing: RasterTiming, jitter: Option<Jitter>, k: usize) -> Self {
        let (mut lines, mut tail) = (Vec::new(), 0);
        if let Some(j) = jitter {
            let mut inserted = 0;
            for y in 0..timing.height {
                let start = timing.h_blank + y * timing.line_clocks() + inserted;
                inserted += j.draw(k, y, j.line_max) as usize;
                lines.push((start, inserted));
            }
            tail = j.draw(k, usize::MAX, j.frame_max) as usize;
        }
        FrameRaster { timing, lines, tail }
    }

    fn inserted(&self) -> usize {
        self.lines.last().map_or(0, |l| l.1)
    }

    /// Clocks from this frame's FVAL rising to the next frame's.
    pub fn len(&self) -> usize {
        self.timing.frame_clocks() + self.inserted() + self.tail
    }

    /// True for a frame of no clocks (never: a frame has at least its blanking).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The clock (from FVAL rising) on which pixel (x, y) is on the bus.
    pub fn pixel_clock(&self, x: usize, y: usize) -> usize {
        let nominal = self.timing.h_blank + y * self.timing.line_clocks() + x;
        nominal + self.lines.get(y).map_or(0, |l| l.1)
    }

    /// The camera bus on clock `t` of the frame (0 is FVAL rising), `image(x, y)` the pixels.
    pub fn bus_at<T: Into<u16>>(&self, t: usize, image: impl Fn(usize, usize) -> T) -> CameraBus {
        let idle = |fval| CameraBus { fval, lval: false, pixel: 0, pixel_valid: true };
        // The last line whose inserted blanking has started by `t`.
        let nominal = match self.lines.partition_point(|l| l.0 <= t).checked_sub(1) {
            None => t,
            Some(y) => {
                let inserted = self.lines[y].1;
                // Line y's first pixel is on clock `pixel_clock(0, y)`; before it, idle clocks.
                if t < self.pixel_clock(0, y) {
                    return idle(true);
                }
                t - inserted
            }
        };
        if nominal >= self.timing.frame_clocks() {
            return idle(false);
        }
        self.timing.bus_at(nominal, image)
    }
}

/// A rectangular window, bounds inclusive, rows and columns 0-based (the contract's convention).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Window {
    /// First column.
    pub xmin: u32,
    /// Last column.
    pub xmax: u32,
    /// First row.
    pub ymin: u32,
    /// Last row.
    pub ymax: u32,
}

impl Window {
    /// The four coordinates in the order the port takes them.
    pub fn bytes(&self) -> [u32; 4] {
        [self.xmin, self.xmax, self.ymin, self.ymax]
    }

    /// Valid iff xmin < xmax and ymin < ymax (thesis 2.2.1, rows made 0-based).
    pub fn is_valid(&self) -> bool {
        self.xmin < self.xmax && self.ymin < self.ymax
    }

    /// The software crop the window unit must deliver: the pixels of the window in raster
    /// order, every other pixel of every other row when `decimate`.
    pub fn crop<T: Copy>(&self, frame: &[T], width: usize, decimate: bool) -> Vec<T> {
        let step = if decimate { 2 } else { 1 };
        let (x0, x1) = (self.xmin as usize, self.xmax as usize + 1);
        let mut out = Vec::with_capacity((x1 - x0).div_ceil(step) * (self.ymax - self.ymin + 1) as usize);
        if !decimate && x0 == 0 && x1 == width {
            // Whole rows (the Watch's frame): one block, not a copy a row.
            out.extend_from_slice(&frame[self.ymin as usize * width..(self.ymax as usize + 1) * width]);
            return out;
        }
        for y in (self.ymin as usize..=self.ymax as usize).step_by(step) {
            let row = &frame[y * width + x0..y * width + x1];
            // A slice copy, and pairs rather than `step_by`: the testbench crops every window
            // of a run here, and `step_by`'s element-wise fold was half a run's host time.
            if decimate {
                out.extend(row.chunks(2).map(|pair| pair[0]));
            } else {
                out.extend_from_slice(row);
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crop_takes_the_windows_pixels_and_every_other_one_decimated() {
        // A 6x5 frame whose pixel is its raster index; the window is columns 1..=3 (an odd
        // width) of rows 1..=4. Hand-listed: full, its 12 pixels row by row; decimated, columns
        // 1 and 3 of rows 1 and 3.
        let frame: Vec<u8> = (0..30).collect();
        let w = Window { xmin: 1, xmax: 3, ymin: 1, ymax: 4 };
        assert_eq!(w.crop(&frame, 6, false), [7, 8, 9, 13, 14, 15, 19, 20, 21, 25, 26, 27]);
        assert_eq!(w.crop(&frame, 6, true), [7, 9, 19, 21]);
        // Whole rows 2..=3 (one block): pixels 12 to 23.
        let rows = Window { xmin: 0, xmax: 5, ymin: 2, ymax: 3 };
        assert_eq!(rows.crop(&frame, 6, false), (12..24).collect::<Vec<u8>>());
    }

    #[test]
    fn ca_d1_runs_at_114_frames_per_second() {
        // Thesis 2.5: 114 frames/s at an ~8 MHz pixel valid clock.
        let rate = RasterTiming::CA_D1.frame_rate(CA_D1_PIXEL_CLOCK_HZ);
        assert!((rate - 114.0).abs() < 0.05, "{rate}");
    }

    #[test]
    fn raster_has_exact_lines_and_blanking_pulses() {
        let t = RasterTiming {
            width: 5,
            height: 3,
            h_blank: 2,
            v_blank_lines: 2,
        };
        let buses: Vec<_> = (0..t.frame_clocks())
            .map(|c| t.bus_at(c, |x, y| (10 * y + x) as u8))
            .collect();
        // Hand count: 3 lines of 5 pixels inside fval, 2 blanking pulses of 5 outside.
        let active: Vec<u16> = buses
            .iter()
            .filter(|b| b.fval && b.lval)
            .map(|b| b.pixel)
            .collect();
        assert_eq!(
            active,
            vec![0, 1, 2, 3, 4, 10, 11, 12, 13, 14, 20, 21, 22, 23, 24]
        );
        assert_eq!(buses.iter().filter(|b| !b.fval && b.lval).count(), 10);
        assert!(
            !buses[0].lval && buses[0].fval,
            "fval rises while lval is low"
        );
        // fval falls h_blank clocks after the last line's lval falls.
        let last_active = buses.iter().rposition(|b| b.fval && b.lval).unwrap();
        let fval_fall = buses.iter().position(|b| !b.fval).unwrap();
        assert_eq!(fval_fall - last_active - 1, 2);
    }

    #[test]
    fn a_frame_without_gaps_is_the_nominal_raster() {
        let t = RasterTiming { width: 7, height: 4, h_blank: 3, v_blank_lines: 2 };
        let image = |x: usize, y: usize| (10 * y + x) as u16;
        let nominal: Vec<CameraBus> = (0..t.frame_clocks()).map(|c| t.bus_at(c, image)).collect();
        assert_eq!(t.frame_with_gaps(image, |_, _| 0), nominal);
        // With gaps: the same pixels in order, LVAL one pulse a line, `pixel_valid` low only
        // inside lines, and the clocks counted by hand: 28 pixels + 2 gap clocks each.
        let gapped = t.frame_with_gaps(image, |_, _| 2);
        assert_eq!(gapped.len(), t.frame_clocks() + 28 * 2);
        let pixels: Vec<u16> = gapped.iter().filter(|b| b.fval && b.lval && b.pixel_valid).map(|b| b.pixel).collect();
        let expected: Vec<u16> = nominal.iter().filter(|b| b.fval && b.lval).map(|b| b.pixel).collect();
        assert_eq!(pixels, expected);
        assert!(gapped.iter().filter(|b| !b.pixel_valid).all(|b| b.fval && b.lval));
    }

    #[test]
    fn jittered_frame_keeps_its_pixels_and_inserts_only_blanking() {
        let t = RasterTiming {
            width: 6,
            height: 5,
            h_blank: 3,
            v_blank_lines: 2,
        };
        let image = |x: usize, y: usize| (10 * y + x) as u8;
        let j = Jitter {
            seed: 7,
            line_max: 9,
            frame_max: 40,
        };
        let nominal = FrameRaster::new(t, None, 0);
        assert_eq!(nominal.len(), t.frame_clocks());
        for c in 0..t.frame_clocks() {
            assert_eq!(nominal.bus_at(c, image), t.bus_at(c, image), "clock {c}");
        }
        let mut gaps = std::collections::BTreeSet::new();
        for k in 0..4 {
            let f = FrameRaster::new(t, Some(j), k);
            let buses: Vec<_> = (0..f.len()).map(|c| f.bus_at(c, image)).collect();
            // The same pixels in the same order, the same LVAL pulses, FVAL one run from 0.
            let active: Vec<u16> = buses.iter().filter(|b| b.fval && b.lval).map(|b| b.pixel).collect();
            let expected: Vec<u16> = (0..5).flat_map(|y| (0..6).map(move |x| image(x, y).into())).collect();
            assert_eq!(active, expected);
            assert_eq!(buses.iter().filter(|b| !b.fval && b.lval).count(), 2 * 6);
            let fall = buses.iter().position(|b| !b.fval).unwrap();
            assert!(buses[fall..].iter().all(|b| !b.fval));
            // Every pixel is where `pixel_clock` says.
            for (x, y) in (0..5).flat_map(|y| (0..6).map(move |x| (x, y))) {
                let b = buses[f.pixel_clock(x, y)];
                assert!(b.fval && b.lval && b.pixel == image(x, y).into(), "pixel ({x}, {y})");
            }
            // Line gaps vary, never shorter than the nominal blanking.
            let mut run = 0;
            for b in &buses[..fall] {
                if b.lval {
                    if run > 0 {
                        gaps.insert(run);
                    }
                    run = 0;
                } else {
                    run += 1;
                }
            }
            assert!(f.len() >= t.frame_clocks());
        }
        assert!(gaps.iter().all(|&g| g >= 3), "{gaps:?}");
        assert!(gaps.len() > 4, "the draw varies the gaps: {gaps:?}");
    }
}
