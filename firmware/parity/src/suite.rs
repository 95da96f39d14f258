//! The suite: every kernel of the thesis's window processors (2.4 matching and differencing,
//! ch. 3 corner detector, 3.4.1 information, 4.3 COOP decision) on the benchmark inputs, a
//! float-format comparison for the M4F's single-precision FPU, and the COOP Foveal pair
//! (4.2) replaying a recorded window stream. One line per result; floats as IEEE bits.
use crate::pgm::{self, PgmError};
use crate::stream::{Frame, Stream, StreamError};
use coopwin_firmware::kernels::confidence::{ConfidencePolicy, KalmanCoop, SseCoop};
use coopwin_firmware::kernels::corner::{CornerDetector, CornerParams};
use coopwin_firmware::kernels::fmath::sqrtf;
use coopwin_firmware::kernels::info::{corner_information, edge_information, edge_information_with_prior};
use coopwin_firmware::kernels::matching::{best_match, best_match_decimated, blocks_matching, Match, MatchError, Method};
use coopwin_firmware::kernels::motion::{detect_motion, MotionArea, MotionError};
use coopwin_firmware::processors::{watch, CornerPartner, Dest, Foveal, FovealKind, Fix, Msg, Outcome, Params, Peripheral, Step, Template, Work};
use coopwin_firmware::kernels::view::WindowView;
use coopwin_firmware::types::{Decimation, Point, Source, WindowRequest};
use core::fmt::{self, Write};

/// The benchmark inputs (`fixtures/bench/`, see its README) and the recorded window stream.
pub mod inputs {
    /// Foveal window, 24x24.
    pub const FOVEAL_WINDOW: &[u8] = include_bytes!("../../../fixtures/bench/foveal_window.pgm");
    /// Foveal template, 20x20.
    pub const FOVEAL_TEMPLATE: &[u8] = include_bytes!("../../../fixtures/bench/foveal_template.pgm");
    /// Peripheral window, 40x40.
    pub const PERIPHERAL_WINDOW: &[u8] = include_bytes!("../../../fixtures/bench/peripheral_window.pgm");
    /// Peripheral template, 16x16.
    pub const PERIPHERAL_TEMPLATE: &[u8] = include_bytes!("../../../fixtures/bench/peripheral_template.pgm");
    /// Watch frame t-1, 256x256.
    pub const WATCH_PREV: &[u8] = include_bytes!("../../../fixtures/bench/watch_prev.pgm");
    /// Watch frame t, 256x256.
    pub const WATCH_NEXT: &[u8] = include_bytes!("../../../fixtures/bench/watch_next.pgm");
    /// Corner window, 20x20.
    pub const CORNER_20: &[u8] = include_bytes!("../../../fixtures/bench/corner_20.pgm");
    /// Corner window, 24x24.
    pub const CORNER_24: &[u8] = include_bytes!("../../../fixtures/bench/corner_24.pgm");
    /// The COOP pair's windows recorded from the testbench (`fixtures/board/README.md`).
    pub const WINDOWS: &[u8] = include_bytes!("../../../fixtures/board/windows.bin");
    /// The adapting COOP pair's windows, recorded alike (`fixtures/board/README.md`).
    pub const WINDOWS_ADAPTIVE: &[u8] = include_bytes!("../../../fixtures/board/windows_adaptive.bin");
    /// The adapting pair's windows with its object partly covered (`fixtures/board/README.md`).
    pub const WINDOWS_COVERED: &[u8] = include_bytes!("../../../fixtures/board/windows_covered.bin");
}

/// Brackets each measured piece of work. The board counts instructions; the host runs it.
pub trait Meter {
    /// Runs the pure computation `f` (possibly several times, for a finer count) and
    /// returns its result.
    fn kernel<R>(&mut self, id: &str, f: &mut dyn FnMut() -> R) -> R;
    /// Runs the stateful step `f` exactly once.
    fn once<R>(&mut self, id: &str, f: &mut dyn FnMut() -> R) -> R;
}

/// A meter that measures nothing (the host).
pub struct NoMeter;

impl Meter for NoMeter {
    fn kernel<R>(&mut self, _: &str, f: &mut dyn FnMut() -> R) -> R {
        f()
    }
    fn once<R>(&mut self, _: &str, f: &mut dyn FnMut() -> R) -> R {
        f()
    }
}

/// Why the suite stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SuiteError {
    /// An embedded image is not a PGM.
    Pgm(&'static str, PgmError),
    /// An image's size does not make a view.
    View(&'static str),
    /// The window stream is malformed.
    Stream(StreamError),
    /// The stream's template is not a valid template (or the Watch's cannot be captured).
    Template,
    /// The Watch benchmark pair shows no motion for the Peripheral to lock on to.
    NoMotion,
    /// The processors asked for a window other than the one recorded at this frame: the
    /// replay no longer follows the recorded run.
    Diverged(u16),
    /// The output sink refused a line.
    Fmt,
}

impl From<fmt::Error> for SuiteError {
    fn from(_: fmt::Error) -> Self {
        SuiteError::Fmt
    }
}

fn image(name: &'static str, bytes: &'static [u8]) -> Result<WindowView<'static>, SuiteError> {
    let p = pgm::parse(bytes).map_err(|e| SuiteError::Pgm(name, e))?;
    WindowView::packed(p.pixels, p.width, p.height).map_err(|_| SuiteError::View(name))
}

/// FNV-1a, 64-bit: a checksum of a byte buffer for one output line.
pub fn fnv1a<'a>(bytes: impl IntoIterator<Item = &'a u8>) -> u64 {
    bytes.into_iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3))
}

