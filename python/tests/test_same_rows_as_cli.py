"""The package against the `coopwin` binary: the same frames give the same CSV rows, bit for
bit (the reference is the CLI's own CSV file, written by a separate process)."""
import cv2
import numpy as np

import coopwin
from coopwin import _coopwin

from conftest import BOX, cli_rows, read_frames, run_cli, tracked_rows, without_file, write_frames

FRAMES = 40


def test_opencv_loop_on_a_real_clip_gives_the_cli_rows(coopwin_bin, vtest, tmp_path):
    # Reference: `coopwin track` on the very frames OpenCV decoded, written as PNG files (the
    # CLI reads a folder of colour PNGs and converts them to gray as the package converts BGR
    # arrays). Every row but the last: the CLI's last row closes a run that ends there, while
    # the tracker's run goes on, so the CLI is given one frame more than the tracker.
    # The frames' rate is the video's, as README's loop gives it (the CLI takes a video's own,
    # and PNG frames need it said).
    fps = cv2.VideoCapture(str(vtest)).get(cv2.CAP_PROP_FPS)
    frames = read_frames(vtest, FRAMES + 1)
    folder = write_frames(tmp_path / "frames", frames)
    expected = cli_rows(coopwin_bin, tmp_path, folder, "--target-box", ",".join(map(str, BOX)), "--fps", str(fps))[:FRAMES]

    tracker = coopwin.TrackerCOOP_create(fps=fps)
    tracker.init(frames[0], BOX)
    got = [tracker.tracker.csv_row]
    answers = []
    for frame in frames[1:FRAMES]:
        answers.append(tracker.update(frame))
        got.append(tracker.tracker.csv_row)
    assert [without_file(r) for r in got] == [without_file(r) for r in expected]
    # The OpenCV-style answer is the row's ok and its box rounded to whole pixels.
    for (ok, box), line in zip(answers, expected[1:]):
        row = coopwin.Row.parse(line)
        assert ok == row.ok
        assert box == tuple(int(np.floor(v + 0.5)) for v in (row.box_x, row.box_y, row.box_w, row.box_h))
    # Not a comparison of empty runs: the target is measured on most frames.
    assert sum(coopwin.Row.parse(r).source == "ncc" for r in got) >= FRAMES // 2


def test_gray_frames_give_the_cli_rows(coopwin_bin, vtest, tmp_path):
    # Reference: the CLI on gray PNG files of the same pixels (no colour conversion on either side).
    grays = [cv2.cvtColor(f, cv2.COLOR_BGR2GRAY) for f in read_frames(vtest, 11)]
    folder = write_frames(tmp_path / "frames", grays)
    expected = cli_rows(coopwin_bin, tmp_path, folder, "--target-box", ",".join(map(str, BOX)), "--fps", "10")[:10]
    tracker = coopwin.Tracker(grays[0], BOX, fps=10)
    got = tracked_rows(tracker, grays[1:10])
    assert [without_file(r) for r in got] == [without_file(r) for r in expected]


def test_track_video_streams_the_cli_rows(coopwin_bin, vtest, tmp_path):
    # Reference: `coopwin track --frames vtest.avi` (FFmpeg decodes both), every row.
    options = ("--target-box", ",".join(map(str, BOX)), "--end-frame", str(FRAMES))
    expected = cli_rows(coopwin_bin, tmp_path, vtest, *options)
    assert list(_coopwin.VideoRows(str(vtest), list(options))) == expected
    rows = list(coopwin.track_video(vtest, BOX, end_frame=FRAMES))
    assert rows == [coopwin.Row.parse(line) for line in expected]
    assert coopwin.Row._fields == coopwin.COLUMNS


def test_verilog_is_the_cli_export(coopwin_bin, tmp_path):
    # Reference: the files `coopwin verilog --out` writes.
    run_cli(coopwin_bin, "verilog", "--width", "640", "--height", "480", "--pixel-bits", "10", "--axis", "--out", str(tmp_path))
    files = coopwin.verilog(640, 480, 10, axis=True)
    assert sorted(files) == sorted(p.name for p in tmp_path.iterdir())
    for name, text in files.items():
        assert text == (tmp_path / name).read_text(), name
