//! Processor cost models: how long a window processor is busy with each kernel call.
//!
//! - `c40`: the TMS320C40 of the thesis, calibrated to its own measurements (2.6). A 20x20 NCC
//!   template in the 24x24 Foveal window updates every 18 ms (two frames at 114 frames/s) over
//!   the top 70% of the image and every 27 ms below: the window completes when the raster
//!   passes it, so that boundary (line 180) puts the NCC's processing time at 2T - 0.70T = 11.4
//!   ms (T = 8.77 ms): 1.14 us per template pixel per placement (25 placements of 400 pixels).
//!   SSD, one product a pixel against NCC's two sums of products, costs half that; the corner
//!   detector 5 us a window pixel (2.9 ms on 24x24, so it runs at frame rate, 3.4); the Watch
//!   differencing 0.75 us a pixel (64K pixels: 49 ms). The thesis's 8.8 ms rate for a 16x16
//!   template is not reproduced by a per-operation cost (7.3 ms of NCC leaves frame rate only
//!   to windows in the top sixth of the image); docs/results.md discusses it.
//! - `native`: our kernels on this machine, from `cargo bench -p coopwin-firmware --bench
//!   kernels` (per-call medians; see docs/results.md for the run they come from).
use coopwin_firmware::kernels::matching::Method;
use coopwin_firmware::processors::Work;

/// Per-operation costs in seconds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CostModel {
    /// Name, for reports.
    pub name: &'static str,
    /// Image differencing, per pixel.
    pub motion_px: f64,
    /// NCC, per template pixel per placement (SSD and SAD cost half).
    pub match_op: f64,
    /// Corner detector, per window pixel.
    pub corner_px: f64,
    /// The COOP decision.
    pub decision: f64,
    /// Fixed overhead of any event (interrupt, bookkeeping).
    pub overhead: f64,
    /// Link bandwidth in bytes per second (the C40's comm ports: 20 Mbyte/s).
    pub link_bytes_per_s: f64,
    /// Link latency per message.
    pub link_latency: f64,
}

impl CostModel {
    /// The thesis's TMS320C40, calibrated as the module docs explain.
    pub const C40: CostModel = CostModel {
        name: "c40",
        motion_px: 0.75e-6,
        match_op: 1.14e-6,
        corner_px: 5.0e-6,
        decision: 0.1e-3,
        overhead: 20e-6,
        link_bytes_per_s: 20e6,
        link_latency: 5e-6,
    };

    /// Our kernels on this machine (see the module docs).
    pub const NATIVE: CostModel = CostModel {
        name: "native",
        motion_px: 0.25e-9,
        match_op: 0.25e-9,
        corner_px: 10e-9,
        decision: 0.1e-6,
        overhead: 0.2e-6,
        link_bytes_per_s: 20e6,
        link_latency: 5e-6,
    };

    /// Seconds a processor is busy for `work`.
    pub fn seconds(&self, work: &Work) -> f64 {
        self.overhead
            + match *work {
                Work::None => 0.0,
                Work::Motion { pixels } => self.motion_px * f64::from(pixels),
                Work::Match { method, template, placements } => {
                    let factor = match method {
                        Method::Ncc | Method::Zncc => 1.0,
                        Method::Ssd | Method::Sad => 0.5,
                    };
                    self.match_op * factor * f64::from(template) * f64::from(placements)
                }
                Work::Corner { pixels } => self.corner_px * f64::from(pixels),
                Work::Decision => self.decision,
            }
    }

    /// Seconds a message of `bytes` takes over a link.
    pub fn link_seconds(&self, bytes: usize) -> f64 {
        self.link_latency + bytes as f64 / self.link_bytes_per_s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn c40_foveal_ncc_matches_the_thesis_rate_boundary() {
        // Hand calculation from 2.6: T = 70192 clocks / 8 MHz; a window ending on line 180
        // plus the NCC must end exactly two frame periods after the frame started.
        let t = 70_192.0 / 8e6;
        let ncc = CostModel::C40.seconds(&Work::Match { method: Method::Ncc, template: 400, placements: 25 });
        let boundary = (16.0 + 180.0 * 272.0) / 8e6 + ncc;
        assert!((boundary - 2.0 * t).abs() < 0.1e-3, "{boundary} vs {}", 2.0 * t);
    }
}
