//! Overlays: each frame with the windows the processors acquired from it, the position
//! reported and the ground truth, as an animated GIF (written here, no program needed) or an
//! MP4 (through FFmpeg, [`crate::frames::video::Mp4Encoder`]); both are drawn and written a
//! frame at a time ([`Painter`]).
//!
//! Frames are drawn in a fixed 256-colour palette: 32 gray levels for the image and a few
//! saturated colours for the marks, so every frame encodes without quantisation and two runs
//! give the same bytes.
//!
//! A GIF is bounded in size ([`GifPlan`]): frames over 480 pixels a side are scaled down (the
//! marks drawn at the smaller size, so none is lost), and a long run keeps every k-th frame
//! (each shown k times as long), so the GIF holds at most 50 million pixels, about 15 MB.
//! An MP4 keeps every frame at full size.
use crate::frames::video::{Mp4Encoder, VideoError};
use crate::frames::{FrameError, FrameSource};
use crate::system::{FrameRecord, Role, RunLog};
use coopwin_firmware::processors::Mode;
use coopwin_firmware::types::Source;
use std::fmt;

/// Gray levels in the palette (indices `0..GRAYS`): few enough that sensor noise does not
/// defeat the GIF's compression, enough to see the scene.
const GRAYS: usize = 32;

/// A mark's colour (palette entries after the grays).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Colour {
    /// Watch windows.
    Blue,
    /// Peripheral windows.
    Yellow,
    /// The Foveal NCC window.
    Green,
    /// The Foveal corner-detector window (COOP's partner).
    Magenta,
    /// A position measured by NCC.
    Red,
    /// A position measured by the corner detector.
    Orange,
    /// The ground truth.
    Cyan,
    /// Text.
    White,
}

impl Colour {
    const ALL: [Colour; 8] =
        [Colour::Blue, Colour::Yellow, Colour::Green, Colour::Magenta, Colour::Red, Colour::Orange, Colour::Cyan, Colour::White];

    fn index(self) -> u8 {
        (GRAYS + Colour::ALL.iter().position(|&c| c == self).unwrap_or(0)) as u8
    }

    fn rgb(self) -> [u8; 3] {
        match self {
            Colour::Blue => [40, 110, 255],
            Colour::Yellow => [255, 220, 0],
            Colour::Green => [0, 230, 60],
            Colour::Magenta => [255, 0, 255],
            Colour::Red => [255, 30, 30],
            Colour::Orange => [255, 140, 0],
            Colour::Cyan => [0, 230, 230],
            Colour::White => [255, 255, 255],
        }
    }
}

/// The palette: `GRAYS` gray levels, the mark colours, black for the rest (RGB triplets).
fn palette() -> Vec<u8> {
    let mut p = Vec::with_capacity(768);
    for i in 0..GRAYS {
        let v = (i * 255 / (GRAYS - 1)) as u8;
        p.extend_from_slice(&[v, v, v]);
    }
    for c in Colour::ALL {
        p.extend_from_slice(&c.rgb());
    }
    p.resize(768, 0);
    p
}

/// One frame being drawn: palette indices, row by row, at `zoom` times the frame's size
/// (marks are given in the frame's coordinates).
#[derive(Clone, Debug)]
pub struct Canvas {
    width: usize,
    height: usize,
    px: Vec<u8>,
    zoom: f64,
}

/// A gray level's palette index.
fn gray_index(v: u8) -> u8 {
    ((usize::from(v) * (GRAYS - 1) + 127) / 255) as u8
}

impl Canvas {
    /// The gray frame `gray` (`width * height` bytes) as a canvas.
    pub fn from_gray(gray: &[u8], width: usize, height: usize) -> Canvas {
        let mut c = Canvas { width, height, px: Vec::new(), zoom: 1.0 };
        c.paint_gray(gray, width);
        c
    }

    /// Replaces the canvas's pixels with the gray frame `gray`, `width` pixels a row,
    /// sampled at the canvas's size (the nearest pixel), reusing its buffer.
    fn paint_gray(&mut self, gray: &[u8], width: usize) {
        self.px.clear();
        if self.width == width {
            self.px.extend(gray.iter().map(|&v| gray_index(v)));
            return;
        }
        let height = gray.len() / width.max(1);
        let at = |i: usize, to: usize, from: usize| ((i * from + from / 2) / to).min(from - 1);
        for y in 0..self.height {
            let row = &gray[at(y, self.height, height) * width..][..width];
            self.px.extend((0..self.width).map(|x| gray_index(row[at(x, self.width, width)])));
        }
    }

