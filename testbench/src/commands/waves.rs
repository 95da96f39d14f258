//! `coopwin waves`: window acquisitions simulated in rust-hdl, as a VCD and the five timing
//! diagrams of Appendix B.
use super::args::parse_window;
use super::{output::OutFile, CliError};
use crate::report::timing_svg;
use coopwin_hdl::sim::appendix_b::{simulate_acquisition, Sequence};
use coopwin_hdl::sim::camera::{RasterTiming, Window};
use coopwin_hdl::sim::vcd::{write_flags_vcd, VCD_CLOCK_PS};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// `coopwin waves`'s options.
// The field docs are the command's help text, where `<stem>` is no HTML tag.
#[allow(rustdoc::invalid_html_tags)]
#[derive(clap::Args)]
pub struct WavesArgs {
    /// The VCD to write; the SVGs go beside it as <stem>-b1_<k>.svg
    #[arg(long)]
    pub out: PathBuf,
    /// Window as XMIN,XMAX,YMIN,YMAX (0-based, inclusive); default the whole frame
    #[arg(long, default_value = "0,255,0,255", value_parser = parse_window)]
    pub window: Window,
    /// Frames to acquire, one coordinate set written before each
    #[arg(long, default_value_t = 1)]
    pub frames: usize,
}

/// Writes the VCD and the diagrams and says so.
pub fn write_waves(args: WavesArgs) -> Result<(), CliError> {
    let svgs = waves(&args.out, args.window, args.frames)?;
    println!("wrote {}", args.out.display());
    for p in svgs {
        println!("wrote {}", p.display());
    }
    Ok(())
}

/// The test card the waves are simulated on: each pixel's value is its column, so the value on
/// D4 says which pixel of the line left (the Y count says which line).
fn test_card() -> Vec<u8> {
    (0..65536u32).map(|i| (i % 256) as u8).collect()
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
    eprintln!("simulating {frames} frame(s) of window {window:?} in rust-hdl ...");
    let rec = simulate_acquisition(RasterTiming::CA_D1, window, false, frames, Arc::new(test_card()))
        .map_err(|e| CliError::new(e.to_string()))?;
    let mut vcd_text = Vec::new();
    write_flags_vcd(&mut vcd_text, &rec, VCD_CLOCK_PS).map_err(|e| CliError::new(e.to_string()))?;
    out.write(&vcd_text)?;
    let mut written = Vec::new();
    for (k, seq) in Sequence::ALL.iter().enumerate() {
        let span = seq.span(&rec).ok_or_else(|| CliError::new(format!("the simulated run lacks the {} sequence", seq.title())))?;
        svgs[k].write(timing_svg::diagram(*seq, &rec, span).as_bytes())?;
        written.push(svgs[k].path.clone());
    }
    Ok(written)
}
