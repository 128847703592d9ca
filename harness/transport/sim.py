"""``sim:`` — the IUT is a model station in this process, in virtual time.

Used by ``ptpcert vectors --check`` (the model plays the IUT), for self-tests and for the
fastest runs. Options as a query string, e.g. ``sim:?app=none&mutant=NAME``; the station and
its application come from the procedure (``transport.sim_factory``), handed in.
"""

from __future__ import annotations

import heapq
from urllib.parse import parse_qs

from ..model.events import Delivered, SendDone, Status
from .base import BREAK, CHAR_ERROR, RESTART, STATUS, Transport, TransportError


def parse_sim_url(url: str) -> dict[str, str]:
    """The options of a ``sim:`` URL (its query string). Which options exist is the
    procedure's business (Procedure.sim_options checks them)."""
    if not url.startswith("sim:"):
        raise TransportError(f"{url!r} is not a sim: URL")
    rest = url[4:].lstrip("/")
    query = rest[1:] if rest.startswith("?") else rest
    return {k: v[-1] for k, v in parse_qs(query, keep_blank_values=True).items()}


class SimTransport(Transport):
    virtual = True
    capabilities = frozenset({BREAK, CHAR_ERROR, RESTART, STATUS})

    def __init__(self, params, host_factory, *, url: str = "sim:", char_time: float = 0.0,
                 tester_char: float | None = None):
        self.url = url
        self.params = params
        self._host_factory = host_factory
        self._char = char_time
        self._tester_char = char_time if tester_char is None else tester_char
        self._now = 0.0
        self.events: list = []

    # -- life cycle ---------------------------------------------------------------
    def open(self) -> None:
        self.host = self._host_factory(self.params)
        self.station = self.host.station
        self._arrivals: list[tuple[float, int, str, int]] = []
        self._seq = 0
        self._out: list[tuple[float, int]] = []   # IUT bytes, completion time
        self._status: list[tuple[float, int]] = []
        self._lines: list[tuple[float, str]] = []
        self.events = []
        self.station.power_on(self._now)
        self._collect()

    def now(self) -> float:
        return self._now

    # -- tester -> IUT ------------------------------------------------------------
    def _push(self, at: float, kind: str, value: int) -> None:
        self._seq += 1
        heapq.heappush(self._arrivals, (at, self._seq, kind, value))

    # The runner hands a character over when it is complete (as a UART on the other side
    # would); so it arrives at once, and each further byte of one write a character later.
    def write(self, data: bytes) -> float:
        t = self._now
        for i, b in enumerate(data):
            self._push(t + i * self._tester_char, "byte", b)
        return t

    def send_break(self, duration: float) -> float:
        self._push(self._now, "break", 0)
        return self._now

    def send_char_error(self, byte: int) -> float:
        self._push(self._now, "invalid", byte)
        return self._now

    # -- time -----------------------------------------------------------------------
    def read(self, deadline: float) -> list[tuple[float, int]]:
        st = self.station
        while True:
            ready = [x for x in self._out if x[0] <= self._now + 1e-12]
            if ready:
                self._out = [x for x in self._out if x[0] > self._now + 1e-12]
                return ready
            t = deadline
            if self._arrivals:
                t = min(t, self._arrivals[0][0])
            d = st.next_deadline()
            if d is not None:
                t = min(t, d)
            if self._out:
                t = min(t, self._out[0][0])
            t = max(t, self._now)
            self._now = t
            while self._arrivals and self._arrivals[0][0] <= t:
                _, _, kind, value = heapq.heappop(self._arrivals)
                st.line_event(t, kind, value)
            d = st.next_deadline()
            if d is not None and d <= t:
                st.handle_timer(t)
            self._collect()
            if t >= deadline and not [x for x in self._out if x[0] <= t + 1e-12]:
                return []

    def _collect(self) -> None:
        char = self._char
        for start, b in self.station.pop_output(self._now):
            self._out.append((start + char, b))
        self._out.sort()
        for e in self.host.drain():
            self.events.append(e)
            if isinstance(e, Status):
                self._status.append((e.time, e.code))
            report = getattr(self.host, "report_line", None)
            line = report(e) if report is not None else None
            if line:
                self._lines.append((e.time, line))

    def status_reports(self) -> list[tuple[float, int]]:
        out, self._status = self._status, []
        return out

    def report_lines(self) -> list[tuple[float, str]]:
        out, self._lines = self._lines, []
        return out

    def delivered(self) -> list[bytes]:
        return [e.payload for e in self.events if isinstance(e, Delivered)]

    def sent(self) -> list[bytes]:
        return [e.payload for e in self.events if isinstance(e, SendDone)]