    /// A frame coordinate on the canvas.
    fn zoomed(&self, v: f64) -> i64 {
        (v * self.zoom).round() as i64
    }

    fn set(&mut self, x: i64, y: i64, c: Colour) {
        if x >= 0 && y >= 0 && (x as usize) < self.width && (y as usize) < self.height {
            self.px[y as usize * self.width + x as usize] = c.index();
        }
    }

    /// The outline of the rectangle with columns `x0..=x1` and rows `y0..=y1`.
    pub fn rect(&mut self, x0: i64, y0: i64, x1: i64, y1: i64, c: Colour) {
        let [x0, y0, x1, y1] = [x0, y0, x1, y1].map(|v| self.zoomed(v as f64));
        for x in x0..=x1 {
            self.set(x, y0, c);
            self.set(x, y1, c);
        }
        for y in y0..=y1 {
            self.set(x0, y, c);
            self.set(x1, y, c);
        }
    }

    /// A cross of arm `r` pixels at the pixel nearest `(x, y)`.
    pub fn cross(&mut self, x: f64, y: f64, r: i64, c: Colour) {
        let (cx, cy) = (self.zoomed(x.round()), self.zoomed(y.round()));
        for d in -r..=r {
            self.set(cx + d, cy, c);
            self.set(cx, cy + d, c);
        }
    }

    /// A diagonal cross (x) of arm `r` pixels at the pixel nearest `(x, y)`.
    pub fn saltire(&mut self, x: f64, y: f64, r: i64, c: Colour) {
        let (cx, cy) = (self.zoomed(x.round()), self.zoomed(y.round()));
        for d in -r..=r {
            self.set(cx + d, cy + d, c);
            self.set(cx + d, cy - d, c);
        }
    }

    /// `text` in a 3x5 pixel font at `(x, y)` (top-left), on a black box; characters the
    /// font lacks are drawn as blanks.
    pub fn text(&mut self, x: i64, y: i64, text: &str, c: Colour) {
        let w = 4 * text.chars().count() as i64 + 1;
        for yy in y..y + 7 {
            for xx in x..x + w {
                if xx >= 0 && yy >= 0 && (xx as usize) < self.width && (yy as usize) < self.height {
                    self.px[yy as usize * self.width + xx as usize] = 0;
                }
            }
        }
        for (k, ch) in text.chars().enumerate() {
            let rows = glyph(ch.to_ascii_uppercase());
            for (r, bits) in rows.iter().enumerate() {
                for b in 0..3 {
                    if bits >> (2 - b) & 1 == 1 {
                        self.set(x + 1 + 4 * k as i64 + b, y + 1 + r as i64, c);
                    }
                }
            }
        }
    }

    /// The canvas as a yuv420p picture (for MP4; BT.601, limited range, as FFmpeg converts
    /// RGB) in `yuv`, reusing its buffer; odd sides are padded with black to even ones. A
    /// 2x2 block takes the colour of its first marked pixel, so one-pixel marks keep theirs.
    fn to_yuv420(&self, yuv: &mut Vec<u8>) {
        let (w2, h2) = (self.width.div_ceil(2) * 2, self.height.div_ceil(2) * 2);
        let lut: Vec<[u8; 3]> = palette().chunks_exact(3).map(|c| yuv601([c[0], c[1], c[2]])).collect();
        let at = |x: usize, y: usize| (x < self.width && y < self.height).then(|| self.px[y * self.width + x]);
        yuv.clear();
        yuv.reserve(w2 * h2 * 3 / 2);
        for y in 0..h2 {
            match (y < self.height).then(|| &self.px[y * self.width..][..self.width]) {
                Some(row) => {
                    yuv.extend(row.iter().map(|&i| lut[usize::from(i)][0]));
                    yuv.resize(yuv.len() + w2 - self.width, 16);
                }
                None => yuv.resize(yuv.len() + w2, 16),
            }
        }
        for plane in [1, 2] {
            for by in (0..h2).step_by(2) {
                for bx in (0..w2).step_by(2) {
                    let block = [at(bx, by), at(bx + 1, by), at(bx, by + 1), at(bx + 1, by + 1)];
                    let mark = block.into_iter().flatten().find(|&i| usize::from(i) >= GRAYS);
                    yuv.push(mark.map_or(128, |i| lut[usize::from(i)][plane]));
                }
            }
        }
    }
}

