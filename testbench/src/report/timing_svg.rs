//! Timing diagrams as SVG, drawn from the simulated flags of a window unit, one per sequence
//! of Appendix B, so they can be laid next to Figures B1.1-B1.5.
use coopwin_hdl::sim::appendix_b::Sequence;
use coopwin_hdl::window_unit::Flags;
use std::fmt::Write as _;

/// A row of a diagram: an input (drawn changing at the falling edge before the rising edge that
/// samples it), a one-bit flag or a multi-bit bus (changing at the rising edge that made it).
enum Row {
    Input(&'static str, fn(&Flags) -> bool),
    Bit(&'static str, fn(&Flags) -> bool),
    Bus(&'static str, fn(&Flags) -> u32),
}

fn rows(seq: Sequence) -> Vec<Row> {
    use Row::{Bit, Bus, Input};
    let camera = [Input("FVAL", |f| f.fval), Input("LVAL", |f| f.lval)];
    let rest: Vec<Row> = match seq {
        Sequence::StartFlagSet => vec![
            Input("CSTRB1", |f| f.coord_strobe),
            Bit("CRDY1", |f| f.coord_ready),
            Bit("START", |f| f.start),
            Bit("WLEN", |f| f.wlen),
        ],
        Sequence::FrameValidRising => vec![
            Bit("FVC", |f| f.fvc),
            Bit("FVLH", |f| f.fvlh),
            Bit("START", |f| f.start),
            Bit("WLEN", |f| f.wlen),
            Bit("STRBEN", |f| f.strben),
            Bus("YCOUNT", |f| f.ycount),
            Bit("YMIN", |f| f.ymin),
            Bit("YVAL", |f| f.yval),
        ],
        Sequence::LineValidRising => vec![
            Bit("LVC", |f| f.lvc),
            Bus("XCOUNT", |f| f.xcount),
            Bit("XMIN", |f| f.xmin),
            Bit("XYVAL", |f| f.xyval),
            Bit("CSTRB4", |f| f.pixel_strobe),
            Bus("D4", |f| f.pixel_out as u32),
        ],
        Sequence::LineValidFalling => vec![
            Bit("LVC", |f| f.lvc),
            Bus("XCOUNT", |f| f.xcount),
            Bit("XMAX", |f| f.xmax),
            Bit("LVHL", |f| f.lvhl),
            Bit("XYVAL", |f| f.xyval),
            Bit("CSTRB4", |f| f.pixel_strobe),
            Bus("D4", |f| f.pixel_out as u32),
            Bus("YCOUNT", |f| f.ycount),
        ],
        Sequence::FrameValidFalling => vec![
            Bit("FVC", |f| f.fvc),
            Bit("LVHL", |f| f.lvhl),
            Bit("FVHL", |f| f.fvhl),
            Bit("YMAX", |f| f.ymax),
            Bit("YVAL", |f| f.yval),
            Bit("WLRST", |f| f.wlrst),
            Bit("STRBEN", |f| f.strben),
        ],
    };
    camera.into_iter().chain(rest).collect()
}

const LABEL_W: usize = 90;
const CLOCK_W: usize = 28;
const ROW_H: usize = 30;
const SWING: usize = 18;

/// The diagram of `seq` over the clocks `span` of `rec` (flags after each rising edge, so a
/// change is drawn at the edge that made it).
pub fn diagram(seq: Sequence, rec: &[Flags], span: std::ops::Range<usize>) -> String {
    let rows = rows(seq);
    let n = span.len();
    let width = (LABEL_W + n * CLOCK_W + 10).max(560);
    let height = (rows.len() + 2) * ROW_H + 20;
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" font-family="monospace" font-size="12">"#
    );
    let _ = writeln!(s, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let _ = writeln!(
        s,
        r#"<text x="4" y="16" font-size="14">{} (simulated, clocks {}..{})</text>"#,
        seq.title(),
        span.start,
        span.end
    );
    // The pixel clock, rising at each sample boundary, with a dotted line down each rising edge
    // and its clock number every 5 clocks.
    let y0 = ROW_H + 10;
    let bottom = y0 + (rows.len() + 1) * ROW_H;
    let _ = writeln!(s, r#"<text x="4" y="{}">PVC</text>"#, y0 + SWING);
    let mut d = String::new();
    for (i, t) in span.clone().enumerate() {
        let x = LABEL_W + i * CLOCK_W;
        let _ = write!(
            d,
            "M{x},{lo} L{x},{hi} L{xm},{hi} L{xm},{lo} L{xe},{lo} ",
            lo = y0 + SWING,
            hi = y0,
            xm = x + CLOCK_W / 2,
            xe = x + CLOCK_W
        );
        let _ = writeln!(s, r##"<path d="M{x},{y0} L{x},{bottom}" stroke="#ccc" stroke-dasharray="2,3"/>"##);
        if t % 5 == 0 {
            let _ = writeln!(s, r##"<text x="{}" y="{}" font-size="10" fill="#555">{t}</text>"##, x + 2, y0 - 4);
        }
    }
    let _ = writeln!(s, r#"<path d="{d}" stroke="gray" fill="none"/>"#);
    for (r, row) in rows.iter().enumerate() {
        let top = y0 + (r + 1) * ROW_H;
        let (lo, hi) = (top + SWING, top);
        match row {
            Row::Bit(name, f) | Row::Input(name, f) => {
                let _ = writeln!(s, r#"<text x="4" y="{lo}">{name}</text>"#);
                // An input sampled at edge t was set up half a clock before it.
                let lead = if matches!(row, Row::Input(..)) { CLOCK_W / 2 } else { 0 };
                let mut d = String::new();
                for (i, t) in span.clone().enumerate() {
                    let y = if f(&rec[t]) { hi } else { lo };
                    let x = (LABEL_W + i * CLOCK_W - lead).max(LABEL_W);
                    let _ = write!(
                        d,
                        "{}{x},{y} L{},{y} ",
                        if i == 0 { "M" } else { "L" },
                        LABEL_W + (i + 1) * CLOCK_W - lead
                    );
                }
                let _ = writeln!(
                    s,
                    r#"<path d="{d}" stroke="black" stroke-width="1.5" fill="none"/>"#
                );
            }
            Row::Bus(name, f) => {
                let _ = writeln!(s, r#"<text x="4" y="{lo}">{name}</text>"#);
                let mut i = 0;
                let ts: Vec<usize> = span.clone().collect();
                while i < ts.len() {
                    let v = f(&rec[ts[i]]);
                    let j = (i..ts.len())
                        .find(|&k| f(&rec[ts[k]]) != v)
                        .unwrap_or(ts.len());
                    let (x0, x1) = (LABEL_W + i * CLOCK_W, LABEL_W + j * CLOCK_W);
                    let m = (hi + lo) / 2;
                    let _ = writeln!(
                        s,
                        r#"<path d="M{x0},{m} L{a},{hi} L{b},{hi} L{x1},{m} L{b},{lo} L{a},{lo} Z" stroke="black" fill="none"/>"#,
                        a = x0 + 3,
                        b = x1.saturating_sub(3).max(x0 + 3)
                    );
                    let _ = writeln!(s, r#"<text x="{}" y="{}">{v}</text>"#, x0 + 5, m + 4);
                    i = j;
                }
            }
        }
    }
    s.push_str("</svg>\n");
    s
}
