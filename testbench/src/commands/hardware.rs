//! `coopwin verilog` and `coopwin waves`: the window logic's Verilog export and its simulated
//! Appendix B waveforms.
use super::{io_error, CliError};
use crate::timing_svg;
use coopwin_hdl::appendix_b::{simulate_acquisition, Sequence};
use coopwin_hdl::camera::{RasterTiming, Window};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Writes `window_unit.v` and `window_network.v` (with `units` units) into `out`.
pub fn verilog(out: &Path, units: usize) -> Result<Vec<PathBuf>, CliError> {
    if units == 0 || units > 64 {
        return Err(CliError(format!("--units must be 1..64, got {units}")));
    }
    std::fs::create_dir_all(out).map_err(|e| io_error("create", out, e))?;
    let files = coopwin_hdl::verilog::exported(units).map_err(CliError)?;
    let mut written = Vec::new();
    for (name, text) in files {
        let path = out.join(name);
        std::fs::write(&path, text).map_err(|e| io_error("write", &path, e))?;
        written.push(path);
    }
    Ok(written)
}

/// Parses XMIN,XMAX,YMIN,YMAX and checks it is a valid window of the 256x256 camera.
pub fn parse_window(s: &str) -> Result<Window, String> {
    let v: Vec<u32> = s
        .split(',')
        .map(|p| {
            p.trim()
                .parse::<u32>()
                .map_err(|_| format!("'{p}' is not a coordinate"))
        })
        .collect::<Result<_, _>>()?;
    let [xmin, xmax, ymin, ymax] = v[..] else {
        return Err(format!(
            "expected XMIN,XMAX,YMIN,YMAX, got {} values",
            v.len()
        ));
    };
    let w = Window {
        xmin,
        xmax,
        ymin,
        ymax,
    };
    if xmax > 255 || ymax > 255 {
        return Err("coordinates must be 0..255 on the 256x256 camera".into());
    }
    if !w.is_valid() {
        return Err("a window needs XMIN < XMAX and YMIN < YMAX".into());
    }
    Ok(w)
}

/// The test card the waves are simulated on: a gradient, so delivered values are recognisable.
fn test_card() -> Vec<u8> {
    (0..65536u32)
        .map(|i| ((i % 256 + i / 256) / 2) as u8)
        .collect()
}

/// Simulates `frames` acquisitions of `window` in rust-hdl, writes the VCD to `vcd`, and an SVG
/// timing diagram per Appendix B sequence beside it. Returns the SVG paths.
pub fn waves(vcd: &Path, window: Window, frames: usize) -> Result<Vec<PathBuf>, CliError> {
    if frames == 0 || frames > 100 {
        return Err(CliError(format!("--frames must be 1..100, got {frames}")));
    }
    if let Some(dir) = vcd.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| io_error("create", dir, e))?;
    }
    let file = std::fs::File::create(vcd).map_err(|e| io_error("create", vcd, e))?;
    eprintln!("simulating {frames} frame(s) of window {window:?} in rust-hdl ...");
    let rec = simulate_acquisition(
        RasterTiming::CA_D1,
        window,
        false,
        frames,
        Arc::new(test_card()),
        Some(Box::new(std::io::BufWriter::new(file))),
    )
    .map_err(|e| CliError(e.to_string()))?;
    let stem = vcd.with_extension("");
    let mut written = Vec::new();
    for (k, seq) in Sequence::ALL.iter().enumerate() {
        let span = seq.span(&rec).ok_or_else(|| {
            CliError(format!(
                "the simulated run lacks the {} sequence",
                seq.title()
            ))
        })?;
        let path = PathBuf::from(format!("{}-b1_{}.svg", stem.display(), k + 1));
        std::fs::write(&path, timing_svg::diagram(*seq, &rec, span))
            .map_err(|e| io_error("write", &path, e))?;
        written.push(path);
    }
    Ok(written)
}
