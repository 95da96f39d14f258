//! Where a command's output files go, and the one rule for writing them.
//!
//! - `-` is standard output.
//! - A new path, or an existing regular file, is written to a temporary file with a unique name
//!   in the same folder (`.NAME.<pid>.<n>.partial`), which is renamed over the path once complete:
//!   a failed run leaves the old file as it was, and a reader never sees half a file.
//! - A symbolic link is followed; what it points at is handled by these rules (so a link to
//!   a regular file stays a link, and its target is replaced). A dangling link is refused.
//! - A character device or a FIFO (`/dev/null`, `/dev/stdout`, a named pipe) is opened and
//!   written through; it is never replaced by a file.
//! - A folder, a block device or a socket is refused.
//! - The folder that holds the output must exist: no folders are created for an output file.
//!
//! - An output is never an input: [`check_apart`] refuses (exit 2) an output that is an input
//!   file (the same file after following links, hard links included), lies inside an input
//!   folder, or is another output of the same run.
//!
//! Outputs are checked before any work starts ([`OutFile::check`]), so a bad path is reported
//! at once, with exit code 2; a folder that cannot take the file (read-only, full, no
//! permission) is found then too, by creating and removing the temporary file, with exit
//! code 1.
use super::{io_error, CliError};
use std::fs::{File, OpenOptions};
use std::io::Write;
use std::os::unix::fs::FileTypeExt;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// An output file, checked against the rule above.
#[derive(Clone, Debug)]
pub struct OutFile {
    /// The path as given.
    pub path: PathBuf,
    kind: Kind,
}

#[derive(Clone, Debug, PartialEq)]
enum Kind {
    Stdout,
    /// Replaced atomically (a new path or a regular file); the resolved path.
    Replace(PathBuf),
    /// Written through (a character device or a FIFO); the resolved path.
    Through(PathBuf),
}

impl OutFile {
    /// Checks that `path` may be written (see the module's rule); `option` names the
    /// command-line option in messages.
    pub fn check(path: &Path, option: &str) -> Result<OutFile, CliError> {
        let bad = |why: String| CliError::arg(format!("{option} {}: {why}", path.display()));
        if path.as_os_str() == "-" {
            return Ok(OutFile { path: path.into(), kind: Kind::Stdout });
        }
        if path.as_os_str().is_empty() {
            return Err(CliError::arg(format!("{option}: the path is empty")));
        }
        let resolved = match std::fs::symlink_metadata(path) {
            Ok(m) if m.file_type().is_symlink() => std::fs::canonicalize(path)
                .map_err(|_| bad("a symbolic link to a file that does not exist; point it at a file or give another path".into()))?,
            Ok(_) => path.to_path_buf(),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => path.to_path_buf(),
            Err(e) => return Err(bad(format!("cannot be examined ({e})"))),
        };
        let kind = match std::fs::metadata(&resolved) {
            Ok(m) => {
                let t = m.file_type();
                if t.is_file() {
                    Kind::Replace(resolved)
                } else if t.is_char_device() || t.is_fifo() {
                    Kind::Through(resolved)
                } else if t.is_dir() {
                    return Err(bad("is a folder; give a file name".into()));
                } else if t.is_block_device() {
                    return Err(bad("is a block device; refusing to write over it".into()));
                } else {
                    return Err(bad("is not a regular file, a device or a FIFO; give a file name".into()));
                }
            }
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Kind::Replace(resolved),
            Err(e) => return Err(bad(format!("cannot be examined ({e})"))),
        };
        if let Kind::Replace(p) = &kind {
            let parent = folder_of(p);
            if !parent.is_dir() {
                return Err(bad(format!("the folder {} does not exist; create it first", parent.display())));
            }
            // The run's output will go through a temporary file here: make sure one can be made.
            let (tmp, _) = temp_file(p).map_err(|e| io_error("write", path, e))?;
            let _ = std::fs::remove_file(tmp);
        }
        Ok(OutFile { path: path.into(), kind })
    }

    /// Standard output (`-`).
    pub fn is_stdout(&self) -> bool {
        self.kind == Kind::Stdout
    }

    /// Writes `bytes` as the whole output.
    pub fn write(&self, bytes: &[u8]) -> Result<(), CliError> {
        let mut s = self.stream()?;
        s.write_all(bytes).map_err(|e| io_error("write", &self.path, e))?;
        s.finish()
    }

