//! `coopwin scene`: writes a synthetic scene's frames as 8-bit PNG and its ground truth.
use super::{io_error, CliError};
use crate::scene::{Scene, SceneConfig};
use std::fmt::Write as _;
use std::path::Path;

/// Most frames `scene` writes: 20 000 frames is about three minutes at 114 frames/s.
pub const MAX_FRAMES: usize = 20_000;

/// Renders every frame of `cfg` into `out` as `frame_00000.png`..., and `groundtruth.csv`
/// with the columns frame,centre_x,centre_y,corner_x,corner_y,visible.
/// `out` must be a new or empty folder (its parent must exist), or, with `force`, a folder
/// whose files are kept apart from the scene's own; `force` never mixes two scenes: it refuses
/// a folder holding frames numbered past this scene's last.
pub fn write_scene(cfg: SceneConfig, out: &Path, force: bool) -> Result<usize, CliError> {
    if cfg.frames == 0 || cfg.frames > MAX_FRAMES {
        return Err(CliError::arg(format!("--frames must be 1..{MAX_FRAMES}, got {}", cfg.frames)));
    }
    let number = |name: &str, v: f64, max: f64| {
        if v.is_nan() {
            Err(CliError::arg(format!("--{name} {v}: not a number")))
        } else if !(0.0..=max).contains(&v) {
            let shown = if v.abs() < 1e6 { format!("{v}") } else { format!("{v:e}") };
            Err(CliError::arg(format!("--{name} must be 0..{max}, got {shown}")))
        } else {
            Ok(())
        }
    };
    number("speed", cfg.speed, 10_000.0)?;
    number("noise", cfg.noise, 255.0)?;
    if super::output::check_folder(out, "--out")? {
        let entries: Vec<String> = std::fs::read_dir(out)
            .map_err(|e| io_error("read", out, e))?
            .filter_map(|e| e.ok().map(|e| e.file_name().to_string_lossy().into_owned()))
            .collect();
        if !entries.is_empty() && !force {
            return Err(CliError::arg(format!(
                "--out {}: the folder is not empty ({} entries); give a new folder, or --force to write the scene's files into it",
                out.display(),
                entries.len()
            )));
        }
        let stale = entries.iter().filter(|e| frame_number(e).is_some_and(|k| k >= cfg.frames)).count();
        if stale > 0 {
            return Err(CliError::arg(format!(
                "--out {}: the folder holds {stale} frame(s) numbered past this scene's {} frames; they would mix two scenes: give a new folder",
                out.display(),
                cfg.frames
            )));
        }
    }
    super::output::create_folder(out, "--out")?;
    let (w, h, n) = (cfg.width as u32, cfg.height as u32, cfg.frames);
    let scene = Scene::new(cfg);
    let mut csv = String::from("frame,centre_x,centre_y,corner_x,corner_y,visible\n");
    for k in 0..n {
        let (pixels, t) = scene.render(k);
        let path = out.join(format!("frame_{k:05}.png"));
        let img = image::GrayImage::from_raw(w, h, pixels)
            .ok_or_else(|| CliError::new("internal: frame buffer size mismatch"))?;
        img.save(&path).map_err(|e| CliError::new(format!("cannot write {}: {e}", path.display())))?;
        let _ = writeln!(
            csv,
            "{},{:.4},{:.4},{:.4},{:.4},{}",
            t.frame, t.centre.0, t.centre.1, t.corner.0, t.corner.1, t.visible as u8
        );
    }
    super::output::OutFile::check(&out.join("groundtruth.csv"), "--out")?.write(csv.as_bytes())?;
    Ok(n)
}

/// K for a file named `frame_K.png` (as [`write_scene`] names frames).
fn frame_number(name: &str) -> Option<usize> {
    name.strip_prefix("frame_")?.strip_suffix(".png")?.parse().ok()
}
