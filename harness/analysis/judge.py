"""The seat judge: one seat judged through the whole capture.

A :class:`SeatJudge` follows its seat with a :class:`~ptpcert.analysis.seat.SeatRun`. When the
run departs from the seat, the difference does not stand at once: the stretch since the model
was last at rest is judged again with every alternative the procedure names (the other
readings of the manual's open points, as the fuzzer does, and, where the capture's timestamps
are coarse, the other seat's bytes as early and as late as the timing resolution allows). An
alternative that follows the seat without a difference turns the finding into an
informational one, and the judge carries on with it. After a difference that stands, the
seat is not judged again until the line has been quiet long enough for every conforming
station to be at rest, until the procedure sees an exchange begin with both stations at rest,
or until a case of a ``ptpcert run`` starts (every station starts afresh, those the run
restarts switched on).

What a run finds is provisional until the run reaches its next rest point; the judge makes
it final there (:meth:`SeatJudge.committed`), and keeps, per chunk, whether the seat's model
was at rest when it began - what the line (:mod:`ptpcert.analysis.line`, which owns the
judges) needs to cut the line into exchanges. ``analysis`` is that
:class:`~ptpcert.analysis.line.LineAnalysis` (imported for type checkers only: it imports this
module).
"""

from __future__ import annotations

import bisect

from math import inf
from typing import TYPE_CHECKING, Any

from ptpcert import results as R
from ptpcert.analysis.interface import EPS, OTHER, Finding
from ptpcert.analysis.order import local_from
from ptpcert.analysis.seat import SeatRun

if TYPE_CHECKING:
    from ptpcert.analysis.line import LineAnalysis