    /// Opens the output for writing piece by piece; [`Stream::finish`] completes it (a stream
    /// dropped unfinished leaves a replaced file untouched and removes its temporary file).
    pub fn stream(&self) -> Result<Stream, CliError> {
        let err = |e| io_error("write", &self.path, e);
        let (file, temp): (Box<dyn Write + Send>, Option<(PathBuf, PathBuf)>) = match &self.kind {
            Kind::Stdout => (Box::new(std::io::stdout()), None),
            Kind::Through(p) => (Box::new(OpenOptions::new().write(true).open(p).map_err(err)?), None),
            Kind::Replace(p) => {
                let (tmp, f) = temp_file(p).map_err(err)?;
                if let Ok(m) = std::fs::metadata(p) {
                    let _ = f.set_permissions(m.permissions());
                }
                (Box::new(f), Some((tmp, p.clone())))
            }
        };
        Ok(Stream { out: std::io::BufWriter::new(file), temp, path: self.path.clone() })
    }
}

/// Where a file is: its device and inode when it exists (so links and hard links to one file
/// agree), else its absolute path with the folder's links resolved.
#[derive(Debug, PartialEq)]
enum Place {
    Inode(u64, u64),
    Path(PathBuf),
}

impl Place {
    fn of(p: &Path) -> Place {
        use std::os::unix::fs::MetadataExt;
        match std::fs::metadata(p) {
            Ok(m) => Place::Inode(m.dev(), m.ino()),
            Err(_) => Place::Path(real_path(p)),
        }
    }
}

/// `p` with its folder's links resolved (`p` itself need not exist).
fn real_path(p: &Path) -> PathBuf {
    let dir = std::fs::canonicalize(folder_of(p)).unwrap_or_else(|_| folder_of(p));
    p.file_name().map_or(dir.clone(), |n| dir.join(n))
}

/// Refuses (exit 2) an output of `outputs` that would overwrite one of `inputs` or another
/// output: an output that is an input file or a file inside an input folder (compared by
/// inode, so links and hard links are seen), that lies inside an input folder, or that is
/// the same file as another output. Each pair is (option, path). Standard output, devices
/// and FIFOs are written through and never replace anything, so they are not compared.
pub fn check_apart(inputs: &[(&str, &Path)], outputs: &[(&str, &OutFile)]) -> Result<(), CliError> {
    let mut input_files = Vec::new();
    let mut input_dirs = Vec::new();
    for &(option, p) in inputs {
        if p.is_dir() {
            let dir = std::fs::canonicalize(p).map_err(|e| io_error("read", p, e))?;
            for entry in std::fs::read_dir(p).map_err(|e| io_error("read", p, e))?.flatten() {
                input_files.push((option, entry.path(), Place::of(&entry.path())));
            }
            input_dirs.push((option, p, dir));
        } else {
            input_files.push((option, p.to_path_buf(), Place::of(p)));
        }
    }
    let replaced: Vec<(&str, &OutFile, Place)> = outputs
        .iter()
        .filter_map(|&(option, o)| match &o.kind {
            Kind::Replace(p) => Some((option, o, Place::of(p))),
            _ => None,
        })
        .collect();
    for (i, (option, o, place)) in replaced.iter().enumerate() {
        let refuse = |why: String| CliError::arg(format!("{option} {}: {why}; give another path", o.path.display()));
        if let Some((input, p, _)) = input_files.iter().find(|(_, _, q)| q == place) {
            return Err(refuse(format!("is the input {input} {}, which it would overwrite", p.display())));
        }
        let Kind::Replace(p) = &o.kind else { continue };
        let real = real_path(p);
        if let Some((input, dir, _)) = input_dirs.iter().find(|(_, _, d)| real.starts_with(d)) {
            return Err(refuse(format!("lies inside the input folder {input} {}", dir.display())));
        }
        if let Some((other, _, _)) = replaced[..i].iter().find(|(_, _, q)| q == place) {
            return Err(refuse(format!("is also the output of {other}")));
        }
    }
    Ok(())
}

