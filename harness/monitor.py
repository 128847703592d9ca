"""Reading a live link from two receive-only ports (``ptpcert monitor``).

Each port hears one station's transmit line (e.g. the two receive wires of a Y cable, or a
pseudo-terminal a tap writes to). Nothing is ever written to a port. Every read is stamped
with the time it returned: a UART hands a character over some time after its stop bit (its
receive FIFO timeout, then the driver's latency), so the timestamps lag the line by up to
the *timing resolution* the analysis is told (:func:`ptpcert.cli_analyze.resolution_for`).
Line conditions come as termios PARMRK marks when ``parmrk`` is set: a real UART is put in
that mode; on a pseudo-terminal the writer marks them in-band.
"""

from __future__ import annotations

import os
import select
import time
from typing import Any, Callable

from . import capture as C
from .iut import ParmrkDecoder


class MonitorError(RuntimeError):
    """A port cannot be opened or read."""


class Port:
    """One receive-only port."""

    def __init__(self, url: str, line: Any, parmrk: bool):
        import serial

        self.url = url
        parity = {"none": serial.PARITY_NONE, "odd": serial.PARITY_ODD, "even": serial.PARITY_EVEN}[line.parity]
        try:
            self.port = serial.serial_for_url(url, baudrate=line.baud_rate or 9600, bytesize=line.data_bits,
                                              parity=parity, stopbits=line.stop_bits, timeout=0)
        except (serial.SerialException, ValueError, OSError) as exc:
            raise MonitorError(f"cannot open {url}: {exc}") from None
        try:
            self.fd = self.port.fileno()
        except Exception:
            self.fd = None
        if parmrk and self.fd is not None and os.isatty(self.fd) and not _is_pty(self.fd):
            import termios
            attrs = termios.tcgetattr(self.fd)
            attrs[0] |= termios.PARMRK | termios.INPCK
            attrs[0] &= ~(termios.IGNPAR | termios.IGNBRK | termios.BRKINT | termios.ISTRIP)
            termios.tcsetattr(self.fd, termios.TCSANOW, attrs)
        self.decoder = ParmrkDecoder(parmrk)
        self.ended = False

    def read(self) -> bytes:
        try:
            data = self.port.read(max(1, self.port.in_waiting))
        except OSError as exc:
            if exc.errno == 5:     # EIO: the other end of a pseudo-terminal was closed
                self.ended = True
                return b""
            raise MonitorError(f"{self.url}: read failed: {exc}") from None
        except Exception as exc:
            raise MonitorError(f"{self.url}: read failed: {exc}") from None
        return data

    def close(self) -> None:
        try:
            self.port.close()
        except Exception:
            pass


def _is_pty(fd: int) -> bool:
    try:
        return os.ttyname(fd).startswith("/dev/pts/")
    except OSError:
        return False


def chunks_of(seat: str, t: float, events: list[tuple[float, str, int]]) -> list[C.Chunk]:
    """Decoded line events of one read as chunks: runs of bytes, BREAKs and characters with
    an error."""
    out: list[C.Chunk] = []
    data = bytearray()
    for _, kind, value in events:
        if kind == "byte":
            data.append(value)
            continue
        if data:
            out.append(C.Chunk(t, seat, bytes(data)))
            data = bytearray()
        if kind == "break":
            out.append(C.Chunk(t, seat, condition=C.Cond.BREAK))
        else:
            out.append(C.Chunk(t, seat, bytes([value]), C.Cond.PARITY))
    if data:
        out.append(C.Chunk(t, seat, bytes(data)))
    return out


class Monitor:
    """Two receive-only ports, read in one loop."""

    def __init__(self, url_a: str, url_b: str, line: Any, parmrk: bool = False):
        self.ports = {}
        try:
            self.ports["a"] = Port(url_a, line, parmrk)
            self.ports["b"] = Port(url_b, line, parmrk)
        except MonitorError:
            self.close()
            raise

    def run(self, analysis, writer, *, stop: Callable[[], bool], duration: float | None = None,
            tick: float = 0.02) -> float:
        """Read until ``stop()`` or ``duration`` (or both ports have ended): every read becomes
        chunks for ``analysis`` (a :class:`~ptpcert.analyze.LineAnalysis`) and ``writer``
        (a :class:`~ptpcert.capture.PcapWriter` or :class:`~ptpcert.capture.HexLogWriter`).
        Returns how long the line was watched (seconds)."""
        t0 = time.monotonic()
        fds = {p.fd: s for s, p in self.ports.items() if p.fd is not None}
        polled = [s for s, p in self.ports.items() if p.fd is None]
        while True:
            now = time.monotonic() - t0
            if stop() or (duration is not None and now >= duration):
                return now
            if all(p.ended for p in self.ports.values()):
                return now
            ready = []
            live = [fd for fd, s in fds.items() if not self.ports[s].ended]
            try:
                if live:
                    r, _, _ = select.select(live, [], [], tick)
                    ready = [fds[fd] for fd in r]
                else:
                    time.sleep(tick)
            except InterruptedError:
                continue
            for s in ready + polled:
                data = self.ports[s].read()
                if not data:
                    continue
                t = round(time.monotonic() - t0, 6)
                for ch in chunks_of(s, t, self.ports[s].decoder.feed(t, data)):
                    writer.chunk(ch)
                    analysis.feed(ch)
            analysis.advance(time.monotonic() - t0)

    def close(self) -> None:
        for p in self.ports.values():
            p.close()
