//! `coopwin corner`: the corner detector of chapter 3 on a person's own window image,
//! answering in JSON.
use super::CliError;
use crate::frames::gray::Gray;
use coopwin_firmware::kernels::corner::{CornerDetector, CornerParams, MAX_DIM};
use coopwin_firmware::kernels::info::edge_information;
use serde_json::json;
use std::path::{Path, PathBuf};

/// `coopwin corner`'s options.
#[derive(clap::Args)]
pub struct CornerArgs {
    /// The window (up to 64x64)
    #[arg(long)]
    pub image: PathBuf,
    /// Sobel magnitude threshold TH
    #[arg(long, default_value_t = 50, value_parser = clap::value_parser!(u16).range(1..=1442))]
    pub threshold: u16,
}

/// Prints the corner as JSON.
pub fn print_corner(args: CornerArgs) -> Result<(), CliError> {
    println!("{}", corner_image(&args.image, args.threshold)?);
    Ok(())
}

/// The corner in a window image, its edge-pixel count and the information measures.
pub fn corner_image(image: &Path, threshold: u16) -> Result<serde_json::Value, CliError> {
    let img = Gray::load(image)?;
    if img.w > MAX_DIM || img.h > MAX_DIM {
        return Err(CliError::new(format!(
            "the corner detector works on windows up to {MAX_DIM}x{MAX_DIM}; this image is {}x{}",
            img.w, img.h
        )));
    }
    let mut det = CornerDetector::default();
    let r = det.detect(&img.view()?, &CornerParams::new(threshold));
    let edges = det.edge_pixels();
    let info = edge_information(edges, (img.w * img.h) as u32);
    Ok(match r {
        Ok(c) => json!({
            "corner": {"x": c.x, "y": c.y},
            "case": format!("{:?}", c.case),
            "edge_pixels": c.edge_pixels,
            "clean_pixels": c.clean_pixels,
            "information_bits": info,
        }),
        Err(reason) => json!({
            "corner": null,
            "reason": format!("{reason:?}"),
            "edge_pixels": edges,
            "information_bits": info,
        }),
    })
}
