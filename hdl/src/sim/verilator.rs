//! The exported `window_network` (4 units) at a sensor's geometry, compiled with Verilator on
//! demand into a shared library beside the C interface of
//! `hdl/verilog/tb/verilator_harness.cpp` (one library per geometry: its parameters are part of
//! the cache key), and stepped one pixel clock per call with the same interface as
//! [`super::driver::NetworkDriver`]. The testbench's `--hdl verilator` window units run on it.
use super::camera::CameraBus;
use super::driver::{CoordBus, UnitOutputs};
use crate::verilog::Geometry;
use std::ffi::c_void;
use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Units in the exported network.
pub const UNITS: usize = crate::verilog::DEFAULT_UNITS;

const HARNESS: &str = include_str!("../../verilog/tb/verilator_harness.cpp");

/// Verilator's flags. The model's C++ is built at -O3 (Verilator's own default, -Os, runs
/// about 20% slower here: 6.8 M against 8.8 M clocks/s for the 4-unit network).
const VERILATOR_FLAGS: [&str; 10] = ["--cc", "--build", "-j", "2", "-O3", "-CFLAGS", "-fPIC", "-MAKEFLAGS", "OPT_FAST=-O3", "--top-module"];

type NewFn = unsafe extern "C" fn() -> *mut c_void;
type StepFn = unsafe extern "C" fn(*mut c_void, u32, *const u32, *mut u32);
type FreeFn = unsafe extern "C" fn(*mut c_void);

/// Why the Verilator model cannot be built or loaded.
#[derive(Debug)]
pub enum VerilatorError {
    /// A tool could not be started.
    Start {
        /// The tool, as named in messages.
        what: &'static str,
        /// The reason.
        source: std::io::Error,
        /// What to install.
        install: &'static str,
    },
    /// A tool ran and failed.
    Failed {
        /// The tool, as named in messages.
        what: &'static str,
        /// Its standard output and error.
        output: String,
    },
    /// A file or folder could not be made.
    Io {
        /// What was being done (`create`, `write`, ...).
        action: &'static str,
        /// The file or folder.
        path: String,
        /// The reason.
        source: std::io::Error,
    },
    /// The finished library could not be put in place.
    Install {
        /// The library built.
        from: PathBuf,
        /// Where it was to go.
        to: PathBuf,
        /// The reason.
        source: std::io::Error,
    },
    /// Verilator's include folder is missing.
    NoInclude(PathBuf),
    /// The library could not be loaded, or lacks a symbol.
    Load(String),
    /// The model's constructor returned nothing.
    NoModel,
    /// The cache folder could be written by someone else: no library is loaded from it.
    Unsafe {
        /// The folder.
        dir: PathBuf,
        /// What is wrong with it.
        why: String,
    },
}

impl std::fmt::Display for VerilatorError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            VerilatorError::Load(e) => f.write_str(e),
            VerilatorError::Start { what, source, install } => write!(f, "cannot run {what}: {source} ({install})"),
            VerilatorError::Failed { what, output } => write!(f, "{what} failed:\n{output}"),
            VerilatorError::Io { action, path, source } => write!(f, "cannot {action} {path}: {source}"),
            VerilatorError::Install { from, to, source } => {
                write!(f, "cannot move {} to {}: {source}", from.display(), to.display())
            }
            VerilatorError::NoInclude(root) => write!(f, "Verilator's include folder not found under {}", root.display()),
            VerilatorError::NoModel => f.write_str("the Verilator model could not be created"),
            VerilatorError::Unsafe { dir, why } => write!(
                f,
                "refusing to load the Verilator model from {}: {why}; remove the folder (or set XDG_CACHE_HOME to a folder of your own) and run again",
                dir.display()
            ),
        }
    }
}

impl std::error::Error for VerilatorError {}

/// The Verilator model of `window_network`.
pub struct VerilatorNetwork {
    handle: *mut c_void,
    step: StepFn,
    free: FreeFn,
    // Declared last: the library outlives the function pointers taken from it.
    _lib: libloading::Library,
}

