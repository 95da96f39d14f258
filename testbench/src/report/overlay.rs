//! Overlays: each frame with the windows the processors acquired from it, the position
//! reported and the ground truth, as an animated GIF (written here, no program needed) or an
//! MP4 (through FFmpeg, [`crate::frames::video::Mp4Encoder`]); both are drawn and written a
//! frame at a time ([`Painter`]).
//!
//! Frames are drawn in a fixed 256-colour palette: 32 gray levels for the image and a few
//! saturated colours for the marks, so every frame encodes without quantisation and two runs
//! give the same bytes.
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

/// One frame being drawn: palette indices, row by row.
#[derive(Clone, Debug)]
pub struct Canvas {
    width: usize,
    height: usize,
    px: Vec<u8>,
}

impl Canvas {
    /// The gray frame `gray` (`width * height` bytes) as a canvas.
    pub fn from_gray(gray: &[u8], width: usize, height: usize) -> Canvas {
        let mut c = Canvas { width, height, px: Vec::new() };
        c.paint_gray(gray);
        c
    }

    /// Replaces the canvas's pixels with the gray frame `gray`, reusing its buffer.
    fn paint_gray(&mut self, gray: &[u8]) {
        self.px.clear();
        self.px.extend(gray.iter().map(|&v| ((usize::from(v) * (GRAYS - 1) + 127) / 255) as u8));
    }

    fn set(&mut self, x: i64, y: i64, c: Colour) {
        if x >= 0 && y >= 0 && (x as usize) < self.width && (y as usize) < self.height {
            self.px[y as usize * self.width + x as usize] = c.index();
        }
    }

    /// The outline of the rectangle with columns `x0..=x1` and rows `y0..=y1`.
    pub fn rect(&mut self, x0: i64, y0: i64, x1: i64, y1: i64, c: Colour) {
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
        let (cx, cy) = (x.round() as i64, y.round() as i64);
        for d in -r..=r {
            self.set(cx + d, cy, c);
            self.set(cx, cy + d, c);
        }
    }

    /// A diagonal cross (x) of arm `r` pixels at the pixel nearest `(x, y)`.
    pub fn saltire(&mut self, x: f64, y: f64, r: i64, c: Colour) {
        let (cx, cy) = (x.round() as i64, y.round() as i64);
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

    /// The canvas as RGB bytes (for MP4).
    pub fn to_rgb(&self) -> Vec<u8> {
        let p = palette();
        self.px.iter().flat_map(|&i| [p[3 * usize::from(i)], p[3 * usize::from(i) + 1], p[3 * usize::from(i) + 2]]).collect()
    }
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
}

impl<'a> Painter<'a> {
    /// A painter of `log`'s frames, with the true points `truth` when known.
    pub fn new(log: &'a RunLog, truth: Option<&'a [(f64, f64)]>, size: (usize, usize)) -> Self {
        Painter { log, truth, size, windows: log.windows_delivered.iter().peekable(), first: 0 }
    }

    /// The same painter, labelling the run's frame 0 as the source's frame `first`.
    pub fn numbered_from(self, first: usize) -> Self {
        Painter { first, ..self }
    }

    /// Draws every record of the log over its frame from `frames`, handing each canvas to
    /// `out` before the next is drawn.
    pub fn draw_all<E: From<FrameError>>(mut self, frames: &mut dyn FrameSource, out: &mut dyn FnMut(&Canvas) -> Result<(), E>) -> Result<(), E> {
        let (w, h) = frames.size();
        let mut c = Canvas { width: w, height: h, px: Vec::new() };
        for rec in &self.log.frames {
            c.paint_gray(frames.frame(rec.frame)?);
            self.mark(&mut c, rec);
            out(&c)?;
        }
        Ok(())
    }

    /// Draws the marks of frame record `rec` on `c`.
    fn mark(&mut self, c: &mut Canvas, rec: &FrameRecord) {
        while let Some(&&(p, _, req)) = self.windows.peek().filter(|d| d.1 <= rec.frame) {
            self.windows.next();
            let colour = match (self.log.roles.get(p), rec.mode) {
                (Some(Role::Watch), _) | (Some(Role::Single), Mode::Watch) => Colour::Blue,
                (Some(Role::Peripheral), _) | (Some(Role::Single), Mode::Detect) => Colour::Yellow,
                (Some(Role::FovealCd), _) => Colour::Magenta,
                _ => Colour::Green,
            };
            let (x0, y0) = (i64::from(req.x0), i64::from(req.y0));
            c.rect(x0, y0, x0 + i64::from(req.width) - 1, y0 + i64::from(req.height) - 1, colour);
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
        let mut f = gif::Frame::from_indexed_pixels(self.size.0, self.size.1, c.px.clone(), None);
        f.delay = self.delay_cs;
        self.enc.write_frame(&f).map_err(|e| GifError(e.to_string()))
    }

    /// Ends the GIF and gives its writer back.
    pub fn finish(self) -> Result<W, GifError> {
        self.enc.into_inner().map_err(|e| GifError(e.to_string()))
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
}
