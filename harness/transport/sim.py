"""``sim:`` — the IUT is a model station in this process, in virtual time.

Used by ``ptpcert vectors --check`` (the model plays the IUT), for self-tests and for the
fastest runs. Options as a query string: ``sim:?app=none&buffer=full&mutant=NAME``.
"""

from __future__ import annotations

import heapq
from urllib.parse import parse_qs

from ..model import Host, Params3964, Station3964
from ..model.events import Delivered, SendDone, Status
from .base import BREAK, CHAR_ERROR, RESTART, STATUS, Transport, TransportError


def parse_sim_url(url: str) -> dict[str, str]:
    if not url.startswith("sim:"):
        raise TransportError(f"{url!r} is not a sim: URL")
    rest = url[4:].lstrip("/")
    query = rest[1:] if rest.startswith("?") else rest
    opts = {k: v[-1] for k, v in parse_qs(query, keep_blank_values=True).items()}
    unknown = sorted(set(opts) - {"app", "buffer", "mutant", "priority"})
    if unknown:
        raise TransportError(f"{url}: unknown option {unknown[0]!r} (known: app, buffer, mutant, priority)")
    if opts.get("buffer", "free") not in ("free", "full"):
        raise TransportError(f"{url}: buffer must be free or full")
    return opts


class SimTransport(Transport):
    virtual = True
    capabilities = frozenset({BREAK, CHAR_ERROR, RESTART, STATUS, "buffer_control"})

    def __init__(self, params: Params3964, *, app: str = "echo", buffer_free: bool = True,
                 station_factory=None, url: str = "sim:", tester_char: float | None = None,
                 host_factory=None):
        self.url = url
        self.params = params
        self.app = app
        self.buffer_free = buffer_free
        self._factory = station_factory or (lambda p: Station3964(p, name="iut"))
        # the application above the station (default: the 3964(R) Host with ``app``)
        self._host_factory = host_factory or (lambda st: Host(st, self.app))
        self._tester_char = params.char_time if tester_char is None else tester_char
        self._now = 0.0
        self.events: list = []

    # -- life cycle ---------------------------------------------------------------
    def open(self) -> None:
        self.station: Station3964 = self._factory(self.params)
        self.host = self._host_factory(self.station)
        self._arrivals: list[tuple[float, int, str, int]] = []
        self._seq = 0
        self._out: list[tuple[float, int]] = []   # IUT bytes, completion time
        self._status: list[tuple[float, int]] = []
        self.events = []
        if not self.buffer_free:
            self.station.buffer_free = False
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
        char = self.params.char_time
        for start, b in self.station.pop_output(self._now):
            self._out.append((start + char, b))
        self._out.sort()
        for e in self.host.drain():
            self.events.append(e)
            if isinstance(e, Status):
                self._status.append((e.time, e.code))

    def status_reports(self) -> list[tuple[float, int]]:
        out, self._status = self._status, []
        return out

    def delivered(self) -> list[bytes]:
        return [e.payload for e in self.events if isinstance(e, Delivered)]

    def sent(self) -> list[bytes]:
        return [e.payload for e in self.events if isinstance(e, SendDone)]