/// [`fnv1a`] of a bit-row edge map spread to a byte per pixel (row-major, 1 = edge).
fn map_hash((rows, w, _): (&[u64], usize, usize)) -> u64 {
    const BYTE: [u8; 2] = [0, 1];
    fnv1a(rows.iter().flat_map(|&r| (0..w).map(move |x| &BYTE[usize::from(r >> x & 1 == 1)])))
}

fn match_line(out: &mut dyn Write, id: &str, m: Result<Match, MatchError>) -> fmt::Result {
    match m {
        Ok(m) => writeln!(
            out,
            "{id} x={} y={} score={:016x} sub={:08x},{:08x} frame={:08x},{:08x}",
            m.x,
            m.y,
            m.score.to_bits(),
            m.sub_x.to_bits(),
            m.sub_y.to_bits(),
            m.frame_x.to_bits(),
            m.frame_y.to_bits()
        ),
        Err(e) => writeln!(out, "{id} error={e:?}"),
    }
}

/// Runs the whole suite, writing its lines to `out`.
pub fn run<W: Write, M: Meter>(out: &mut W, meter: &mut M) -> Result<(), SuiteError> {
    run_kernels(out, meter)?;
    tracker(out, meter, &Replay::THESIS)?;
    tracker(out, meter, &Replay::ADAPTIVE)?;
    tracker(out, meter, &Replay::COVERED)
}

/// The suite before the COOP pair's replay (the lines before the first `tracker` line): every
/// kernel, the number formats and the decisions.
fn run_kernels<W: Write, M: Meter>(out: &mut W, meter: &mut M) -> Result<(), SuiteError> {
    kernels(out, meter)?;
    float_formats(out, meter)?;
    decisions(out, meter)
}

fn kernels<W: Write, M: Meter>(out: &mut W, meter: &mut M) -> Result<(), SuiteError> {
    let fw = image("foveal_window", inputs::FOVEAL_WINDOW)?;
    let ft = image("foveal_template", inputs::FOVEAL_TEMPLATE)?;
    matches(out, meter, &fw, &ft, [("foveal_ncc_20in24", Method::Ncc), ("foveal_zncc_20in24", Method::Zncc)])?;
    // An adapting track's check of a partly covered object (issue 38): the template's 16
    // blocks at its best placement, (2, 2).
    let (matching, textured) = meter.kernel("foveal_blocks_20in24", &mut || blocks_matching(&fw, &ft, (2, 2), 4, 0.9));
    writeln!(out, "foveal_blocks_20in24 matching={matching} textured={textured}")?;
    peripheral_kernels(out, meter)?;
    peripheral_steps(out, meter)?;
    watch_strips(out, meter)?;
    let prev = image("watch_prev", inputs::WATCH_PREV)?;
    let next = image("watch_next", inputs::WATCH_NEXT)?;
    let area = meter.kernel("watch_motion_256", &mut || detect_motion(&prev, &next, WATCH_THRESHOLD));
    motion_line(out, area)?;
    corner_kernels(out, meter)
}

/// `tpl` matched in `win` by each of `methods`, one line each under its id.
fn matches<W: Write, M: Meter, const N: usize>(
    out: &mut W,
    meter: &mut M,
    win: &WindowView<'_>,
    tpl: &WindowView<'_>,
    methods: [(&str, Method); N],
) -> Result<(), SuiteError> {
    for (id, method) in methods {
        let m = meter.kernel(id, &mut || best_match(method, win, tpl));
        match_line(out, id, m)?;
    }
    Ok(())
}

/// The Peripheral's kernels (2.3.2): SSD and SAD of the 16x16 template in the 40x40 window,
/// and SSD at 25 %.
fn peripheral_kernels<W: Write, M: Meter>(out: &mut W, meter: &mut M) -> Result<(), SuiteError> {
    let pw = image("peripheral_window", inputs::PERIPHERAL_WINDOW)?;
    let pt = image("peripheral_template", inputs::PERIPHERAL_TEMPLATE)?;
    matches(out, meter, &pw, &pt, [("peripheral_ssd_16in40", Method::Ssd), ("peripheral_sad_16in40", Method::Sad)])?;
    let id = "peripheral_ssd_16in40_dec";
    let m = meter.kernel(id, &mut || best_match_decimated(Method::Ssd, &pw, &pt));
    match_line(out, id, m)?;
    Ok(())
}

/// The differencing threshold of the Watch benchmark (`watch_motion_256`, OpenCV's `absdiff`
/// > 30 in `fixtures/bench/README.md`).
const WATCH_THRESHOLD: u8 = 30;

/// The line `watch_motion_256 bbox=XMIN,XMAX,YMIN,YMAX count=N` (or `none=..`): the whole
/// frame's motion, from one Watch or merged from its strips'.
fn motion_line<W: Write>(out: &mut W, area: Result<Option<MotionArea>, MotionError>) -> fmt::Result {
    match area {
        Ok(Some(a)) => writeln!(out, "watch_motion_256 bbox={},{},{},{} count={}", a.xmin, a.xmax, a.ymin, a.ymax, a.count),
        other => writeln!(out, "watch_motion_256 none={other:?}"),
    }
}

/// Strips the Watch's 256x256 frame is split into, each its own processor (issue 22: a whole
/// previous frame, 64 KiB, does not fit one processor's 64 KiB beside anything else): 256x64,
/// a 16 KiB previous strip and a 16 KiB window each.
pub const WATCH_STRIPS: u16 = 4;
/// Bytes of one strip of the 256x256 benchmark frame.
const STRIP_BYTES: usize = 256 * 256 / WATCH_STRIPS as usize;

