//! `coopwin waves`: window acquisitions simulated in rust-hdl, as a VCD and the five timing
//! diagrams of Appendix B, on a unit of any geometry `coopwin verilog` exports (the coordinate
//! sets written by the firmware's writer for that sensor: eight bytes above 256).
use super::args::{parse_window, SensorArgs};
use super::{output::OutFile, CliError};
use crate::report::timing_svg;
use crate::units::clocks::Clocks;
use coopwin_hdl::sim::appendix_b::{simulate_acquisition, AcquisitionError, Sequence};
use coopwin_hdl::sim::camera::{RasterTiming, Window};
use coopwin_hdl::sim::driver::{with_widths, WidthsVisitor};
use coopwin_hdl::sim::vcd::{write_flags_vcd, VCD_CLOCK_PS};
use coopwin_hdl::verilog::Geometry;
use coopwin_hdl::window_unit::Flags;
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
    #[arg(long, value_parser = parse_window)]
    pub window: Option<Window>,
    /// Frames to acquire, one coordinate set written before each
    #[arg(long, default_value_t = 1)]
    pub frames: usize,
    /// The sensor's geometry (--width, --height, --pixel-bits)
    #[command(flatten)]
    pub sensor: SensorArgs,
}

/// Writes the VCD and the diagrams and says so.
pub fn write_waves(args: WavesArgs) -> Result<(), CliError> {
    let g = args.sensor.geometry()?;
    let window = args.window.unwrap_or(Window { xmin: 0, xmax: g.width as u32 - 1, ymin: 0, ymax: g.height as u32 - 1 });
    let svgs = waves(&args.out, &g, window, args.frames)?;
    println!("wrote {}", args.out.display());
    for p in svgs {
        println!("wrote {}", p.display());
    }
    Ok(())
}

/// The test card the waves are simulated on: each pixel's value is its column (modulo the
/// pixel's range), so the value on D4 says which pixel of the line left (the Y count says
/// which line).
fn test_card(g: &Geometry) -> Vec<u16> {
    let range = 1usize << g.pixel_bits;
    (0..g.width * g.height).map(|i| (i % g.width % range) as u16).collect()
}

/// The acquisition on a unit of the widths `coopwin_hdl::sim::driver::stepped_widths` picks.
struct Acquire {
    timing: RasterTiming,
    window: Window,
    frames: usize,
    image: Arc<Vec<u16>>,
}

impl WidthsVisitor for Acquire {
    type Out = Result<Vec<Flags>, AcquisitionError>;
    fn visit<const C: usize, const P: usize>(self) -> Self::Out {
        simulate_acquisition::<C, P>(self.timing, self.window, false, self.frames, self.image)
    }
}

/// Simulates `frames` acquisitions of `window` on a unit of sensor `g` in rust-hdl, writes the
/// VCD to `vcd`, and an SVG timing diagram per Appendix B sequence beside it. Returns the SVG
/// paths.
pub fn waves(vcd: &Path, g: &Geometry, window: Window, frames: usize) -> Result<Vec<PathBuf>, CliError> {
    if frames == 0 || frames > 100 {
        return Err(CliError::arg(format!("--frames must be 1..100, got {frames}")));
    }
    let last = |n: usize| n as u32 - 1;
    if !window.is_valid() || window.xmax > last(g.width) || window.ymax > last(g.height) {
        return Err(CliError::arg(format!(
            "--window {},{},{},{}: the unit takes xmin < xmax <= {} and ymin < ymax <= {}",
            window.xmin,
            window.xmax,
            window.ymin,
            window.ymax,
            last(g.width),
            last(g.height)
        )));
    }
    if vcd.as_os_str() == "-" {
        return Err(CliError::arg("--out -: the VCD needs a file name (the SVGs are written beside it)"));
    }
    let out = OutFile::check(vcd, "--out")?;
    let stem = vcd.with_extension("");
    let svgs: Vec<OutFile> = (1..=Sequence::ALL.len())
        .map(|k| OutFile::check(&PathBuf::from(format!("{}-b1_{k}.svg", stem.display())), "--out"))
        .collect::<Result<_, _>>()?;
    eprintln!("simulating {frames} frame(s) of window {window:?} on a {}x{}x{} unit in rust-hdl ...", g.width, g.height, g.pixel_bits);
    // The CA-D1's blanking (RasterTiming::CA_D1 at 256x256), at the sensor's size.
    let timing = Clocks::camera_timing((g.width, g.height));
    let rec = with_widths(g, Acquire { timing, window, frames, image: Arc::new(test_card(g)) }).map_err(|e| CliError::new(e.to_string()))?;
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
