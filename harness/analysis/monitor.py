"""Reading a live link from two receive-only ports (``ptpcert monitor``).

Each port hears one station's transmit line (e.g. the two receive wires of a Y cable, or a
pseudo-terminal a tap writes to). Nothing is ever written to a port. Every read is stamped
with the time it returned: a UART hands a character over some time after its stop bit (its
receive FIFO timeout, then the driver's latency), so the timestamps lag the line by up to
the *timing resolution* the analysis is told (:func:`ptpcert.cli.analyze.resolution_for`).
Line conditions come as termios PARMRK marks when ``parmrk`` is set: a real UART is put in
that mode; on a pseudo-terminal the writer marks them in-band.
"""

from __future__ import annotations

import os
import select
import time
from typing import Any, Callable

from ptpcert import capture as C
from ptpcert import priority
from ptpcert.model.parmrk import ParmrkDecoder


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
        self.char = line.char_time
        self.stalls = 0
        try:
            self.ports["a"] = Port(url_a, line, parmrk)
            self.ports["b"] = Port(url_b, line, parmrk)
        except MonitorError:
            self.close()
            raise

    def run(self, analysis, writer, *, stop: Callable[[], bool], duration: float | None = None,
            tick: float = 0.02, resolution: float = 0.01) -> float:
        """Read until ``stop()`` or ``duration`` (or both ports have ended): every read becomes
        chunks for ``analysis`` (a :class:`~ptpcert.analysis.LineAnalysis`) and ``writer``
        (a :class:`~ptpcert.capture.PcapWriter` or :class:`~ptpcert.capture.HexLogWriter`).
        A thread of its own reads the ports and stamps what it reads at once; the analysis
        runs beside it. When that thread came to a port so late that it found more characters
        waiting than the timing resolution accounts for, when they came (and in which order
        with the other station's) is lost: a ``lost`` chunk on both seats says so (the
        analysis does not blame a station for what it then cannot tell). Returns how long
        the line was watched (seconds)."""
        import queue
        import sys
        import threading

        t0 = time.monotonic()
        q: queue.Queue = queue.Queue()
        done = threading.Event()
        self.stalls = 0
        old = sys.getswitchinterval()
        sys.setswitchinterval(0.001)     # the reader gets its turn within a millisecond

        def reader() -> None:
            with priority.thread():     # the real-time class where the monitor was granted it
                read_all()

        def read_all() -> None:
            fds = {p.fd: s for s, p in self.ports.items() if p.fd is not None}
            polled = [s for s, p in self.ports.items() if p.fd is None]
            try:
                while not done.is_set():
                    live = [fd for fd, s in fds.items() if not self.ports[s].ended]
                    if not live and not polled:
                        break
                    if live:
                        r, _, _ = select.select(live, [], [], tick)
                    else:
                        r = []
                        time.sleep(tick)
                    ready = [fds[fd] for fd in r] + polled
                    got = [(s, self.ports[s].read()) for s in ready]
                    now = time.monotonic()
                    t = round(now - t0, 6)
                    if any(len(d) * self.char > resolution for _, d in got):
                        q.put((t, None, b""))       # came late to a backlog
                    for s, data in got:
                        if data:
                            q.put((t, s, data))
                    q.put((t, "round", b""))        # everything read up to t is in the queue
            except MonitorError as exc:
                q.put((time.monotonic() - t0, "error", str(exc).encode()))
            finally:
                q.put(None)

        th = threading.Thread(target=reader, name="ptpcert-monitor-reader", daemon=True)
        th.start()
        ended = False
        seen = 0.0       # the reader's latest round: what was on the line up to then is in
        try:
            while True:
                now = time.monotonic() - t0
                if stop() or (duration is not None and now >= duration) or ended:
                    return now
                try:
                    item = q.get(timeout=tick)
                except queue.Empty:
                    item = ()
                while item is not None and item != ():
                    t, s, data = item
                    if s == "error":
                        raise MonitorError(data.decode())
                    if s == "round":
                        seen = t
                    elif s is None:
                        self.stalls += 1
                        for seat in ("a", "b"):
                            ch = C.Chunk(t, seat, condition=C.Cond.LOST)
                            writer.chunk(ch)
                            analysis.feed(ch)
                    else:
                        for ch in chunks_of(s, t, self.ports[s].decoder.feed(t, data)):
                            writer.chunk(ch)
                            analysis.feed(ch)
                    if stop():
                        break       # Ctrl-C: what the reader has queued is not waited for
                    try:
                        item = q.get_nowait()
                    except queue.Empty:
                        item = ()
                if item is None:
                    ended = True
                analysis.advance(seen)
        finally:
            done.set()
            th.join(2)
            sys.setswitchinterval(old)

    def close(self) -> None:
        for p in self.ports.values():
            p.close()
