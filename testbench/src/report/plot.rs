//! Line charts and grouped bar charts as SVG, and their PNG rendering (resvg), for the
//! reports and experiments.
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// One named series of (x, y) points; `None` y values break the line.
pub struct Series {
    /// Legend label.
    pub label: String,
    /// Points.
    pub points: Vec<(f64, Option<f64>)>,
}

/// A chart: title, axis labels and series.
pub struct Chart {
    /// Title above the plot.
    pub title: String,
    /// X axis label.
    pub x_label: String,
    /// Y axis label.
    pub y_label: String,
    /// The data.
    pub series: Vec<Series>,
    /// Fixed y range; otherwise from the data.
    pub y_range: Option<(f64, f64)>,
}

const COLORS: [&str; 6] = ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b"];
const W: f64 = 720.0;
const H: f64 = 420.0;
const L: f64 = 70.0;
const R: f64 = 20.0;
const T: f64 = 40.0;
const B: f64 = 55.0;

fn nice_ticks(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    let span = (hi - lo).max(1e-12);
    let raw = span / n as f64;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0].iter().map(|m| m * mag).find(|s| *s >= raw).unwrap_or(10.0 * mag);
    let mut t = (lo / step).ceil() * step;
    let mut out = Vec::new();
    while t <= hi + 1e-9 * span {
        out.push(t);
        t += step;
    }
    out
}

fn fmt_tick(v: f64) -> String {
    if v.abs() >= 100.0 || v == v.round() {
        format!("{v:.0}")
    } else {
        format!("{v:.2}").trim_end_matches('0').trim_end_matches('.').to_string()
    }
}

