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
    /// Frames in the run ([`Clocks::OPEN_ENDED`] for frames handed in one at a time, with no
    /// end known).
    pub frames: usize,
    /// Each frame's jittered raster; without jitter none is kept, every frame's being the
    /// nominal one (so a run with no end known needs no memory per frame).
    rasters: Vec<FrameRaster>,
    /// Clock on which each of `rasters`' frames' FVAL rises, and the end of the last one.
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

    /// The frame count of a run whose frames are handed in one at a time (the Python
    /// package's trackers): it goes on until its source stops.
    pub const OPEN_ENDED: usize = usize::MAX;

    /// `frames` frames of `timing`, with `jitter`'s extra blanking if any (an open-ended run
    /// takes none: its rasters are nominal).
    pub fn new(timing: RasterTiming, frames: usize, jitter: Option<Jitter>) -> Self {
        let jittered = if frames == Self::OPEN_ENDED { 0 } else { jitter.map_or(0, |_| frames) };
        let rasters: Vec<FrameRaster> = (0..jittered).map(|k| FrameRaster::new(timing, jitter, k)).collect();
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
        match self.rasters.len() {
            0 => self.timing.frame_clocks() as u64,
            n => (self.starts[n] - self.starts[0]) / n as u64,
        }
    }
    /// The blanking before frame 0.
    pub fn blank(&self) -> u64 {
        self.starts[0]
    }
    /// The first frame with the nominal raster, and the clock its FVAL rises on.
    fn nominal_from(&self) -> (usize, u64) {
        let known = self.rasters.len();
        (known, self.starts[known])
    }
    /// Frame `k`'s raster, if `k` is a frame of the run.
    fn raster(&self, k: usize) -> Option<std::borrow::Cow<'_, FrameRaster>> {
        match self.rasters.get(k) {
            Some(r) => Some(std::borrow::Cow::Borrowed(r)),
            None => (k < self.frames).then(|| std::borrow::Cow::Owned(FrameRaster::new(self.timing, None, k))),
        }
    }
    /// Clock on which frame k's FVAL rises (past the jittered rasters, as if the run went on
    /// unjittered).
    pub fn frame_start(&self, k: usize) -> u64 {
        let (known, end) = self.nominal_from();
        match self.starts.get(k) {
            Some(&c) => c,
            None => end.saturating_add(((k - known) as u64).saturating_mul(self.timing.frame_clocks() as u64)),
        }
    }
    /// The frame whose period holds clock `c` (0 before frame 0).
    pub fn frame_at(&self, c: u64) -> usize {
        let (known, end) = self.nominal_from();
        if c >= end {
            return known + ((c - end) / self.timing.frame_clocks() as u64) as usize;
        }
        self.starts.partition_point(|&s| s <= c).saturating_sub(1)
    }
    /// The first frame whose FVAL rises on or after clock `c`.
    pub fn first_frame_from(&self, c: u64) -> usize {
        let (known, end) = self.nominal_from();
        if c > end {
            return known + (c - end).div_ceil(self.timing.frame_clocks() as u64) as usize;
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
        let Some(raster) = self.raster(k) else { return (CameraBus::default(), None) };
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
        self.raster(k).map_or(0, |r| r.pixel_clock(x, y)) as u64 + 1
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