class SeatJudge:
    """Judges one seat through the whole capture: a run that follows it, the alternatives
    tried when the run departs from it, and the resumption after a difference that stands."""

    def __init__(self, analysis: "LineAnalysis", seat: str):
        self.analysis = analysis
        self.kit = analysis.kit
        self.seat = seat
        self.obs = analysis.items[seat]
        self.inputs = analysis.items[OTHER[seat]]
        self.end: float | None = None
        self.run: SeatRun | None = None
        self.candidates: list[SeatRun] = []
        self.failing: SeatRun | None = None
        self.findings: list[Finding] = []
        self.events: list[tuple[float, int]] = []
        self.flags: dict[int, bool] = {}
        #: chunks before this index are settled: their flags are final (or unknown)
        self.settled = 0
        self.lost_at: float | None = -inf      # not following: since when (-inf: not started)
        #: the chunk where the seat was last followed again: a run begun there that departs
        #: again is not begun there once more (the next resumption is in a later chunk), so
        #: the judge always moves on, whatever the timestamps of the chunk's bytes
        self.resumed_in = -1
        self.resets_done = 0
        #: the model has been seen at rest after taking part in the line (or began where the
        #: line was quiet, or at a case mark): its findings are not the recording's start
        self.anchored = False

    # -- provisional results become final at rest points ----------------------------------
    def partner_sent_between(self, lo: float, hi: float) -> bool:
        """Did the other seat send anything stamped after ``lo`` and by ``hi``?"""
        i = bisect.bisect_right(self.inputs, lo, key=lambda it: it.t)
        return i < len(self.inputs) and self.inputs[i].t <= hi

    def committed(self, run: SeatRun) -> None:
        if run is self.run:
            if not self.anchored and (run.i_in, run.i_obs) != run.start_pos:
                self.anchored = True
            self._take(run)

    def _take(self, run: SeatRun) -> None:
        for f in run.findings:
            self._emit(f)
        run.findings = []
        self.events += run.events
        run.events = []
        for t, n in run.notes:
            self.analysis.note(self.seat, t, n)
        run.notes = []
        self.flags.update(run.flags)
        run.flags.clear()
        a = self.analysis
        n = len(a.chunks)
        k_in = self.inputs[run.i_in].chunk if run.i_in < len(self.inputs) else n
        k_obs = self.obs[run.i_obs].chunk if run.i_obs < len(self.obs) else n
        self.settled = max(self.settled, min(k_in, k_obs))

    def _emit(self, f: Finding, since: float | None = None) -> None:
        if self.seat not in self.analysis.judged:
            return
        f = self.analysis.graded(f, self.anchored, since)
        self.findings.append(f)
        self.analysis.found(f)

    def flag(self, k: int) -> Any:
        """Was the seat's model at rest when chunk ``k`` began? True/False, "unknown" (not
        followed there), or None (not settled yet)."""
        if k in self.flags:
            return self.flags[k]
        if k < self.settled:
            return "unknown"
        return None

    # -- driving --------------------------------------------------------------------------
    def advance(self, until: float, final: bool = False) -> None:
        a = self.analysis
        for _ in range(10_000_000):
            reset = a.next_reset(self.resets_done)
            limit = until if reset is None else min(until, reset[0] - 1e-7)
            if self.failing is not None:
                # the stretch being decided ends at the next reset, or with the recording
                if not self._decide(limit, final or (reset is not None and reset[0] <= until)):
                    return
                continue
            if self.run is None and not self._resume(limit):
                if reset is not None and reset[0] <= until:
                    self._reset(reset)
                    continue
                if final:
                    self.settled = len(a.chunks)
                return
            run = self.run
            res = run.step(limit)
            if res == "fail":
                if run.failed.kind == "end":
                    self._take(run)
                    self.run, self.lost_at = None, inf
                    continue
                self._start_deciding(run)
                continue
            if res == "wait":
                return
            if reset is not None and reset[0] <= until:
                self._reset(reset)
                continue
            return
        raise RuntimeError("line analysis makes no progress")

    def finish(self) -> None:
        """The recording has ended: what is provisional becomes final."""
        if self.failing is not None:
            self._decide(inf, True)
        if self.run is not None:
            self._close_run(self.run)
        self.settled = len(self.analysis.chunks)

    def _close_run(self, run: SeatRun) -> None:
        self._take(run)
        if run.expect_startup:
            rule, ref, code = self.kit.startup_rule(self.seat)
            self._emit(Finding(self.seat, run.t0, R.FAIL, "start-up", rule, ref,
                               f"no start-up {self.kit.startup_name(self.seat)} after the station was switched on: "
                               f"{rule} ({ref})",
                               expected=rule, observed="nothing", codes=(code,) if code else ()))

    def _reset(self, reset: tuple[float, str, int, frozenset]) -> None:
        """A case of a run begins: every station starts afresh (those the run restarts are
        switched on)."""
        t, _text, chunk, power = reset
        self.resets_done += 1
        if self.failing is not None:
            self._decide(t, True)
        if self.run is not None:
            self._close_run(self.run)
        self.settled = max(self.settled, chunk)
        i_in = self.analysis.index_of_chunk(self.inputs, chunk)
        i_obs = self.analysis.index_of_chunk(self.obs, chunk)
        self.run = SeatRun(self, self.kit.fresh(self.seat, t), t, i_in, i_obs,
                           expect_startup=self.seat in power and self.kit.announces_startup(self.seat))
        self.lost_at = None
        self.anchored = True

    def _resume(self, until: float) -> bool:
        """Not following the seat: start again where the line has been quiet long enough."""
        a = self.analysis
        while True:
            found = a.resync_chunk(self.lost_at, after=self.resumed_in)
            if found is None:
                return False
            k, j = found
            seat_k = a.chunks[k].seat
            first = a.chunk_items[k][0] + j
            start = a.items[seat_k][first].start
            if self.lost_at is None or self.lost_at == -inf or a.items[seat_k][first].t > self.lost_at:
                break
            # a chunk read after the difference whose bytes, stamped back from its read, began
            # before it: the exchange that departed, not a new one
            self.resumed_in = k
        t0 = start - 2 * self.kit.char(self.seat) - 1e-6
        prev = a.items[seat_k][first - 1].t if j else (a.chunks[k - 1].t if k > 0 else -inf)
        t0 = max(t0, prev + EPS)
        if t0 > until:
            return False
        self.settled = max(self.settled, k + (1 if j else 0))
        self.resumed_in = k
        i_in = a.index_of_chunk(self.inputs, k) + (j if seat_k != self.seat else 0)
        i_obs = a.index_of_chunk(self.obs, k) + (j if seat_k == self.seat else 0)
        self.run = SeatRun(self, self.kit.fresh(self.seat, t0), t0, i_in, i_obs)
        if k > 0 or a.chunks[0].t >= a.rest:
            self.anchored = True    # after a quiet line every conforming station is at rest
        self.lost_at = None
        return True

    def _start_deciding(self, run: SeatRun) -> None:
        self.failing = run
        t_r, i_in, i_obs, startup, memo = run.rest
        self.candidates = []
        if self.seat not in self.analysis.judged:
            return      # followed for its STATUS events only: no alternatives
        for v in self.kit.variants(self.seat, self.analysis.resolution):
            host = self.kit.fresh(self.seat, t_r, v.readings)
            cand = SeatRun(self, host, t_r, i_in, i_obs, variant=v, expect_startup=startup)
            cand.memo = dict(memo)
            cand.shift_until = run.failed.t
            if v.local:
                cand.shift_from = local_from(self.inputs, self.obs, run.failed.t)
            self.candidates.append(cand)

    def _decide(self, until: float, final: bool) -> bool:
        """Run the alternatives; True when the difference stands or an alternative was taken."""
        run = self.failing
        t_fail = run.failed.t
        for cand in list(self.candidates):
            res = cand.step(until, rest_after=t_fail)
            if res == "rest" or (res == "fail" and cand.failed.kind == "end"):
                self._adopt(run, cand)
                return True
            if res == "fail" or (res == "wait" and final):
                self.candidates.remove(cand)
        if self.candidates and not final:
            return False
        if self.candidates:     # no more of the line: an alternative that never departed stands
            self._adopt(run, self.candidates[0])
            return True
        # the difference stands
        self._take(run)
        self._emit(run.failed, since=run.rest[0])
        self.failing, self.candidates, self.run = None, [], None
        self.lost_at = run.failed.t
        return True

    def _adopt(self, failing: SeatRun, cand: SeatRun) -> None:
        f = failing.failed
        v = cand.variant
        kind = v.kind or ("reading" if v.readings is not None else "resolution")
        cand.findings.insert(0, Finding(
            self.seat, f.t, R.INFORMATIONAL, kind, f.rule,
            f.reference, f"{f.message} - but the model {v.description} follows the seat",
            expected=f.expected, observed=f.observed, window=f.window, codes=f.codes,
            readings=(v.name,) if kind == "reading" else (), rules=f.rules))
        self.failing, self.candidates = None, []
        if cand.failed is not None:      # the recording ended: nothing more to follow
            self._take(cand)
            self.run, self.lost_at = None, inf
            return
        self.run = cand
        cand.variant = None   # from here on the run is the judge's own
        if cand.rested(cand.now):
            self._take(cand)
