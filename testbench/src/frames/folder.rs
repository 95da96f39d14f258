//! A folder of PNG frames (`coopwin track --frames`): listed in natural order of their names,
//! checked once for size and readability, decoded on demand.
use super::{FrameCache, FrameError, FrameSource};
use std::path::{Path, PathBuf};

/// Smallest and largest frame side accepted: the largest sensor the window unit's Verilog
/// takes (`coopwin verilog`, 4096x4096).
pub const SIDES: std::ops::RangeInclusive<usize> = 64..=4096;

/// PNG frames in a folder, in natural order of their names (`img2.png` before `img10.png`),
/// decoded on demand (a few kept in memory).
pub struct FolderFrames {
    paths: Vec<PathBuf>,
    size: (usize, usize),
    cache: FrameCache,
}

/// Why a folder of frames cannot be tracked.
#[derive(Debug)]
pub enum FolderError {
    /// The folder cannot be listed.
    Unreadable {
        /// The folder.
        dir: PathBuf,
        /// The reason.
        source: std::io::Error,
    },
    /// The folder holds no PNG file.
    NoFrames(PathBuf),
    /// A frame is not a readable PNG.
    NotPng {
        /// The file.
        path: PathBuf,
        /// The decoder's reason.
        source: image::ImageError,
    },
    /// A PNG frame's file has no end marker (the `IEND` chunk) near its end: cut short.
    Truncated(PathBuf),
    /// The first frame's size is outside [`SIDES`].
    BadSize {
        /// The file.
        path: PathBuf,
        /// Its size.
        size: (usize, usize),
    },
    /// Two frames differ in size.
    MixedSizes {
        /// The first frame and its size.
        first: (PathBuf, (usize, usize)),
        /// A frame of another size, and that size.
        other: (PathBuf, (usize, usize)),
    },
}

impl std::fmt::Display for FolderError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FolderError::Unreadable { dir, source } => write!(f, "cannot read the frames folder {}: {source}", dir.display()),
            FolderError::NoFrames(dir) => write!(f, "no PNG frames in {}", dir.display()),
            FolderError::NotPng { path, source } => write!(f, "{}: not a readable PNG ({source})", path.display()),
            FolderError::Truncated(path) => write!(f, "{}: not a readable PNG (no IEND chunk at its end: cut short)", path.display()),
            FolderError::BadSize { path, size } => {
                write!(f, "{}: frames must be {1}x{1} to {2}x{2}, this one is {3}x{4}", path.display(), SIDES.start(), SIDES.end(), size.0, size.1)
            }
            FolderError::MixedSizes { first: (a, s), other: (b, d) } => write!(
                f,
                "mixed frame sizes: {} is {}x{}, {} is {}x{}",
                a.display(),
                s.0,
                s.1,
                b.display(),
                d.0,
                d.1
            ),
        }
    }
}

impl std::error::Error for FolderError {}

impl FolderFrames {
    /// Lists and checks the folder: it must hold PNG frames, all of one size within
    /// [`SIDES`]. Every frame's header and end are read now, so a bad file (unreadable, not a
    /// PNG, cut short, another size) is named with the reason before tracking starts; the
    /// pixels are decoded once, when tracked (a file damaged inside is named then, and no
    /// output is written).
    pub fn open(dir: &Path) -> Result<Self, FolderError> {
        let entries = std::fs::read_dir(dir).map_err(|source| FolderError::Unreadable { dir: dir.into(), source })?;
        let mut paths: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x.eq_ignore_ascii_case("png")))
            .collect();
        paths.sort_by(|a, b| natural_cmp(&a.to_string_lossy(), &b.to_string_lossy()));
        let first = paths.first().ok_or_else(|| FolderError::NoFrames(dir.into()))?;
        let size = header_size(first)?;
        if !SIDES.contains(&size.0) || !SIDES.contains(&size.1) {
            return Err(FolderError::BadSize { path: first.clone(), size });
        }
        for p in &paths[1..] {
            let d = header_size(p)?;
            if d != size {
                return Err(FolderError::MixedSizes { first: (first.clone(), size), other: (p.clone(), d) });
            }
        }
        Ok(FolderFrames { paths, size, cache: FrameCache::default() })
    }

    /// The frames' file names, in tracking order.
    pub fn names(&self) -> Vec<String> {
        self.paths.iter().map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default()).collect()
    }
}