/// The Watch benchmark pair through [`WATCH_STRIPS`] strip processors (2.3.3, MPDF's Watch
/// windows covering the frame): a line each, `watch_strip K rows=Y0-Y1 ..`, and their areas
/// merged (`watch::merge`), which must be the whole frame's `watch_motion_256`.
fn watch_strips<W: Write, M: Meter>(out: &mut W, meter: &mut M) -> Result<Option<MotionArea>, SuiteError> {
    let prev = image("watch_prev", inputs::WATCH_PREV)?;
    let next = image("watch_next", inputs::WATCH_NEXT)?;
    let (w, h) = (next.width() as u16, next.height() as u16);
    let frame = WindowRequest { x0: 0, y0: 0, width: w, height: h, decimation: Decimation::Full };
    let mut merged = None;
    for k in 0..WATCH_STRIPS {
        let s = watch::strip(frame, k, WATCH_STRIPS).ok_or(SuiteError::View("watch strip"))?;
        let area = watch_strip(meter, &prev, &next, s)?;
        write!(out, "watch_strip {k} rows={}-{}", s.y0, s.y0 + s.height - 1)?;
        match area {
            Some(a) => writeln!(out, " bbox={},{},{},{} count={}", a.xmin, a.xmax, a.ymin, a.ymax, a.count)?,
            None => writeln!(out, " none")?,
        }
        merged = watch::merge(merged, area);
    }
    Ok(merged)
}

/// One strip's Watch processor, metered as `watch_strip`: its previous acquisition and the
/// window the unit delivers, each [`STRIP_BYTES`] in its own RAM (here this frame), differenced.
#[inline(never)]
fn watch_strip<M: Meter>(
    meter: &mut M,
    prev: &WindowView<'_>,
    next: &WindowView<'_>,
    s: WindowRequest,
) -> Result<Option<MotionArea>, SuiteError> {
    let (mut last, mut window) = ([0u8; STRIP_BYTES], [0u8; STRIP_BYTES]);
    let rows = |v: &WindowView<'_>, buf| v.sub(0, usize::from(s.y0), usize::from(s.width), usize::from(s.height))?.pack_into(buf);
    let bad = SuiteError::View("watch strip");
    let last = rows(prev, &mut last).ok_or(bad)?;
    let window = rows(next, &mut window).ok_or(bad)?;
    meter.kernel("watch_strip", &mut || detect_motion(&last, &window, WATCH_THRESHOLD)).map_err(|_| bad)
}

/// The Watch processors' image (issue 22: one image a processor): the strips' lines and their
/// merged area, which `scripts/board.sh` holds to the whole frame's `watch_motion_256` line.
pub fn run_watch<W: Write, M: Meter>(out: &mut W, meter: &mut M) -> Result<(), SuiteError> {
    let merged = watch_strips(out, meter)?;
    motion_line(out, Ok(merged))?;
    Ok(())
}

/// Where the Peripheral scenarios lose the object: a corner of the frame far from it.
const LOST_AT: Point = Point { x: 20.0, y: 236.0 };
/// Most windows a Peripheral scenario runs (an adapting sweep's 40x40 window, then its 64x64
/// window and nine tiles, each twice for its two looks, and a spare).
const PERIPHERAL_STEPS: u16 = 22;

/// The Peripheral processor (2.3.2) on the Watch's benchmark frame `watch_next`: its template
/// captured there at the centre of the Watch's motion (as `Watch` captures it), then
/// * `peripheral_lockon`: the thesis's lock-on (L1 -> L2), the Watch's motion area to an
///   approximate location for the Foveal window (SSD at 25 %);
/// * `peripheral_lost`: the thesis's Detection mode after a loss far from the object: the 40x40
///   and 64x64 windows there, then back to waiting for motion;
/// * `peripheral_sweep`: an adapting track's re-detection after the same loss (zero-mean NCC of
///   the first template and the last trusted one, the same look; the two sizes, then the
///   frame's 128x128 tiles, 64x64 samples each, searched by candidates, until it is found).
fn peripheral_steps<W: Write, M: Meter>(out: &mut W, meter: &mut M) -> Result<(), SuiteError> {
    let prev = image("watch_prev", inputs::WATCH_PREV)?;
    let next = image("watch_next", inputs::WATCH_NEXT)?;
    let params = Params::default();
    let a = detect_motion(&prev, &next, params.motion_threshold).ok().flatten().ok_or(SuiteError::NoMotion)?;
    let centre = Point { x: (a.xmin + a.xmax) as f32 / 2.0, y: (a.ymin + a.ymax) as f32 / 2.0 };
    let tpl = Template::capture(&next, centre, usize::from(params.template)).ok_or(SuiteError::Template)?;
    let motion = Msg::Motion { xmin: a.xmin as u16, xmax: a.xmax as u16, ymin: a.ymin as u16, ymax: a.ymax as u16 };
    peripheral_run(out, meter, "peripheral_lockon", Peripheral::new(params, Some(tpl.clone())), &[motion], &next)?;
    peripheral_run(out, meter, "peripheral_lost", Peripheral::new(params, Some(tpl.clone())), &[Msg::Lost(LOST_AT)], &next)?;
    // The last look an adapting track trusted, sent on its loss (the same look here): a sweep
    // matches both templates, its worst cost.
    let lost = [Msg::Lost(LOST_AT), Msg::Template(tpl.clone())];
    peripheral_run(out, meter, "peripheral_sweep", Peripheral::new(params.adaptive(), Some(tpl)), &lost, &next)
}

