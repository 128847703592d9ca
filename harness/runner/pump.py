"""The line of one case: the byte pump that reads what the IUT sends (with the deadline a
step gives, looking at least every few milliseconds in real time), the record of
everything on the line (the transcript, bounded by the flood limit), and the reading
position the steps consume the IUT's bytes from.

:class:`CaseLine` is the case's state that every layer above shares (the vector, its
parameters, the tolerance, the reference time ``ref``), on top of the machine watch
(:class:`ptpcert.runner.disturbance.MachineWatch`), which it samples after every read. The
partner play (:mod:`ptpcert.runner.partner`) and the step interpreter
(:mod:`ptpcert.runner.steps`) build on it. All waiting of a case happens in
:meth:`CaseLine.pump`, through :meth:`Transport.read` with a deadline.

The per-byte paths are here (``CaseLine._take_in`` for a long block read in one go,
:meth:`CaseLine.record`, :meth:`CaseLine.consume`): keep them to plain list and dict work.
"""

from __future__ import annotations

from typing import Any

from ptpcert import results as R
from ptpcert.scenario import Step, Vector
from ptpcert.transport.base import Transport

from .disturbance import MachineWatch
from .options import RunOptions, Tolerance


class Flood(RuntimeError):
    """The IUT sent more bytes in one case than the flood limit (a fail)."""


class StepFailed(Exception):
    """A step (or the partner play) found the IUT otherwise than the case expects: the
    divergence, in words, and whether only its timing was off (``late_only``)."""

    def __init__(self, div: R.Divergence, message: str, late_only: bool = False):
        self.div, self.message, self.late_only = div, message, late_only
        super().__init__(message)