/// An RGB colour as BT.601 limited-range Y, U, V (FFmpeg's conversion to yuv420p).
fn yuv601([r, g, b]: [u8; 3]) -> [u8; 3] {
    let (r, g, b) = (f64::from(r), f64::from(g), f64::from(b));
    let y = 16.0 + (65.481 * r + 128.553 * g + 24.966 * b) / 255.0;
    let u = 128.0 + (-37.797 * r - 74.203 * g + 112.0 * b) / 255.0;
    let v = 128.0 + (112.0 * r - 93.786 * g - 18.214 * b) / 255.0;
    [y, u, v].map(|c| c.round().clamp(0.0, 255.0) as u8)
}

/// Rows of a 3x5 glyph, 3 bits each (most significant = left).
fn glyph(c: char) -> [u8; 5] {
    match c {
        '0' => [7, 5, 5, 5, 7],
        '1' => [2, 6, 2, 2, 7],
        '2' => [7, 1, 7, 4, 7],
        '3' => [7, 1, 7, 1, 7],
        '4' => [5, 5, 7, 1, 1],
        '5' => [7, 4, 7, 1, 7],
        '6' => [7, 4, 7, 5, 7],
        '7' => [7, 1, 1, 1, 1],
        '8' => [7, 5, 7, 5, 7],
        '9' => [7, 5, 7, 1, 7],
        'A' => [2, 5, 7, 5, 5],
        'B' => [6, 5, 6, 5, 6],
        'C' => [7, 4, 4, 4, 7],
        'D' => [6, 5, 5, 5, 6],
        'E' => [7, 4, 6, 4, 7],
        'F' => [7, 4, 6, 4, 4],
        'G' => [7, 4, 5, 5, 7],
        'H' => [5, 5, 7, 5, 5],
        'I' => [7, 2, 2, 2, 7],
        'K' => [5, 5, 6, 5, 5],
        'L' => [4, 4, 4, 4, 7],
        'M' => [5, 7, 7, 5, 5],
        'N' => [6, 5, 5, 5, 5],
        'O' => [7, 5, 5, 5, 7],
        'P' => [7, 5, 7, 4, 4],
        'R' => [6, 5, 6, 5, 5],
        'S' => [7, 4, 7, 1, 7],
        'T' => [7, 2, 2, 2, 2],
        'U' => [5, 5, 5, 5, 7],
        'V' => [5, 5, 5, 5, 2],
        'W' => [5, 5, 7, 7, 5],
        'X' => [5, 5, 2, 5, 5],
        'Y' => [5, 5, 2, 2, 2],
        '.' => [0, 0, 0, 0, 2],
        '-' => [0, 0, 7, 0, 0],
        ':' => [0, 2, 0, 2, 0],
        '/' => [1, 1, 2, 4, 4],
        _ => [0; 5],
    }
}

/// Draws a run's frames one at a time, in order: each with the windows each processor was
/// delivered from it (Watch blue, Peripheral yellow, Foveal green, COOP's corner-detector
/// window magenta), the position at the end of its period with a `size` box (red when NCC
/// measured it, orange for the corner detector), the true point when known (a cyan x), and
/// the frame number with the source or mode. Holds one canvas, whatever the run's length.
pub struct Painter<'a> {
    log: &'a RunLog,
    truth: Option<&'a [(f64, f64)]>,
    size: (usize, usize),
    windows: std::iter::Peekable<std::slice::Iter<'a, (usize, usize, coopwin_firmware::types::WindowRequest)>>,
    /// The source's number of the run's frame 0 (`track --start-frame`), for the labels.
    first: usize,
    /// The camera's binning: the windows are drawn over the sensor's pixels they cover.
    bin: usize,
}

impl<'a> Painter<'a> {
    /// A painter of `log`'s frames, with the true points `truth` when known.
    pub fn new(log: &'a RunLog, truth: Option<&'a [(f64, f64)]>, size: (usize, usize)) -> Self {
        Painter { log, truth, size, windows: log.windows_delivered.iter().peekable(), first: 0, bin: 1 }
    }

    /// The same painter, labelling the run's frame 0 as the source's frame `first`.
    pub fn numbered_from(self, first: usize) -> Self {
        Painter { first, ..self }
    }

    /// The same painter, for a run over the frames binned `bin` x `bin`.
    pub fn binned(self, bin: usize) -> Self {
        Painter { bin: bin.max(1), ..self }
    }

