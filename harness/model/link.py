"""Two model stations wired back to back, in virtual time.

A byte a station starts transmitting at time ``s`` arrives complete at the other station
at ``s + character time``. A hook may drop, corrupt (deliver as a character with a
parity error) or duplicate any byte in flight, and line breaks can be injected. Pure: no
clock, no I/O; used by tests, the fuzzer, benchmarks and the ``sim:`` transport.

Any station with the driver interface can sit at either end (a 3964(R) station, an ASCII
driver). ``host_factory(station, app)`` builds the application above each one (default: the
echo application :class:`~ptpcert.model.app.Host`). A station that drives modem outputs
(``pop_signals``) is wired to the other as a null-modem cable: its RTS is the other's CTS,
its DTR the other's DSR.
"""

from __future__ import annotations

import heapq
from dataclasses import dataclass, field
from functools import partial
from itertools import repeat
from math import inf
from operator import add, mul
from typing import Any, Callable, Iterator, NamedTuple

from ptpcert.model.app import Host

from .events import Event

#: what a null-modem cable connects: an output of one station to an input of the other
NULL_MODEM = {"rts": "cts", "dtr": "dsr"}

DELIVER, DROP, CORRUPT, DUPLICATE = "deliver", "drop", "corrupt", "duplicate"


class WireByte(NamedTuple):
    """One character on the line: started at ``start`` by ``src``, value ``byte``;
    ``fate`` is what the link did with it. A named tuple: a link records hundreds of
    thousands of them in a fuzzing run, and a tuple is the cheapest object to make."""

    start: float
    src: str
    byte: int
    fate: str = DELIVER


#: WireByte from a tuple of its four fields, what WireByte._make does without its Python frame
_wire_byte_of = partial(tuple.__new__, WireByte)


def _wire_bytes(start: float, src: str, data: bytes, char: float) -> Iterator[WireByte]:
    """The characters of ``data`` sent back to back by ``src`` from ``start``, ``char``
    seconds apart (the i-th at ``start + i * char``), left alone by the link; made in
    bulk (no Python code runs per character)."""
    n = len(data)
    starts = repeat(start, n) if char == 0 else map(add, repeat(start, n), map(mul, range(n), repeat(char, n)))
    return map(_wire_byte_of, zip(starts, repeat(src, n), data, repeat(DELIVER, n)))


class WireRun(NamedTuple):
    """Characters on the line as the link records them: ``data`` started by ``src`` back to
    back from ``start``, ``char`` seconds apart (the i-th at ``start + i * char``), each
    with ``fate``. A character a hook did something with is a run of its own."""

    start: float
    src: str
    data: bytes
    char: float
    fate: str = DELIVER


def _default_host(station: Any, app: str) -> Host:
    return Host(station, app)