/// Runs `p` from the messages `start` on the windows it asks for, cut from `frame` as the unit
/// delivers them, until it hands a location to the Foveal processor or asks for none; a line a
/// window: `{name} K win=X0,Y0,WxH placements=N approx=X,Y` (or `approx=none`). Each window is
/// metered as `name`.
#[inline(never)]
fn peripheral_run<W: Write, M: Meter>(
    out: &mut W,
    meter: &mut M,
    name: &str,
    mut p: Peripheral,
    start: &[Msg],
    frame: &WindowView<'_>,
) -> Result<(), SuiteError> {
    let mut want = None;
    for m in start {
        want = p.on_message(m).request.or(want);
    }
    for k in 0..PERIPHERAL_STEPS {
        let Some(r) = want else { break };
        let full = frame.sub(usize::from(r.x0), usize::from(r.y0), usize::from(r.width), usize::from(r.height));
        let view = full.map(|v| if r.decimation == Decimation::Quarter { v.decimated() } else { v }).ok_or(SuiteError::Diverged(k))?;
        let step = meter.once(name, &mut || p.on_window(&view));
        write!(out, "{name} {k} win={},{},{}x{}", r.x0, r.y0, r.width, r.height)?;
        if let Work::Match { placements, .. } = step.work {
            write!(out, " placements={placements}")?;
        }
        let approx = step.sends.iter().find_map(|(d, m)| match m {
            Msg::Approx(a) if *d == Dest::Foveal => Some(*a),
            _ => None,
        });
        match approx {
            Some(a) => writeln!(out, " approx={:08x},{:08x}", a.x.to_bits(), a.y.to_bits())?,
            None => writeln!(out, " approx=none")?,
        }
        if approx.is_some() {
            break;
        }
        want = step.request;
    }
    Ok(())
}

/// The Peripheral processor's image (issue 22: one image a processor): its kernels and the
/// processor's scenarios on the Watch's benchmark frame (`peripheral_steps`).
pub fn run_peripheral<W: Write, M: Meter>(out: &mut W, meter: &mut M) -> Result<(), SuiteError> {
    peripheral_kernels(out, meter)?;
    peripheral_steps(out, meter)
}

/// The corner detector's kernels (ch. 3) and the information measures (3.4.1): what the COOP
/// partner's image runs besides its replays.
fn corner_kernels<W: Write, M: Meter>(out: &mut W, meter: &mut M) -> Result<(), SuiteError> {
    // Sized for the benchmark's largest corner window, as a Foveal processor's.
    let mut det = CornerDetector::<24>::sized();
    let params = CornerParams::new(50);
    let mut edges24 = 0;
    for (id, name, bytes) in [("corner_20", "corner_20", inputs::CORNER_20), ("corner_24", "corner_24", inputs::CORNER_24)] {
        let v = image(name, bytes)?;
        // Detection is a pure function of the window; the detector only holds scratch space.
        match meter.kernel(id, &mut || det.detect(&v, &params)) {
            Ok(c) => writeln!(
                out,
                "{id} x={:08x} y={:08x} case={:?} edge={} clean={} map={:016x}",
                c.x.to_bits(),
                c.y.to_bits(),
                c.case,
                c.edge_pixels,
                c.clean_pixels,
                map_hash(det.clean_rows())
            )?,
            Err(e) => writeln!(out, "{id} none={e:?}")?,
        }
        edges24 = det.edge_pixels();
    }
    // The thesis's rules alone (3.2-3.3), without the line-fit refinement of the default.
    let v = image("corner_24", inputs::CORNER_24)?;
    let literal = CornerParams::literal(50);
    match meter.kernel("corner_24_literal", &mut || det.detect(&v, &literal)) {
        Ok(c) => writeln!(out, "corner_24_literal x={:08x} y={:08x} case={:?}", c.x.to_bits(), c.y.to_bits(), c.case)?,
        Err(e) => writeln!(out, "corner_24_literal none={e:?}")?,
    }
    let info = meter.kernel("info", &mut || {
        (edge_information(edges24, 576), edge_information_with_prior(edges24, 576, 0.1), corner_information(0.37))
    });
    let bits = |v: Option<f64>| v.map_or(0, f64::to_bits);
    writeln!(out, "info n={edges24} i={:016x} prior={:016x} cd={:016x}", info.0.to_bits(), bits(info.1), bits(info.2))?;
    Ok(())
}

