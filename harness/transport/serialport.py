"""A serial line through pyserial: a device path (``/dev/ttyUSB0``), ``rfc2217://host:port``
(a network serial server: ser2net, Moxa, Digi), ``socket://host:port`` (a raw TCP serial
server) or ``loop://`` (self-tests), with the profile's baud rate and character frame.

The IUT behind a serial line is not started by the harness: it is persistent across cases
(no start-up NAK to wait for; cases that need to see the start-up are unsupported).

Each kind of URL has its limits, declared in :data:`SERIAL_SCHEMES` and enforced with a clean
:class:`TransportError`:

* a device: BREAK through the UART (held for the asked duration, after the characters
  before it are out); a character with a parity error by switching the parity for that
  one character. A pseudo-terminal carries neither, so a pty given as the device has no
  line conditions.
* ``rfc2217://``: BREAK as the RFC 2217 SET-CONTROL commands BREAK-ON / BREAK-OFF, sent
  in the data stream without waiting for the server's acknowledgement (pyserial waits
  >= 50 ms for each, which would void every timed case). No character errors: switching
  the parity remotely cannot be timed against the characters still in the server's UART.
  pyserial's rfc2217 has no write timeout (its socket has one).
* ``socket://``: bytes only; a raw TCP server drops BREAK.
* ``loop://``: bytes only.

``rfc2217://`` and ``socket://`` declare :data:`~.base.NETWORK`: a server that stalls longer
than CDT puts a gap on the line the harness never sent, so the runner confirms a failure
over them by running the case once more.

Waiting for input costs nothing per call: where the port has a file descriptor (a device,
``socket://``) the caller selects on it and stamps the bytes when select returns; where it
has none (``rfc2217://``, ``loop://``) a reader thread blocks in pyserial's read (a timeout
set once, when the port is opened) and stamps the bytes when they are handed over, whatever
the caller is doing. pyserial's read timeout is never changed after opening: over rfc2217
that renegotiates every port setting, with a sleep of at least 50 ms.
"""

from __future__ import annotations

import os
import re
import select
import threading
import time
from dataclasses import dataclass

from .. import priority
from .base import BREAK, CHAR_ERROR, NETWORK, CloseInfo, Transport, TransportError

#: the transport carries BREAK / character errors as real line conditions (not PARMRK marks)
NATIVE = "native_line_conditions"


@dataclass(frozen=True)
class Scheme:
    """What one kind of pyserial URL can do."""

    name: str
    write_timeout: bool   # pyserial accepts write_timeout for it
    line_break: bool      # it can carry a BREAK
    char_error: bool      # it can send a character with a parity error
    reader: str           # "select": a file descriptor to select on; "thread": a reader thread
    note: str             # how it carries line conditions, for error messages


SERIAL_SCHEMES: dict[str, Scheme] = {
    "device": Scheme("device", True, True, True, "select",
                     "BREAK through the UART, parity errors by switching the parity for one character"),
    "rfc2217": Scheme("rfc2217", False, True, False, "thread",
                      "BREAK as RFC 2217 BREAK-ON/BREAK-OFF; no character errors (the parity cannot be "
                      "switched remotely in step with the characters still in the server's UART)"),
    "socket": Scheme("socket", True, False, False, "select",
                     "bytes only: a raw TCP serial server drops BREAK; use rfc2217:// for line conditions"),
    "loop": Scheme("loop", False, False, False, "thread", "bytes only"),
}

_READER_TIMEOUT = 0.05   # the read timeout of thread-read ports, set once when opening


def scheme_of(url: str) -> Scheme:
    """The :class:`Scheme` of a pyserial URL or device path; a clean error for the rest."""
    lowered = url.strip().lower()
    if "://" not in lowered:
        return SERIAL_SCHEMES["device"]
    name = lowered.split("://", 1)[0]
    if name not in SERIAL_SCHEMES or name == "device":
        raise TransportError(f"{url}: {name}:// is not a supported serial URL; use a device path "
                             f"(/dev/ttyUSB0), rfc2217://host:port, socket://host:port or loop://")
    if name in ("rfc2217", "socket"):
        from urllib.parse import urlsplit
        try:
            parts = urlsplit(url.strip())
            ok = bool(parts.hostname) and parts.port is not None
        except ValueError:
            ok = False
        if not ok:
            raise TransportError(f"{url}: give the server's host and TCP port, e.g. {name}://10.0.0.7:4001")
    return SERIAL_SCHEMES[name]


