"""Every `coopwin track` option either works from Python as in the CLI (the same rows as the
CLI's with that option) or raises ValueError naming it and saying what to use instead; none
is ignored, and none leaves a run waiting."""
import os
import shutil

import cv2
import pytest

import coopwin
from coopwin import _coopwin

from conftest import BOX, FRAME, cli_rows, read_frames, tracked_rows, without_file, write_frames

TARGET = "--target-box=" + ",".join(map(str, BOX))

#: The CLI's options a Tracker (frames handed in one at a time) refuses, and a word of what
#: its message offers instead.
NOT_FOR_TRACKER = [
    ("--start-frame", "--start-frame=3", "track_video"),
    ("--end-frame", "--end-frame=5", "track_video"),
    ("--blank-jitter", "--blank-jitter=40,2000,3", "track_video"),
    ("--hdl rust-hdl", "--hdl=rust-hdl", "track_video"),
    ("--hdl verilator", "--hdl=verilator", "track_video"),
    ("--pixel-bits", "--pixel-bits=10", "track_video"),
    ("--allow-damaged", "--allow-damaged", "track_video"),
    ("--out", "--out=rows.csv", "coopwin track --out"),
    ("--overlay", "--overlay=run.gif", "coopwin track --overlay"),
    ("--vcd", "--vcd=units.vcd", "coopwin track --hdl rust-hdl --vcd"),
    ("--list", "--list", "coopwin track --list"),
]

#: The options track_video refuses: it returns rows and writes nothing.
NOT_FOR_TRACK_VIDEO = [entry for entry in NOT_FOR_TRACKER if entry[0] in ("--out", "--overlay", "--vcd", "--list")]


