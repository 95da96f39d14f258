//! The firmware builds without the standard library or an allocator: the crate is
//! `#![no_std]` (a `use std` in it fails to compile), and this test checks with `cargo tree`
//! that none of its normal dependencies pulls in `std` or `alloc` through a feature.
use std::process::Command;

#[test]
fn dependencies_are_no_std_without_alloc() {
    let manifest = concat!(env!("CARGO_MANIFEST_DIR"), "/Cargo.toml");
    let out = Command::new(env!("CARGO"))
        .args(["tree", "--offline", "--manifest-path", manifest, "-p", "coopwin-firmware", "-e", "normal,features", "--prefix", "none"])
        .output()
        .expect("run cargo tree");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let tree = String::from_utf8_lossy(&out.stdout);
    let crates: std::collections::BTreeSet<&str> =
        tree.lines().filter(|l| !l.contains(" feature ")).filter_map(|l| l.split_whitespace().next()).collect();
    let allowed = ["byteorder", "coopwin-firmware", "embedded-hal", "embedded-io", "hash32", "heapless", "libm", "stable_deref_trait"];
    for c in &crates {
        assert!(allowed.contains(c), "unexpected dependency {c}:\n{tree}");
    }
    for l in tree.lines() {
        assert!(!l.contains("feature \"std\"") && !l.contains("feature \"alloc\""), "std/alloc enabled: {l}");
    }
    let lib = include_str!("../src/lib.rs");
    assert!(lib.contains("#![no_std]"));
}
