"""Shared for the package's tests: the `coopwin` binary they compare against, and a real clip.

The binary is $COOPWIN_BIN (the Rust test testbench/tests/python.rs sets it to the one cargo
built), else the workspace's target/release/coopwin (`cargo build --release`).
"""
import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
#: opencv-doc's clip (Debian package opencv-doc; .ci/run installs it).
VTEST = pathlib.Path("/usr/share/doc/opencv-doc/examples/data/vtest.avi")


@pytest.fixture(scope="session")
def coopwin_bin() -> pathlib.Path:
    path = pathlib.Path(os.environ.get("COOPWIN_BIN", ROOT / "target" / "release" / "coopwin"))
    assert path.is_file(), f"no coopwin binary at {path}: run `cargo build --release` or set COOPWIN_BIN"
    return path


@pytest.fixture(scope="session")
def vtest() -> pathlib.Path:
    assert VTEST.is_file(), f"{VTEST} is missing: apt-get install opencv-doc"
    return VTEST


def run_cli(binary: pathlib.Path, *args: str) -> subprocess.CompletedProcess:
    """`coopwin ARGS`; fails the test, with its stderr, when it exits non-zero."""
    out = subprocess.run([str(binary), *args], capture_output=True, text=True)
    assert out.returncode == 0, f"coopwin {' '.join(args)} exited {out.returncode}: {out.stderr}"
    return out
