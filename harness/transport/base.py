"""The transport interface: how the runner reaches an implementation under test (IUT).

A transport carries bytes both ways with timestamps, may carry line conditions (BREAK, a
character with a parity/framing error) towards the IUT, may start and stop the IUT, and
may collect the STATUS events the IUT reports. It never interprets the protocol.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

#: Capabilities a transport may declare.
BREAK = "break"              # can send a BREAK condition to the IUT
CHAR_ERROR = "char_error"    # can send a character with a parity/framing error
RESTART = "restart"          # starts a fresh IUT for every case (sees its start-up)
STATUS = "status"            # collects the STATUS events the IUT reports
SETUPS = "setups"            # starts the IUT with a per-case command (profile [iut.setups])
NETWORK = "network"          # a network serial server sits between the harness and the line: its
                             # delays can stretch a gap on the line beyond what the harness sent

STATUS_LINE = re.compile(rb"STATUS\s+16#([0-9A-Fa-f]{4})")


class TransportError(RuntimeError):
    """The transport cannot work (wrong URL, port busy, command not found...): a harness
    or configuration fault, never a verdict on the IUT."""


class IUTDied(RuntimeError):
    """The IUT left the line during a case: its process ended, or (``returncode`` None) it
    closed its side of the line while it kept running."""

    def __init__(self, returncode: int | None, stderr_tail: str, message: str | None = None):
        self.returncode, self.stderr_tail = returncode, stderr_tail
        super().__init__(message or f"the IUT process ended (exit status {returncode})")


@dataclass
class CloseInfo:
    returncode: int | None = None
    stderr: str = ""
    killed: bool = False
    notes: list[str] = field(default_factory=list)


class Transport:
    """Base class. Times are seconds on the transport's clock (:meth:`now`)."""

    url: str = ""
    capabilities: frozenset[str] = frozenset()
    #: True when the clock is virtual (the sim: transport): waits cost no real time
    virtual: bool = False

    def open(self) -> None:
        """Connect (and start the IUT, where the transport starts it)."""

    def now(self) -> float:
        raise NotImplementedError

    def write(self, data: bytes) -> float:
        """Send bytes now; returns the time they were handed to the line."""
        raise NotImplementedError

    def send_break(self, duration: float) -> float:
        raise TransportError(f"{self.url}: this transport cannot send BREAK")

    def send_char_error(self, byte: int) -> float:
        raise TransportError(f"{self.url}: this transport cannot send a character error")

    def read(self, deadline: float) -> list[tuple[float, int]]:
        """Wait until at least one byte has arrived or ``deadline`` has passed; return the
        bytes received so far as (time, byte) pairs (possibly empty)."""
        raise NotImplementedError

    def ready(self) -> bool | None:
        """Whether a freshly started IUT waits for input yet (True), is still starting up
        (False), or the transport cannot tell (None). For procedures whose IUT announces
        nothing on the line at start-up, so that no stimulus waits in a pipe for a process
        that is not reading yet (its timing would be lost)."""
        return True

    def cpu_wait(self) -> float | None:
        """Seconds the IUT's processes have spent, since they started, runnable but waiting
        for a CPU (the machine's load stalling them), or None where the IUT does not run on
        this machine or the system does not tell."""
        return None

    def status_reports(self) -> list[tuple[float, int]]:
        """STATUS events the IUT reported since the last call (time, code)."""
        return []

    def report_lines(self) -> list[tuple[float, str]]:
        """Every line the IUT reported (stderr) since the last call, STATUS lines included,
        for procedures that report more than STATUS (e.g. RK 512 request results)."""
        return []

    def close(self) -> CloseInfo:
        return CloseInfo()

    def describe(self) -> str:
        return self.url


class StatusParser:
    """Picks ``STATUS 16#XXXX`` lines out of an IUT's stderr stream."""

    def __init__(self, keep: int = 64 * 1024, keep_lines: int = 4096):
        self._partial = b""
        self.text = bytearray()
        self.keep = keep
        self.keep_lines = keep_lines
        self.reports: list[tuple[float, int]] = []
        self.lines: list[tuple[float, str]] = []
        #: STATUS lines beyond ``keep_lines`` in one case, counted but not kept
        self.dropped = 0

    def feed(self, t: float, data: bytes) -> None:
        self.text += data
        if len(self.text) > self.keep:
            del self.text[: len(self.text) - self.keep]
        buf = self._partial + data
        *lines, self._partial = buf.split(b"\n")
        # an IUT that writes without end of line: keep the start of the line only (a STATUS
        # line is short), so memory and time stay bounded
        self._partial = self._partial[:4096]
        for line in lines:
            m = STATUS_LINE.search(line)
            if m:
                if len(self.reports) < self.keep_lines:
                    self.reports.append((t, int(m.group(1), 16)))
                else:
                    self.dropped += 1
            if len(self.lines) < self.keep_lines:
                self.lines.append((t, line[:4096].decode("utf-8", "replace").rstrip("\r")))

    def drain(self) -> list[tuple[float, int]]:
        out, self.reports = self.reports, []
        return out

    def drain_lines(self) -> list[tuple[float, str]]:
        out, self.lines = self.lines, []
        return out

    def tail(self, n: int = 2000) -> str:
        return bytes(self.text[-n:]).decode("utf-8", "replace")
