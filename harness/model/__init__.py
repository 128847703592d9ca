"""The reference model: pure codec, parameters, readings of the open points, the
transition table and the sans-IO station. Standard library only; no clocks, no I/O."""

from . import codec, events, table
from .codec import DLE, ETX, MAX_BLOCK, NAK, STX, FrameError, bcc, body, frame, parse, parse_body, stuff, unstuff
from .events import Delivered, Event, SendDone, SendFailed, Status, status_text
from .params import T_BLOCK, T_NAKTIM, ParameterError, Params3964
from .readings import READINGS, Readings
from .station import Job, ModelError, Station3964
from .app import Host

__all__ = [
    "codec", "events", "table", "DLE", "ETX", "MAX_BLOCK", "NAK", "STX", "FrameError",
    "bcc", "body", "frame", "parse", "parse_body", "stuff", "unstuff", "Delivered", "Event",
    "SendDone", "SendFailed", "Status", "status_text", "T_BLOCK", "T_NAKTIM",
    "ParameterError", "Params3964", "READINGS", "Readings", "Job", "ModelError", "Station3964", "Host",
]