def is_pty(fd: int) -> bool:
    """Whether ``fd`` is a pseudo-terminal (on which BREAK and parity errors do not exist)."""
    try:
        return os.ttyname(fd).startswith(("/dev/pts/", "/dev/pty"))
    except OSError:
        return False


def _reason(exc: BaseException) -> str:
    """pyserial's message without its repetitions ("could not open port X: [Errno 2] ...")."""
    if isinstance(getattr(exc, "errno", None), int):
        return os.strerror(exc.errno)
    return re.sub(r"^could not open port \S+: ", "", str(exc), flags=re.I) or type(exc).__name__


class SerialLine:
    """A pyserial port opened within its scheme's limits, read with arrival timestamps.
    Used by the harness (:class:`SerialTransport`) and by ``ptpcert iut --port``."""

    def __init__(self, url: str, params):
        self.url = url
        self.params = params
        self.scheme = scheme_of(url)
        self.port = None
        self.fd: int | None = None
        self.pty = False
        self._pending: list[tuple[float, int]] = []
        self._cond = threading.Condition()
        self._reader: threading.Thread | None = None
        self._stop = False
        self._error: str | None = None

    # -- life cycle -------------------------------------------------------------------
    def open(self) -> None:
        if self.port is not None:
            return
        import serial

        p = self.params
        parity = {"none": serial.PARITY_NONE, "odd": serial.PARITY_ODD, "even": serial.PARITY_EVEN}[p.parity]
        kw = dict(baudrate=p.baud_rate or 9600, bytesize=p.data_bits, parity=parity, stopbits=p.stop_bits)
        # the read timeout is set here, once: never again (see the module's doc)
        kw["timeout"] = 0 if self.scheme.reader == "select" else _READER_TIMEOUT
        if self.scheme.write_timeout:
            kw["write_timeout"] = 5
        try:
            self.port = serial.serial_for_url(self.url, **kw)
        except (serial.SerialException, ValueError, OSError, NotImplementedError) as exc:
            raise TransportError(f"cannot open {self.url}: {_reason(exc)}") from None
        if self.scheme.reader == "select":
            self.fd = self.port.fileno()
            self.pty = self.scheme.name == "device" and is_pty(self.fd)
        sock = getattr(self.port, "_socket", None)
        if sock is not None:
            # pyserial's socket:// leaves Nagle's algorithm on: with delayed ACKs a paced
            # block then stalls for ~40 ms, longer than the shortest CDT
            import socket
            try:
                sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            except OSError:
                pass
        if self.scheme.reader == "thread":
            self._reader = threading.Thread(target=self._read_loop, name=f"ptpcert reader {self.url}",
                                            daemon=True)
            self._reader.start()

    def close(self) -> None:
        port, self.port = self.port, None
        if port is None:
            return
        with self._cond:
            self._stop = True
        try:
            port.close()
        except Exception:
            pass
        if self._reader is not None:
            self._reader.join(2.0)
            self._reader = None

    @property
    def line_break(self) -> bool:
        return self.scheme.line_break and not self.pty

    @property
    def char_error(self) -> bool:
        return self.scheme.char_error and not self.pty and self.params.parity != "none"

    # -- input ------------------------------------------------------------------------
    def _read_loop(self) -> None:
        """Thread-read ports: block in pyserial's read (its timeout fixed at opening) and
        stamp each chunk when it is handed over."""
        port = self.port
        while True:
            priority.sync()     # the run's scheduling class, for the time of the cases
            try:
                first = port.read(1)
                t = time.monotonic()
                more = port.read(port.in_waiting) if first and port.in_waiting else b""
            except Exception as exc:
                with self._cond:
                    if not self._stop:
                        self._error = f"{self.url}: connection lost: {exc}"
                    self._cond.notify_all()
                return
            with self._cond:
                if self._stop:
                    return
                if first:
                    self._pending.extend((t, b) for b in first + more)
                    self._cond.notify_all()

    def _take(self) -> list[tuple[float, int]]:
        out, self._pending = self._pending, []
        return out

    def _collect(self, deadline: float) -> None:
        """Select-read ports: wait for input until ``deadline`` (inf: without limit) and keep
        it, stamped when select returns."""
        timeout = None if deadline == float("inf") else max(0.0, deadline - time.monotonic())
        try:
            r, _, _ = select.select([self.fd], [], [], timeout)
        except InterruptedError:
            return
        if not r:
            return
        t = time.monotonic()
        try:
            data = self.port.read(4096)
        except Exception as exc:
            raise TransportError(f"{self.url}: read failed: {exc}") from None
        self._pending.extend((t, b) for b in data)

    def read(self, deadline: float) -> list[tuple[float, int]]:
        """Wait until at least one byte has arrived or ``deadline`` has passed (inf: no
        limit); return what arrived, as (arrival time, byte)."""
        if self.port is None:
            raise TransportError(f"{self.url}: the port is not open")
        if self.scheme.reader == "thread":
            with self._cond:
                while not self._pending and self._error is None:
                    left = None if deadline == float("inf") else deadline - time.monotonic()
                    if left is not None and left <= 0:
                        break
                    self._cond.wait(left)
                if self._pending:
                    return self._take()
                if self._error is not None:
                    raise TransportError(self._error)
                return []
        while not self._pending:
            self._collect(deadline)
            if time.monotonic() >= deadline:
                break
        return self._take()

    def _hold(self, until: float) -> None:
        """Let time pass until ``until`` while input keeps being stamped as it arrives."""
        if self.scheme.reader == "thread":
            left = until - time.monotonic()
            if left > 0:
                time.sleep(left)
            return
        while time.monotonic() < until:
            self._collect(until)

    # -- output -----------------------------------------------------------------------
    def write(self, data: bytes) -> float:
        t = time.monotonic()
        try:
            self.port.write(data)
        except Exception as exc:
            raise TransportError(f"{self.url}: write failed: {exc}") from None
        return t

    def send_break(self, duration: float) -> float:
        """Hold a BREAK for ``duration`` seconds; returns when it began."""
        if not self.line_break:
            why = "a pseudo-terminal has no BREAK" if self.pty else self.scheme.note
            raise TransportError(f"{self.url}: cannot send BREAK ({why})")
        try:
            if self.scheme.name == "rfc2217":
                from serial import rfc2217

                t = time.monotonic()
                self.port.rfc2217_send_subnegotiation(rfc2217.SET_CONTROL, rfc2217.SET_CONTROL_BREAK_ON)
                self._hold(t + duration)
                self.port.rfc2217_send_subnegotiation(rfc2217.SET_CONTROL, rfc2217.SET_CONTROL_BREAK_OFF)
                return t
            self.port.flush()          # the characters before it go out whole
            t = time.monotonic()
            self.port.break_condition = True
            try:
                self._hold(t + duration)
            finally:
                self.port.break_condition = False
            return t
        except TransportError:
            raise
        except Exception as exc:
            raise TransportError(f"{self.url}: cannot send BREAK: {exc}") from None

    def send_char_error(self, byte: int) -> float:
        """Send ``byte`` with a wrong parity bit (the parity switched for that character)."""
        if not self.char_error:
            why = ("a pseudo-terminal has no parity errors" if self.pty else
                   "the frame has no parity bit" if self.params.parity == "none" else self.scheme.note)
            raise TransportError(f"{self.url}: cannot send a character with a parity error ({why})")
        import serial

        port = self.port
        good = port.parity
        try:
            port.flush()
            port.parity = serial.PARITY_ODD if good == serial.PARITY_EVEN else serial.PARITY_EVEN
            t = time.monotonic()
            port.write(bytes([byte]))
            port.flush()
            port.parity = good
        except Exception as exc:
            raise TransportError(f"{self.url}: cannot send a character error: {exc}") from None
        return t