/// The folder that holds `p` (`.` for a bare file name).
fn folder_of(p: &Path) -> PathBuf {
    match p.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// A new file beside `p` with a name no other writer uses.
fn temp_file(p: &Path) -> std::io::Result<(PathBuf, File)> {
    static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let name = p.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    loop {
        let n = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let tmp = folder_of(p).join(format!(".{name}.{}.{n}.partial", std::process::id()));
        match OpenOptions::new().write(true).create_new(true).open(&tmp) {
            Ok(f) => return Ok((tmp, f)),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists && n < 10_000 => continue,
            Err(e) => return Err(e),
        }
    }
}

/// An output being written.
pub struct Stream {
    out: std::io::BufWriter<Box<dyn Write + Send>>,
    /// (temporary file, final path) when the output is replaced at the end.
    temp: Option<(PathBuf, PathBuf)>,
    path: PathBuf,
}

impl Write for Stream {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.out.write(buf)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.out.flush()
    }
}

impl Stream {
    /// Flushes, and puts a replaced file in place.
    pub fn finish(mut self) -> Result<(), CliError> {
        self.out.flush().map_err(|e| io_error("write", &self.path, e))?;
        if let Some((tmp, target)) = self.temp.take() {
            if let Err(e) = std::fs::rename(&tmp, &target) {
                let _ = std::fs::remove_file(&tmp);
                return Err(io_error("write", &self.path, e));
            }
        }
        Ok(())
    }

    /// A writer that can be handed to a consumer that drops it when done (the VCD tracer),
    /// with [`Shared::finish`] to complete the output afterwards and report any write error.
    pub fn shared(self) -> Shared {
        Shared(Arc::new(Mutex::new(SharedState { stream: Some(self), error: None })))
    }
}

impl Drop for Stream {
    fn drop(&mut self) {
        if let Some((tmp, _)) = self.temp.take() {
            let _ = std::fs::remove_file(tmp);
        }
    }
}

struct SharedState {
    stream: Option<Stream>,
    error: Option<std::io::Error>,
}

/// A [`Stream`] shared between a writer handed away and its owner (see [`Stream::shared`]).
/// Write errors are kept and reported by [`Shared::finish`].
#[derive(Clone)]
pub struct Shared(Arc<Mutex<SharedState>>);

impl Write for Shared {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let mut s = self.0.lock().unwrap_or_else(|e| e.into_inner());
        let r = match s.stream.as_mut() {
            Some(st) => st.write(buf),
            None => Err(std::io::Error::other("the output is already finished")),
        };
        if let Err(e) = &r {
            s.error.get_or_insert_with(|| std::io::Error::new(e.kind(), e.to_string()));
        }
        r
    }
    fn flush(&mut self) -> std::io::Result<()> {
        let mut s = self.0.lock().unwrap_or_else(|e| e.into_inner());
        let r = s.stream.as_mut().map_or(Ok(()), |st| st.flush());
        if let Err(e) = &r {
            s.error.get_or_insert_with(|| std::io::Error::new(e.kind(), e.to_string()));
        }
        r
    }
}

impl Shared {
    /// Completes the output, or reports the first write error (the old file then stays).
    pub fn finish(&self) -> Result<(), CliError> {
        let mut s = self.0.lock().unwrap_or_else(|e| e.into_inner());
        let stream = s.stream.take().ok_or_else(|| CliError::new("internal: output finished twice"))?;
        if let Some(e) = s.error.take() {
            return Err(io_error("write", &stream.path, e));
        }
        stream.finish()
    }
}

/// Checks an output folder (`--out` of `scene`, `verilog`, `experiment`): it may exist (as a
/// folder) or be new, in a folder that exists. Returns whether it exists.
pub fn check_folder(dir: &Path, option: &str) -> Result<bool, CliError> {
    let bad = |why: String| CliError::arg(format!("{option} {}: {why}", dir.display()));
    match std::fs::metadata(dir) {
        Ok(m) if m.is_dir() => Ok(true),
        Ok(_) => Err(bad("exists and is not a folder".into())),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            let parent = folder_of(dir);
            if parent.is_dir() {
                Ok(false)
            } else {
                Err(bad(format!("the folder {} does not exist; create it first", parent.display())))
            }
        }
        Err(e) => Err(bad(format!("cannot be examined ({e})"))),
    }
}

/// Creates a checked output folder (only the last component; see [`check_folder`]).
pub fn create_folder(dir: &Path, option: &str) -> Result<(), CliError> {
    if !check_folder(dir, option)? {
        std::fs::create_dir(dir).map_err(|e| io_error("create", dir, e))?;
    }
    Ok(())
}