/// Runs a build tool; its output becomes the error when it fails.
fn run_tool(cmd: &mut Command, what: &'static str) -> Result<(), VerilatorError> {
    let out = cmd
        .output()
        .map_err(|source| VerilatorError::Start { what, source, install: "apt-get install -y verilator g++" })?;
    if out.status.success() {
        Ok(())
    } else {
        let output = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
        Err(VerilatorError::Failed { what, output })
    }
}

/// The per-user cache the model is built in: `$XDG_CACHE_HOME/coopwin`, else
/// `$HOME/.cache/coopwin`, else `coopwin-<uid>` in the system temp folder.
pub fn cache_root() -> PathBuf {
    let absolute = |v: Option<std::ffi::OsString>| v.map(PathBuf::from).filter(|p| p.is_absolute());
    match (absolute(std::env::var_os("XDG_CACHE_HOME")), absolute(std::env::var_os("HOME"))) {
        (Some(xdg), _) => xdg.join("coopwin"),
        (None, Some(home)) => home.join(".cache").join("coopwin"),
        // SAFETY: geteuid has no preconditions.
        (None, None) => std::env::temp_dir().join(format!("coopwin-{}", unsafe { libc::geteuid() })),
    }
}

/// Where the library for the current Verilog at geometry `g` lives under the cache `root`:
/// `verilator-<key>/libwindow_network.so`, the key a hash of the geometry, the Verilog (its
/// parameters' defaults set to `g`), the harness and the flags.
pub fn library_in(root: &Path, g: &Geometry) -> PathBuf {
    let files = crate::verilog::exported(UNITS, g);
    root.join(format!("verilator-{:016x}", key(g, &files))).join("libwindow_network.so")
}

/// Makes `dir` (mode 0700) if it is missing, then checks that it is a real folder (not a
/// link), owned by this user and closed to everyone else: only then may a library in it be
/// loaded, since whoever can write there chooses the code this process runs.
fn private_dir(dir: &Path) -> Result<(), VerilatorError> {
    use std::os::unix::fs::{DirBuilderExt, MetadataExt};
    let io = |action, source| VerilatorError::Io { action, path: dir.display().to_string(), source };
    match std::fs::DirBuilder::new().mode(0o700).create(dir) {
        Ok(()) => {}
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
        Err(source) => return Err(io("create", source)),
    }
    let m = std::fs::symlink_metadata(dir).map_err(|source| io("examine", source))?;
    // SAFETY: geteuid has no preconditions.
    let me = unsafe { libc::geteuid() };
    let why = if !m.file_type().is_dir() {
        Some("it is not a folder (a link or a file)".to_string())
    } else if m.uid() != me {
        Some(format!("it belongs to user {}, not to you (user {me})", m.uid()))
    } else if m.mode() & 0o077 != 0 {
        Some(format!("its mode is {:04o}, open to other users (it must be 0700)", m.mode() & 0o7777))
    } else {
        None
    };
    match why {
        Some(why) => Err(VerilatorError::Unsafe { dir: dir.into(), why }),
        None => Ok(()),
    }
}

/// Builds (or reuses) the shared library for the current Verilog at geometry `g` in the
/// per-user cache ([`cache_root`]).
pub fn build(g: &Geometry) -> Result<PathBuf, VerilatorError> {
    build_in(&cache_root(), g)
}

