//! `coopwin motion`: image differencing between two frames (the Watch window's motion
//! detection, thesis 2.3), answering in JSON.
use super::CliError;
use crate::frames::gray::Gray;
use coopwin_firmware::kernels::motion::detect_motion;
use serde_json::json;
use std::path::{Path, PathBuf};

/// `coopwin motion`'s options.
#[derive(clap::Args)]
pub struct MotionArgs {
    /// Earlier frame
    #[arg(long)]
    pub prev: PathBuf,
    /// Later frame
    #[arg(long)]
    pub next: PathBuf,
    /// Difference threshold (a pixel moves when |next - prev| > threshold)
    #[arg(long, default_value_t = 30)]
    pub threshold: u8,
}

/// Prints the motion area as JSON.
pub fn print_motion(args: MotionArgs) -> Result<(), CliError> {
    println!("{}", motion_images(&args.prev, &args.next, args.threshold)?);
    Ok(())
}

/// The motion area between two images of one size.
pub fn motion_images(prev: &Path, next: &Path, threshold: u8) -> Result<serde_json::Value, CliError> {
    let (a, b) = (Gray::load(prev)?, Gray::load(next)?);
    if (a.w, a.h) != (b.w, b.h) {
        return Err(CliError::new(format!("the images differ in size: {}x{} and {}x{}", a.w, a.h, b.w, b.h)));
    }
    let area = detect_motion(&a.view()?, &b.view()?, threshold).map_err(|e| CliError::new(format!("motion: {e}")))?;
    Ok(match area {
        Some(m) => json!({"moving": true, "xmin": m.xmin, "xmax": m.xmax, "ymin": m.ymin, "ymax": m.ymax, "count": m.count}),
        None => json!({"moving": false, "count": 0}),
    })
}
