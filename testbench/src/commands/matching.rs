//! `coopwin match`: the firmware's template matching (thesis 2.4) on a person's own images,
//! answering in JSON.
use super::CliError;
use crate::frames::gray::Gray;
use coopwin_firmware::kernels::matching::{best_match, MatchError, Method};
use serde_json::json;
use std::path::{Path, PathBuf};

/// `--method`.
#[derive(Clone, Copy, clap::ValueEnum)]
// No doc comments on the variants: clap would list them as help beside each value.
#[allow(missing_docs)]
pub enum MethodArg {
    Ncc,
    Zncc,
    Ssd,
    Sad,
}

impl From<MethodArg> for Method {
    fn from(m: MethodArg) -> Method {
        match m {
            MethodArg::Ncc => Method::Ncc,
            MethodArg::Zncc => Method::Zncc,
            MethodArg::Ssd => Method::Ssd,
            MethodArg::Sad => Method::Sad,
        }
    }
}

/// `coopwin match`'s options.
#[derive(clap::Args)]
pub struct MatchArgs {
    /// The search image
    #[arg(long)]
    pub image: PathBuf,
    /// The template (no larger than the image)
    #[arg(long)]
    pub template: PathBuf,
    /// Measure: ncc and ssd as in the thesis, sad, or zero-mean ncc
    #[arg(long, value_enum, default_value_t = MethodArg::Ncc)]
    pub method: MethodArg,
    /// Match at 25% resolution (every other pixel of every other row), as the Peripheral window
    #[arg(long)]
    pub decimate: bool,
}

/// Prints the best placement as JSON.
pub fn print_match(args: MatchArgs) -> Result<(), CliError> {
    println!("{}", match_images(&args.image, &args.template, args.method.into(), args.decimate)?);
    Ok(())
}

/// Smallest template side `match` accepts: below 3x3 a template has no shape to place.
pub const MIN_TEMPLATE: usize = 3;

/// Best placement of `template` in `image` by `method` (25% resolution when `decimate`).
pub fn match_images(image: &Path, template: &Path, method: Method, decimate: bool) -> Result<serde_json::Value, CliError> {
    let (img, tpl) = (Gray::load(image)?, Gray::load(template)?);
    if tpl.w > img.w || tpl.h > img.h {
        return Err(CliError::new(format!("the template ({}x{}) is larger than the image ({}x{})", tpl.w, tpl.h, img.w, img.h)));
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
