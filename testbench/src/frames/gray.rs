//! One image file as 8-bit gray, for the kernel commands (`coopwin match`, `corner`, `motion`).
use coopwin_firmware::kernels::view::{ViewError, WindowView};
use std::path::{Path, PathBuf};

/// An image as 8-bit gray (colour converted).
pub struct Gray {
    /// Pixels, row-major.
    pub px: Vec<u8>,
    /// Width.
    pub w: usize,
    /// Height.
    pub h: usize,
}

/// Why an image cannot be used.
#[derive(Debug)]
pub enum ImageError {
    /// The file does not exist.
    NoSuchFile(PathBuf),
    /// The file is not an image the decoder reads.
    Unreadable {
        /// The file.
        path: PathBuf,
        /// The decoder's reason.
        source: image::ImageError,
    },
    /// The pixels cannot be viewed as a window.
    View(ViewError),
}

impl std::fmt::Display for ImageError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ImageError::NoSuchFile(p) => write!(f, "{}: no such file", p.display()),
            ImageError::Unreadable { path, source } => write!(f, "{}: not a readable image ({source})", path.display()),
            ImageError::View(e) => write!(f, "image view: {e}"),
        }
    }
}

impl std::error::Error for ImageError {}

impl Gray {
    /// Loads `path`, or says why not.
    pub fn load(path: &Path) -> Result<Gray, ImageError> {
        if !path.exists() {
            return Err(ImageError::NoSuchFile(path.into()));
        }
        let img = image::open(path).map_err(|source| ImageError::Unreadable { path: path.into(), source })?;
        let g = img.to_luma8();
        let (w, h) = (g.width() as usize, g.height() as usize);
        Ok(Gray { px: g.into_raw(), w, h })
    }

    /// The image as the firmware's kernels see a window.
    pub fn view(&self) -> Result<WindowView<'_>, ImageError> {
        WindowView::packed(&self.px, self.w, self.h).map_err(ImageError::View)
    }
}