/// The Foveal NCC's normalisation `P / sqrt(E_R E_I)` over the 25 placements of the 20x20
/// template in the 24x24 window, in three number formats: f64 (what `matching` uses; soft
/// float on the M4F), f32 (the M4F's FPU, `VSQRT`), and Q1.15 fixed point from an integer
/// square root. The integer sums are exact in all three, so only the last step differs.
fn float_formats<W: Write, M: Meter>(out: &mut W, meter: &mut M) -> Result<(), SuiteError> {
    let fw = image("foveal_window", inputs::FOVEAL_WINDOW)?;
    let ft = image("foveal_template", inputs::FOVEAL_TEMPLATE)?;
    let (n, nx, ny) = (ft.width(), fw.width() - ft.width() + 1, fw.height() - ft.height() + 1);
    let px = |v: &WindowView<'_>, x: usize, y: usize| u64::from(v.get(x, y).unwrap_or(0));
    let mut sums = [(0u64, 0u64); 25];
    let e_r: u64 = (0..n * n).map(|i| px(&ft, i % n, i / n).pow(2)).sum();
    for (k, s) in sums.iter_mut().enumerate().take(nx * ny) {
        let (ox, oy) = (k % nx, k / nx);
        for i in 0..n * n {
            let (u, v) = (i % n, i / n);
            let w = px(&fw, ox + u, oy + v);
            s.0 += px(&ft, u, v) * w;
            s.1 += w * w;
        }
    }
    let f64s = meter.kernel("ncc_norm25_f64", &mut || {
        sums.map(|(p, e)| p as f64 / libm::sqrt(e_r as f64 * e as f64))
    });
    let f32s = meter.kernel("ncc_norm25_f32", &mut || {
        sums.map(|(p, e)| p as f32 / sqrtf(e_r as f32 * e as f32))
    });
    let q15s = meter.kernel("ncc_norm25_q15", &mut || {
        // P / sqrt(E_R E_I) in Q1.15: P and both energies are under 2^25 (400 * 255²), so
        // the product fits u64 and P << 15 as well.
        sums.map(|(p, e)| ((p << 15) / isqrt(e_r * e).max(1)).min(1 << 15) as u16)
    });
    let best = |s: &[f64]| s.iter().enumerate().fold(0, |b, (i, &v)| if v > s[b] { i } else { b });
    let f32w: [f64; 25] = core::array::from_fn(|i| f64::from(f32s[i]));
    let q15w: [f64; 25] = core::array::from_fn(|i| f64::from(q15s[i]));
    let mut bytes64 = [0u8; 200];
    let mut bytes32 = [0u8; 100];
    let mut bytes16 = [0u8; 50];
    for i in 0..25 {
        bytes64[8 * i..8 * i + 8].copy_from_slice(&f64s[i].to_le_bytes());
        bytes32[4 * i..4 * i + 4].copy_from_slice(&f32s[i].to_le_bytes());
        bytes16[2 * i..2 * i + 2].copy_from_slice(&q15s[i].to_le_bytes());
    }
    // Largest deviation from the f64 scores, in units of 1e-9.
    let dev = |w: &[f64; 25]| w.iter().zip(&f64s).map(|(a, b)| libm::fabs(a - b)).fold(0.0, f64::max);
    let q15dev: [f64; 25] = core::array::from_fn(|i| q15w[i] / 32768.0);
    writeln!(out, "ncc_norm25_f64 best={} sum={:016x}", best(&f64s), fnv1a(&bytes64))?;
    writeln!(out, "ncc_norm25_f32 best={} sum={:016x} maxdev_e9={}", best(&f32w), fnv1a(&bytes32), (dev(&f32w) * 1e9) as u64)?;
    writeln!(out, "ncc_norm25_q15 best={} sum={:016x} maxdev_e9={}", best(&q15dev), fnv1a(&bytes16), (dev(&q15dev) * 1e9) as u64)?;
    Ok(())
}

/// Integer square root, rounded down (Newton's method from above).
fn isqrt(v: u64) -> u64 {
    if v < 2 {
        return v;
    }
    let mut x = 1u64 << ((64 - v.leading_zeros()).div_ceil(2));
    loop {
        let y = (x + v / x) / 2;
        if y >= x {
            return x;
        }
        x = y;
    }
}

/// The COOP decision (4.3) and the Kalman policy (5.2) on a fixed sequence: NCC steady, CD
/// with a disturbance, one decision a frame (the thesis's 8.8 ms).
fn decisions<W: Write, M: Meter>(out: &mut W, meter: &mut M) -> Result<(), SuiteError> {
    let mut sse = SseCoop::new(4).map_err(|_| SuiteError::Template)?;
    let mut kal = KalmanCoop::new(1.0e4, 0.25, 0.3).map_err(|_| SuiteError::Template)?;
    let mut picks = [0u8; 2];
    let mut hist = [[0u8; 16]; 2];
    for k in 0..16u32 {
        let t = f64::from(k) * 0.0088;
        let ncc = (100.0 + 50.0 * t + 0.1 * f64::from(k % 3), 50.0 + 20.0 * t);
        let wobble = if (6..9).contains(&k) { 3.0 } else { 0.05 * f64::from(k % 2) };
        let cd = (100.5 + 50.0 * t + wobble, 50.2 + 20.0 * t);
        for (j, policy) in [&mut sse as &mut dyn ConfidencePolicy, &mut kal].into_iter().enumerate() {
            let id = if j == 0 { "coop_decision_sse" } else { "coop_decision_kalman" };
            let pick = meter.once(id, &mut || {
                let _ = policy.push(Source::Ncc, t, ncc.0, ncc.1);
                let _ = policy.push(Source::Cd, t, cd.0, cd.1);
                policy.choose()
            });
            hist[j][k as usize] = if pick == Source::Ncc { b'N' } else { b'C' };
            picks[j] += u8::from(pick == Source::Cd);
        }
    }
    for (j, id) in ["coop_decision_sse", "coop_decision_kalman"].into_iter().enumerate() {
        write!(out, "{id} picks=")?;
        for &c in &hist[j] {
            out.write_char(char::from(c))?;
        }
        writeln!(out, " cd={}", picks[j])?;
    }
    let fit = |s: Source| sse.fit(s).map_or((0, 0, 0), |f| (f.a.to_bits(), f.b.to_bits(), f.sse.to_bits()));
    let (n, c) = (fit(Source::Ncc), fit(Source::Cd));
    writeln!(out, "coop_decision_sse fit_ncc={:016x},{:016x},{:016x} fit_cd={:016x},{:016x},{:016x}", n.0, n.1, n.2, c.0, c.1, c.2)?;
    let score = |s: Source| kal.score(s).map_or(0, f64::to_bits);
    writeln!(out, "coop_decision_kalman score_ncc={:016x} score_cd={:016x}", score(Source::Ncc), score(Source::Cd))?;
    Ok(())
}

/// Messages to the partner go to it; the Peripheral's (Tracked, Lost) have no processor here.
fn to_partner(step: &Step) -> impl Iterator<Item = &Msg> {
    step.sends.iter().filter(|(d, _)| *d == Dest::FovealCd).map(|(_, m)| m)
}

