"""Two model stations wired back to back, in virtual time.

A byte a station starts transmitting at time ``s`` arrives complete at the other station
at ``s + character time``. A hook may drop, corrupt (deliver as a character with a
parity error) or duplicate any byte in flight, and line breaks can be injected. Pure: no
clock, no I/O; used by tests, the fuzzer, benchmarks and the ``sim:`` transport.
"""

from __future__ import annotations

import heapq
from dataclasses import dataclass, field
from math import inf
from typing import Callable

from .app import Host
from .events import Event
from .station import Station3964

DELIVER, DROP, CORRUPT, DUPLICATE = "deliver", "drop", "corrupt", "duplicate"


@dataclass(frozen=True, slots=True)
class WireByte:
    """One character on the line: started at ``start`` by ``src``, value ``byte``;
    ``fate`` is what the link did with it."""

    start: float
    src: str
    byte: int
    fate: str = DELIVER


@dataclass
class Link:
    a: Station3964
    b: Station3964
    #: called for every byte put on the line; returns DELIVER, DROP, CORRUPT or DUPLICATE
    hook: Callable[[WireByte], str] | None = None
    now: float = 0.0
    wire: list[WireByte] = field(default_factory=list)
    events: list[tuple[str, Event]] = field(default_factory=list)
    max_steps_per_instant: int = 100_000
    record_wire: bool = True
    #: stations whose application sends back every block they receive (the echo convention)
    echo: set[str] = field(default_factory=set)

    def __post_init__(self) -> None:
        if self.a.name == self.b.name:
            raise ValueError("the two stations need different names")
        self._flight: list[tuple[float, int, str, str, int]] = []  # (arrive, seq, dest, kind, value)
        self._seq = 0
        self._peer = {self.a.name: self.b, self.b.name: self.a}
        self._hosts = {st.name: Host(st, "echo" if st.name in self.echo else "none") for st in (self.a, self.b)}

    # -- control -------------------------------------------------------------------
    def power_on(self, at: float | None = None, *, b_at: float | None = None) -> None:
        """Switch both stations on (``b_at``: the second one later, if given)."""
        t = self.now if at is None else at
        self.run_until(t)
        self.a.power_on(t)
        if b_at is None:
            self.b.power_on(t)
        self._collect(t)
        if b_at is not None:
            self.run_until(b_at)
            self.b.power_on(b_at)
            self._collect(b_at)

    def request(self, station: Station3964, payload: bytes, at: float | None = None) -> None:
        t = self.now if at is None else at
        self.run_until(t)
        station.request_send(t, payload)
        self._collect(t)

    def inject_break(self, to: Station3964, at: float | None = None) -> None:
        """A BREAK condition reaches ``to`` at ``at``."""
        self._push(self.now if at is None else at, to.name, "break", 0)

    def inject(self, to: Station3964, data: bytes, at: float | None = None,
               kind: str = "byte") -> None:
        """Characters arriving at ``to`` from outside the two stations (noise)."""
        t = self.now if at is None else at
        for b in data:
            self._push(t, to.name, kind, b)

    # -- engine ----------------------------------------------------------------------
    def next_time(self) -> float:
        t = self._flight[0][0] if self._flight else inf
        for st in (self.a, self.b):
            d = st.next_deadline()
            if d is not None and d < t:
                t = d
        return t

    def run_until(self, until: float) -> None:
        """Process everything that happens up to and including ``until``."""
        steps = 0
        last = None
        while True:
            t = self.next_time()
            if t > until:
                break
            t = max(t, self.now)
            if t == last:
                steps += 1
                if steps > self.max_steps_per_instant:
                    raise RuntimeError(f"link makes no progress at t={t}")
            else:
                last, steps = t, 0
            self.now = t
            # inputs of this instant first, then deadlines (the station's ordering rule)
            while self._flight and self._flight[0][0] <= t:
                _, _, dest, kind, value = heapq.heappop(self._flight)
                st = self.a if dest == self.a.name else self.b
                st.line_event(t, kind, value)
            for st in (self.a, self.b):
                d = st.next_deadline()
                if d is not None and d <= t:
                    st.handle_timer(t)
            self._collect(t)
        self.now = max(self.now, until) if until != inf else self.now

    def run_until_quiet(self, limit: float) -> bool:
        """Run until both stations are idle with nothing in flight and nothing scheduled,
        or until ``limit``. Returns True when quiet was reached."""
        while True:
            t = self.next_time()
            if t == inf:
                return self.a.idle and self.b.idle
            if t > limit:
                self.run_until(limit)
                return False
            self.run_until(t)

    # -- internals -------------------------------------------------------------------
    def _push(self, at: float, dest: str, kind: str, value: int) -> None:
        self._seq += 1
        heapq.heappush(self._flight, (at, self._seq, dest, kind, value))

    def _collect(self, t: float) -> None:
        for st in (self.a, self.b):
            runs = st.pop_output_runs(t)
            if runs:
                char = st.params.char_time
                dest = self._peer[st.name].name
                hook = self.hook
                if hook is None and char == 0:
                    # no line timing and nothing to tamper with: whole runs arrive at once
                    for start, data in runs:
                        if self.record_wire:
                            self.wire.extend(WireByte(start, st.name, b) for b in data)
                        self._push(start, dest, "bytes", data)
                    continue
                for start, data in runs:
                    for i, byte in enumerate(data):
                        at = start + i * char
                        fate = DELIVER if hook is None else hook(WireByte(at, st.name, byte))
                        if self.record_wire:
                            self.wire.append(WireByte(at, st.name, byte, fate))
                        if fate == DROP:
                            continue
                        kind = "invalid" if fate == CORRUPT else "byte"
                        self._push(at + char, dest, kind, byte)
                        if fate == DUPLICATE:
                            self._push(at + 2 * char, dest, kind, byte)
            if st.has_events:
                self.events.extend((st.name, e) for e in self._hosts[st.name].drain(t))

    # -- views -----------------------------------------------------------------------
    def transcript(self) -> list[tuple[str, bytes]]:
        """The wire as runs of consecutive bytes per sender: [(name, bytes), ...]."""
        runs: list[tuple[str, bytearray]] = []
        for w in self.wire:
            if runs and runs[-1][0] == w.src:
                runs[-1][1].append(w.byte)
            else:
                runs.append((w.src, bytearray([w.byte])))
        return [(n, bytes(b)) for n, b in runs]

    def events_of(self, station: Station3964, kind: type | None = None) -> list[Event]:
        return [e for n, e in self.events if n == station.name and (kind is None or isinstance(e, kind))]