    /// Draws every `step`-th record of the log over its frame from `frames` at `size` (the
    /// frames' size or smaller), handing each canvas to `out` before the next is drawn.
    pub fn draw_all<E: From<FrameError>>(mut self, frames: &mut dyn FrameSource, (size, step): ((usize, usize), usize), out: &mut dyn FnMut(&Canvas) -> Result<(), E>) -> Result<(), E> {
        let (w, _) = frames.size();
        let mut c = Canvas { width: size.0, height: size.1, px: Vec::new(), zoom: size.0 as f64 / w as f64 };
        for rec in self.log.frames.iter().step_by(step.max(1)) {
            c.paint_gray(frames.frame(rec.frame)?, w);
            self.mark(&mut c, rec);
            out(&c)?;
        }
        Ok(())
    }

    /// Draws the marks of frame record `rec` on `c`.
    fn mark(&mut self, c: &mut Canvas, rec: &FrameRecord) {
        while let Some(&&(p, k, req)) = self.windows.peek().filter(|d| d.1 <= rec.frame) {
            self.windows.next();
            if k < rec.frame {
                // A frame left out of the overlay (every k-th frame of a long GIF).
                continue;
            }
            let colour = match (self.log.roles.get(p), rec.mode) {
                (Some(Role::Watch), _) | (Some(Role::Single), Mode::Watch) => Colour::Blue,
                (Some(Role::Peripheral), _) | (Some(Role::Single), Mode::Detect) => Colour::Yellow,
                (Some(Role::FovealCd), _) => Colour::Magenta,
                _ => Colour::Green,
            };
            let k = self.bin as i64;
            let (x0, y0) = (i64::from(req.x0) * k, i64::from(req.y0) * k);
            c.rect(x0, y0, x0 + i64::from(req.width) * k - 1, y0 + i64::from(req.height) * k - 1, colour);
        }
        if let Some(&(tx, ty)) = self.truth.and_then(|t| t.get(rec.frame)) {
            c.saltire(tx, ty, 3, Colour::Cyan);
        }
        let label = match (rec.point, rec.source) {
            (Some((x, y)), source) => {
                let colour = if source == Some(Source::Cd) { Colour::Orange } else { Colour::Red };
                let (hw, hh) = ((self.size.0 as f64 - 1.0) / 2.0, (self.size.1 as f64 - 1.0) / 2.0);
                c.rect((x - hw).round() as i64, (y - hh).round() as i64, (x + hw).round() as i64, (y + hh).round() as i64, colour);
                c.cross(x, y, 2, colour);
                if source == Some(Source::Cd) { "CD" } else { "NCC" }
            }
            (None, _) => match rec.mode {
                Mode::Watch => "WATCH",
                Mode::Detect => "DETECT",
                Mode::Track => "COAST",
            },
        };
        c.text(1, 1, &format!("{} {label}", rec.frame + self.first), Colour::White);
    }
}

/// Why an overlay could not be encoded.
#[derive(Debug)]
pub struct GifError(String);

impl fmt::Display for GifError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "GIF encoding failed: {}", self.0)
    }
}

impl std::error::Error for GifError {}

/// An endlessly looping GIF written canvas by canvas into `W`, each shown `delay_cs`
/// hundredths of a second.
pub struct GifWriter<W: std::io::Write> {
    enc: gif::Encoder<W>,
    size: (u16, u16),
    delay_cs: u16,
}

impl<W: std::io::Write> GifWriter<W> {
    /// Starts a `width` x `height` GIF in `out`.
    pub fn new(out: W, (width, height): (usize, usize), delay_cs: u16) -> Result<Self, GifError> {
        let side = |v: usize| u16::try_from(v).map_err(|_| GifError(format!("a side of {v} px is over GIF's 65535")));
        let size = (side(width)?, side(height)?);
        let mut enc = gif::Encoder::new(out, size.0, size.1, &palette()).map_err(|e| GifError(e.to_string()))?;
        enc.set_repeat(gif::Repeat::Infinite).map_err(|e| GifError(e.to_string()))?;
        Ok(GifWriter { enc, size, delay_cs })
    }

    /// Appends a frame.
    pub fn push(&mut self, c: &Canvas) -> Result<(), GifError> {
        let mut f = gif::Frame::from_indexed_pixels(self.size.0, self.size.1, c.px.as_slice(), None);
        f.delay = self.delay_cs;
        self.enc.write_frame(&f).map_err(|e| GifError(e.to_string()))
    }

