"""Type stubs of coopwin's Rust extension (the CLI's options in, its CSV rows out)."""
from typing import Iterator, List, Tuple

import numpy as np
import numpy.typing as npt

#: ``coopwin track``'s CSV header.
TRACK_HEADER: str
#: The hash of the sources the extension was built from (python/source_hash.rs).
SOURCE_HASH: str

class FrameRun:
    """A run fed one frame at a time (behind :class:`coopwin.Tracker`)."""

    #: The first frame's CSV row.
    first_row: str

    def __init__(self, frame: npt.NDArray[np.uint8], options: List[str]) -> None:
        """A run from ``frame`` with ``coopwin track``'s options (``["--target-box=10,20,30,40"]``;
        without ``--fps``, the 8 MHz pixel clock's rate over the frame's raster). Options of a
        whole source's run or that write files (``--start-frame``, ``--end-frame``,
        ``--blank-jitter``, ``--hdl rust-hdl``/``verilator``, ``--pixel-bits``,
        ``--allow-damaged``, ``--out``, ``--overlay``, ``--vcd``, ``--list``) raise ValueError."""
    def push(self, frame: npt.NDArray[np.uint8]) -> str:
        """Tracks the next frame and returns its CSV row."""

class VideoRows(Iterator[str]):
    """``coopwin track --frames path``'s CSV rows, streamed (behind :func:`coopwin.track_video`)."""

    def __init__(self, path: str, options: List[str]) -> None:
        """Opens ``path`` (FileNotFoundError when missing) and starts the run; ``--out``,
        ``--overlay``, ``--vcd`` and ``--list`` raise ValueError (nothing is written)."""
    def __iter__(self) -> "VideoRows": ...
    def __next__(self) -> str: ...

def verilog(options: List[str]) -> List[Tuple[str, str]]:
    """``coopwin verilog``'s files for its options: (file name, Verilog text) pairs."""
