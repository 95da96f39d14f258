"""`python -m coopwin.trax` through a real TraX client (vot-trax's `trax.client.Client`, started
as the VOT toolkit starts a tracker: a process on pipes, its stderr merged into its stdout).
The reference for every reply is `coopwin.Tracker` fed the same frames in this process: its
row's box and confidence where it is ok, the empty rectangle and 0 where it is not."""
import os
import socket
import subprocess
import sys

import cv2
import numpy as np
import pytest
from trax import FileImage, MemoryImage, Rectangle, TraxException
from trax.client import Client

import coopwin

from conftest import BOX, read_frames, write_frames

FRAMES = 30


class Session:
    """A TraX client on a `python -m coopwin.trax ARGS` process, as the VOT toolkit runs one."""

    def __init__(self, cwd, *args):
        self.process = subprocess.Popen(
            [sys.executable, "-m", "coopwin.trax", *args],
            cwd=cwd,
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            bufsize=0,
        )
        # The server's output that is not TraX messages (vot-trax 4.0.2's client needs a
        # logger: without one it fails to start).
        self.log = []
        self.client = Client(stream=(self.process.stdin.fileno(), self.process.stdout.fileno()), log=self.log.append)

    def close(self):
        """Quits if the session is alive, and returns the server's exit status."""
        try:
            self.client.quit()
        except TraxException:
            pass
        try:
            return self.process.wait(timeout=30)
        finally:
            self.process.stdin.close()
            self.process.stdout.close()


@pytest.fixture
def session(tmp_path):
    sessions = []

    def start(*args):
        sessions.append(Session(tmp_path, *args))
        return sessions[-1]

    yield start
    for s in sessions:
        if s.process.poll() is None:
            s.process.kill()
            s.close()


def reply(objects):
    """The one object's (x, y, w, h) and confidence of a TraX reply."""
    assert len(objects) == 1
    region, properties = objects[0]
    assert region.type == Rectangle.RECTANGLE
    return tuple(region.bounds()), float(properties["confidence"])


def over_trax(v):
    """A rectangle's value as it reaches the client: libtrax holds 32-bit floats and writes
    them with 4 decimals ("%.4f") on the wire. (Properties travel as Python's own text.)"""
    return float(np.float32(f"{np.float32(v):.4f}"))


def expected(tracker):
    """Reference: the Tracker's row: its box and confidence where ok, else nothing (0)."""
    r = tracker.row
    if not r.ok:
        return (0.0, 0.0, 0.0, 0.0), 0.0
    return tuple(over_trax(v) for v in (r.box_x, r.box_y, r.box_w, r.box_h)), r.confidence


def replies(client, images):
    """The replies to an initialisation on BOX in `images[0]`, then to each later image."""
    objects, _ = client.initialize({"color": images[0]}, [(Rectangle.create(*BOX), {})], {})
    got = [reply(objects)]
    for image in images[1:]:
        objects, _ = client.frame({"color": image}, {}, [])
        got.append(reply(objects))
    return got


def tracker_replies(frames, **options):
    tracker = coopwin.Tracker(frames[0], BOX, **options)
    want = [expected(tracker)]
    for frame in frames[1:]:
        tracker.update(frame)
        want.append(expected(tracker))
    return want


def test_path_images_give_the_trackers_regions(vtest, tmp_path, session):
    # The VOT toolkit's way: image files by path, the options on the command line.
    frames = read_frames(vtest, FRAMES)
    folder = write_frames(tmp_path / "frames", frames)
    paths = sorted(folder.iterdir())
    s = session("--fps", "10")
    assert s.client.tracker_name == "coopwin"
    got = replies(s.client, [FileImage.create(str(p)) for p in paths])
    want = tracker_replies(frames, fps=10)
    assert got == want
    assert s.close() == 0
    # Both kinds of reply were compared: the tracker vouches for the walker's first frames,
    # then loses it and finds it again unconfirmed (a box and a confidence, not ok).
    vouched = sum(w != ((0.0, 0.0, 0.0, 0.0), 0.0) for w in want)
    assert 0 < vouched < FRAMES


