//! Puts the memory map where cortex-m-rt's link.x looks for it (`memory.x`): the mps2-an386's
//! (`memory-mps2.x`), or the STM32F405's with the `stm32f405` feature (`memory-stm32f405.x`),
//! 64 KiB of it for a one-processor image (`partner`, `peripheral`, `watch`, `master`:
//! `memory-stm32f405-64k.x`).
use std::{env, fs, path::PathBuf};

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    // Neither file is named memory.x: the linker would find one in the package directory first.
    let feature = |f: &str| env::var_os(format!("CARGO_FEATURE_{f}")).is_some();
    let one = ["PARTNER", "PERIPHERAL", "WATCH", "MASTER"].into_iter().any(feature);
    let map = match (feature("STM32F405"), one) {
        (true, true) => "memory-stm32f405-64k.x",
        (true, false) => "memory-stm32f405.x",
        (false, _) => "memory-mps2.x",
    };
    fs::copy(map, out.join("memory.x")).expect("copy the memory map");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=memory-mps2.x");
    println!("cargo:rerun-if-changed=memory-stm32f405.x");
    println!("cargo:rerun-if-changed=memory-stm32f405-64k.x");
}