/// Builds (or reuses) the shared library for the current Verilog at geometry `g` under the
/// cache `root`.
///
/// The library lives at [`library_in`]`(root)`. The cache folder and the key's folder are
/// made with mode 0700 and checked (owner and mode, see `private_dir`) before a library
/// there is used. Each build runs in a folder of its own under the key's folder (named by
/// process id and a counter), and the finished library is linked into place without
/// replacing one that is already there; so concurrent threads and processes never see a
/// half-built library, and the first one installed is the one every run loads.
pub fn build_in(root: &Path, g: &Geometry) -> Result<PathBuf, VerilatorError> {
    // One build at a time within a process; other processes are kept apart by the private folders.
    static BUILDING: std::sync::Mutex<()> = std::sync::Mutex::new(());
    let _guard = BUILDING.lock().unwrap_or_else(|e| e.into_inner());
    let files = crate::verilog::exported(UNITS, g);
    let lib = library_in(root, g);
    let dir = lib.parent().map_or_else(|| root.to_path_buf(), Path::to_path_buf);
    if let Some(parent) = root.parent() {
        std::fs::create_dir_all(parent).map_err(|source| VerilatorError::Io { action: "create", path: parent.display().to_string(), source })?;
    }
    private_dir(root)?;
    private_dir(&dir)?;
    if lib.exists() {
        return Ok(lib);
    }
    let work = private_folder(&dir)?;
    let built = compile(&work, &files);
    let installed = built.and_then(|so| install(&so, &lib));
    // Only this build's own folder is removed; a failed build's output is not needed either.
    let _ = std::fs::remove_dir_all(&work);
    installed.map(|()| lib)
}