/// Side of the COOP master's corner detector: it finds the corner of the template
/// (`Support`), 20x20 at the thesis's sizes.
pub const MASTER_SIDE: usize = 24;
/// Used pixels the COOP master's Lucas-Kanade template holds: the interior of the thesis's
/// 20x20 template (a larger template is tracked without the refinement).
pub const MASTER_LK: usize = 18 * 18;
/// Side of the COOP partner's corner detector: the Foveal window, which it asks for wherever
/// its master sends it (a coasting or adapting master's own window is wider).
pub const PARTNER_SIDE: usize = 24;

/// The COOP Foveal pair (4.2): a master running NCC and the decision, a partner running the
/// corner detector on the same coordinates, wired to each other as their link would be.
/// The testbench's recorder and the replay below drive it alike. The replay records the
/// master's window; the partner's (the Foveal window where the master sends it, as the
/// testbench's own unit cuts it) lies within it. It keeps the processors'
/// answers ([`Step`], over 4 KiB each) and has them filled in place, as a board loop would:
/// the master's decision and one answer at a time from either processor. Built empty in its
/// owner's slot ([`CoopPair::new`]) and started in place ([`CoopPair::start`]), so no copy of
/// it passes through the stack.
pub struct CoopPair {
    master: Foveal<MASTER_SIDE, MASTER_LK>,
    partner: CornerPartner<PARTNER_SIDE>,
    /// The window the partner asked for last (`None` once it stopped).
    partner_window: Option<WindowRequest>,
    /// The partner's result in the last frame, and its window's origin.
    corner: (Option<Point>, (u32, u32)),
    /// The master's answer to the partner's result (its decision).
    decision: Step,
    /// The answer being passed on: the master's to its window, then the partner's to the same
    /// window, then the partner's to the decision's messages.
    scratch: Step,
}

impl CoopPair {
    /// An idle pair (no template) with `params`, returned into the caller's slot; an adapting
    /// pair's ([`Params::adapt`]) master guards with the adapting track's parameters, as the
    /// testbench's does. Never inlined: whatever temporaries the compiler builds it through
    /// are in this frame, which ends before the replay's deepest calls, not in its caller's.
    #[inline(never)]
    pub fn new(params: Params) -> Self {
        CoopPair {
            master: coop_master(params),
            partner: CornerPartner::sized(params),
            partner_window: None,
            corner: (None, (0, 0)),
            decision: Step::new(Work::None),
            scratch: Step::new(Work::None),
        }
    }

    /// Starts a new pair's track from `start` with `template`, in place. Never inlined: the
    /// template's preparation does not add to the replay's stack.
    #[inline(never)]
    pub fn start(&mut self, template: Template, start: Point) {
        let CoopPair { master, decision, .. } = self;
        master.set_template(template);
        master.start_at_into(start, decision);
        self.tell_partner();
    }

    /// The decision's messages for the partner go to it; it keeps the window it asks for.
    fn tell_partner(&mut self) {
        let CoopPair { partner, partner_window, decision, scratch, .. } = self;
        for m in to_partner(decision) {
            partner.on_message_into(m, scratch);
            *partner_window = scratch.request;
        }
    }

    /// The window the pair wants next (the master's, which holds the partner's; `None` once
    /// lost).
    pub fn want(&self) -> Option<WindowRequest> {
        self.decision.request
    }

    /// One COOP frame: the window goes to the master and its part the partner asked for to
    /// the partner, whose result goes to the master, which decides; returns the master's
    /// decision step (`None` if the partner had no window in it or sent no result).
    /// Metered as `id`: both Foveal kernels and the decision. Never inlined, so a
    /// profile finds its frames (`scripts/board_profile.py`).
    #[inline(never)]
    pub fn frame<M: Meter>(&mut self, meter: &mut M, id: &str, view: &WindowView<'_>, t: f64) -> Option<&Step> {
        let r = self.partner_window?;
        let (ox, oy) = view.origin();
        let (dx, dy) = (usize::from(r.x0).checked_sub(ox as usize)?, usize::from(r.y0).checked_sub(oy as usize)?);
        let own = view.sub(dx, dy, usize::from(r.width), usize::from(r.height))?;
        let CoopPair { master, partner, decision, scratch, corner, .. } = self;
        meter.once(id, &mut || {
            // The master's own answer only records its NCC result until the partner's comes.
            master.on_window_into(view, t, scratch);
            partner.on_window_into(&own, scratch);
            *corner = (result(scratch)?, own.origin());
            master.on_message_into(&Msg::Result(corner.0), t, decision);
            Some(())
        })?;
        self.tell_partner();
        Some(&self.decision)
    }
}

/// The COOP master (4.2-4.3) with `params`, idle.
#[inline(always)]
fn coop_master(params: Params) -> Foveal<MASTER_SIDE, MASTER_LK> {
    Foveal::sized(FovealKind::CoopMaster, params)
}

/// [`coop_master`] returned into its caller's slot: never inlined, so whatever temporaries the
/// compiler builds it through end with this frame, as [`CoopPair::new`]'s do.
#[inline(never)]
fn lone_master(params: Params) -> Foveal<MASTER_SIDE, MASTER_LK> {
    coop_master(params)
}

/// The corner the partner's answer sends its master, if it sent one.
fn result(step: &Step) -> Option<Option<Point>> {
    step.sends.iter().find_map(|(d, m)| match m {
        Msg::Result(r) if *d == Dest::Foveal => Some(*r),
        _ => None,
    })
}

/// The line `{name}_cd K win=X0,Y0 x=.. y=..` (or `none`): the partner's corner in frame `k`
/// from its window at `(x0, y0)`, as the pair's replay and the partner's own image print it.
fn corner_line<W: Write>(out: &mut W, name: &str, k: u16, (x0, y0): (u32, u32), corner: Option<Point>) -> fmt::Result {
    write!(out, "{name}_cd {k} win={x0},{y0}")?;
    match corner {
        Some(p) => writeln!(out, " x={:08x} y={:08x}", p.x.to_bits(), p.y.to_bits()),
        None => writeln!(out, " none"),
    }
}

