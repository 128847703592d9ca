"""What an RK 512 station reports besides the link's STATUS events (which pass through as
:class:`ptpcert.model.events.Status`): request results, what the passive side wrote or
read, the frames received and sent, and the application's wake-ups.

:func:`interface_lines` turns events into the lines an RK 512 IUT writes on stderr:
``RESULT <label> OK``, ``RESULT <label> STATUS 16#0905``, ``FETCHED <label> <hex>`` (before
the RESULT of a FETCH that succeeded) and ``STATUS 16#xxxx``.
"""

from __future__ import annotations

from dataclasses import dataclass

from ptpcert.model.events import Status, status_text


@dataclass(frozen=True, slots=True)
class RequestResult:
    """A SEND or FETCH of the active side ended: ``ok`` (DONE) or not (ERROR, ``code`` the
    STATUS). ``data`` is what a FETCH that succeeded stores: LEN bytes."""

    time: float
    label: str
    ok: bool
    code: int | None = None
    data: bytes | None = None

    def lines(self) -> list[str]:
        out = []
        if self.ok and self.data is not None:
            out.append(f"FETCHED {self.label} {self.data.hex().upper()}")
        out.append(f"RESULT {self.label} OK" if self.ok else f"RESULT {self.label} STATUS {status_text(self.code)}")
        return out


@dataclass(frozen=True, slots=True)
class Served:
    """The passive side moved data for a partner's frame: ``op`` "write" (a SEND's data
    stored) or "read" (a FETCH's data read). ``area`` is the data type letter, ``number``
    the DB/DX number (0 otherwise), ``start`` the byte offset in the area. ``final`` marks
    the last frame of the request (NDR); ``flag`` is the coordination flag (byte, bit) the
    station set to "locked" with it (AMB-08), None when it set none."""

    time: float
    op: str
    area: str
    number: int
    start: int
    data: bytes
    final: bool
    flag: tuple[int, int] | None = None


@dataclass(frozen=True, slots=True)
class FrameReceived:
    """A 3964(R) block arrived intact: one RK 512 frame (its user data)."""

    time: float
    frame: bytes


@dataclass(frozen=True, slots=True)
class FrameSent:
    """The partner acknowledged one of our frames. ``reason`` is the manual reference of
    the table row that produced it."""

    time: float
    frame: bytes
    reason: str = ""


@dataclass(frozen=True, slots=True)
class FrameNotSent:
    """The link gave up on one of our frames; ``code`` is its final STATUS."""

    time: float
    frame: bytes
    code: int


@dataclass(frozen=True, slots=True)
class Ready:
    """The station is up (start-up complete): the application may issue requests."""

    time: float


@dataclass(frozen=True, slots=True)
class Wakeup:
    """An application timer set with ``wake_at`` ran out; ``tag`` is the caller's."""

    time: float
    tag: object = None


Rk512Event = RequestResult | Served | FrameReceived | FrameSent | FrameNotSent | Ready | Wakeup


def interface_lines(event) -> list[str]:
    """The stderr lines of an RK 512 IUT for one event (none for most events)."""
    if isinstance(event, Status):
        return [f"STATUS {status_text(event.code)}"]
    if isinstance(event, RequestResult):
        return event.lines()
    return []
