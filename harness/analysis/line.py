"""The line: both seats of a link judged together, and the line cut into exchanges.

A :class:`LineAnalysis` takes the capture chunk by chunk (:meth:`~LineAnalysis.feed`, and
:meth:`~LineAnalysis.mark` for its marks), turns each chunk into the items its seat put on the
line (:class:`~ptpcert.analysis.interface.Item`: bytes, characters with an error, BREAKs, at
their estimated times), and keeps a :class:`~ptpcert.analysis.judge.SeatJudge` for each seat.
Both seats' stations are followed, since what a CP 341 in each seat raises is part of every
finding; only the judged seats' differences are findings. A finding that the recording itself
may explain (near a place where it lost data, where a read returned both seats' characters at
once, or before the seat's model was first seen at rest) is graded informational here.

Exchanges. The report groups the line into exchanges: an exchange ends where every judged
station's model is at rest (idle, nothing to send, no job) when the next byte begins, at a
case mark, or after a quiet line as long as the longest timer. :mod:`ptpcert.analysis.results`
turns each exchange, and each of its findings, into a case of the run results.

Live use (``ptpcert monitor``) feeds chunks as they are read and calls
:meth:`LineAnalysis.advance` with the current time; the analysis judges up to a lag behind it
(the longest window), so that every byte the model predicts has had its chance to arrive.
Findings and finished exchanges are handed to the listener as soon as they stand. A whole
recording ends with :meth:`LineAnalysis.close`.
"""

from __future__ import annotations

import bisect
from dataclasses import dataclass, field, replace
from math import inf
from typing import Any, Callable, Iterable

from ptpcert import capture as C
from ptpcert import results as R
from ptpcert.analysis.interface import EPS, OTHER, QUANTUM, SEATS, Finding, Item, ProcedureAnalyzer
from ptpcert.analysis.judge import SeatJudge


@dataclass
class Exchange:
    """Consecutive chunks of the line between two points where the judged stations rest."""

    index: int
    first: int                   # index of its first chunk
    last: int                    # index of its last chunk
    t0: float
    t1: float
    case: str = ""               # the case of a run it belongs to (from the capture's marks)
    findings: list[Finding] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    events: dict[str, list[int]] = field(default_factory=lambda: {"a": [], "b": []})

    @property
    def verdict(self) -> str:
        grades = {f.grade for f in self.findings}
        if R.FAIL in grades:
            return R.FAIL
        if R.INFORMATIONAL in grades:
            return R.INFORMATIONAL
        return R.PASS


