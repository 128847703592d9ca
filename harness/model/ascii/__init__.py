"""Reference model of the CP 341 ASCII driver (§2.2.4): parameters, readings of the open
points, the transition tables, the sans-IO station and its application. Standard library
only; no clocks, no I/O."""

from . import codec, events, table
from .app import APPS, AsciiHost
from .codec import Piece, char_name, describe, send_bytes, split_frames
from .events import FrameDiscarded, FrameStored
from .params import AsciiParams
from .readings import READINGS, AsciiReadings
from .station import AsciiJob, AsciiStation, SignalRecord, Timer, TxRecord, Why

__all__ = [
    "codec", "events", "table", "APPS", "AsciiHost", "Piece", "char_name", "describe",
    "send_bytes", "split_frames", "FrameDiscarded", "FrameStored", "AsciiParams", "READINGS",
    "AsciiReadings", "AsciiJob", "AsciiStation", "SignalRecord", "Timer", "TxRecord", "Why",
]
