//! `coopwin._coopwin`: the Python package's Rust side, over the same library code the
//! `coopwin` CLI runs (`coopwin_testbench::tracking` and `commands::verilog`). It takes and gives
//! the CLI's options and CSV rows; `coopwin/__init__.py` turns them into the OpenCV-style
//! trackers, `track_video`'s rows and `verilog`'s files.
use clap::parser::ValueSource;
use clap::{CommandFactory, FromArgMatches, Parser, ValueEnum};
use coopwin_testbench::commands::args::HdlArg;
use coopwin_testbench::commands::track::TrackArgs;
use coopwin_testbench::commands::verilog::{verilog_files, VerilogArgs};
use coopwin_testbench::commands::CliError;
use coopwin_testbench::frames::folder::SIDES;
use coopwin_testbench::frames::input::InputError;
use coopwin_testbench::frames::{FrameError, FrameSource};
use coopwin_testbench::report::csv::{self, FrameInfo};
use coopwin_testbench::tracking::{track_frames, TrackError, TrackRun};
use coopwin_testbench::units::clocks::Clocks;
use numpy::{PyArrayDescrMethods, PyArrayDyn, PyArrayMethods, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::exceptions::{PyFileNotFoundError, PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use std::collections::VecDeque;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{channel, sync_channel, Receiver, Sender};
use std::sync::{Arc, Mutex};

/// `coopwin track`'s options, as the CLI parses them (so a bad value gets the CLI's message).
#[derive(Parser)]
#[command(name = "coopwin track", no_binary_name = true)]
struct TrackOptions {
    #[command(flatten)]
    track: TrackArgs,
}

/// `coopwin verilog`'s options.
#[derive(Parser)]
#[command(name = "coopwin verilog", no_binary_name = true)]
struct VerilogOptions {
    #[command(flatten)]
    verilog: VerilogArgs,
}

/// Parses `options` as the CLI would, after `--frames frames`; a bad one is a ValueError
/// with clap's first line ("invalid value ... for '--fps <FPS>': ..."), and so is an option
/// `api` cannot honour (one of `refused`, or a clocked `--hdl` where `clocked` is false),
/// saying why and what to use instead.
fn track_args(frames: &str, options: Vec<String>, api: &str, refused: &[Refusal], clocked: bool) -> PyResult<TrackArgs> {
    let argv = ["--frames".to_string(), frames.to_string()].into_iter().chain(options);
    let matches = TrackOptions::command().try_get_matches_from(argv).map_err(clap_error)?;
    let args = TrackOptions::from_arg_matches(&matches).map_err(clap_error)?.track;
    let given = |id: &str| matches.value_source(id) == Some(ValueSource::CommandLine);
    if let Some((id, why)) = refused.iter().find(|(id, _)| given(id)) {
        return Err(PyValueError::new_err(format!("--{} is not available from {api}: {why}", id.replace('_', "-"))));
    }
    if !clocked && !matches!(args.hdl, HdlArg::Model) {
        let hdl = args.hdl.to_possible_value().map(|v| v.get_name().to_string()).unwrap_or_default();
        return Err(PyValueError::new_err(format!(
            "--hdl {hdl} is not available from {api}: the clocked window units read each frame's pixels as its period starts, before the previous frame's answer is out, so frames handed in one at a time would wait on each other; use coopwin.track_video(path, box, hdl=\"{hdl}\") or `coopwin track --hdl {hdl}`"
        )));
    }
    Ok(args)
}

/// A `coopwin track` option (clap's id) that a Python entry point refuses, and why (with what
/// to use instead).
type Refusal = (&'static str, &'static str);

/// Options that write files or print instead of tracking: the package returns rows instead.
const WRITES: [Refusal; 4] = [
    ("out", "the rows are returned (Tracker.csv_row, track_video's Row tuples), not written; write them yourself, or run `coopwin track --out FILE`"),
    ("overlay", "the package writes no files; run `coopwin track --overlay FILE`"),
    ("vcd", "the package writes no files; run `coopwin track --hdl rust-hdl --vcd FILE`"),
    ("list", "it prints the frames' order and tracks nothing; run `coopwin track --list`"),
];

/// Options of a run over a source of known frames, which a Tracker fed one frame at a time is
/// not (besides [`WRITES`]).
const NOT_FED: [Refusal; 5] = [
    ("start_frame", "a Tracker tracks the frames it is handed, from the one it is created with; create it on the frame to start from (coopwin.track_video(path, box, start_frame=N) starts a video later)"),
    ("end_frame", "a Tracker tracks the frames it is handed; stop calling update (coopwin.track_video(path, box, end_frame=N) stops a video's run)"),
    ("blank_jitter", "jittered blanking is drawn for each frame of a run whose length is known; use coopwin.track_video(path, box, blank_jitter=(LINE, FRAME, SEED)) or `coopwin track --blank-jitter`"),
    ("pixel_bits", "it sets the clocked window units' pixel width, and a Tracker runs the behavioural model; use coopwin.track_video(path, box, hdl=\"rust-hdl\", pixel_bits=N)"),
    ("allow_damaged", "it concerns a video's decoding, and a Tracker is handed decoded frames; use coopwin.track_video(path, allow_damaged=True)"),
];

/// clap's message, without its "error: " and its usage lines.
fn clap_error(e: clap::Error) -> PyErr {
    let text = e.render().to_string();
    let line = text.lines().next().unwrap_or_default();
    PyValueError::new_err(line.strip_prefix("error: ").unwrap_or(line).to_string())
}

/// A CLI error as Python's ValueError (a bad option) with the CLI's message.
fn cli_error(e: CliError) -> PyErr {
    PyValueError::new_err(e.message)
}

/// A run's error as Python's ValueError (a bad option, or input that cannot be tracked) with
/// the CLI's message. (A missing input is FileNotFoundError, raised by [`VideoRows::new`]
/// before the run would make it a message.)
fn track_error(e: TrackError) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// A frame as the CLI's 8-bit gray pixels and its (width, height): a `uint8` array, gray
/// (H x W, or H x W x 1) or BGR (H x W x 3, OpenCV's order), converted to gray as the CLI
/// converts a colour PNG frame (the `image` crate's luma, ITU-R BT.709 weights), 64x64 to
/// 4096x4096 as the CLI takes.
fn gray(frame: &Bound<'_, PyAny>) -> PyResult<(Vec<u8>, (usize, usize))> {
    let array = frame
        .cast::<PyUntypedArray>()
        .map_err(|_| PyTypeError::new_err(format!("frame must be a NumPy array (uint8, H x W gray or H x W x 3 BGR), got {}", type_name(frame))))?;
    let dtype = array.dtype();
    if !dtype.is_equiv_to(&numpy::dtype::<u8>(frame.py())) {
        return Err(PyTypeError::new_err(format!("frame must be a uint8 array (8-bit pixels), got dtype {dtype}; convert with frame.astype(numpy.uint8) after scaling to 0..255")));
    }
    let shape = array.shape().to_vec();
    let (h, w, channels) = match shape[..] {
        [h, w] => (h, w, 1),
        [h, w, c @ (1 | 3)] => (h, w, c),
        _ => return Err(PyValueError::new_err(format!("frame must be H x W (gray) or H x W x 3 (BGR), got shape {shape:?}"))),
    };
    if !SIDES.contains(&w) || !SIDES.contains(&h) {
        return Err(PyValueError::new_err(format!("frames must be {0}x{0} to {1}x{1}, this one is {w}x{h}", SIDES.start(), SIDES.end())));
    }
    let array = frame.cast::<PyArrayDyn<u8>>()?.readonly();
    // A C-contiguous array is read in place; any other layout is walked in row-major order.
    let px: Vec<u8> = match array.as_slice() {
        Ok(s) => s.to_vec(),
        Err(_) => array.as_array().iter().copied().collect(),
    };
    let px = match channels {
        1 => px,
        _ => {
            let rgb = px.chunks_exact(3).flat_map(|bgr| [bgr[2], bgr[1], bgr[0]]).collect();
            let img = image::RgbImage::from_raw(w as u32, h as u32, rgb).ok_or_else(|| PyValueError::new_err("frame: pixel count does not match its shape"))?;
            image::DynamicImage::ImageRgb8(img).to_luma8().into_raw()
        }
    };
    Ok((px, (w, h)))
}

fn type_name(x: &Bound<'_, PyAny>) -> String {
    x.get_type().name().map(|n| n.to_string()).unwrap_or_else(|_| "an object".into())
}

/// Frames handed in one at a time by [`FrameRun::push`]: a source with no end known. The
/// run asks for frame `k + 1` only once frame `k`'s record is out, so it waits here for the
/// caller's next frame; a few recent frames are held for the windows still to be cut.
struct Fed {
    size: (usize, usize),
    from_caller: Receiver<Vec<u8>>,
    received: usize,
    held: VecDeque<(usize, Vec<u8>)>,
}

impl Fed {
    /// Frames held (the run reads windows of the current frame, seldom of the one before).
    const HELD: usize = 2;
}

impl FrameSource for Fed {
    fn size(&self) -> (usize, usize) {
        self.size
    }
    fn len(&self) -> usize {
        Clocks::OPEN_ENDED
    }
    fn frame(&mut self, k: usize) -> Result<&[u8], FrameError> {
        // The caller gone (the tracker dropped) ends the run.
        while self.received <= k {
            let px = self.from_caller.recv().map_err(|_| FrameError::Interrupted)?;
            if self.held.len() == Self::HELD {
                self.held.pop_front();
            }
            self.held.push_back((self.received, px));
            self.received += 1;
        }
        self.held.iter().find(|(j, _)| *j == k).map(|(_, px)| px.as_slice()).ok_or(FrameError::Missing(k))
    }
}

/// A run fed one frame at a time: the first frame's CSV row, then `push(frame)` returns each
/// next frame's, the line `coopwin track --out` writes for it (without a file name).
#[pyclass(module = "coopwin._coopwin")]
struct FrameRun {
    /// The first frame's row.
    #[pyo3(get)]
    first_row: String,
    size: (usize, usize),
    to_run: Mutex<Option<Sender<Vec<u8>>>>,
    rows: Mutex<Receiver<Result<String, String>>>,
}

#[pymethods]
impl FrameRun {
    /// A run from `frame` with `coopwin track`'s `options` (e.g. ["--target-box",
    /// "10,20,30,40", "--fps", "30"]), tracked up to the end of the frame's period.
    #[new]
    fn new(py: Python<'_>, frame: &Bound<'_, PyAny>, options: Vec<String>) -> PyResult<Self> {
        let (px, (w, h)) = gray(frame)?;
        let refused: Vec<Refusal> = WRITES.into_iter().chain(NOT_FED).collect();
        let args = track_args("<frames>", options, "coopwin.Tracker", &refused, false)?;
        let options = args.options();
        options.check_against((w, h), 1).map_err(track_error)?;
        let cfg = options.config((w, h), options.fps);
        let (to_run, from_caller) = channel();
        let (to_caller, rows) = channel();
        let fed = Fed { size: (w, h), from_caller, received: 0, held: VecDeque::new() };
        std::thread::Builder::new()
            .name("coopwin-tracker".into())
            .spawn(move || {
                let mut fed = fed;
                let period = cfg.frame_period(&fed);
                let info = FrameInfo { period, ..FrameInfo::default() };
                let shape = options.csv_box((w, h));
                let out = track_frames(&mut fed, &cfg, None, &|| false, &mut |_| {}, &mut |r| {
                    let _ = to_caller.send(Ok(csv::track_row(r, info, shape)));
                });
                if let Err(e) = out {
                    let _ = to_caller.send(Err(e.to_string()));
                }
            })
            .map_err(|e| PyRuntimeError::new_err(format!("cannot start the tracker's thread: {e}")))?;
        let mut run = FrameRun { first_row: String::new(), size: (w, h), to_run: Mutex::new(Some(to_run)), rows: Mutex::new(rows) };
        run.first_row = run.track(py, px)?;
        Ok(run)
    }

    /// Tracks `frame` (uint8, gray or BGR, the run's size) and returns its CSV row.
    fn push(&self, py: Python<'_>, frame: &Bound<'_, PyAny>) -> PyResult<String> {
        let (px, (w, h)) = gray(frame)?;
        if (w, h) != self.size {
            let (rw, rh) = self.size;
            return Err(PyValueError::new_err(format!("frame is {w}x{h}; this tracker's frames are {rw}x{rh} (the first frame's size)")));
        }
        self.track(py, px)
    }
}

impl FrameRun {
    /// Hands the run the next frame's gray pixels and waits for the frame's row.
    fn track(&self, py: Python<'_>, px: Vec<u8>) -> PyResult<String> {
        let ended = || PyRuntimeError::new_err("the tracker's run has ended (it failed earlier); create a new tracker");
        let sent = self.to_run.lock().map_err(|_| ended())?.as_ref().map(|s| s.send(px));
        if !matches!(sent, Some(Ok(()))) {
            return Err(ended());
        }
        match py.detach(|| next_row(&self.rows)) {
            Some(Ok(row)) => Ok(row),
            Some(Err(message)) => {
                // The run failed on this frame: no further frame is taken.
                self.to_run.lock().map_err(|_| ended())?.take();
                Err(PyValueError::new_err(message))
            }
            None => Err(ended()),
        }
    }
}

/// A run's thread's next row (or its error); None once the run has ended and said all.
fn next_row(rows: &Mutex<Receiver<Result<String, String>>>) -> Option<Result<String, String>> {
    rows.lock().ok()?.recv().ok()
}

/// The CSV rows of `coopwin track --frames path` with `options`, streamed from a run on its
/// own thread as they are made; dropping it stops the run.
#[pyclass(module = "coopwin._coopwin")]
struct VideoRows {
    rows: Mutex<Receiver<Result<String, String>>>,
}

/// Rows made ahead of the reader.
const ROWS_AHEAD: usize = 64;

#[pymethods]
impl VideoRows {
    /// Opens and checks the input (a video file or a folder of PNG frames) now, so a missing
    /// file or a bad option raises here; the run starts at once.
    #[new]
    fn new(py: Python<'_>, path: PathBuf, options: Vec<String>) -> PyResult<Self> {
        if !path.exists() {
            return Err(PyFileNotFoundError::new_err(InputError::NoSuchFile(path).to_string()));
        }
        let args = track_args(&path.to_string_lossy(), options, "coopwin.track_video", &WRITES, true)?;
        let mut run = py.detach(|| TrackRun::open(&args.frames, &args.options(), &|| false)).map_err(track_error)?;
        let (to_caller, rows) = sync_channel(ROWS_AHEAD);
        let stop = Arc::new(AtomicBool::new(false));
        std::thread::Builder::new()
            .name("coopwin-track-video".into())
            .spawn(move || {
                let out = run.track(None, &|| stop.load(Ordering::Relaxed), &mut |_| {}, &mut |_, row| {
                    if to_caller.send(Ok(row)).is_err() {
                        // Nobody reads the rows any more.
                        stop.store(true, Ordering::Relaxed);
                    }
                });
                if let Err(e) = out {
                    let _ = to_caller.send(Err(e.to_string()));
                }
            })
            .map_err(|e| PyRuntimeError::new_err(format!("cannot start the run's thread: {e}")))?;
        Ok(VideoRows { rows: Mutex::new(rows) })
    }

    fn __iter__(slf: PyRef<'_, Self>) -> PyRef<'_, Self> {
        slf
    }

    fn __next__(&self, py: Python<'_>) -> PyResult<Option<String>> {
        match py.detach(|| next_row(&self.rows)) {
            Some(Ok(row)) => Ok(Some(row)),
            Some(Err(message)) => Err(PyValueError::new_err(message)),
            None => Ok(None),
        }
    }
}

/// `coopwin verilog`'s files for `options` (e.g. ["--width", "640", "--axis"]): (name, text)
/// pairs, as `coopwin verilog --out` writes them.
#[pyfunction]
fn verilog(options: Vec<String>) -> PyResult<Vec<(String, String)>> {
    let args = VerilogOptions::try_parse_from(["--out".to_string(), "-".to_string()].into_iter().chain(options)).map_err(clap_error)?.verilog;
    let g = args.sensor.geometry().map_err(cli_error)?;
    let files = verilog_files(args.units, &g, args.netlist.into(), args.axis).map_err(cli_error)?;
    Ok(files.into_iter().map(|(name, text)| (name.to_string(), text)).collect())
}

/// The CSV's header (the columns of every row), and the hash of the sources the extension
/// was built from (python/source_hash.rs; testbench/tests/python.rs checks it is the
/// checkout's).
#[pymodule]
fn _coopwin(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("TRACK_HEADER", csv::TRACK_HEADER)?;
    m.add("SOURCE_HASH", env!("COOPWIN_SOURCE_HASH"))?;
    m.add_class::<FrameRun>()?;
    m.add_class::<VideoRows>()?;
    m.add_function(wrap_pyfunction!(verilog, m)?)?;
    Ok(())
}