@dataclass
class Link:
    a: Any
    b: Any
    #: called for every byte put on the line; returns DELIVER, DROP, CORRUPT or DUPLICATE
    hook: Callable[[WireByte], str] | None = None
    now: float = 0.0
    events: list[tuple[str, Event]] = field(default_factory=list)
    max_steps_per_instant: int = 100_000
    record_wire: bool = True
    #: stations whose application sends back every block they receive (the echo convention)
    echo: set[str] = field(default_factory=set)
    #: the application of a station by name (an object with ``drain(now)``, e.g. an RK 512
    #: host); a station not named here gets host_factory(station, "echo" or "none")
    hosts: dict[str, object] = field(default_factory=dict)
    #: builds the application of a station not named in ``hosts`` (default: the echo application, :class:`~ptpcert.model.app.Host`)
    host_factory: Callable[[Any, str], Any] = _default_host

    def __post_init__(self) -> None:
        if self.a.name == self.b.name:
            raise ValueError("the two stations need different names")
        self._flight: list[tuple[float, int, str, str, int]] = []  # (arrive, seq, dest, kind, value)
        #: every character put on the line (with ``record_wire``), as runs in line order;
        #: :attr:`wire` is the same one character at a time
        self.wire_runs: list[WireRun] = []
        self._wire: list[WireByte] = []
        self._wire_made = 0       # runs already in _wire
        self._wire_pending = 0    # characters of the runs not yet in _wire
        self._seq = 0
        self._peer = {self.a.name: self.b, self.b.name: self.a}
        self._hosts = {st.name: self.hosts.get(st.name)
                       or self.host_factory(st, "echo" if st.name in self.echo else "none")
                       for st in (self.a, self.b)}
        #: modem-line changes: (time, station, output, value)
        self.signals: list[tuple[float, str, str, int]] = []
        # per station, looked up once: (station, its application, the peer's name, whether
        # it drives modem outputs)
        self._ends = tuple((st, self._hosts[st.name], self._peer[st.name].name, hasattr(st, "pop_signals"))
                           for st in (self.a, self.b))
        # A run of characters towards a station that only stores them (a block's data at
        # 9600 baud) is handed over in one call (see _stream) where both stations can say
        # so and their applications act only on their events.
        self._streams = (all(hasattr(st, "quiet_run") and hasattr(st, "output_stream") for st in (self.a, self.b))
                         and all(type(h) is Host for h in self._hosts.values()))
        # With no line timing, the characters of an instant go to a station as one "bytes"
        # event also when a hook sees each of them (see _collect); False: one event each.
        self._group_instant = True
        # a null-modem cable: each station's inputs start at the other's outputs
        for st in (self.a, self.b):
            peer = self._peer[st.name]
            if hasattr(st, "pop_signals") and hasattr(peer, "set_line"):
                for out, inp in NULL_MODEM.items():
                    setattr(peer, inp, getattr(st, out))

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

    def request(self, station: Any, payload: bytes, at: float | None = None) -> None:
        t = self.now if at is None else at
        self.run_until(t)
        station.request_send(t, payload)
        self._collect(t)

    def inject_break(self, to: Any, at: float | None = None) -> None:
        """A BREAK condition reaches ``to`` at ``at``."""
        self._push(self.now if at is None else at, to.name, "break", 0)

    def inject(self, to: Any, data: bytes, at: float | None = None,
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
        self._run(until, quiet=False)

    def run_until_quiet(self, limit: float) -> bool:
        """Run until both stations are idle with nothing in flight and nothing scheduled,
        or until ``limit``. Returns True when quiet was reached."""
        if self._run(limit, quiet=True):
            return self.a.idle and self.b.idle
        return False

    def _run(self, until: float, quiet: bool) -> bool:
        """The event loop: instant by instant up to ``until``; with ``quiet``, return True
        (without moving the clock on) as soon as nothing is scheduled any more."""
        steps = 0
        last = None
        a, b = self.a, self.b
        flight = self._flight
        pop = heapq.heappop
        while True:
            t = flight[0][0] if flight else inf
            d = a.next_deadline()
            if d is not None and d < t:
                t = d
            d = b.next_deadline()
            if d is not None and d < t:
                t = d
            if t == inf and quiet:
                return True
            if t > until:
                break
            if t < self.now:
                t = self.now
            if t == last:
                steps += 1
                if steps > self.max_steps_per_instant:
                    raise RuntimeError(f"link makes no progress at t={t}")
            else:
                last, steps = t, 0
            self.now = t
            # inputs of this instant first, then deadlines (the station's ordering rule)
            while flight and flight[0][0] <= t:
                arrive, _, dest, kind, value = pop(flight)
                st = a if dest == a.name else b
                if kind == "byte" and self._streams and arrive == t:
                    end = self._stream(st, t, value, until)
                    if end is not None:
                        t = self.now = end
                        continue
                st.line_event(t, kind, value)
            d = a.next_deadline()
            if d is not None and d <= t:
                a.handle_timer(t)
            d = b.next_deadline()
            if d is not None and d <= t:
                b.handle_timer(t)
            self._collect(t)
        self.now = max(self.now, until) if until != inf else self.now
        return False

    # -- internals -------------------------------------------------------------------
    def _record(self, start: float, src: str, data: bytes, char: float, fate: str = DELIVER) -> None:
        self.wire_runs.append(WireRun(start, src, data, char, fate))
        self._wire_pending += len(data)

    def _push(self, at: float, dest: str, kind: str, value: int) -> None:
        self._seq += 1
        heapq.heappush(self._flight, (at, self._seq, dest, kind, value))

    def _stream(self, rx: Any, t: float, first: int, until: float) -> float | None:
        """``first`` arrives at ``rx`` now (``t``) and its peer is sending a run of
        characters back to back from now on: hand over at once the characters of the run
        that arrive before anything else happens, if ``rx`` would only store them (see
        ``Station3964.quiet_run``). Exactly what the instant-by-instant loop does, in one
        call: the bytes leave the peer at the same times, the hook sees each of them in the
        same order, and nothing else is due in between (no other character in flight, no
        deadline of the peer but pacing its characters, none of ``rx``). Returns the
        arrival time of the last character handed over (the loop goes on from there), or
        None to deliver ``first`` alone."""
        tx = self._peer[rx.name]
        out = tx.output_stream()
        if out is None or tx.has_events:
            return None
        start, data, horizon = out
        char = tx.params.char_time
        if char <= 0 or abs(start - t) > 1e-9:
            return None
        # the i-th character of the run (i = 1, 2, ...) arrives at t + i * char; all of them
        # before the next character in flight, the peer's next deadline, and ``until``
        nxt = self._flight[0][0] if self._flight else inf
        lim = min(nxt, horizon) - 1e-9
        k = int((min(lim, until) - t) / char) if min(lim, until) < inf else len(data)
        k = min(max(k, 0), len(data))
        if k < 1:
            return None
        run = bytes((first,)) + data[:k]
        m = rx.quiet_run(t, run, char) - 1    # characters of the peer's run taken at once
        if m < 1:
            return None
        hook, record = self.hook, self.record_wire
        popped = m
        if hook is None:
            if record:
                self._record(start, tx.name, data[:m], char)
        else:
            for i in range(m):
                at = start + i * char
                fate = hook(WireByte(at, tx.name, data[i]))
                if record:
                    self._record(at, tx.name, data[i:i + 1], char, fate)
                if fate != DELIVER:
                    # this character goes its own way, as the loop would send it; the run
                    # handed over ends before it
                    popped, m = i + 1, i
                    if fate != DROP:
                        kind = "invalid" if fate == CORRUPT else "byte"
                        self._push(at + char, rx.name, kind, data[i])
                        if fate == DUPLICATE:
                            self._push(at + 2 * char, rx.name, kind, data[i])
                    break
        got = sum(len(x) for _, x in tx.pop_output_runs(start + (popped - 0.5) * char))
        if got != popped:   # pragma: no cover - the station paces its run one character apart
            raise RuntimeError(f"link: {tx.name} handed out {got} characters, not {popped}")
        rx.receive_run(t, run[:m + 1], char)
        return t + m * char

    def _collect(self, t: float) -> None:
        record = self.record_wire
        for st, host, dest, signals in self._ends:
            runs = st.pop_output_runs(t)
            if runs:
                name = st.name
                char = st.params.char_time
                hook = self.hook
                if hook is None and char == 0:
                    # no line timing and nothing to tamper with: whole runs arrive at once
                    for start, data in runs:
                        if record:
                            self._record(start, name, data, 0)
                        self._push(start, dest, "bytes", data)
                elif char == 0 and self._group_instant:
                    # no line timing with a hook: the characters a run keeps intact (and a
                    # duplicated one twice) arrive together as one "bytes" event, exactly as
                    # one "byte" event each at the same instant would; a corrupted one
                    # arrives as an "invalid" event of its own between them, in its place
                    for start, data in runs:
                        keep = bytearray()
                        for byte in data:
                            fate = hook(WireByte(start, name, byte))
                            if record:
                                self._record(start, name, bytes((byte,)), 0, fate)
                            if fate == DELIVER:
                                keep.append(byte)
                            elif fate == DUPLICATE:
                                keep += bytes((byte, byte))
                            elif fate == CORRUPT:
                                if keep:
                                    self._push(start, dest, "bytes", bytes(keep))
                                    keep.clear()
                                self._push(start, dest, "invalid", byte)
                        if keep:
                            self._push(start, dest, "bytes", bytes(keep))
                else:
                    for start, data in runs:
                        if hook is None and record:
                            self._record(start, name, data, char)
                        for i, byte in enumerate(data):
                            at = start + i * char
                            if hook is None:
                                fate = DELIVER
                            else:
                                fate = hook(WireByte(at, name, byte))
                                if record:
                                    self._record(at, name, bytes((byte,)), char, fate)
                            if fate == DROP:
                                continue
                            kind = "invalid" if fate == CORRUPT else "byte"
                            self._push(at + char, dest, kind, byte)
                            if fate == DUPLICATE:
                                self._push(at + 2 * char, dest, kind, byte)
            # every instant: an application may act without a new event (a delayed read)
            events = host.drain(t)
            if events:
                name = st.name
                self.events.extend((name, e) for e in events)
            # signals after the application: what it did may have switched one
            if signals:
                peer = self._peer[st.name]
                for at, out, value in st.pop_signals(t):
                    self.signals.append((at, st.name, out, value))
                    if out in NULL_MODEM and hasattr(peer, "set_line"):
                        self._push(at, peer.name, NULL_MODEM[out], value)

    # -- views -----------------------------------------------------------------------
    @property
    def wire(self) -> list[WireByte]:
        """Every character put on the line (with ``record_wire``), in line order, one
        WireByte each. Built from :attr:`wire_runs` when asked for: a fuzzing run puts
        hundreds of thousands of characters on the line and looks at few of them. A caller
        may clear the list; later characters are added to it."""
        runs = self.wire_runs
        if self._wire_made < len(runs):
            wire = self._wire
            for run in runs[self._wire_made:]:
                if run.fate == DELIVER:
                    wire.extend(_wire_bytes(run.start, run.src, run.data, run.char))
                else:
                    wire.append(WireByte(run.start, run.src, run.data[0], run.fate))
            self._wire_made, self._wire_pending = len(runs), 0
        return self._wire

    @property
    def wire_length(self) -> int:
        """``len(link.wire)`` without building it."""
        return len(self._wire) + self._wire_pending

    def transcript(self) -> list[tuple[str, bytes]]:
        """The wire as runs of consecutive bytes per sender: [(name, bytes), ...]."""
        runs: list[tuple[str, bytearray]] = []
        for w in self.wire:
            if runs and runs[-1][0] == w.src:
                runs[-1][1].append(w.byte)
            else:
                runs.append((w.src, bytearray([w.byte])))
        return [(n, bytes(b)) for n, b in runs]

    def events_of(self, station: Any, kind: type | None = None) -> list[Event]:
        return [e for n, e in self.events if n == station.name and (kind is None or isinstance(e, kind))]
