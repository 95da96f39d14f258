"""Shared for the package's tests: the `coopwin` binary they compare against, a real clip, and
the CLI's rows to compare with.

The binary is $COOPWIN_BIN (the Rust test testbench/tests/python.rs sets it to the one cargo
built), else the workspace's target/release/coopwin (`cargo build --release`).
"""
import os
import pathlib
import subprocess

import cv2
import numpy as np
import pytest

import coopwin
from coopwin import _coopwin

ROOT = pathlib.Path(__file__).resolve().parents[2]
#: opencv-doc's clip (Debian package opencv-doc; .ci/run installs it).
VTEST = pathlib.Path("/usr/share/doc/opencv-doc/examples/data/vtest.avi")
#: A walker in vtest.avi's first frame (x, y, w, h).
BOX = (280, 180, 40, 80)
#: A 160x120 frame with texture everywhere (a horizontal ramp).
FRAME = np.tile(np.arange(256, dtype=np.uint8), (120, 1))[:, :160]


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


def cli_rows(binary: pathlib.Path, tmp_path: pathlib.Path, frames: pathlib.Path, *options: str) -> list:
    """The CSV lines (header checked, then dropped) `coopwin track --frames FRAMES OPTIONS` writes."""
    out = tmp_path / "cli.csv"
    run_cli(binary, "track", "--frames", str(frames), "--out", str(out), *options)
    lines = out.read_text().splitlines()
    assert lines[0] == _coopwin.TRACK_HEADER
    return lines[1:]


def without_file(line: str) -> list:
    """A row without its `file` column (a folder's file name; frames from memory have none)."""
    fields = line.split(",")
    del fields[coopwin.COLUMNS.index("file")]
    return fields


def read_frames(video: pathlib.Path, n: int) -> list:
    """The first `n` frames of `video` as OpenCV decodes them (BGR arrays)."""
    cap = cv2.VideoCapture(str(video))
    frames = []
    for k in range(n):
        ok, frame = cap.read()
        assert ok, f"frame {k} of {video}"
        frames.append(frame)
    return frames


def write_frames(folder: pathlib.Path, frames: list) -> pathlib.Path:
    """`frames` as PNG files in `folder` (created), in order: a folder the CLI tracks."""
    folder.mkdir()
    for k, frame in enumerate(frames):
        assert cv2.imwrite(str(folder / f"f{k:04d}.png"), frame)
    return folder


def tracked_rows(tracker: coopwin.Tracker, frames: list) -> list:
    """The tracker's CSV row of its first frame, then of each of `frames` handed to it."""
    rows = [tracker.csv_row]
    for frame in frames:
        tracker.update(frame)
        rows.append(tracker.csv_row)
    return rows