def test_memory_images_give_the_trackers_regions(vtest, session):
    # TraX's memory images are RGB: the server turns them back to OpenCV's BGR.
    frames = read_frames(vtest, 12)
    s = session()
    got = replies(s.client, [MemoryImage.create(cv2.cvtColor(f, cv2.COLOR_BGR2RGB)) for f in frames])
    assert got == tracker_replies(frames)
    assert s.close() == 0


def test_socket_mode_gives_the_trackers_regions(vtest, tmp_path):
    # The VOT toolkit's other way: it listens on a local port, names it in TRAX_SOCKET, and
    # the tracker (libtrax's server) connects there instead of speaking on its pipes.
    frames = read_frames(vtest, 12)
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as listening:
        listening.bind(("127.0.0.1", 0))
        listening.listen(1)
        env = dict(os.environ, TRAX_SOCKET=str(listening.getsockname()[1]))
        process = subprocess.Popen([sys.executable, "-m", "coopwin.trax"], cwd=tmp_path, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        try:
            client = Client(stream=listening.fileno(), timeout=30, log=lambda _: None)
            assert client.tracker_name == "coopwin"
            got = replies(client, [MemoryImage.create(cv2.cvtColor(f, cv2.COLOR_BGR2RGB)) for f in frames])
            client.quit()
            assert process.wait(timeout=30) == 0
        finally:
            if process.poll() is None:
                process.kill()
            output, errors = process.communicate()
    assert got == tracker_replies(frames)
    # Nothing went to standard output: the session was the socket's.
    assert output == b"", errors.decode(errors="replace")


def test_fractional_initial_region_is_rounded_to_whole_pixels(vtest, session):
    # VOT's ground truth has fractional edges: (279.6, 180.4, 40.2, 79.7) has its edges
    # nearest 280, 180, 320, 260, BOX's.
    frames = read_frames(vtest, 3)
    s = session()
    objects, _ = s.client.initialize({"color": MemoryImage.create(frames[0][:, :, ::-1])}, [(Rectangle.create(279.6, 180.4, 40.2, 79.7), {})], {})
    got = [reply(objects)] + [reply(s.client.frame({"color": MemoryImage.create(f[:, :, ::-1])}, {}, [])[0]) for f in frames[1:]]
    assert got == tracker_replies(frames)
    assert s.close() == 0


def test_box_outside_the_frame_ends_the_session_with_the_trackers_message(vtest, session):
    frame = read_frames(vtest, 1)[0]
    s = session()
    with pytest.raises(TraxException, match=r"ValueError: --target-box 900,700,20,20: its centre .* is outside the 768x576 frames"):
        s.client.initialize({"color": MemoryImage.create(frame)}, [(Rectangle.create(900, 700, 20, 20), {})], {})
    assert s.close() == 1


def test_missing_image_file_ends_the_session_naming_it(tmp_path, session):
    s = session()
    missing = tmp_path / "no-such-frame.jpg"
    with pytest.raises(TraxException, match=f"FileNotFoundError: no such image file.*{missing.name}"):
        s.client.initialize({"color": FileImage.create(str(missing))}, [(Rectangle.create(*BOX), {})], {})
    assert s.close() == 1


def test_16_bit_images_are_refused_with_the_trackers_message(session):
    s = session()
    with pytest.raises(TraxException, match="TypeError: frame must be a uint8 array"):
        s.client.initialize({"color": MemoryImage.create(np.zeros((120, 160), np.uint16))}, [(Rectangle.create(*BOX), {})], {})
    assert s.close() == 1


def test_a_bad_option_ends_the_session_with_the_clis_message(vtest, session):
    # The option is checked by the CLI's parser when the tracker starts.
    frame = read_frames(vtest, 1)[0]
    s = session("--fps", "fast")
    with pytest.raises(TraxException, match="invalid value 'fast' for '--fps"):
        s.client.initialize({"color": MemoryImage.create(frame)}, [(Rectangle.create(*BOX), {})], {})
    assert s.close() == 1


def test_an_unknown_option_is_refused_before_serving(tmp_path):
    out = subprocess.run([sys.executable, "-m", "coopwin.trax", "--speed", "3"], cwd=tmp_path, capture_output=True, text=True, timeout=30)
    assert out.returncode == 2
    assert "unrecognized arguments: --speed 3" in out.stderr
