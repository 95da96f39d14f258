//! The Python package's tests (python/tests, pytest) as part of the README's one test command.
//! They compare the installed package (`pip install ./python`, which .ci/run does) against
//! this build's `coopwin` binary; a machine without the package, or with one built from other
//! sources than this checkout's, fails here, saying how to install it.
use std::path::Path;
use std::process::Command;

include!("../../python/source_hash.rs");

/// How to install the package from this checkout.
const INSTALL: &str = "python3 -m pip install --no-build-isolation ./python (as .ci/run does)";

#[test]
fn python_package_gives_the_cli_rows() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let installed = Command::new("python3").args(["-c", "import coopwin, cv2, pytest"]).output();
    let installed = installed.is_ok_and(|o| o.status.success());
    assert!(
        installed,
        "the Python package or its test tools are missing: python3 -m pip install -r python/tests/requirements.txt && {INSTALL}"
    );
    // The extension's build identity against this checkout's sources: another checkout's
    // build would be compared with this one's binary.
    let ask = "from coopwin import _coopwin; print(getattr(_coopwin, 'SOURCE_HASH', 'none (built before it had one)')); print(_coopwin.__file__)";
    let out = Command::new("python3").args(["-c", ask]).current_dir(&root).output().expect("run python3");
    let text = String::from_utf8_lossy(&out.stdout);
    let mut lines = text.lines();
    let (built, file) = (lines.next().unwrap_or_default(), lines.next().unwrap_or_default());
    let here = source_hash(&root).expect("hash this checkout's sources");
    assert_eq!(
        built, here,
        "the installed extension {file} was built from other sources (hash {built}) than this checkout's ({here}): reinstall it from here with {INSTALL}"
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
