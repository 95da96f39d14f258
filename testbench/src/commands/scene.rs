//! `coopwin scene`: writes a synthetic scene's frames as 8-bit PNG and its ground truth.
use super::{io_error, CliError};
use crate::scene::{Scene, SceneConfig};
use std::fmt::Write as _;
use std::path::Path;

/// Renders every frame of `cfg` into `out` as `frame_00000.png`..., and `groundtruth.csv`
/// with the columns frame,centre_x,centre_y,corner_x,corner_y,visible.
pub fn write_scene(cfg: SceneConfig, out: &Path) -> Result<usize, CliError> {
    if cfg.frames == 0 {
        return Err(CliError("--frames must be at least 1".into()));
    }
    if !(cfg.speed.is_finite() && cfg.speed >= 0.0) {
        return Err(CliError(format!("--speed must be a non-negative number, got {}", cfg.speed)));
    }
    if !(cfg.noise.is_finite() && cfg.noise >= 0.0) {
        return Err(CliError(format!("--noise must be a non-negative number, got {}", cfg.noise)));
    }
    std::fs::create_dir_all(out).map_err(|e| io_error("create", out, e))?;
    let (w, h, n) = (cfg.width as u32, cfg.height as u32, cfg.frames);
    let scene = Scene::new(cfg);
    let mut csv = String::from("frame,centre_x,centre_y,corner_x,corner_y,visible\n");
    for k in 0..n {
        let (pixels, t) = scene.render(k);
        let path = out.join(format!("frame_{k:05}.png"));
        let img = image::GrayImage::from_raw(w, h, pixels)
            .ok_or_else(|| CliError("internal: frame buffer size mismatch".into()))?;
        img.save(&path).map_err(|e| CliError(format!("cannot write {}: {e}", path.display())))?;
        let _ = writeln!(
            csv,
            "{},{:.4},{:.4},{:.4},{:.4},{}",
            t.frame, t.centre.0, t.centre.1, t.corner.0, t.corner.1, t.visible as u8
        );
    }
    let gt = out.join("groundtruth.csv");
    std::fs::write(&gt, csv).map_err(|e| io_error("write", &gt, e))?;
    Ok(n)
}
