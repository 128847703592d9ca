"""The UART transmitter of a model station: what the station has scheduled to send, and
when each of its characters leaves the line.

A station hands its transmitter whole runs of characters (:meth:`Transmitter.schedule`);
the characters of a run go out back to back, one character time apart, after whatever is
already scheduled. The driver or link above the station takes them off as they start
(:meth:`Transmitter.pop`), so the transmitter always knows which characters are already on
the line when something interrupts the station: a character that has started cannot be
taken back (:meth:`Transmitter.cut`). A real-time driver that wrote late, or an analysis
that learns a transmission began earlier, moves what is still scheduled
(:meth:`Transmitter.shift`).

Each run carries a ``kind`` (a station's own label, e.g. data or flow control) and a
``why`` (whatever the station keeps to explain it); the transmitter only hands them back.
What the station's public interface makes of it (``pop_output``, ``busy_until``,
``transmitting``, its deadlines) stays in the station: this module knows no procedure.

Pure: standard library only, no clock, no I/O. Sits in the neutral model below every
procedure's station, which owns one transmitter and tells it the time. Speed matters here:
fuzzing and benchmarks put hundreds of thousands of characters through it.
"""

from __future__ import annotations

from collections import deque
from math import inf
from typing import Any

#: The model's time tolerance in seconds: instants closer together than this are one.
EPS = 1e-9

#: The default kind of a run.
DATA = "data"


def characters(runs, char: float) -> list[tuple[float, int]]:
    """The characters of ``runs`` ((start of the first character, bytes), sent back to back
    ``char`` seconds apart) one by one, as (start time, byte) pairs in order."""
    out: list[tuple[float, int]] = []
    for start, data in runs:
        out.extend((start + i * char, b) for i, b in enumerate(data))
    return out


class Transmitter:
    """A station's transmitter; ``char`` is the character time in seconds (0: characters
    take no time on the line)."""

    __slots__ = ("char", "runs", "free_at", "popped_end", "popped_end_of")

    def __init__(self, char: float) -> None:
        self.char = char
        #: what is scheduled and not handed out yet, in line order, as runs
        #: [start of the first character, bytes, kind, why]
        self.runs: deque[list] = deque()
        #: when everything scheduled so far will have left the line (-inf before the first)
        self.free_at = -inf
        #: when the last character handed out by :meth:`pop` has left the line
        self.popped_end = -inf
        #: the same, per kind of run
        self.popped_end_of: dict[str, float] = {}

    def schedule(self, now: float, data: bytes, kind: str = DATA, why: Any = None) -> tuple[float, float]:
        """Send ``data`` back to back as soon as the line is free, not before ``now``.
        Returns (start of its first character, end of its last)."""
        start = self.free_at
        if now > start:
            start = now
        end = self.free_at = start + len(data) * self.char
        self.runs.append([start, bytes(data), kind, why])
        return start, end

    def cut(self, limit: float, slack: float = 0.0) -> list[tuple[bytes, str, Any]]:
        """Take back every character that has not started by ``limit``: runs that start
        later go, and the last run that has begun keeps the characters that have started
        (counted up to ``limit + slack``). Returns what was taken back, in line order, as
        (bytes, kind, why)."""
        removed = []
        runs, char = self.runs, self.char
        while runs:
            start, data, kind, why = runs[-1]
            if start > limit + EPS:
                runs.pop()
                removed.append((data, kind, why))
                continue
            n = len(data) if char == 0 else min(len(data), int((limit + slack - start) / char + 1e-6) + 1)
            if n < len(data):
                runs[-1] = [start, data[:n], kind, why]
                removed.append((data[n:], kind, why))
            break
        removed.reverse()
        if runs:
            start, data = runs[-1][0], runs[-1][1]
            self.free_at = start + len(data) * char
        else:
            self.free_at = self.popped_end
        return removed

    def pop(self, now: float | None, labelled: bool = False) -> list:
        """Hand out the characters that have started by ``now`` (everything scheduled when
        ``now`` is None), in line order, as runs (start of the first character, bytes); a
        run that is partly on the line is split. With ``labelled`` each run comes as
        [start, bytes, kind, why]."""
        runs = self.runs
        if not runs:
            return []
        out = []
        char = self.char
        limit = inf if now is None else now + EPS
        whole = char == 0 or limit == inf
        ends = self.popped_end_of
        while runs:
            run = runs[0]
            start = run[0]
            if start > limit:
                break
            data = run[1]
            n = len(data) if whole else int((limit - start) / char + 1e-6) + 1
            if n < len(data):
                # the run is partly on the line: what has started goes, the rest waits
                kind, why = run[2], run[3]
                runs[0] = [start + n * char, data[n:], kind, why]
                data = data[:n]
                run = [start, data, kind, why]
                end = ends[kind] = start + n * char
                out.append(run if labelled else (start, data))
                break
            runs.popleft()
            end = ends[run[2]] = start + len(data) * char
            out.append(run if labelled else (start, data))
        if out:
            # a run never starts before the end of what was handed out before it
            self.popped_end = end
        return out

    def shift(self, delta: float) -> None:
        """Move what is scheduled, and the ends of what was handed out, by ``delta`` seconds
        (later when positive): the line carried the station's characters that much later
        (or sooner) than scheduled."""
        for run in self.runs:
            run[0] += delta
        self.free_at += delta
        self.popped_end += delta
        ends = self.popped_end_of
        for kind in ends:
            ends[kind] += delta

    def last_end(self, kind: str) -> float:
        """When the last character of this kind handed to the line (scheduled or handed
        out) leaves it; -inf if there was none."""
        for start, data, k, _ in reversed(self.runs):
            if k == kind:
                return start + len(data) * self.char
        return self.popped_end_of.get(kind, -inf)
