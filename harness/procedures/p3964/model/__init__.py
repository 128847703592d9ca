"""The 3964/3964R reference model: pure codec, parameters, readings of the open points, the
transition table, the sans-IO station and its application. Standard library only; no clocks,
no I/O."""

from ptpcert.model.app import Host
from ptpcert.model.errors import ModelError, ParameterError
from ptpcert.model.events import Delivered, Event, SendDone, SendFailed, Status, status_text

from . import codec, table
from .codec import DLE, ETX, MAX_BLOCK, NAK, STX, FrameError, bcc, body, frame, parse, parse_body, stuff, unstuff
from .params import T_BLOCK, T_NAKTIM, Params3964
from .readings import READINGS, Readings
from .station import Job, Station3964

__all__ = [
    "codec", "table", "DLE", "ETX", "MAX_BLOCK", "NAK", "STX", "FrameError",
    "bcc", "body", "frame", "parse", "parse_body", "stuff", "unstuff", "Delivered", "Event",
    "SendDone", "SendFailed", "Status", "status_text", "T_BLOCK", "T_NAKTIM",
    "ParameterError", "Params3964", "READINGS", "Readings", "Job", "ModelError", "Station3964", "Host",
]