/// The COOP partner's image (issue 22: one image a processor): the corner kernels, and the
/// partner alone on each replay's windows, its own the Foveal window centred in the master's
/// recorded one (where the master's `Follow` puts it), printing the pair's `{name}_cd` lines.
pub fn run_partner<W: Write, M: Meter>(out: &mut W, meter: &mut M) -> Result<(), SuiteError> {
    corner_kernels(out, meter)?;
    partner(out, meter, &Replay::THESIS)?;
    partner(out, meter, &Replay::ADAPTIVE)
}

/// The partner alone on `replay`'s windows (see [`run_partner`]), metered as `partner_frame`.
#[inline(never)]
fn partner<W: Write, M: Meter>(out: &mut W, meter: &mut M, replay: &Replay<'_>) -> Result<(), SuiteError> {
    let s = Stream::parse(replay.windows).map_err(SuiteError::Stream)?;
    let params = Params::default();
    let mut partner = CornerPartner::<PARTNER_SIDE>::sized(params);
    let mut step = Step::new(Work::None);
    let side = usize::from(params.foveal);
    for (k, f) in s.frames().enumerate() {
        let k = k as u16;
        let (w, h) = (usize::from(f.w), usize::from(f.h));
        let view = WindowView::new(f.pixels, w, h, w, u32::from(f.x0), u32::from(f.y0)).map_err(|_| SuiteError::View("window"))?;
        let own = view.sub(w.saturating_sub(side) / 2, h.saturating_sub(side) / 2, side, side).ok_or(SuiteError::Diverged(k))?;
        let corner = meter.once("partner_frame", &mut || {
            partner.on_window_into(&own, &mut step);
            result(&step)
        });
        corner_line(out, replay.name, k, own.origin(), corner.ok_or(SuiteError::Diverged(k))?)?;
    }
    Ok(())
}

/// A replay of the COOP pair: its recorded window stream and the pair's parameters.
#[derive(Clone, Copy, Debug)]
pub struct Replay<'a> {
    /// Its lines' first word (`{name} K ...`, `{name}_total ...`).
    pub name: &'static str,
    /// The meter id of its frames.
    pub meter: &'static str,
    /// The meter id of its master's frames alone (the master's image, [`run_master`]).
    pub master_meter: &'static str,
    /// The pair adapts its template ([`Params::adaptive`]); otherwise the thesis's defaults.
    pub adapt: bool,
    /// The recorded stream (`fixtures/board/README.md`).
    pub windows: &'a [u8],
}

impl Replay<'static> {
    /// The thesis's pair (fixed template, 4.2-4.3) on `windows.bin`.
    pub const THESIS: Replay<'static> = Replay { name: "tracker", meter: "coop_frame", master_meter: "master_frame", adapt: false, windows: inputs::WINDOWS };
    /// The adapting pair (`track`'s default, issue 21: [`Params::adaptive`]) on
    /// `windows_adaptive.bin`.
    pub const ADAPTIVE: Replay<'static> =
        Replay { name: "adaptive", meter: "coop_frame_adaptive", master_meter: "master_frame_adaptive", adapt: true, windows: inputs::WINDOWS_ADAPTIVE };
    /// The adapting pair on `windows_covered.bin`, its object partly covered (issue 38):
    /// replayed on the whole suite's images only.
    pub const COVERED: Replay<'static> =
        Replay { name: "covered", meter: "coop_frame_covered", master_meter: "master_frame_covered", adapt: true, windows: inputs::WINDOWS_COVERED };
}

/// Replays `replay`'s stream through a [`CoopPair`]. Each frame the master must ask for the
/// window recorded next, or the replay has left the recorded run.
#[inline(never)]
pub fn tracker<W: Write, M: Meter>(out: &mut W, meter: &mut M, replay: &Replay<'_>) -> Result<(), SuiteError> {
    let s = Stream::parse(replay.windows).map_err(SuiteError::Stream)?;
    let (tpl, params) = start_of(&s, replay)?;
    let mut pair = CoopPair::new(params);
    pair.start(tpl, Point { x: s.start.0, y: s.start.1 });
    let mut tally = (0u32, 0u32);
    let name = replay.name;
    for (k, f) in s.frames().enumerate() {
        let k = k as u16;
        let view = recorded(pair.want(), &f, k)?;
        let step = pair.frame(meter, replay.meter, &view, f.t).ok_or(SuiteError::Diverged(k))?;
        decision_line(out, name, k, &f, step, &mut tally)?;
        corner_line(out, name, k, pair.corner.1, pair.corner.0)?;
    }
    writeln!(out, "{name}_total frames={} reports={} cd={}", s.count, tally.0, tally.1)?;
    Ok(())
}

/// A replay's template and the pair's parameters.
fn start_of(s: &Stream<'_>, replay: &Replay<'_>) -> Result<(Template, Params), SuiteError> {
    let anchor = Point { x: s.anchor.0, y: s.anchor.1 };
    let tpl = Template::from_parts(usize::from(s.side), anchor, s.template).ok_or(SuiteError::Template)?;
    Ok((tpl, if replay.adapt { Params::default().adaptive() } else { Params::default() }))
}

/// Frame `k`'s recorded window as a view, if the processors asked for it (`want`); otherwise the
/// replay has left the recorded run.
fn recorded<'a>(want: Option<WindowRequest>, f: &Frame<'a>, k: u16) -> Result<WindowView<'a>, SuiteError> {
    let r = want.ok_or(SuiteError::Diverged(k))?;
    if (r.x0, r.y0, r.width, r.height) != (f.x0, f.y0, f.w, f.h) {
        return Err(SuiteError::Diverged(k));
    }
    let (w, h) = (usize::from(f.w), usize::from(f.h));
    WindowView::new(f.pixels, w, h, w, u32::from(f.x0), u32::from(f.y0)).map_err(|_| SuiteError::View("window"))
}

