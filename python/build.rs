//! Embeds the build identity (python/source_hash.rs) in the extension as COOPWIN_SOURCE_HASH.
include!("source_hash.rs");

fn main() {
    let root = std::path::Path::new(&std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR")).join("..");
    // A folder is watched with every file in it.
    for source in SOURCE_DIRS.iter().chain(&SOURCE_FILES) {
        println!("cargo:rerun-if-changed={}", root.join(source).display());
    }
    let hash = source_hash(&root).unwrap_or_else(|e| panic!("hash the extension's sources under {}: {e}", root.display()));
    println!("cargo:rustc-env=COOPWIN_SOURCE_HASH={hash}");
}