impl Chart {
    /// The chart as an SVG document.
    pub fn svg(&self) -> String {
        let xs = self.series.iter().flat_map(|s| s.points.iter().map(|p| p.0));
        let ys = self.series.iter().flat_map(|s| s.points.iter().filter_map(|p| p.1));
        let (x0, x1) = xs.fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v), b.max(v)));
        let (mut y0, mut y1) = self.y_range.unwrap_or_else(|| ys.fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v), b.max(v))));
        let (x0, x1) = if x0 > x1 { (0.0, 1.0) } else if x0 == x1 { (x0 - 1.0, x1 + 1.0) } else { (x0, x1) };
        if y0 > y1 {
            (y0, y1) = (0.0, 1.0);
        } else if y0 == y1 {
            (y0, y1) = (y0 - 1.0, y1 + 1.0);
        } else if self.y_range.is_none() {
            let pad = 0.05 * (y1 - y0);
            (y0, y1) = (y0 - pad, y1 + pad);
        }
        let px = |x: f64| L + (x - x0) / (x1 - x0) * (W - L - R);
        let py = |y: f64| H - B - (y - y0) / (y1 - y0) * (H - T - B);
        let mut s = String::new();
        let _ = writeln!(s, r#"<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="DejaVu Sans, sans-serif" font-size="12">"#);
        let _ = writeln!(s, r#"<rect width="100%" height="100%" fill="white"/>"#);
        let _ = writeln!(s, r#"<text x="{}" y="24" font-size="15" text-anchor="middle">{}</text>"#, W / 2.0, esc(&self.title));
        for t in nice_ticks(x0, x1, 8) {
            let _ = writeln!(s, r##"<line x1="{0}" y1="{1}" x2="{0}" y2="{2}" stroke="#ddd"/><text x="{0}" y="{3}" text-anchor="middle">{4}</text>"##, px(t), T, H - B, H - B + 16.0, fmt_tick(t));
        }
        for t in nice_ticks(y0, y1, 6) {
            let _ = writeln!(s, r##"<line x1="{0}" y1="{1}" x2="{2}" y2="{1}" stroke="#ddd"/><text x="{3}" y="{4}" text-anchor="end">{5}</text>"##, L, py(t), W - R, L - 6.0, py(t) + 4.0, fmt_tick(t));
        }
        let _ = writeln!(s, r#"<rect x="{L}" y="{T}" width="{}" height="{}" fill="none" stroke="black"/>"#, W - L - R, H - T - B);
        let _ = writeln!(s, r#"<text x="{}" y="{}" text-anchor="middle">{}</text>"#, (L + W - R) / 2.0, H - 12.0, esc(&self.x_label));
        let _ = writeln!(s, r#"<text x="16" y="{0}" text-anchor="middle" transform="rotate(-90 16 {0})">{1}</text>"#, (T + H - B) / 2.0, esc(&self.y_label));
        for (i, ser) in self.series.iter().enumerate() {
            let c = COLORS[i % COLORS.len()];
            let mut d = String::new();
            let mut pen_up = true;
            for &(x, y) in &ser.points {
                match y {
                    Some(y) => {
                        let _ = write!(d, "{}{:.1},{:.1} ", if pen_up { "M" } else { "L" }, px(x), py(y.clamp(y0, y1)));
                        pen_up = false;
                    }
                    None => pen_up = true,
                }
            }
            let _ = writeln!(s, r#"<path d="{d}" stroke="{c}" stroke-width="1.6" fill="none"/>"#);
            if ser.points.len() <= 40 {
                for &(x, y) in &ser.points {
                    if let Some(y) = y {
                        let _ = writeln!(s, r#"<circle cx="{:.1}" cy="{:.1}" r="3" fill="{c}"/>"#, px(x), py(y.clamp(y0, y1)));
                    }
                }
            }
            let ly = T + 16.0 + 18.0 * i as f64;
            let _ = writeln!(s, r#"<line x1="{}" y1="{ly}" x2="{}" y2="{ly}" stroke="{c}" stroke-width="3"/><text x="{}" y="{}">{}</text>"#, W - R - 170.0, W - R - 150.0, W - R - 144.0, ly + 4.0, esc(&ser.label));
        }
        s.push_str("</svg>\n");
        s
    }
}

/// A grouped bar chart: for each group (an object, a condition), one bar per series, side by
/// side, the series named in a legend row under the title.
pub struct Bars {
    /// Title above the plot.
    pub title: String,
    /// Y axis label.
    pub y_label: String,
    /// The groups' labels, left to right; a `-` splits a label over two lines.
    pub groups: Vec<String>,
    /// The series: a label and a value a group (`None`: no bar).
    pub series: Vec<(String, Vec<Option<f64>>)>,
    /// The y range.
    pub y_range: (f64, f64),
}

/// Height of a bar chart (a legend row and two-line group labels more than a line chart's).
const BARS_H: f64 = 470.0;

impl Bars {
    /// The chart as an SVG document.
    pub fn svg(&self) -> String {
        let (top, bottom) = (T + 28.0, 62.0);
        let (y0, y1) = if self.y_range.1 > self.y_range.0 { self.y_range } else { (0.0, 1.0) };
        let py = |y: f64| BARS_H - bottom - (y.clamp(y0, y1) - y0) / (y1 - y0) * (BARS_H - top - bottom);
        let groups = self.groups.len().max(1) as f64;
        let slot = (W - L - R) / groups;
        let bar = slot * 0.8 / self.series.len().max(1) as f64;
        let mut s = String::new();
        let _ = writeln!(s, r#"<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{BARS_H}" font-family="DejaVu Sans, sans-serif" font-size="12">"#);
        let _ = writeln!(s, r#"<rect width="100%" height="100%" fill="white"/>"#);
        let _ = writeln!(s, r#"<text x="{}" y="24" font-size="15" text-anchor="middle">{}</text>"#, W / 2.0, esc(&self.title));
        // Legend entries one after another, each as wide as its label (about 7 px a character).
        let mut x = L;
        for (i, (label, _)) in self.series.iter().enumerate() {
            let _ = writeln!(s, r#"<rect x="{x:.1}" y="{}" width="12" height="12" fill="{}"/><text x="{:.1}" y="{}">{}</text>"#, T + 2.0, COLORS[i % COLORS.len()], x + 16.0, T + 12.0, esc(label));
            x += 16.0 + 7.0 * label.chars().count() as f64 + 20.0;
        }
        for t in nice_ticks(y0, y1, 6) {
            let _ = writeln!(s, r##"<line x1="{0}" y1="{1:.1}" x2="{2}" y2="{1:.1}" stroke="#ddd"/><text x="{3}" y="{4:.1}" text-anchor="end">{5}</text>"##, L, py(t), W - R, L - 6.0, py(t) + 4.0, fmt_tick(t));
        }
        for (g, label) in self.groups.iter().enumerate() {
            let x0 = L + slot * g as f64 + slot * 0.1;
            for (i, (_, values)) in self.series.iter().enumerate() {
                if let Some(v) = values.get(g).copied().flatten() {
                    let _ = writeln!(s, r#"<rect x="{:.1}" y="{:.1}" width="{:.1}" height="{:.1}" fill="{}"/>"#, x0 + bar * i as f64, py(v), bar * 0.92, py(y0) - py(v), COLORS[i % COLORS.len()]);
                }
            }
            let centre = L + slot * (g as f64 + 0.5);
            let (first, second) = label.split_once('-').unwrap_or((label, ""));
            let _ = writeln!(s, r#"<text x="{centre:.1}" y="{}" font-size="10" text-anchor="middle">{}</text><text x="{centre:.1}" y="{}" font-size="10" text-anchor="middle">{}</text>"#, BARS_H - bottom + 16.0, esc(first), BARS_H - bottom + 31.0, esc(second));
        }
        let _ = writeln!(s, r#"<rect x="{L}" y="{top}" width="{}" height="{}" fill="none" stroke="black"/>"#, W - L - R, BARS_H - top - bottom);
        let _ = writeln!(s, r#"<text x="16" y="{0}" text-anchor="middle" transform="rotate(-90 16 {0})">{1}</text>"#, (top + BARS_H - bottom) / 2.0, esc(&self.y_label));
        s.push_str("</svg>\n");
        s
    }
}

fn esc(t: &str) -> String {
    t.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

/// Why a chart could not be rendered or written.
#[derive(Debug)]
pub enum PlotError {
    /// The SVG does not parse.
    Svg(resvg::usvg::Error),
    /// The SVG has no area to draw on.
    Empty,
    /// The PNG cannot be encoded.
    Png(String),
    /// A file cannot be written.
    Io {
        /// The file.
        path: PathBuf,
        /// The reason.
        source: std::io::Error,
    },
}

impl std::fmt::Display for PlotError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PlotError::Svg(e) => write!(f, "SVG: {e}"),
            PlotError::Empty => f.write_str("empty SVG"),
            PlotError::Png(e) => write!(f, "PNG: {e}"),
            PlotError::Io { path, source } => write!(f, "cannot write {}: {source}", path.display()),
        }
    }
}

impl std::error::Error for PlotError {}

/// Renders an SVG document to PNG bytes (system fonts for the text).
pub fn png(svg: &str) -> Result<Vec<u8>, PlotError> {
    let mut opt = resvg::usvg::Options::default();
    opt.fontdb_mut().load_system_fonts();
    let tree = resvg::usvg::Tree::from_str(svg, &opt).map_err(PlotError::Svg)?;
    let size = tree.size().to_int_size();
    let mut pixmap = resvg::tiny_skia::Pixmap::new(size.width(), size.height()).ok_or(PlotError::Empty)?;
    resvg::render(&tree, resvg::tiny_skia::Transform::default(), &mut pixmap.as_mut());
    pixmap.encode_png().map_err(|e| PlotError::Png(e.to_string()))
}

/// Writes `name.svg` and `name.png` into `dir`.
pub fn write(chart: &Chart, dir: &Path, name: &str) -> Result<(), PlotError> {
    write_svg(&chart.svg(), dir, name)
}

/// Writes the document `svg` as `name.svg` and `name.png` into `dir`.
pub fn write_svg(svg: &str, dir: &Path, name: &str) -> Result<(), PlotError> {
    let file = |ext: &str, bytes: &[u8]| {
        let path = dir.join(format!("{name}.{ext}"));
        std::fs::write(&path, bytes).map_err(|source| PlotError::Io { path, source })
    };
    file("svg", svg.as_bytes())?;
    file("png", &png(svg)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_round_and_cover_the_range() {
        assert_eq!(nice_ticks(0.0, 10.0, 5), vec![0.0, 2.0, 4.0, 6.0, 8.0, 10.0]);
        let t = nice_ticks(0.13, 0.61, 5);
        let want = [0.2, 0.3, 0.4, 0.5, 0.6];
        assert_eq!(t.len(), want.len());
        assert!(t.iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-12), "{t:?}");
    }

    #[test]
    fn chart_renders_to_a_png_with_ink_where_the_line_is() {
        let chart = Chart {
            title: "t".into(),
            x_label: "x".into(),
            y_label: "y".into(),
            series: vec![Series { label: "a".into(), points: vec![(0.0, Some(0.0)), (1.0, Some(1.0))] }],
            y_range: Some((0.0, 1.0)),
        };
        let bytes = png(&chart.svg()).unwrap();
        let img = image::load_from_memory(&bytes).unwrap().to_rgb8();
        assert_eq!((img.width(), img.height()), (720, 420));
        // The diagonal's midpoint is drawn in the first series' blue.
        let (mx, my) = ((L + (W - L - R) / 2.0) as u32, (T + (H - T - B) / 2.0) as u32);
        let near_blue = (mx - 3..=mx + 3).any(|x| (my - 3..=my + 3).any(|y| {
            let p = img.get_pixel(x, y);
            p[2] > 150 && p[0] < 120
        }));
        assert!(near_blue);
    }

    #[test]
    fn bars_stand_as_high_as_their_values_in_their_series_colour() {
        let bars = Bars {
            title: "t".into(),
            y_label: "y".into(),
            groups: vec!["one".into(), "two-lines".into()],
            series: vec![("a".into(), vec![Some(100.0), Some(50.0)]), ("b".into(), vec![None, Some(25.0)])],
            y_range: (0.0, 100.0),
        };
        let img = image::load_from_memory(&png(&bars.svg()).unwrap()).unwrap().to_rgb8();
        assert_eq!((img.width(), img.height()), (720, BARS_H as u32));
        // Hand calculation of the layout: plot rows from 68 (y = 100) to 408 (y = 0), two
        // slots of 315 px from x = 70, bars 126 px wide from 10 % into a slot.
        let blue = |x: u32, y: u32| {
            let p = img.get_pixel(x, y);
            p[2] > 150 && p[0] < 80
        };
        let (bar_a1, bar_a2, bar_b2) = (70 + 31 + 60, 70 + 315 + 31 + 60, 70 + 315 + 31 + 126 + 60);
        assert!(blue(bar_a1, 75) && blue(bar_a1, 400), "the first bar reaches 100");
        assert!(!blue(bar_a2, 230) && blue(bar_a2, 245), "the second stops at 50 (row 238)");
        let orange_red = |x: u32, y: u32| img.get_pixel(x, y)[0] > 180 && img.get_pixel(x, y)[2] < 80;
        assert!(!orange_red(bar_b2, 315) && orange_red(bar_b2, 330), "series b's bar stops at 25 (row 323)");
        assert!(!blue(70 + 31 + 126 + 60, 300) && !orange_red(70 + 31 + 126 + 60, 300), "no bar where b has no value");
    }
}
