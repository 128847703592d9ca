"""``ptpcert iut``: the bundled reference implementation.

The reference model as a real-time station on stdin/stdout (or on a serial port given by
``--port``), with the echo application: every block it receives it sends back as a new
block. It paces what it sends at the character time of the baud rate and character format
(``--baud 0``: no pacing), reads PARMRK marking of line conditions with ``--parmrk``, and
reports each STATUS event on stderr as one line ``STATUS 16#XXXX``.
"""

from __future__ import annotations

import os
import select
import sys
import time
from itertools import groupby

from .model.events import Delivered, SendDone, SendFailed, Status
from .driver import Endpoint, drive_station
from .model.parmrk import ParmrkDecoder


class StdioEndpoint(Endpoint):
    """stdin/stdout as the line."""

    def __init__(self, fd_in: int = 0, fd_out: int = 1, parmrk: bool = False):
        self.fd_in, self.fd_out = fd_in, fd_out
        self.decoder = ParmrkDecoder(parmrk)

    def now(self) -> float:
        return time.monotonic()

    def poll(self, deadline: float) -> list[tuple[float, str, int]]:
        timeout = None if deadline == float("inf") else max(0.0, deadline - time.monotonic())
        r, _, _ = select.select([self.fd_in], [], [], timeout)
        if not r:
            return []
        data = os.read(self.fd_in, 65536)
        if not data:
            raise EOFError
        return self.decoder.feed(time.monotonic(), data)

    def write(self, data: bytes) -> float:
        t = time.monotonic()
        os.write(self.fd_out, data)
        return t


class SerialEndpoint(Endpoint):
    """A serial line as the line (``--port``: a device path or a pyserial URL, opened as the
    harness opens it). On a real tty device with ``--parmrk`` the kernel marks breaks and
    parity errors (termios PARMRK); on a pseudo-terminal the marks come in-band from the
    other side."""

    def __init__(self, url: str, params, parmrk: bool):  # params: the line's settings
        from .transport.serialport import SerialLine

        self.line = SerialLine(url, params)   # TransportError: not a serial URL we support
        self.line.open()                      # TransportError: cannot be opened
        fd = self.line.fd
        if parmrk and fd is not None and os.isatty(fd) and not self.line.pty:
            import termios
            attrs = termios.tcgetattr(fd)
            attrs[0] |= termios.PARMRK | termios.INPCK
            attrs[0] &= ~(termios.IGNPAR | termios.IGNBRK | termios.BRKINT | termios.ISTRIP)
            termios.tcsetattr(fd, termios.TCSANOW, attrs)
        self.decoder = ParmrkDecoder(parmrk)

    def now(self) -> float:
        return time.monotonic()

    def poll(self, deadline: float) -> list[tuple[float, str, int]]:
        from .transport.base import TransportError
        try:
            items = self.line.read(deadline)
        except TransportError:
            raise EOFError from None   # the line has gone (a device unplugged, a server closed)
        out: list[tuple[float, str, int]] = []
        for t, group in groupby(items, key=lambda item: item[0]):
            out += self.decoder.feed(t, bytes(b for _, b in group))
        return out

    def write(self, data: bytes) -> float:
        return self.line.write(data)


def run_iut(host, line, *, parmrk: bool, port: str | None = None, verbose: bool = False) -> int:
    """Drive ``host`` (a model station with its application) in real time on stdin/stdout or
    ``port``, with the line settings ``line``. Every STATUS event goes to stderr as
    ``STATUS 16#XXXX``; an application may report more lines (``host.report_line(event)``)."""
    station = host.station
    if port:
        from .transport.base import TransportError
        try:
            ep: Endpoint = SerialEndpoint(port, line, parmrk)
        except TransportError as exc:
            print(f"ptpcert iut: {exc}", file=sys.stderr)
            return 2
    else:
        ep = StdioEndpoint(parmrk=parmrk)
    err = sys.stderr
    report = getattr(host, "report_line", None)

    def on_event(e) -> None:
        if isinstance(e, Status):
            err.write(f"STATUS 16#{e.code:04X}\n")
        line_ = report(e) if report is not None else None
        if line_:
            err.write(line_ + "\n")
        elif verbose and isinstance(e, (Delivered, SendDone, SendFailed)):
            err.write(f"# {type(e).__name__} {e.payload.hex(' ')}\n")
        err.flush()

    station.power_on(ep.now())
    try:
        drive_station(host, ep, on_event=on_event)
    except (EOFError, BrokenPipeError, KeyboardInterrupt):
        pass
    err.flush()
    if not port:
        os._exit(0)  # the line has ended: leave at once, without interpreter teardown
    return 0
