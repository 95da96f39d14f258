//! `coopwin verilog` and `coopwin waves`: the window logic's Verilog export and its simulated
//! Appendix B waveforms.
use super::{output::OutFile, CliError};
use crate::timing_svg;
use coopwin_hdl::sim::appendix_b::{simulate_acquisition, Sequence};
use coopwin_hdl::sim::camera::{RasterTiming, Window};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Writes `window_unit.v` and `window_network.v` (with `units` units) into `out`.
pub fn verilog(out: &Path, units: usize) -> Result<Vec<PathBuf>, CliError> {
    if units == 0 || units > 64 {
        return Err(CliError::arg(format!("--units must be 1..64, got {units}")));
    }
    super::output::create_folder(out, "--out")?;
    let files = coopwin_hdl::verilog::exported(units).map_err(CliError::new)?;
    let mut written = Vec::new();
    for (name, text) in files {
        let path = out.join(name);
        OutFile::check(&path, "--out")?.write(text.as_bytes())?;
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
        return Err(CliError::arg(format!("--frames must be 1..100, got {frames}")));
    }
    if vcd.as_os_str() == "-" {
        return Err(CliError::arg("--out -: the VCD needs a file name (the SVGs are written beside it)"));
    }
    let out = OutFile::check(vcd, "--out")?;
    let stem = vcd.with_extension("");
    let svgs: Vec<OutFile> = (1..=Sequence::ALL.len())
        .map(|k| OutFile::check(&PathBuf::from(format!("{}-b1_{k}.svg", stem.display())), "--out"))
        .collect::<Result<_, _>>()?;
    let stream = out.stream()?.shared();
    eprintln!("simulating {frames} frame(s) of window {window:?} in rust-hdl ...");
    let rec = simulate_acquisition(
        RasterTiming::CA_D1,
        window,
        false,
        frames,
        Arc::new(test_card()),
        Some(Box::new(stream.clone())),
    )
    .map_err(|e| CliError::new(e.to_string()))?;
    stream.finish()?;
    let mut written = Vec::new();
    for (k, seq) in Sequence::ALL.iter().enumerate() {
        let span = seq.span(&rec).ok_or_else(|| {
            CliError::new(format!(
                "the simulated run lacks the {} sequence",
                seq.title()
            ))
        })?;
        svgs[k].write(timing_svg::diagram(*seq, &rec, span).as_bytes())?;
        written.push(svgs[k].path.clone());
    }
    Ok(written)
}
