//! The Python package's tests (python/tests, pytest) as part of the README's one test command.
//! They compare the installed package (`pip install ./python`, which .ci/run does) against
//! this build's `coopwin` binary; a machine without the package fails here, saying how to
//! install it.
use std::path::Path;
use std::process::Command;

#[test]
fn python_package_gives_the_cli_rows() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let installed = Command::new("python3").args(["-c", "import coopwin, cv2, pytest"]).output();
    let installed = installed.is_ok_and(|o| o.status.success());
    assert!(
        installed,
        "the Python package or its test tools are missing: python3 -m pip install maturin==1.16.0 pytest opencv-contrib-python-headless && python3 -m pip install ./python (as .ci/run does)"
    );
    let out = Command::new("python3")
        .args(["-m", "pytest", "-q", "-p", "no:cacheprovider", "python/tests"])
        .current_dir(&root)
        .env("COOPWIN_BIN", env!("CARGO_BIN_EXE_coopwin"))
        .output()
        .expect("run python3 -m pytest");
    let text = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "pytest python/tests failed:\n{text}");
    // pytest exits 0 with nothing collected only with -q's "no tests ran" (exit 5), so a pass
    // here ran the tests; their count is in the output.
    assert!(text.contains(" passed"), "{text}");
}