class CaseLine(MachineWatch):
    """One vector's line against an open transport: what came and went when, and where the
    steps have read to."""

    def __init__(self, vector: Vector, steps: tuple[Step, ...], tr: Transport,
                 params: Any, tol: Tolerance, opts: RunOptions):
        self.v, self.steps, self.p, self.tol, self.opts = vector, steps, params, tol, opts
        self.proc = proc = vector.proc
        #: the conforming partner the tester plays where a vector lets it
        self.tp = proc.tester_params(params, vector.tester_params)
        self.char = proc.char_time(params)
        self.tester_char = proc.char_time(self.tp)
        edges = proc.edge_timers(params)
        #: a late stimulus matters only near the IUT's shortest timer; the line is quiet
        #: after the longest
        #: how late the IUT may begin a transmission besides (Procedure.transmit_lead)
        self.lead = proc.transmit_lead(params)
        self.longest = max(edges) + self.lead
        super().__init__(tr, min(edges))
        self.t0 = tr.now()
        #: what the next step's times count from (the end of the last thing on the line)
        self.ref = self.t0
        self.rx: list[tuple[float, int]] = []
        self.rx_log: list[int] = []   # where each received byte is in the transcript
        #: per received byte, the earliest it may have left the IUT (real time: the look
        #: before the read that returned it; otherwise its stamp)
        self.rx_floor: list[float] = []
        self.pos = 0
        self.log: list[dict] = []
        #: bytes on the line not kept in the transcript (beyond the flood limit), per side
        self.dropped: dict[str, int] = {}
        self.dropped_at: dict[str, tuple[float, int]] = {}
        self.kept: dict[str, int] = {"tester": 0, "iut": 0}
        #: the waits the protocol itself forced in this case (seconds; the harness's overhead
        #: is measured against them)
        self.forced = 0.0
        self.step_index = -1
        #: bytes an expect step passes over where it does not expect them
        self.skippable = frozenset(proc.interleaved(params))
        # What was on the line when, as exactly as the harness can know it (real time only):
        # the harness looks at the line at least every ``look`` seconds while it waits, so an
        # IUT byte it reads left the IUT after the look before (its lower bound, by log
        # index); a descheduled harness misses looks, and the bound shows it.
        self.look = max(0.001, min(0.005, self.shortest / 10))
        self.last_look = self.t0
        self.lower_bound: dict[int, float] = {}

    def rel(self, t: float) -> float:
        """A time as the transcript gives it: seconds since the case's line opened, to the
        microsecond."""
        return round(t - self.t0, 6)

    def pump(self, deadline: float) -> None:
        """Look at the line once: read what the IUT sent by ``deadline`` (in real time by one
        look period at the most, then watch the machine) and take it in. Beyond the flood
        limit, what is left is only counted, and Flood ends the case."""
        if self.realtime:
            looked = self.last_look
            until = min(deadline, looked + self.look) if deadline > looked else deadline
            items = self.tr.read(until)
            self.last_look = items[-1][0] if items else self.tr.now()
            self.watch(until)
        else:
            items = self.tr.read(deadline)
        limit = self.opts.flood_limit
        room = max(0, limit - len(self.rx))
        if items:
            self._take_in(items[:room], looked if self.realtime else None)
        if len(items) > room:
            self._drop("iut", len(items) - room, items[room][0])
            raise Flood(f"the IUT sent more than {limit} bytes in one case (the transcript keeps the first {limit})")

    def _take_in(self, items: list[tuple[float, int]], looked: float | None) -> None:
        """Keep the IUT's bytes of one read: received, stamped and logged. This is the
        harness's inner loop while an IUT sends a long block (a 1024-byte block stuffed with
        DLEs is 2,051 bytes in one read), and the tester's reply as a partner waits for it: so
        it is kept to plain list and dict work per byte (the same as ``record`` per byte)."""
        self.rx.extend(items)
        log, rx_log, step = self.log, self.rx_log, self.step_index
        t0, last_t, rt = self.t0, None, 0.0
        if looked is None:
            self.rx_floor.extend(t for t, _ in items)
        else:
            self.rx_floor.extend([looked] * len(items))
            lb, lower_bound = self.rel(looked), self.lower_bound
        # (the caller keeps the IUT's bytes within the flood limit: all of these are logged)
        for t, b in items:
            i = len(log)
            if looked is not None:
                lower_bound[i] = lb
            rx_log.append(i)
            if t != last_t:
                last_t, rt = t, round(t - t0, 6)
            log.append({"t": rt, "dir": "iut", "kind": "byte", "byte": b, "step": step})
        self.kept["iut"] += len(items)

    def record(self, entry: dict) -> None:
        """Log a byte, a character error or a BREAK on the line; beyond the flood limit of
        one side, only count it (a transcript is bounded, whatever the IUT does)."""
        d = entry["dir"]
        if self.kept[d] >= self.opts.flood_limit:
            self._drop(d, 1, self.t0 + entry["t"])
            return
        self.kept[d] += 1
        self.log.append(entry)

    def _drop(self, d: str, n: int, t: float) -> None:
        self.dropped[d] = self.dropped.get(d, 0) + n
        self.dropped_at.setdefault(d, (t, self.step_index))

    def transcript(self) -> list[dict]:
        """The transcript as the results keep it: bytes as runs, and a marker of what was
        not kept."""
        out = R.pack_transcript(self.log)
        for d, n in self.dropped.items():
            t, step = self.dropped_at[d]
            out.append({"t": self.rel(t), "dir": d, "kind": "dropped", "bytes": n,
                        "kept": self.opts.flood_limit, "step": step})
        return out

    def wait_until(self, t: float) -> None:
        """Watch the line until ``t`` (a step's bytes go out on time from here)."""
        now = self.tr.now()
        if self.realtime and now - self.last_look > self.look and now >= t:
            self.pump(now)   # behind time (sending a long block): still look at the line
        while self.tr.now() < t:
            self.pump(t)

    def consume(self) -> tuple[float, int]:
        """Take the next received byte; the transcript then shows it under the step that
        consumed it (not the one that was running when it arrived)."""
        item = self.rx[self.pos]
        self.log[self.rx_log[self.pos]]["step"] = self.step_index
        self.pos += 1
        return item

    def next_byte(self, deadline: float) -> tuple[float, int] | None:
        """The next received byte, not consumed, waiting for it until ``deadline`` (None: none
        came by then)."""
        while self.pos >= len(self.rx):
            if self.tr.now() >= deadline:
                return None
            self.pump(deadline)
        return self.rx[self.pos]

    def next_wanted(self, deadline: float, wanted: set[int]) -> tuple[float, int] | None:
        """The next received byte, passing over the procedure's interleaved bytes (e.g. an
        XON) that arrive in time and are not among those ``wanted`` here."""
        while True:
            item = self.next_byte(deadline)
            if item is None or item[0] > deadline or item[1] not in self.skippable or item[1] in wanted:
                return item
            self.consume()
            self.log[self.rx_log[self.pos - 1]]["skipped"] = True

    def fail(self, expected: str, observed: str, t: float, window=None, late_only=False):
        """End the case at the current step: the IUT did ``observed`` at ``t`` where the case
        expected ``expected`` (in ``window``, absolute times, where there was one)."""
        div = R.Divergence(self.step_index, self.rel(t), expected, observed,
                           None if window is None else (self.rel(window[0]), self.rel(window[1])))
        raise StepFailed(div, f"step {self.step_index + 1}: expected {expected}; {observed}", late_only)

    def mark(self, kind: str, **kw) -> None:
        """Put a note in the transcript at the current step (a window watched, the start)."""
        self.log.append({"kind": kind, "dir": "note", "step": self.step_index, **kw})