/// The library's key: a hash of the geometry, the Verilog, the harness and the flags (the
/// same in every process of one build of this crate).
fn key(g: &Geometry, files: &[(&'static str, String); 2]) -> u64 {
    let mut h = std::hash::DefaultHasher::new();
    ((g.width, g.height, g.pixel_bits), &files[0].1, &files[1].1, HARNESS, VERILATOR_FLAGS).hash(&mut h);
    h.finish()
}

/// A new folder under `dir` that no other build uses: `build-<pid>-<n>`, created with
/// `create_dir` (which fails when the name exists), so a name left by an earlier process is
/// skipped, never reused or deleted.
fn private_folder(dir: &Path) -> Result<PathBuf, VerilatorError> {
    static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    loop {
        let n = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let work = dir.join(format!("build-{}-{n}", std::process::id()));
        match std::fs::create_dir(&work) {
            Ok(()) => return Ok(work),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists && n < 1000 => continue,
            Err(source) => return Err(VerilatorError::Io { action: "create", path: work.display().to_string(), source }),
        }
    }
}

/// Verilates and links the model in `work`; returns the library's path there.
fn compile(work: &Path, files: &[(&'static str, String)]) -> Result<PathBuf, VerilatorError> {
    let write = |name: &str, text: &str| {
        std::fs::write(work.join(name), text).map_err(|source| VerilatorError::Io { action: "write", path: name.into(), source })
    };
    for (name, text) in files {
        write(name, text)?;
    }
    write("harness.cpp", HARNESS)?;
    run_tool(
        Command::new("verilator")
            .current_dir(work)
            .args(VERILATOR_FLAGS)
            .args(["window_network", "window_unit.v", "window_network.v", "-Mdir", "obj"]),
        "verilator",
    )?;
    let include = verilator_include()?;
    let so = work.join("libwindow_network.so");
    run_tool(
        Command::new("g++")
            .current_dir(work)
            .args(["-shared", "-fPIC", "-O3", "-std=c++17", "-Iobj"])
            .arg(format!("-I{}", include.display()))
            .arg(format!("-I{}", include.join("vltstd").display()))
            .args(["harness.cpp", "obj/Vwindow_network__ALL.a"])
            .arg(include.join("verilated.cpp"))
            .arg(include.join("verilated_threads.cpp"))
            .args(["-pthread", "-o"])
            .arg(&so),
        "g++ (linking the Verilator model)",
    )?;
    Ok(so)
}

/// Puts the finished library at `lib` in one step. A hard link never replaces an existing
/// file: when another build got there first, its library (built from the same key) stays.
fn install(so: &Path, lib: &Path) -> Result<(), VerilatorError> {
    match std::fs::hard_link(so, lib) {
        Ok(()) => Ok(()),
        Err(_) if lib.exists() => Ok(()),
        // A file system without hard links: a rename is atomic too (it may replace an
        // identical library another build installed meanwhile; loaded copies stay valid).
        Err(_) => std::fs::rename(so, lib).map_err(|source| VerilatorError::Install { from: so.into(), to: lib.into(), source }),
    }
}

fn verilator_include() -> Result<PathBuf, VerilatorError> {
    let out = Command::new("verilator")
        .arg("--getenv")
        .arg("VERILATOR_ROOT")
        .output()
        .map_err(|source| VerilatorError::Start { what: "verilator", source, install: "apt-get install -y verilator" })?;
    let root = PathBuf::from(String::from_utf8_lossy(&out.stdout).trim());
    let inc = root.join("include");
    if inc.join("verilated.cpp").exists() {
        Ok(inc)
    } else {
        Err(VerilatorError::NoInclude(root))
    }
}

impl VerilatorNetwork {
    /// Builds if needed and loads the model of sensor `g`, at power-on.
    pub fn new(g: &Geometry) -> Result<Self, VerilatorError> {
        Self::load(&build(g)?)
    }

    fn load(path: &Path) -> Result<Self, VerilatorError> {
        // SAFETY: the library is the one built above from our harness; its three symbols have
        // exactly the signatures declared here (see verilator_harness.cpp).
        unsafe {
            let lib = libloading::Library::new(path)
                .map_err(|e| VerilatorError::Load(format!("cannot load {}: {e}", path.display())))?;
            let symbol = |e: libloading::Error| VerilatorError::Load(e.to_string());
            let new: NewFn = *lib.get::<NewFn>(b"wn_new\0").map_err(symbol)?;
            let step: StepFn = *lib.get::<StepFn>(b"wn_step\0").map_err(symbol)?;
            let free: FreeFn = *lib.get::<FreeFn>(b"wn_free\0").map_err(symbol)?;
            let handle = new();
            if handle.is_null() {
                return Err(VerilatorError::NoModel);
            }
            Ok(VerilatorNetwork { handle, step, free, _lib: lib })
        }
    }

    /// One pixel clock: the camera bus, each unit's port (missing units idle), the outputs after
    /// the rising edge into `out` (as many as given).
    pub fn step(&mut self, cam: CameraBus, ports: &[CoordBus], out: &mut [UnitOutputs]) {
        let c = u32::from(cam.fval) | u32::from(cam.lval) << 1 | u32::from(cam.pixel_valid) << 2 | u32::from(cam.pixel) << 16;
        let mut p = [0u32; UNITS];
        for (slot, port) in p.iter_mut().zip(ports) {
            *slot = (port.data & 0xff) | u32::from(port.strobe) << 8 | u32::from(port.decimate) << 9;
        }
        let mut o = [0u32; UNITS];
        // SAFETY: `handle` is live until drop; both arrays hold the 4 words the harness reads
        // and writes.
        unsafe { (self.step)(self.handle, c, p.as_ptr(), o.as_mut_ptr()) };
        for (dst, w) in out.iter_mut().zip(o) {
            *dst = UnitOutputs {
                coord_ready: w & 1 != 0,
                pixel_strobe: w & 2 != 0,
                coord_error: w & 4 != 0,
                pixel_out: (w >> 16) as u16,
            };
        }
    }
}

impl Drop for VerilatorNetwork {
    fn drop(&mut self) {
        // SAFETY: created by wn_new, freed once.
        unsafe { (self.free)(self.handle) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_geometry_has_its_own_library() {
        // The rule stated in `library_in`: the key holds the geometry, so a model compiled for
        // one sensor is never loaded for another (the harness would drive the wrong widths).
        let root = Path::new("/cache");
        let vga = |bits| Geometry::new(640, 480, bits).unwrap();
        assert_eq!(library_in(root, &Geometry::CA_D1), library_in(root, &Geometry::CA_D1));
        assert_ne!(library_in(root, &Geometry::CA_D1), library_in(root, &vga(8)));
        assert_ne!(library_in(root, &vga(8)), library_in(root, &vga(10)));
    }
}