class LineAnalysis:
    """Judges a link, fed chunk by chunk (:meth:`feed`, :meth:`mark`, :meth:`advance`,
    :meth:`close`) or from a whole capture (:func:`~ptpcert.analysis.results.analyze`).
    ``judge``: the seats to
    judge; ``resolution``: seconds by which a timestamp may lag the byte's completion;
    ``restart_at_cases``: seats whose station is switched on at every case mark (a run
    against an IUT it restarts); ``listener``: an object with ``finding(f)`` and
    ``exchange(line, e)`` methods, told as soon as each stands."""

    def __init__(self, kit: ProcedureAnalyzer, *, judge: Iterable[str] = SEATS, resolution: float = 0.0,
                 restart_at_cases: Iterable[str] = (), listener: Any = None):
        self.kit = kit
        self.judged = tuple(s for s in SEATS if s in set(judge))
        self.resolution = float(resolution)
        self.restart_at_cases = frozenset(restart_at_cases)
        self.listener = listener
        self.chunks: list[C.Chunk] = []
        self.items: dict[str, list[Item]] = {"a": [], "b": []}
        #: per chunk: (the index of its first item in its seat's items, how many it has)
        self.chunk_items: list[tuple[int, int]] = []
        self._last_with_items: list[int] = []          # per chunk: the last earlier chunk with items (-1)
        self.marks: list[C.Mark] = []
        self.resets: list[tuple[float, str, int, frozenset]] = []
        self._reset_chunks: list[int] = []
        self.gaps: list[tuple[float, str, str]] = []    # (t, seat, condition)
        #: the times of reads that returned both seats' characters at once (consecutive chunks
        #: of both seats with one timestamp): the order of those characters is not known
        self.shared_reads: list[float] = []
        self.notes: list[tuple[float, str, str]] = []   # (t, seat, text)
        self.end: float | None = None
        self.complete = False
        self.known_until = -inf
        self.rest = kit.rest_gap() + self.resolution
        #: how far from a difference a read of unknown order or lost data may have misled
        #: the model: the resolution and two character times
        self.order_span = self.resolution + 2 * max(kit.char(s) for s in SEATS)
        self.horizon = 4 * self.rest + 1.0
        # both seats' stations are followed (what a CP 341 in each seat raises is part of every
        # finding); only the judged seats' differences are findings
        self.judges = {s: SeatJudge(self, s) for s in SEATS}
        self._done_until = -inf
        self._resync_from: dict[float, int] = {}
        self.exchanges: list[Exchange] = []
        self._open: Exchange | None = None
        self._next_chunk = 0
        self._cursors: dict[int, int] = {}

    # -- input ----------------------------------------------------------------------------
    def feed(self, chunk: C.Chunk) -> None:
        """The next chunk (chunks come in time order)."""
        if self.chunks and chunk.t < self.chunks[-1].t:
            chunk = replace(chunk, t=self.chunks[-1].t)
        k = len(self.chunks)
        prev_k = k - 1
        while prev_k >= 0 and not self.chunk_items[prev_k][1]:
            prev_k -= 1
        if (self.resolution > 0 and chunk.data and self.chunks and self.chunks[-1].t == chunk.t
                and self.chunks[-1].seat != chunk.seat and self.chunks[-1].data
                and (not self.shared_reads or self.shared_reads[-1] != chunk.t)):
            self.shared_reads.append(chunk.t)
        self.chunks.append(chunk)
        self.known_until = max(self.known_until, chunk.t)
        seat = chunk.seat
        items = self.items[seat]
        first = len(items)
        c = self.kit.char(seat)
        prev = items[-1].t if items else -inf
        cond = chunk.condition
        if cond is None or cond is C.Cond.PARITY or cond is C.Cond.FRAMING:
            data = chunk.data or b"\x00"
            kind = "byte" if cond is None else "invalid"
            n = len(data)
            ct = chunk.t
            floor = prev
            if self.resolution > 0 and n > 1:
                # a read of several characters is spread back at the line's pace, but not
                # behind the other seat's last character: with a timing resolution the order
                # of characters stamped within it of each other is the ordering rule's
                other = self.items[OTHER[seat]]
                if other and other[-1].t > floor:
                    floor = other[-1].t
            for i, b in enumerate(data):
                t = ct - (n - 1 - i) * c
                if t < floor:
                    t = floor
                start = t - c
                items.append(Item(t, kind, b, k, start if start > prev else prev))
                prev = t
        elif chunk.condition is C.Cond.BREAK:
            t = max(prev, chunk.t)
            items.append(Item(t, "break", chunk.duration, k, max(prev, t - c)))
        elif chunk.condition in C.GAPS:
            self.gaps.append((chunk.t, seat, chunk.condition.value))
        self.chunk_items.append((first, len(items) - first))
        self._last_with_items.append(prev_k)

    def mark(self, m: C.Mark) -> None:
        """A mark of the capture: a case of a run begins ("case ID ..."), or a station is
        switched on ("power-on a", "power-on b", "power-on" for both)."""
        self.marks.append(m)
        text = m.text.strip()
        low = text.lower()
        k = len(self.chunks)
        if low.startswith("case "):
            self.resets.append((m.t, text, k, self.restart_at_cases))
        elif low.startswith("power-on"):
            seats = frozenset(s for s in low[len("power-on"):].split() if s in SEATS) or frozenset(SEATS)
            self.resets.append((m.t, text, k, seats))
        else:
            return
        self._reset_chunks.append(k)

    def next_reset(self, done: int):
        return self.resets[done] if done < len(self.resets) else None

    # -- positions ------------------------------------------------------------------------
    def index_of_chunk(self, items: list[Item], k: int) -> int:
        lo, hi = 0, len(items)
        while lo < hi:
            mid = (lo + hi) // 2
            if items[mid].chunk < k:
                lo = mid + 1
            else:
                hi = mid
        return lo

    def index_at(self, items: list[Item], t: float) -> int:
        lo, hi = 0, len(items)
        while lo < hi:
            mid = (lo + hi) // 2
            if items[mid].start < t - EPS:
                lo = mid + 1
            else:
                hi = mid
        return lo

    def chunk_start(self, k: int) -> float:
        first, n = self.chunk_items[k]
        if not n:
            return self.chunks[k].t
        return self.items[self.chunks[k].seat][first].start

    def quiet_before(self, item: Item) -> float:
        """How long the line was quiet before ``item``'s chunk (inf at the capture's start)."""
        p = self._last_with_items[item.chunk]
        return inf if p < 0 else item.start - self.chunks[p].t

    def resync_chunk(self, since: float | None, after: int = -1) -> tuple[int, int] | None:
        """Where to follow a seat again after ``since`` (and in a chunk after ``after``): the
        first chunk that follows a quiet line (or begins the capture), or where the procedure
        sees an exchange begin with both stations at rest. (chunk, index of the item in it)."""
        if since is None or since == inf:
            return None
        # a chunk's answer depends only on it and the chunks before it: a search that found
        # nothing goes on from where it stopped (a busy line is not scanned anew at every step)
        start = max(self._first_after(since), self._resync_from.get(since, 0), after + 1)
        for k in range(start, len(self.chunks)):
            if not self.chunk_items[k][1]:
                continue
            p = self._last_with_items[k]
            if since == -inf or p < 0 or self.chunks[k].t - self.chunks[p].t >= self.rest:
                self._resync_from[since] = k
                return k, 0
            j = self.kit.resync_at(self, k)
            if j is not None:
                self._resync_from[since] = k
                return k, j
        self._resync_from[since] = len(self.chunks)
        return None

    def before(self, k: int, n: int, within: int = 0) -> list[tuple[str, Item]]:
        """The last ``n`` items of the line before chunk ``k`` (both seats, in time order), or
        before its item ``within``."""
        first, m = self.chunk_items[k]
        seat = self.chunks[k].seat
        out: list[tuple[str, Item]] = [(seat, it) for it in self.items[seat][first:first + within]]
        j = k - 1
        while j >= 0 and len(out) < n:
            first, m = self.chunk_items[j]
            seat = self.chunks[j].seat
            out[:0] = [(seat, it) for it in self.items[seat][first:first + m]]
            j -= 1
        return out[-n:]

    def _first_after(self, t: float) -> int:
        if t == -inf:
            return 0
        lo, hi = 0, len(self.chunks)
        while lo < hi:
            mid = (lo + hi) // 2
            if self.chunks[mid].t <= t:
                lo = mid + 1
            else:
                hi = mid
        return lo

    # -- judging --------------------------------------------------------------------------
    def advance(self, now: float) -> None:
        """Judge what can be judged at ``now`` (live use): everything up to a character time
        before it, except a byte the model sends whose window is still open and which the
        seat has not sent yet."""
        self.known_until = max(self.known_until, now)
        # a byte that began before now may not have been read yet: judge up to where every
        # byte that began is in (a character time, and the resolution, behind)
        until = now - max(self.kit.char(s) for s in SEATS) - self.resolution - 2 * QUANTUM
        if until <= self._done_until:
            return
        for j in self.judges.values():
            j.advance(until)
        self._done_until = until
        self._segment(until)

    def close(self, end: float | None = None) -> None:
        """The recording has ended (at ``end``, when known): judge everything."""
        last = self.chunks[-1].t if self.chunks else 0.0
        # a recording whose end is not known ended no sooner than its last character: what
        # was due after that is not judged
        self.end = max(end, last) if end is not None else last
        self.complete = True
        self.known_until = inf
        for j in self.judges.values():
            j.end = self.end
            j.advance(inf, final=True)
            j.finish()
        self._done_until = inf
        self._segment(inf, final=True)

    # -- findings -------------------------------------------------------------------------
    def graded(self, f: Finding, anchored: bool = True, since: float | None = None) -> Finding:
        """A finding that the recording itself may explain is informational: near a place
        where it lost data, or before the seat's model was first seen at rest after the
        recording began (it may have begun inside an exchange, which the model joined at rest)."""
        if f.grade != R.FAIL:
            return f
        near = self._gaps_near(f.t, since)
        shared = None if near or f.order_free else self._shared_read_near(f.t, since)
        if near:
            f.grade = R.INFORMATIONAL
            f.notes.append(f"the recording lost data {1000 * (near[0][0] - f.t):+.3f} ms from here "
                           f"({near[0][2]} on seat {near[0][1]}'s line): the model may have missed a character")
        elif shared is not None:
            f.grade = R.INFORMATIONAL
            f.notes.append(f"both stations' characters were read at once {1000 * (shared - f.t):+.3f} ms from here: "
                           f"their order within the timing resolution ({1000 * self.resolution:.3f} ms) is not "
                           "known, and the model may have taken them in the wrong one")
        elif not anchored:
            f.grade = R.INFORMATIONAL
            f.notes.append("the model had not yet been seen at rest since the recording began: the recording may "
                           "have begun inside an exchange, which the model joined at rest")
        return f

    def _gaps_near(self, t: float, since: float | None) -> list[tuple[float, str, str]]:
        """Places where the recording lost data that may explain a difference at ``t``. Without
        the model's last rest point (``since``): any within the longest timer. With it: one
        since then (what the model took in around it, it carried on with), or one a little
        later whose late characters, stamped back from their read, reach back to ``t``."""
        if since is None:
            return [g for g in self.gaps if abs(g[0] - t) <= self.rest]
        span = self.order_span
        out = []
        for g in self.gaps:
            if g[0] <= t:
                if g[0] > since or g[0] >= t - span:
                    out.append(g)
            elif self._gap_reach(g[0]) - span <= t:
                out.append(g)
        return out

    def _gap_reach(self, g: float) -> float:
        """How far back the characters read at a place where data was lost are stamped."""
        k = self._first_after(g - 1e-9)
        reach = g
        while k < len(self.chunks) and self.chunks[k].t <= g + 1e-9:
            first, n = self.chunk_items[k]
            if n:
                reach = min(reach, self.items[self.chunks[k].seat][first].start)
            k += 1
        return reach

    def _shared_read_near(self, t: float, since: float | None = None) -> float | None:
        """A read that returned both seats' characters at once where their unknown order may
        have misled the model that departed from the seat at ``t``: since the model was last
        at rest (``since``; from there on it carried what it took in), or within the timing
        resolution and two character times of ``t``."""
        reads = self.shared_reads
        if not reads:
            return None
        span = self.order_span
        # a read before the rest point was taken in before the model rested: settled
        lo = t - span if since is None else min(t - span, since)
        i = bisect.bisect_right(reads, lo)
        return reads[i] if i < len(reads) and reads[i] <= t + span else None

    def found(self, f: Finding) -> None:
        if self.listener is not None and hasattr(self.listener, "finding"):
            self.listener.finding(f)

    def note(self, seat: str, t: float, text: str) -> None:
        self.notes.append((t, seat, text))

    def findings(self) -> list[Finding]:
        return sorted((f for j in self.judges.values() for f in j.findings), key=lambda f: f.t)

    # -- exchanges ------------------------------------------------------------------------
    def _boundary(self, k: int) -> bool | None:
        """Does chunk ``k`` begin a new exchange? None: not settled yet."""
        first, n = self.chunk_items[k]
        if not n:
            return False
        p = self._last_with_items[k]
        if p < 0:
            return True
        i = bisect.bisect_right(self._reset_chunks, p)
        if i < len(self._reset_chunks) and self._reset_chunks[i] <= k:
            return True
        if self.chunks[k].t - self.chunks[p].t >= self.rest:
            return True
        if not self.judged:
            return False
        for s in self.judged:
            f = self.judges[s].flag(k)
            if f is None:
                return None
            if f is not True:
                return False
        return True

    def _segment(self, until: float, final: bool = False) -> None:
        chunks = self.chunks
        while self._next_chunk < len(chunks):
            k = self._next_chunk
            if chunks[k].t > until and not final:
                break
            b = True if final and self._open is None else self._boundary(k)
            if b is None:
                if not final:
                    break
                b = False
            if b or self._open is None:
                self._finish_open()
                self._open = Exchange(len(self.exchanges) + 1, k, k, chunks[k].t, chunks[k].t)
            else:
                self._open.last, self._open.t1 = k, chunks[k].t
            self._next_chunk += 1
        e = self._open
        if e is not None and (final or (self._next_chunk >= len(chunks) and until - e.t1 >= self.rest
                                        and all(j.settled >= len(chunks) or j.run is None
                                                for j in map(self.judges.get, self.judged)))):
            self._finish_open()

    def _finish_open(self) -> None:
        e = self._open
        if e is None:
            return
        self._open = None
        self.exchanges.append(e)
        # a chunk's characters end up to its time: its first one bounds the exchange (a finding
        # on a character of a chunk read at once belongs to that chunk's exchange)
        nxt = self._begin(e.last + 1) if e.last + 1 < len(self.chunks) else inf
        lo = -inf if e.index == 1 else self._begin(e.first)
        cur, slack = self._cursors, self.horizon
        for j in self.judges.values():
            e.findings += _between(j.findings, lo, nxt, _time_of, cur, slack)
            e.events[j.seat] = [c for _, c in _between(j.events, lo, nxt, _first, cur, slack)]
        e.findings.sort(key=_time_of)
        e.notes = [f"seat {s}: {text}" for t, s, text in _between(self.notes, lo, nxt, _first, cur, slack)]
        cases = [m.text for m in self.marks if m.t <= e.t0 + EPS and m.text.lower().startswith("case ")]
        e.case = cases[-1] if cases else ""
        if self.listener is not None and hasattr(self.listener, "exchange"):
            self.listener.exchange(self, e)

    def _begin(self, k: int) -> float:
        """When the first character of chunk ``k`` was complete (its time if it has none)."""
        first, n = self.chunk_items[k]
        return self.items[self.chunks[k].seat][first].t if n else self.chunks[k].t

    def exchange_items(self, e: Exchange) -> list[tuple[str, Item]]:
        out = []
        for k in range(e.first, e.last + 1):
            seat = self.chunks[k].seat
            first, n = self.chunk_items[k]
            out += [(seat, it) for it in self.items[seat][first:first + n]]
        return out

    def label(self, e: Exchange) -> str:
        return self.kit.label(self.exchange_items(e)) or f"{e.last - e.first + 1} chunks"


def _time_of(f: Finding) -> float:
    return f.t


def _first(x: tuple) -> float:
    return x[0]


def _between(items: list, lo: float, hi: float, key: Callable[[Any], float], cursor: dict, slack: float) -> list:
    """The items with lo <= key < hi. The items come nearly in time order (none later than
    ``slack`` out of place) and the calls ask for later and later times: a cursor per list
    keeps each call short."""
    n = len(items)
    i = min(cursor.get(id(items), 0), n)
    while i > 0 and key(items[i - 1]) >= lo - slack:
        i -= 1
    while i < n and key(items[i]) < lo - slack:
        i += 1
    cursor[id(items)] = i
    out = []
    while i < n:
        k = key(items[i])
        if k >= hi + slack:
            break
        if lo <= k < hi:
            out.append(items[i])
        i += 1
    return out