/// The line `{name} K win=X0,Y0 [size=WxH] x=.. y=.. algo=.. [scale=.. angle=..] [unconfirmed]`
/// (or `lost=..`, `none`): the master's decision in frame `k`; `tally` counts the reports and
/// those from the corner.
fn decision_line<W: Write>(out: &mut W, name: &str, k: u16, f: &Frame<'_>, step: &Step, tally: &mut (u32, u32)) -> fmt::Result {
    write!(out, "{name} {k} win={},{}", f.x0, f.y0)?;
    if (f.w, f.h) != (24, 24) {
        write!(out, " size={}x{}", f.w, f.h)?;
    }
    match step.outcome {
        Outcome::Measured(Fix { at: p, source: algo, shape, .. }) | Outcome::Unconfirmed(Fix { at: p, source: algo, shape, .. }) => {
            tally.0 += 1;
            tally.1 += u32::from(algo == Source::Cd);
            write!(out, " x={:08x} y={:08x} algo={algo:?}", p.x.to_bits(), p.y.to_bits())?;
            if let Some(sh) = shape {
                write!(out, " scale={:08x} angle={:08x}", sh.scale.to_bits(), sh.angle_deg.to_bits())?;
            }
            if step.outcome.vouched().is_none() {
                write!(out, " unconfirmed")?;
            }
            writeln!(out)
        }
        Outcome::Lost(p) => writeln!(out, " lost={:08x},{:08x}", p.x.to_bits(), p.y.to_bits()),
        _ => writeln!(out, " none"),
    }
}

/// What the NCC master's image receives from its partner over the link: the partner's corner
/// each frame, as the partner's own image prints it (`expected.txt`'s `{name}_cd` lines, which
/// `scripts/board.sh` holds that image to).
pub const PARTNER_RESULTS: &str = include_str!("../../../fixtures/board/expected.txt");

/// The partner's results of replay `name` in frame order, from `results` (lines as
/// [`PARTNER_RESULTS`]'s): `None` for a malformed line.
fn partner_results<'a>(results: &'a str, name: &'a str) -> impl Iterator<Item = Option<Option<Point>>> + 'a {
    results.lines().filter_map(move |l| {
        let rest = l.strip_prefix(name)?.strip_prefix("_cd ")?;
        // "K win=X0,Y0 x=BITS y=BITS" or "K win=X0,Y0 none".
        let mut f = rest.split(' ').skip(2);
        let bits = |v: Option<&str>, key: &str| {
            v?.strip_prefix(key).and_then(|h| u32::from_str_radix(h, 16).ok()).map(f32::from_bits)
        };
        Some(match f.next() {
            Some("none") => Some(None),
            x => bits(x, "x=").zip(bits(f.next(), "y=")).map(|(x, y)| Some(Point { x, y })),
        })
    })
}

/// The COOP master's image (issue 22: one image a processor): the master alone on both
/// replays' recorded windows, its partner's results read as the partner's image sends them
/// ([`PARTNER_RESULTS`]), printing the pair's decision lines and totals.
pub fn run_master<W: Write, M: Meter>(out: &mut W, meter: &mut M) -> Result<(), SuiteError> {
    master(out, meter, &Replay::THESIS, PARTNER_RESULTS)?;
    master(out, meter, &Replay::ADAPTIVE, PARTNER_RESULTS)
}

/// The master alone on `replay` (see [`run_master`]) with its partner's corners from `results`
/// (lines as [`PARTNER_RESULTS`]'s): its window, then its partner's result, into one answer
/// (the window's own only records the NCC result, 4.2), metered as the replay's
/// `master_meter`.
#[inline(never)]
pub fn master<W: Write, M: Meter>(out: &mut W, meter: &mut M, replay: &Replay<'_>, results: &str) -> Result<(), SuiteError> {
    let s = Stream::parse(replay.windows).map_err(SuiteError::Stream)?;
    let (tpl, params) = start_of(&s, replay)?;
    let mut master = lone_master(params);
    let mut step = Step::new(Work::None);
    master.set_template(tpl);
    master.start_at_into(Point { x: s.start.0, y: s.start.1 }, &mut step);
    let mut results = partner_results(results, replay.name);
    let mut tally = (0u32, 0u32);
    for (k, f) in s.frames().enumerate() {
        let k = k as u16;
        let view = recorded(step.request, &f, k)?;
        let corner = results.next().flatten().ok_or(SuiteError::Diverged(k))?;
        meter.once(replay.master_meter, &mut || {
            master.on_window_into(&view, f.t, &mut step);
            master.on_message_into(&Msg::Result(corner), f.t, &mut step);
        });
        decision_line(out, replay.name, k, &f, &step, &mut tally)?;
    }
    writeln!(out, "{}_total frames={} reports={} cd={}", replay.name, s.count, tally.0, tally.1)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn isqrt_is_the_floor_root() {
        for v in (0u64..5000).chain([u64::MAX, 1 << 48, (1 << 48) - 1, 999_999_999_999]) {
            let r = isqrt(v);
            assert!(u128::from(r) * u128::from(r) <= u128::from(v), "{v}");
            assert!(u128::from(r + 1) * u128::from(r + 1) > u128::from(v), "{v}");
        }
    }

    #[test]
    fn fnv1a_matches_the_published_vectors() {
        // From the FNV reference (Fowler, Noll, Vo): "" and "a".
        assert_eq!(fnv1a(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a(b"a"), 0xaf63_dc4c_8601_ec8c);
    }
}