    /// Ends the GIF and gives its writer back.
    pub fn finish(self) -> Result<W, GifError> {
        self.enc.into_inner().map_err(|e| GifError(e.to_string()))
    }
}

/// The overlay formats, told by the file's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OverlayKind {
    /// An animated GIF (written by coopwin), bounded in size ([`GifPlan`]).
    Gif,
    /// An H.264 MP4 (through FFmpeg), every frame at full size.
    Mp4,
}

/// Why an overlay could not be written.
#[derive(Debug)]
pub enum OverlayError {
    /// A frame could not be had.
    Frame(FrameError),
    /// The GIF could not be encoded.
    Gif(GifError),
    /// FFmpeg could not encode the MP4.
    Video(VideoError),
}

wrap_errors!(OverlayError { Frame(FrameError), Gif(GifError), Video(VideoError) });

impl fmt::Display for OverlayError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            OverlayError::Frame(e) => e.fmt(f),
            OverlayError::Gif(e) => e.fmt(f),
            OverlayError::Video(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for OverlayError {}

/// How a GIF overlay is bounded: its size, and every how many frames it keeps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GifPlan {
    /// Width and height drawn.
    pub size: (usize, usize),
    /// Every `step`-th frame is kept.
    pub step: usize,
}

impl GifPlan {
    /// Longest side of a GIF overlay.
    pub const SIDE: usize = 480;
    /// Pixels in all the frames of a GIF overlay (at the ~0.3 bytes a pixel measured on
    /// vtest.avi, about 15 MB).
    pub const PIXELS: usize = 50_000_000;

    /// The plan for `frames` frames of `size`.
    pub fn for_run(size: (usize, usize), frames: usize) -> GifPlan {
        let longest = size.0.max(size.1);
        let scaled = |v: usize| if longest > Self::SIDE { (v * Self::SIDE).div_ceil(longest).max(1) } else { v };
        let size = (scaled(size.0), scaled(size.1));
        GifPlan { size, step: (frames * size.0 * size.1).div_ceil(Self::PIXELS).max(1) }
    }

    /// What was reduced from frames of `full` size, in words (`None` when nothing was).
    pub fn reduced(&self, full: (usize, usize)) -> Option<String> {
        let mut what = Vec::new();
        if self.size != full {
            what.push(format!("scaled from {}x{} to {}x{}", full.0, full.1, self.size.0, self.size.1));
        }
        if self.step > 1 {
            what.push(format!("one frame in {} kept", self.step));
        }
        (!what.is_empty()).then(|| what.join(", "))
    }
}

