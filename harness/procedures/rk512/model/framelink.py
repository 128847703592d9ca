"""Two RK 512 layers over an ideal in-memory frame link, in virtual time: no 3964(R), no
characters, no line errors. A frame handed over at ``t`` arrives whole at the partner at
``t + delay`` and is acknowledged to its sender at that instant, right after the partner
took it. For speed (the fuzzer's level 1, benchmarks) and for checks of the RK 512 rules
alone. Pure: no clock, no I/O.
"""

from __future__ import annotations

from collections import deque
from math import inf

from .core import Rk512Core


class FrameLink:
    """Two :class:`Rk512Core` objects wired together. ``frames`` records (time, sender
    name, frame) when ``record`` is set; ``events`` collects (name, event) of both; a
    ``hosts`` mapping (name -> application with ``drain``) runs applications. The cores'
    per-frame events (FrameReceived, FrameSent) are switched off unless ``frame_events``:
    ``frames`` has them."""

    def __init__(self, a: Rk512Core, b: Rk512Core, *, delay: float = 0.0, record: bool = True,
                 hosts: dict | None = None, frame_events: bool = False):
        if a.name == b.name:
            raise ValueError("the two cores need different names")
        self.a, self.b = a, b
        self.delay = delay
        self.record = record
        self.now = 0.0
        self.frames: list[tuple[float, str, bytes]] = []
        self.events: list[tuple[str, object]] = []
        # Every frame takes the same ``delay`` and frames are handed over in time order, so
        # they arrive in the order they were handed over: a FIFO is the event queue.
        self._q: deque[tuple] = deque()
        self._peer = {a.name: b, b.name: a}
        self._hosts = dict(hosts or {})
        for core in (a, b):
            core._lower_send = self._sender(core)
            core.frame_events = frame_events

    def _sender(self, core: Rk512Core):
        peer = self._peer[core.name]

        q = self._q
        name = core.name

        def send(now: float, frame: bytes) -> None:
            if self.record:
                self.frames.append((now, name, frame))
            q.append((now + self.delay, peer, frame, core))
        return send

    # -- control ------------------------------------------------------------------------
    def power_on(self, at: float | None = None) -> None:
        t = self.now if at is None else at
        self.run_until(t)
        self.a.power_on(t)
        self.b.power_on(t)
        self._collect()

    def request(self, core: Rk512Core, req, at: float | None = None) -> bool:
        t = self.now if at is None else at
        self.run_until(t)
        ok = core.request(t, req)
        self._collect()
        return ok

    # -- engine -----------------------------------------------------------------------------
    def next_time(self) -> float:
        t = self._q[0][0] if self._q else inf
        for c in (self.a, self.b):
            d = c.own_deadline()
            if d < t:
                t = d
        return t

    def run_until(self, until: float) -> None:
        q = self._q
        a, b = self.a, self.b
        while True:
            t = self.next_time()
            if t > until:
                break
            if t < self.now:
                t = self.now
            self.now = t
            while q and q[0][0] <= t:
                _, dest, frame, src = q.popleft()
                dest.frame_received(t, frame)   # the partner takes the block...
                src.frame_sent(t)               # ...and acknowledges it
            if a.own_deadline() <= t:
                a.handle_timer(t)
            if b.own_deadline() <= t:
                b.handle_timer(t)
            self._collect()
        if until != inf and until > self.now:
            self.now = until

    def run_until_quiet(self, limit: float) -> bool:
        """Run until nothing is in flight and no timer runs, or until ``limit``."""
        while True:
            t = self.next_time()
            if t == inf:
                return self.a.idle and self.b.idle
            if t > limit:
                self.run_until(limit)
                return False
            self.run_until(t)

    def _collect(self) -> None:
        for core in (self.a, self.b):
            if core.has_events:
                host = self._hosts.get(core.name)
                evs = host.drain(self.now) if host is not None else core.pop_events()
                name = core.name
                self.events += [(name, e) for e in evs]
