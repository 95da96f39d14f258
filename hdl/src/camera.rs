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
    /// Pixel value (OD0-OD7); meaningful while `fval & lval`.
    pub pixel: u8,
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
    /// 70 176 clocks a frame, i.e. 114.0 frames/s at 8 MHz.
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
    pub fn bus_at(&self, t: usize, image: impl Fn(usize, usize) -> u8) -> CameraBus {
        let line = self.line_clocks();
        let active_end = self.h_blank + self.height * line;
        if t < self.h_blank {
            CameraBus {
                fval: true,
                lval: false,
                pixel: 0,
            }
        } else if t < active_end {
            let (y, in_line) = ((t - self.h_blank) / line, (t - self.h_blank) % line);
            let lval = in_line < self.width;
            let pixel = if lval { image(in_line, y) } else { 0 };
            CameraBus {
                fval: true,
                lval,
                pixel,
            }
        } else {
            // Blanking: lval pulses for `width` clocks after `h_blank` clocks of each line slot.
            let in_line = (t - active_end) % line;
            let lval = in_line >= self.h_blank;
            CameraBus {
                fval: false,
                lval,
                pixel: 0,
            }
        }
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
    /// The four coordinate bytes in the order the port takes them.
    pub fn bytes(&self) -> [u32; 4] {
        [self.xmin, self.xmax, self.ymin, self.ymax]
    }

    /// Valid iff xmin < xmax and ymin < ymax (thesis 2.2.1, rows made 0-based).
    pub fn is_valid(&self) -> bool {
        self.xmin < self.xmax && self.ymin < self.ymax
    }

    /// The software crop the window unit must deliver: the pixels of the window in raster
    /// order, every other pixel of every other row when `decimate`.
    pub fn crop(&self, frame: &[u8], width: usize, decimate: bool) -> Vec<u8> {
        let step = if decimate { 2 } else { 1 };
        let mut out = Vec::new();
        for y in (self.ymin..=self.ymax).step_by(step) {
            for x in (self.xmin..=self.xmax).step_by(step) {
                out.push(frame[y as usize * width + x as usize]);
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
        let active: Vec<u8> = buses
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
}
