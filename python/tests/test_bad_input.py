"""Bad input raises a clear Python exception (the CLI's message where the CLI has one), never
a panic; each expected message is the one the CLI prints, or names what to fix."""
import subprocess

import numpy as np
import pytest

import coopwin

from conftest import FRAME


def test_wrong_dtype_is_a_type_error():
    with pytest.raises(TypeError, match="uint8"):
        coopwin.Tracker(FRAME.astype(np.float32), (10, 10, 20, 20))


def test_not_an_array_is_a_type_error():
    with pytest.raises(TypeError, match="NumPy array"):
        coopwin.Tracker(FRAME.tolist(), (10, 10, 20, 20))


@pytest.mark.parametrize("shape", [(120,), (120, 160, 2), (120, 160, 3, 1)])
def test_wrong_shape_is_a_value_error(shape):
    with pytest.raises(ValueError, match="H x W"):
        coopwin.Tracker(np.zeros(shape, np.uint8), (10, 10, 20, 20))


def test_too_small_a_frame_is_refused_as_the_cli_refuses_it():
    with pytest.raises(ValueError, match="frames must be 64x64 to 4096x4096, this one is 160x10"):
        coopwin.Tracker(FRAME[:10], (1, 1, 5, 5))


def test_box_outside_the_frame_names_the_box():
    # The CLI's message for `--target-box 740,500,60,60` on these frames.
    with pytest.raises(ValueError, match=r"--target-box 740,500,60,60: its centre \(769.5, 529.5\) is outside the 160x120 frames"):
        coopwin.Tracker(FRAME, (740, 500, 60, 60))


def test_box_of_the_wrong_kind():
    with pytest.raises(TypeError, match="box"):
        coopwin.Tracker(FRAME, "10,10,20,20")
    with pytest.raises(TypeError, match="whole pixels"):
        coopwin.Tracker(FRAME, (10.5, 10, 20, 20))
    with pytest.raises(ValueError, match="4 values"):
        coopwin.Tracker(FRAME, (10, 10, 20))
    with pytest.raises(ValueError, match="negative"):
        coopwin.Tracker(FRAME, (-1, 10, 20, 20))


def test_bad_option_value_gets_the_cli_message():
    with pytest.raises(ValueError, match="--fps"):
        coopwin.Tracker(FRAME, (10, 10, 20, 20), fps=-3)
    with pytest.raises(ValueError, match="--strategy"):
        coopwin.Tracker(FRAME, (10, 10, 20, 20), strategy="nonsense")


def test_flat_target_is_refused_at_the_start():
    with pytest.raises(ValueError, match="flat"):
        coopwin.Tracker(np.zeros((120, 160), np.uint8), (10, 10, 20, 20))


def test_frame_of_another_size_and_the_tracker_goes_on():
    tracker = coopwin.Tracker(FRAME, (60, 40, 20, 20))
    with pytest.raises(ValueError, match="160x120"):
        tracker.update(np.zeros((64, 64), np.uint8))
    ok, box = tracker.update(FRAME)  # nothing lost: the next good frame is tracked
    assert tracker.row.frame == 1


def test_update_before_init():
    with pytest.raises(RuntimeError, match="init"):
        coopwin.TrackerCOOP_create().update(FRAME)


@pytest.mark.parametrize("path", ["/no/such.avi", "/no/such/folder"])
def test_missing_input_is_file_not_found_with_the_cli_message(coopwin_bin, path):
    with pytest.raises(FileNotFoundError) as missing:
        coopwin.track_video(path, (1, 1, 5, 5))
    cli = subprocess.run([str(coopwin_bin), "track", "--frames", path], capture_output=True, text=True)
    assert cli.returncode == 1
    assert str(missing.value) == f"{path}: no such file or folder"
    assert str(missing.value) in cli.stderr


def test_bad_sensor_for_verilog():
    with pytest.raises(ValueError, match="16 to 4096"):
        coopwin.verilog(5, 5, 8)
