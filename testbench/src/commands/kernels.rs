//! `coopwin match`, `coopwin corner`, `coopwin motion`: the firmware's kernels on a person's
//! own images, answering in JSON.
use super::CliError;
use coopwin_firmware::kernels::corner::{CornerDetector, CornerParams, MAX_DIM};
use coopwin_firmware::kernels::info::edge_information;
use coopwin_firmware::kernels::matching::{best_match, MatchError, Method};
use coopwin_firmware::kernels::motion::detect_motion;
use coopwin_firmware::kernels::view::WindowView;
use serde_json::json;
use std::path::Path;

/// An image as 8-bit gray (colour converted).
pub struct Gray {
    /// Pixels, row-major.
    pub px: Vec<u8>,
    /// Width.
    pub w: usize,
    /// Height.
    pub h: usize,
}

impl Gray {
    /// Loads `path`, or says why not.
    pub fn load(path: &Path) -> Result<Gray, CliError> {
        if !path.exists() {
            return Err(CliError::new(format!("{}: no such file", path.display())));
        }
        let img = image::open(path).map_err(|e| CliError::new(format!("{}: not a readable image ({e})", path.display())))?;
        let g = img.to_luma8();
        let (w, h) = (g.width() as usize, g.height() as usize);
        Ok(Gray { px: g.into_raw(), w, h })
    }

    fn view(&self) -> Result<WindowView<'_>, CliError> {
        WindowView::packed(&self.px, self.w, self.h).map_err(|e| CliError::new(format!("image view: {e}")))
    }
}

/// Smallest template side `match` accepts: below 3x3 a template has no shape to place.
pub const MIN_TEMPLATE: usize = 3;

/// Best placement of `template` in `image` by `method` (25% resolution when `decimate`).
pub fn match_images(image: &Path, template: &Path, method: Method, decimate: bool) -> Result<serde_json::Value, CliError> {
    let (img, tpl) = (Gray::load(image)?, Gray::load(template)?);
    if tpl.w > img.w || tpl.h > img.h {
        return Err(CliError::new(format!(
            "the template ({}x{}) is larger than the image ({}x{})",
            tpl.w, tpl.h, img.w, img.h
        )));
    }
    let (iv, tv) = (img.view()?, tpl.view()?);
    let (iv, tv) = if decimate { (iv.decimated(), tv.decimated()) } else { (iv, tv) };
    let at = if decimate { " at 25% resolution" } else { "" };
    if tv.width() < MIN_TEMPLATE || tv.height() < MIN_TEMPLATE {
        return Err(CliError::new(format!(
            "{}: the template is {}x{}{at}; a match needs at least {MIN_TEMPLATE}x{MIN_TEMPLATE} pixels (a smaller one fits anywhere)",
            template.display(),
            tv.width(),
            tv.height()
        )));
    }
    if matches!(method, Method::Ncc | Method::Zncc) {
        let first = tv.get(0, 0);
        let flat = (0..tv.height()).all(|y| tv.row_iter(y).all(|p| Some(p) == first));
        if flat {
            return Err(CliError::new(format!(
                "{}: the template is flat (every pixel {}{at}); correlation cannot place it: use a template with contrast, or --method ssd",
                template.display(),
                first.unwrap_or(0)
            )));
        }
    }
    let m = best_match(method, &iv, &tv).map_err(|e| {
        CliError::new(match e {
            MatchError::ZeroEnergy => "the template is flat (zero energy or variance): nothing to match".into(),
            MatchError::NoMatch => "no placement has any contrast: no match".into(),
            MatchError::TooLarge => "the image is too large for the firmware's buffers (256 columns, or 4096 pixels at 25%)".into(),
            other => format!("cannot match: {other:?}"),
        })
    })?;
    Ok(json!({"x": m.x, "y": m.y, "score": m.score, "subpixel_x": m.sub_x, "subpixel_y": m.sub_y}))
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