/// The size in `p`'s header, once a PNG is known to hold its `IEND` chunk near its end (a
/// file cut short does not): its pixels are decoded when tracked, not twice.
fn header_size(p: &Path) -> Result<(usize, usize), FolderError> {
    let not_png = |source| FolderError::NotPng { path: p.into(), source };
    let io = |e| not_png(image::ImageError::IoError(e));
    let reader = image::ImageReader::open(p).map_err(io)?.with_guessed_format().map_err(io)?;
    // Another format under a .png name is decoded as what it is, as before.
    let png = reader.format() == Some(image::ImageFormat::Png);
    let (w, h) = reader.into_dimensions().map_err(not_png)?;
    if png && !has_iend(p).map_err(io)? {
        return Err(FolderError::Truncated(p.into()));
    }
    Ok((w as usize, h as usize))
}

/// The empty `IEND` chunk that ends every PNG (length 0, its type, its CRC).
const IEND: [u8; 12] = [0, 0, 0, 0, b'I', b'E', b'N', b'D', 0xAE, 0x42, 0x60, 0x82];

/// Bytes at the end of a PNG searched for [`IEND`]: some encoders append data after it.
const IEND_SEARCH: u64 = 4096;

/// Whether the last [`IEND_SEARCH`] bytes of the file `p` hold [`IEND`].
fn has_iend(p: &Path) -> std::io::Result<bool> {
    use std::io::{Read, Seek, SeekFrom};
    let mut f = std::fs::File::open(p)?;
    let len = f.metadata()?.len();
    f.seek(SeekFrom::Start(len.saturating_sub(IEND_SEARCH)))?;
    let mut tail = Vec::new();
    f.read_to_end(&mut tail)?;
    Ok(tail.windows(IEND.len()).any(|w| w == IEND))
}

/// Orders names as a person would: runs of digits compare by their value, so `img2` comes
/// before `img10`; names equal by that measure fall back to plain text order.
pub fn natural_cmp(a: &str, b: &str) -> std::cmp::Ordering {
    use std::cmp::Ordering;
    let (mut x, mut y) = (a.as_bytes(), b.as_bytes());
    while let (Some(&c), Some(&d)) = (x.first(), y.first()) {
        let ord = if c.is_ascii_digit() && d.is_ascii_digit() {
            let run = |s: &[u8]| s.iter().take_while(|b| b.is_ascii_digit()).count();
            let (m, n) = (run(x), run(y));
            let trim = |s: &[u8]| {
                let z = s.iter().take_while(|&&b| b == b'0').count();
                s[z..].to_vec()
            };
            let (p, q) = (trim(&x[..m]), trim(&y[..n]));
            let o = p.len().cmp(&q.len()).then_with(|| p.cmp(&q));
            x = &x[m..];
            y = &y[n..];
            o
        } else {
            x = &x[1..];
            y = &y[1..];
            c.cmp(&d)
        };
        if ord != Ordering::Equal {
            return ord;
        }
    }
    x.len().cmp(&y.len()).then_with(|| a.cmp(b))
}

impl FrameSource for FolderFrames {
    fn size(&self) -> (usize, usize) {
        self.size
    }
    fn len(&self) -> usize {
        self.paths.len()
    }
    fn frame(&mut self, k: usize) -> Result<&[u8], FrameError> {
        let paths = &self.paths;
        self.cache.get_or_make(k, || {
            let p = paths.get(k).ok_or(FrameError::Missing(k))?;
            let img = image::open(p).map_err(|source| FrameError::Decode { path: p.clone(), source })?;
            Ok(img.to_luma8().into_raw())
        })
    }
}

#[cfg(test)]
mod tests {
    use super::natural_cmp;

    #[test]
    fn names_sort_by_the_value_of_their_numbers() {
        // Reference: the order a person numbering the files meant, written out by hand.
        let want = ["a.png", "img0.png", "img2.png", "img002b.png", "img10.png", "img11.png", "img100.png", "img100x2.png", "img100x10.png"];
        let mut got = want.to_vec();
        got.reverse();
        got.sort_by(|a, b| natural_cmp(a, b));
        assert_eq!(got, want);
        // Equal values with different zero padding still have a fixed order.
        assert_eq!(natural_cmp("f01.png", "f1.png"), "f01.png".cmp("f1.png"));
    }
}
