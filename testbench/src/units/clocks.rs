//! The camera raster in run clocks: where each frame starts, and each frame's raster (with
//! jittered blanking when the run asks for it). Clock 0 is the start of the vertical blanking
//! before frame 0.
use crate::frames::FrameSource;
use coopwin_firmware::types::{Decimation, WindowRequest};
use coopwin_hdl::sim::camera::{CameraBus, FrameRaster, Jitter, RasterTiming};

/// Raster geometry in run clocks: where each frame starts, and each frame's raster (with
/// jittered blanking when the run asks for it).
#[derive(Clone, Debug)]
pub struct Clocks {
    /// The camera's nominal raster.
    pub timing: RasterTiming,
    /// Frames in the run.
    pub frames: usize,
    /// Each frame's raster.
    rasters: Vec<FrameRaster>,
    /// Clock on which each frame's FVAL rises, and the end of the last frame.
    starts: Vec<u64>,
}

impl Clocks {
    /// The raster for a source's frame size: the CA-D1's blanking, scaled to the frame, with
    /// `jitter`'s extra blanking if any.
    pub fn for_frames(source: &dyn FrameSource, jitter: Option<Jitter>) -> Self {
        Clocks::new(Clocks::camera_timing(source.size()), source.len(), jitter)
    }

    /// The nominal raster of `(width, height)` frames: the CA-D1's blanking, scaled to them.
    pub fn camera_timing((width, height): (usize, usize)) -> RasterTiming {
        RasterTiming { width, height, h_blank: 16, v_blank_lines: 2 }
    }

    /// `frames` frames of `timing`, with `jitter`'s extra blanking if any.
    pub fn new(timing: RasterTiming, frames: usize, jitter: Option<Jitter>) -> Self {
        let rasters: Vec<FrameRaster> = (0..frames).map(|k| FrameRaster::new(timing, jitter, k)).collect();
        let blank = (timing.v_blank_lines * timing.line_clocks()) as u64;
        let starts = std::iter::once(blank)
            .chain(rasters.iter().scan(blank, |c, r| {
                *c += r.len() as u64;
                Some(*c)
            }))
            .collect();
        Clocks { timing, frames, rasters, starts }
    }
    /// Clocks a frame period (the mean, with jitter).
    pub fn period(&self) -> u64 {
        match self.frames {
            0 => self.timing.frame_clocks() as u64,
            n => (self.starts[n] - self.starts[0]) / n as u64,
        }
    }
    /// The blanking before frame 0.
    pub fn blank(&self) -> u64 {
        self.starts[0]
    }
    /// Clock on which frame k's FVAL rises (for k past the run, as if it went on unjittered).
    pub fn frame_start(&self, k: usize) -> u64 {
        match self.starts.get(k) {
            Some(&c) => c,
            None => self.starts[self.frames] + (k - self.frames) as u64 * self.timing.frame_clocks() as u64,
        }
    }
    /// The frame whose period holds clock `c` (0 before frame 0).
    pub fn frame_at(&self, c: u64) -> usize {
        let end = self.starts[self.frames];
        if c >= end {
            return self.frames + ((c - end) / self.timing.frame_clocks() as u64) as usize;
        }
        self.starts.partition_point(|&s| s <= c).saturating_sub(1)
    }
    /// The first frame whose FVAL rises on or after clock `c`.
    pub fn first_frame_from(&self, c: u64) -> usize {
        let end = self.starts[self.frames];
        if c > end {
            return self.frames + (c - end).div_ceil(self.timing.frame_clocks() as u64) as usize;
        }
        self.starts.partition_point(|&s| s < c)
    }
    /// The first clock at or after `c` that lies `phase` clocks after a frame's FVAL rising.
    pub fn next_phase(&self, c: u64, phase: u64) -> u64 {
        let k = self.frame_at(c);
        let t = self.frame_start(k) + phase;
        if t >= c {
            t
        } else {
            self.frame_start(k + 1) + phase
        }
    }
    /// The camera bus on run clock `c`, with frame `k`'s pixels when `c` falls in frame `k`'s
    /// period, and that frame.
    pub(crate) fn bus(&self, c: u64, frame: Option<(usize, &[u8])>) -> (CameraBus, Option<usize>) {
        let b = self.blank();
        if c < b {
            // The blanking lines of the frame before the run.
            let p = self.timing.frame_clocks() as u64;
            return (self.timing.bus_at((p - b + c) as usize, |_, _| 0u8), None);
        }
        let Some((k, pixels)) = frame else { return (CameraBus::default(), None) };
        let Some(raster) = self.rasters.get(k) else { return (CameraBus::default(), None) };
        let w = self.timing.width;
        let r = (c - self.frame_start(k)) as usize;
        (raster.bus_at(r, |x, y| pixels.get(y * w + x).copied().unwrap_or(0)), Some(k))
    }
    /// Clocks from frame k's FVAL rising to the clock the window's last pixel is strobed.
    pub(crate) fn last_strobe(&self, k: usize, req: &WindowRequest) -> u64 {
        let (w, h) = delivered_extent(req);
        let x = usize::from(req.x0) + w as usize - 1;
        let y = usize::from(req.y0) + h as usize - 1;
        // The unit strobes a pixel one clock after it is on the bus.
        self.rasters.get(k).map_or(0, |r| r.pixel_clock(x, y)) as u64 + 1
    }
}

/// Columns and rows spanned from the window's first to its last delivered pixel.
fn delivered_extent(req: &WindowRequest) -> (u64, u64) {
    let (w, h) = (u64::from(req.width), u64::from(req.height));
    match req.decimation {
        Decimation::Full => (w, h),
        // The last delivered pixel is the last one an even distance from xmin (and ymin).
        Decimation::Quarter => ((w - 1) / 2 * 2 + 1, (h - 1) / 2 * 2 + 1),
    }
}