class SerialTransport(Transport):
    """The harness's side of a serial line: persistent across cases (see :meth:`shutdown`)."""

    def __init__(self, url: str, params):  # params: the line settings (model.line.LineSettings)
        self.url = url
        self.params = params
        self.line = SerialLine(url, params)   # raises TransportError for an unsupported scheme
        self.capabilities = self._capabilities()

    def _capabilities(self) -> frozenset[str]:
        caps = set()
        if self.line.line_break:
            caps |= {BREAK, NATIVE}
        if self.line.char_error:
            caps.add(CHAR_ERROR)
        if self.line.scheme.name in ("rfc2217", "socket"):
            caps.add(NETWORK)
        return frozenset(caps)

    @property
    def port(self):
        return self.line.port

    def open(self) -> None:
        self.line.open()
        self.capabilities = self._capabilities()   # a device found to be a pty has none

    def now(self) -> float:
        return time.monotonic()

    def write(self, data: bytes) -> float:
        return self.line.write(data)

    def send_break(self, duration: float) -> float:
        return self.line.send_break(max(duration, 0.001))

    def send_char_error(self, byte: int) -> float:
        return self.line.send_char_error(byte)

    def read(self, deadline: float) -> list[tuple[float, int]]:
        return self.line.read(deadline)

    def close(self) -> CloseInfo:
        return CloseInfo()  # persistent across cases; see shutdown()

    def shutdown(self) -> None:
        self.line.close()
