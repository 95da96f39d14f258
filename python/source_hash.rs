// The extension's build identity: a hash of the sources it is built from. python/build.rs
// embeds it in the extension and testbench/tests/python.rs compares it with the checkout's,
// so pytest never runs an extension built from other sources. Included by both (`include!`),
// so neither needs a crate for it; no git, so a copy without .git hashes the same.

/// Folders of the extension's sources, from the workspace root: the library crates' and the
/// package's own (its Python code is installed with the extension).
const SOURCE_DIRS: [&str; 5] = ["firmware/src", "hdl/src", "testbench/src", "python/src", "python/coopwin"];

/// Single files of the build: the manifests and the lock file.
const SOURCE_FILES: [&str; 7] = ["Cargo.toml", "Cargo.lock", "firmware/Cargo.toml", "hdl/Cargo.toml", "testbench/Cargo.toml", "python/Cargo.toml", "python/pyproject.toml"];

/// The kinds of file hashed in SOURCE_DIRS (not a build's `.so` nor `__pycache__`).
const SOURCE_EXTENSIONS: [&str; 4] = ["rs", "v", "py", "pyi"];

/// FNV-1a (64 bits) over every source's path from `root` and its bytes, in path order, as
/// 16 hex digits.
fn source_hash(root: &std::path::Path) -> std::io::Result<String> {
    let mut files = Vec::new();
    for dir in SOURCE_DIRS {
        source_files(root, &root.join(dir), &mut files)?;
    }
    files.extend(SOURCE_FILES.iter().map(|f| f.to_string()));
    files.sort();
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    for name in &files {
        let bytes = std::fs::read(root.join(name))?;
        // The path, a separator and the length first, so no two file sets hash alike by
        // moving bytes from one file to the next.
        for b in name.bytes().chain([0]).chain((bytes.len() as u64).to_le_bytes()).chain(bytes) {
            hash = (hash ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
        }
    }
    Ok(format!("{hash:016x}"))
}

/// The source files under `dir`, as paths from `root` with `/` between their parts.
fn source_files(root: &std::path::Path, dir: &std::path::Path, out: &mut Vec<String>) -> std::io::Result<()> {
    for entry in std::fs::read_dir(dir)? {
        let path = entry?.path();
        if path.is_dir() {
            source_files(root, &path, out)?;
        } else if path.extension().is_some_and(|e| SOURCE_EXTENSIONS.iter().any(|s| e == *s)) {
            let relative = path.strip_prefix(root).map_err(std::io::Error::other)?;
            out.push(relative.components().map(|c| c.as_os_str().to_string_lossy()).collect::<Vec<_>>().join("/"));
        }
    }
    Ok(())
}