@pytest.mark.parametrize("name,option,instead", NOT_FOR_TRACKER, ids=[e[0] for e in NOT_FOR_TRACKER])
def test_tracker_refuses_what_it_cannot_honour(name, option, instead, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # where a file named by an option would go
    with pytest.raises(ValueError) as refused:
        _coopwin.FrameRun(FRAME, ["--target-box=60,40,20,20", option])
    message = str(refused.value)
    assert message.startswith(f"{name} is not available from coopwin.Tracker: "), message
    assert instead in message, message
    assert not list(tmp_path.iterdir()), "a refused option wrote a file"


@pytest.mark.parametrize("name,option,instead", NOT_FOR_TRACK_VIDEO, ids=[e[0] for e in NOT_FOR_TRACK_VIDEO])
def test_track_video_refuses_what_it_cannot_honour(vtest, name, option, instead, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ValueError) as refused:
        _coopwin.VideoRows(str(vtest), [TARGET, option])
    message = str(refused.value)
    assert message.startswith(f"{name} is not available from coopwin.track_video: "), message
    assert instead in message, message
    assert not list(tmp_path.iterdir()), "a refused option wrote a file"


def test_tracker_takes_the_behavioural_model_said_outright():
    # --hdl model is the Tracker's own units: taken, not refused.
    run = _coopwin.FrameRun(FRAME, ["--target-box=60,40,20,20", "--hdl=model"])
    assert coopwin.Row.parse(run.first_row).frame == 0


def test_default_rate_is_the_pixel_clocks_over_the_raster(coopwin_bin, vtest, tmp_path):
    # Without fps, frames are 8 MHz pixel clocks apart over the raster, 16 + (H + 2) (W + 16)
    # clocks: 17.65 frames/s on vtest.avi's 768x576 (not 114, which is 256x256's), as the CLI
    # runs a folder of the same frames.
    frames = read_frames(vtest, 4)
    expected = cli_rows(coopwin_bin, tmp_path, write_frames(tmp_path / "frames", frames), TARGET)[:3]
    tracker = coopwin.Tracker(frames[0], BOX)
    got = tracked_rows(tracker, frames[1:3])
    assert [without_file(r) for r in got] == [without_file(r) for r in expected]
    period = (16 + (576 + 2) * (768 + 16)) / 8e6
    assert tracker.row.time_s == pytest.approx(2 * period, abs=1e-6)
    assert 1 / period == pytest.approx(17.65, abs=0.01)
    # And 114 frames/s is the thesis camera's 256x256.
    small = coopwin.Tracker(cv2.resize(frames[0], (256, 256)), (100, 60, 32, 32))
    small.update(cv2.resize(frames[1], (256, 256)))
    assert 1 / small.row.time_s == pytest.approx(113.97, abs=0.01)


def test_track_video_starts_and_stops_where_the_cli_does(coopwin_bin, vtest, tmp_path):
    expected = cli_rows(coopwin_bin, tmp_path, vtest, TARGET, "--start-frame", "5", "--end-frame", "25")
    rows = list(coopwin.track_video(vtest, BOX, start_frame=5, end_frame=25))
    assert rows == [coopwin.Row.parse(line) for line in expected]
    assert [r.frame for r in rows] == list(range(5, 25))


def test_track_video_jitters_the_blanking_as_the_cli_does(coopwin_bin, vtest, tmp_path):
    # PNG frames, whose times are frame periods (a video's come from its timestamps).
    folder = write_frames(tmp_path / "frames", read_frames(vtest, 10))
    expected = cli_rows(coopwin_bin, tmp_path, folder, TARGET, "--fps", "10", "--blank-jitter", "40,20000,3")
    rows = list(coopwin.track_video(folder, BOX, fps=10, blank_jitter=(40, 20000, 3)))
    assert rows == [coopwin.Row.parse(line) for line in expected]
    # Not ignored: the longer blanking stretches the frame period in time_s.
    steady = list(coopwin.track_video(folder, BOX, fps=10))
    assert rows[-1].time_s > steady[-1].time_s


@pytest.mark.parametrize("hdl", ["rust-hdl", "verilator"])
def test_track_video_runs_the_clocked_units_as_the_cli_does(coopwin_bin, vtest, tmp_path, hdl):
    # The clocked units step every pixel clock (rust-hdl's simulator, or the exported Verilog
    # built by Verilator): a 128x128 crop around the walker keeps it short. Without Verilator
    # this fails, as the EDA tests do, unless COOPWIN_ALLOW_MISSING_EDA=1 skips it visibly.
    if hdl == "verilator" and shutil.which("verilator") is None and os.environ.get("COOPWIN_ALLOW_MISSING_EDA") == "1":
        pytest.skip("verilator is not installed (COOPWIN_ALLOW_MISSING_EDA=1)")
    crop = [f[150:278, 240:368] for f in read_frames(vtest, 6)]
    folder = write_frames(tmp_path / "crop", crop)
    options = ("--target-box", "40,30,40,80", "--fps", "10", "--hdl", hdl, "--pixel-bits", "10")
    expected = cli_rows(coopwin_bin, tmp_path, folder, *options)
    rows = list(coopwin.track_video(folder, (40, 30, 40, 80), fps=10, hdl=hdl, pixel_bits=10))
    assert rows == [coopwin.Row.parse(line) for line in expected]
    assert sum(r.source == "ncc" for r in rows) >= 3
    # --pixel-bits without clocked units is refused as the CLI refuses it.
    with pytest.raises(ValueError, match="--pixel-bits sets the clocked window units' pixel width"):
        coopwin.track_video(folder, (40, 30, 40, 80), pixel_bits=10)


def test_tracker_holds_the_writes_as_the_cli_does(coopwin_bin, vtest, tmp_path):
    # --write-phase, which the Tracker's keywords leave out, still works given to its run.
    frames = read_frames(vtest, 9)
    options = [TARGET, "--fps=10", "--write-phase=40000"]
    expected = cli_rows(coopwin_bin, tmp_path, write_frames(tmp_path / "frames", frames), *options)[:8]
    run = _coopwin.FrameRun(frames[0], options)
    got = [run.first_row] + [run.push(f) for f in frames[1:8]]
    assert [without_file(r) for r in got] == [without_file(r) for r in expected]
    steady = coopwin.Tracker(frames[0], BOX, fps=10)
    plain = tracked_rows(steady, frames[1:8])
    assert plain != got, "--write-phase changed nothing"


def test_a_large_box_is_binned_as_the_cli_bins_it(coopwin_bin, vtest, tmp_path):
    # vtest's man in the black coat, 44x80: both bin the frames 2x2 unasked (the CLI's rule,
    # 22 px across binned; bin=2 gives the same rows), and neither with bin=1. Reference: the
    # CLI's rows.
    frames = read_frames(vtest, 5)
    folder = write_frames(tmp_path / "frames", frames)
    coat = (642, 240, 44, 80)
    runs = []
    for options, keywords in (((), {}), (("--bin", "1"), {"bin": 1})):
        expected = cli_rows(coopwin_bin, tmp_path, folder, "--target-box=642,240,44,80", *options)
        got = tracked_rows(coopwin.Tracker(frames[0], coat, **keywords), frames[1:])
        assert [without_file(r) for r in got] == [without_file(r) for r in expected]
        runs.append(got)
    assert runs[0] != runs[1], "binning changed nothing"
    assert tracked_rows(coopwin.Tracker(frames[0], coat, bin=2), frames[1:]) == runs[0]
