"""Any pyserial URL (``/dev/ttyUSB0``, ``rfc2217://host:port``, ``socket://host:port``,
``loop://``) through ``serial_for_url``, with the profile's baud rate and character frame.

The IUT behind a serial port is not started by the harness: it is persistent across cases
(no start-up NAK to wait for; cases that need to see the start-up are unsupported). BREAK
goes out through pyserial where the port carries it (real ports and ``rfc2217://``), not on
``loop://`` and ``socket://``, which drop it. A character with a parity error is sent on a
real port by switching the parity for that one character.
"""

from __future__ import annotations

import select
import time

from .base import BREAK, CHAR_ERROR, CloseInfo, Transport, TransportError

_NO_BREAK = ("loop://", "socket://", "spy://", "alt://", "hwgrep://")


class SerialTransport(Transport):
    def __init__(self, url: str, params):  # params: the line's settings (model.line.LineSettings)
        self.url = url
        self.params = params
        self.port = None
        caps = set()
        lowered = url.lower()
        if not lowered.startswith(_NO_BREAK):
            caps.add(BREAK)
            caps.add("native_line_conditions")
            if "://" not in lowered and params.parity != "none":
                caps.add(CHAR_ERROR)
        self.capabilities = frozenset(caps)

    def open(self) -> None:
        if self.port is not None:
            return
        import serial

        p = self.params
        parity = {"none": serial.PARITY_NONE, "odd": serial.PARITY_ODD, "even": serial.PARITY_EVEN}[p.parity]
        try:
            self.port = serial.serial_for_url(self.url, baudrate=p.baud_rate or 9600, bytesize=p.data_bits,
                                              parity=parity, stopbits=p.stop_bits, timeout=0,
                                              write_timeout=5)
        except (serial.SerialException, ValueError, OSError) as exc:
            raise TransportError(f"cannot open {self.url}: {exc}") from None
        sock = getattr(self.port, "_socket", None)
        if sock is not None:
            # pyserial's socket:// leaves Nagle's algorithm on: with delayed ACKs a paced
            # block then stalls for ~40 ms, longer than the shortest CDT
            import socket
            try:
                sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            except OSError:
                pass
        try:
            self.fd = self.port.fileno()
        except Exception:
            self.fd = None

    def now(self) -> float:
        return time.monotonic()

    def write(self, data: bytes) -> float:
        t = self.now()
        try:
            self.port.write(data)
        except Exception as exc:
            raise TransportError(f"{self.url}: write failed: {exc}") from None
        return t

    def send_break(self, duration: float) -> float:
        t = self.now()
        try:
            self.port.send_break(duration=max(duration, 0.001))
        except Exception as exc:
            raise TransportError(f"{self.url}: cannot send BREAK: {exc}") from None
        return t

    def send_char_error(self, byte: int) -> float:
        import serial

        port = self.port
        good = port.parity
        port.flush()
        port.parity = serial.PARITY_ODD if good == serial.PARITY_EVEN else serial.PARITY_EVEN
        t = self.now()
        port.write(bytes([byte]))
        port.flush()
        port.parity = good
        return t

    def read(self, deadline: float) -> list[tuple[float, int]]:
        port = self.port
        while True:
            remaining = deadline - self.now()
            try:
                if self.fd is not None:
                    r, _, _ = select.select([self.fd], [], [], max(0.0, remaining))
                    data = port.read(max(1, port.in_waiting)) if r else b""
                else:
                    port.timeout = max(0.0, min(remaining, 0.02))
                    data = port.read(max(1, port.in_waiting))
            except Exception as exc:
                raise TransportError(f"{self.url}: read failed: {exc}") from None
            t = self.now()
            if data:
                return [(t, b) for b in data]
            if t >= deadline:
                return []

    def close(self) -> CloseInfo:
        return CloseInfo()  # persistent across cases; see shutdown()

    def shutdown(self) -> None:
        if self.port is not None:
            try:
                self.port.close()
            finally:
                self.port = None
