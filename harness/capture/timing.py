"""How a capture's times were taken: :class:`Timing` (the transport, the character time on
the line, and the timing *resolution*: how much earlier than its timestamp a character may
have been complete), its one-line text form that the hex log's header and the pcap start
record carry, and :func:`run_timing`, what a ``ptpcert run`` against an ``--iut`` URL gives.
``ptpcert analyze`` takes the resolution from here unless ``--resolution-ms`` says otherwise.
Specified in ``docs/capture-formats.md`` ("Times").
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import Any

from ptpcert.capture.model import CaptureError

#: What took the times. ``line``: a recorder that timestamps each character on the line
#: itself (exact); ``sim``: virtual time, exact; ``pipe``: a process's pipe or pseudo-
#: terminal (exec:, pty:): the write and read times of a pipe, no baud rate, a station
#: writes at its own pace; ``port``: the harness's reads and writes of a serial port (or a
#: port server); ``monitor``: receive-only ports read as data arrives; ``unknown``.
TRANSPORTS = ("line", "sim", "pipe", "port", "monitor", "unknown")

#: the harness's own scheduling when it stamps a read or a write (a loaded machine)
HOST_SLACK = 0.002
#: character times a pipe's stamps may be off the line's: a station writes a character
#: before the one it answers would be complete on a line, and the harness reads a burst
#: whose first character was complete earlier (three: measured with a station that writes
#: whole blocks at once and one that writes a character per millisecond, 9600 bit/s)
PIPE_CHARS = 3


def _seconds(v: Any, what: str, optional: bool = False) -> float | None:
    if v is None and optional:
        return None
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v < 0:
        raise CaptureError(f"timing: {what} {v!r} is not a number of seconds >= 0")
    return round(float(v), 6)


@dataclass(frozen=True)
class Timing:
    """How the times of a capture were taken."""

    transport: str = "unknown"
    resolution: float = 0.0              # seconds a character may have been complete before its stamp
    char_time: float | None = None       # seconds per character on the line (None: no baud rate known)

    def __post_init__(self) -> None:
        if self.transport not in TRANSPORTS:
            raise CaptureError(f"timing: transport {self.transport!r} is not one of {', '.join(TRANSPORTS)}")
        object.__setattr__(self, "resolution", _seconds(self.resolution, "resolution"))
        object.__setattr__(self, "char_time", _seconds(self.char_time, "character time", True))

    def text(self) -> str:
        """The one-line form: ``transport=pipe resolution=0.005438 char_time=0.001146``."""
        out = f"transport={self.transport} resolution={self.resolution:.6f}"
        return out + ("" if self.char_time is None else f" char_time={self.char_time:.6f}")

    @classmethod
    def parse(cls, text: str) -> "Timing":
        """A timing from its one-line form (unknown keys are refused, so a typo is not lost)."""
        values: dict[str, Any] = {}
        for word in text.split():
            key, sep, value = word.partition("=")
            if not sep or key not in ("transport", "resolution", "char_time"):
                raise CaptureError(f"timing: {word!r} is not transport=..., resolution=SECONDS or char_time=SECONDS")
            if key == "transport":
                values[key] = value
            else:
                try:
                    values[key] = float(value)
                except ValueError:
                    raise CaptureError(f"timing: {key} {value!r} is not a number of seconds") from None
        return cls(**values)

    def to_dict(self) -> dict[str, Any]:
        return {"transport": self.transport, "resolution": self.resolution, "char_time": self.char_time}

    @classmethod
    def from_dict(cls, d: Any) -> "Timing":
        if not isinstance(d, dict):
            raise CaptureError(f"timing must be an object, not {d!r}")
        unknown = sorted(set(d) - {"transport", "resolution", "char_time"})
        if unknown:
            raise CaptureError(f"timing: unknown field {unknown[0]!r}")
        return cls(d.get("transport", "unknown"), d.get("resolution", 0.0), d.get("char_time"))

    def describe(self) -> str:
        """For people: what took the times and how far they may be off."""
        how = {"line": "stamped on the line", "sim": "virtual time", "pipe": "a pipe's write and read times",
               "port": "the harness's reads and writes of a serial port",
               "monitor": "receive-only ports, stamped when a read returned", "unknown": "taken somehow"}
        char = "" if self.char_time is None else f", character time {1000 * self.char_time:.3f} ms"
        return f"times {how[self.transport]}: resolution {1000 * self.resolution:.3f} ms{char}"


_SCHEME = re.compile(r"^([a-z][a-z0-9+.-]*):", re.IGNORECASE)


def run_timing(url: str, char_time: float | None) -> Timing:
    """How the harness's transcript times of a run against ``url`` (its ``--iut``) were
    taken: ``sim:`` exact; ``exec:``/``pty:`` a pipe (:data:`PIPE_CHARS` character times
    and the host's slack); anything else a serial port or port server, read as data comes
    (one character time and the host's slack)."""
    m = _SCHEME.match(url.strip())
    scheme = m.group(1).lower() if m else ""
    char = char_time or 0.0
    if scheme == "sim":
        return Timing("sim", 0.0, char_time)
    if scheme in ("exec", "pty"):
        return Timing("pipe", PIPE_CHARS * char + HOST_SLACK, char_time)
    return Timing("port", char + HOST_SLACK, char_time)