impl OverlayKind {
    /// The format of `path`: `.gif` or `.mp4` (any case); `None` for anything else.
    pub fn of(path: &std::path::Path) -> Option<OverlayKind> {
        match path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
            Some("gif") => Some(OverlayKind::Gif),
            Some("mp4") => Some(OverlayKind::Mp4),
            _ => None,
        }
    }

    /// Draws `painter`'s run over `frames` and writes it to `out`, a frame at a time, at `fps`
    /// frames a second, and gives `out` back with what was reduced to bound a GIF (see
    /// [`GifPlan`]). A GIF shows each frame for its time rounded to hundredths, at least
    /// 0.02 s (browsers slow anything shorter).
    pub fn write<W: std::io::Write + Send + 'static>(self, out: W, frames: &mut dyn FrameSource, painter: Painter, fps: f64) -> Result<(W, Option<String>), OverlayError> {
        let full = frames.size();
        match self {
            OverlayKind::Gif => {
                let plan = GifPlan::for_run(full, painter.log.frames.len());
                let delay = (100.0 * plan.step as f64 / fps.max(1e-3)).round().clamp(2.0, 65535.0) as u16;
                let mut gif = GifWriter::new(out, plan.size, delay)?;
                painter.draw_all(frames, (plan.size, plan.step), &mut |c| gif.push(c).map_err(OverlayError::from))?;
                Ok((gif.finish()?, plan.reduced(full)))
            }
            OverlayKind::Mp4 => {
                let mut mp4 = Mp4Encoder::start((full.0.div_ceil(2) * 2, full.1.div_ceil(2) * 2), fps, out)?;
                let mut yuv = Vec::new();
                painter.draw_all(frames, (full, 1), &mut |c| {
                    c.to_yuv420(&mut yuv);
                    mp4.push(&yuv).map_err(OverlayError::from)
                })?;
                Ok((mp4.finish()?, None))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn marks_land_on_the_pixels_they_name() {
        let mut c = Canvas::from_gray(&[255u8; 100], 10, 10);
        // The white frame maps to the last gray entry.
        assert_eq!(c.px[0], (GRAYS - 1) as u8);
        c.rect(1, 2, 4, 6, Colour::Green);
        let g = Colour::Green.index();
        assert_eq!((c.px[2 * 10 + 1], c.px[6 * 10 + 4], c.px[4 * 10 + 1], c.px[4 * 10 + 4]), (g, g, g, g));
        assert_eq!(c.px[4 * 10 + 2], (GRAYS - 1) as u8, "inside the outline is untouched");
        c.cross(7.4, 7.6, 1, Colour::Red);
        assert_eq!(c.px[8 * 10 + 7], Colour::Red.index());
        // Off-canvas marks are clipped, not a panic.
        c.rect(-5, -5, 20, 20, Colour::Blue);
        c.text(8, 8, "COOP 12", Colour::White);
    }

    #[test]
    fn the_gif_decodes_to_the_same_frames() {
        // Reference: the gif crate's own decoder reading back what was written.
        let a = Canvas::from_gray(&(0..64).map(|v| (v * 4) as u8).collect::<Vec<_>>(), 8, 8);
        let mut b = a.clone();
        b.cross(3.0, 3.0, 2, Colour::Orange);
        let mut gif = GifWriter::new(Vec::new(), (8, 8), 4).expect("starts");
        gif.push(&a).expect("encodes");
        gif.push(&b).expect("encodes");
        let bytes = gif.finish().expect("ends");
        let mut opts = gif::DecodeOptions::new();
        opts.set_color_output(gif::ColorOutput::Indexed);
        let mut dec = opts.read_info(bytes.as_slice()).expect("a GIF");
        for want in [&a, &b] {
            let f = dec.read_next_frame().expect("readable").expect("a frame");
            assert_eq!((f.width, f.height, f.delay), (8, 8, 4));
            assert_eq!(&f.buffer[..], &want.px[..]);
        }
        assert!(dec.read_next_frame().expect("readable").is_none());
    }

    #[test]
    fn the_mp4_picture_is_bt601_with_each_mark_in_its_colour() {
        // Reference: BT.601 limited range worked by hand: gray v gives Y = 16 + 219 v / 255
        // and U = V = 128; red (255, 30, 30) gives U = 128 + (-37.797*255 - 74.203*30 +
        // 112*30) / 255 = 94.65 and V = 128 + (112*255 - 93.786*30 - 18.214*30) / 255 = 226.8.
        let mut c = Canvas::from_gray(&[255u8; 15], 5, 3);
        c.set(2, 0, Colour::Red);
        let mut yuv = Vec::new();
        c.to_yuv420(&mut yuv);
        // 5x3 padded to 6x4 with black: Y plane 24 bytes, U and V 3x2 each.
        assert_eq!(yuv.len(), 24 + 6 + 6);
        assert_eq!(&yuv[..5], &[235, 235, yuv601(Colour::Red.rgb())[0], 235, 235]);
        assert_eq!(yuv[5], 16, "padding is black");
        assert_eq!(&yuv[18..24], &[16; 6], "the padded row");
        let (u, v) = (&yuv[24..30], &yuv[30..36]);
        assert_eq!((u[1], v[1]), (95, 227), "the block holding the red pixel");
        assert_eq!((u[0], v[0], u[3], v[3]), (128, 128, 128, 128), "gray blocks");
        assert_eq!(yuv601([0, 0, 0]), [16, 128, 128]);
    }

    #[test]
    fn a_gif_is_scaled_and_thinned_to_its_budget() {
        // Reference: the arithmetic. 768x576 (vtest.avi) scales by 480/768 to 480x360, and
        // 795 of those frames are 137.4 M pixels: every 3rd frame keeps them under 50 M.
        let plan = GifPlan::for_run((768, 576), 795);
        assert_eq!(plan, GifPlan { size: (480, 360), step: 3 });
        assert_eq!(plan.reduced((768, 576)).as_deref(), Some("scaled from 768x576 to 480x360, one frame in 3 kept"));
        // The main job's 256x256 scene is left as it is.
        let small = GifPlan::for_run((256, 256), 600);
        assert_eq!((small, small.reduced((256, 256))), (GifPlan { size: (256, 256), step: 1 }, None));
    }
}
