"""One seat's RK 512 frame layer, as the line reveals it (:class:`SeatFrames`).

The RK 512 analyzer (:mod:`~ptpcert.procedures.rk512.analysis.analyzer`) hands each seat's
frame layer what the 3964(R) link shows of it: a block the seat begins to send
(:meth:`SeatFrames.handed_over`), a block the seat accepted from the partner
(:meth:`~SeatFrames.received`), a block of the seat's the partner accepted
(:meth:`~SeatFrames.sent`) or never took (:meth:`~SeatFrames.failed`), and the frame layer's
own deadlines (:meth:`~SeatFrames.due`). Every such block is one RK 512 frame. The frame layer
feeds them to the seat's passive and active probes
(:mod:`~ptpcert.procedures.rk512.analysis.probe`), keeps what each side did since it was last
at rest for the alternatives to replay, and reports a frame the seat owes that did not come
within T_RES. How the seat's own frames are judged is
:class:`~ptpcert.procedures.rk512.analysis.judging.FrameJudging`, mixed in.

A frame whose block the line does not show to its end (the recording, or a case of a run,
ended inside it) is judged by what is there: its first four bytes, and a length beyond the
one due.

Where the analysis joins a line whose requests may be open (after a difference that stood,
on a line that was quiet for less than T_RES), the frame layer judges only what it can
place: a response or continuation it cannot match is not judged until the line was quiet
for longer than every T_RES, or a case mark restarted the stations.
"""

from __future__ import annotations

import bisect
import copy
from math import inf
from typing import TYPE_CHECKING

from ptpcert import results as R
from ptpcert.analysis import OTHER, SEATS
from ptpcert.analysis.interface import EPS
from ptpcert.model.codes import Code
from ptpcert.procedures.rk512.analysis.judging import COMMAND_RULE, FrameJudging, response_problem
from ptpcert.procedures.rk512.analysis.probe import Expect, Probe, to_passive
from ptpcert.procedures.rk512.model import codec as K
from ptpcert.procedures.rk512.model.table import PState

if TYPE_CHECKING:
    from ptpcert.procedures.rk512.analysis.analyzer import Rk512Analyzer


class SeatFrames(FrameJudging):
    """The RK 512 layer of one seat as the line reveals it (see the module docstring)."""

    def __init__(self, kit: "Rk512Analyzer", seat: str, *, anchored: bool | None = None):
        self.kit = kit
        self.seat = seat
        self.params = kit.rk[seat]
        self.partner = kit.rk[OTHER[seat]]
        self.passive = Probe(self.params, name=f"{seat}-passive")
        self.active = Probe(self.params, name=f"{seat}-active")
        #: what the passive side took since it was last idle, to replay with alternatives
        self.plog: list[tuple] = []
        #: what the active side did since the seat's request began, likewise
        self.alog: list[tuple] = []
        #: the readings, condition or timing the passive probe follows now (None: the model's)
        self.pvariant: tuple | None = None
        self.anchored = anchored
        self.quiet_until = -inf
        self.handed: dict[bytes, float] = {}
        self.overdue: list[Expect] = []

    def __deepcopy__(self, memo):
        # the analyzer and the parameters are shared; the probes and what was seen are copied
        new = copy.copy(self)
        memo[id(self)] = new
        for k in ("passive", "active", "plog", "alog", "handed", "overdue"):
            setattr(new, k, copy.deepcopy(getattr(self, k), memo))
        return new

    # -- state ----------------------------------------------------------------------------
    @property
    def resting(self) -> bool:
        return self.passive.resting and self.active.resting

    def deadline(self) -> float:
        t = min(self.passive.own_deadline(), self.active.own_deadline())
        for e in self.passive.expect + self.active.expect:
            if not e.reported:
                t = min(t, self._due(e))
        if self.anchored is False and self.quiet_until < t:
            t = self.quiet_until
        return t

    def _due(self, e: Expect) -> float:
        t_res = self.partner.t_res
        return e.since + 1.05 * t_res + self.kit.late_abs + 4 * self.kit.char(self.seat)

    def _anchor(self, run) -> bool:
        """Is the seat's RK 512 state known (no request open that the analysis did not see)?"""
        if self.anchored:
            return True
        memo = run.memo
        if memo.get("rk512_anchored"):
            self.anchored = True
            return True
        if self.anchored is None:
            a = run.judge.analysis
            t0 = run.t0
            quiet = self.kit.quiet()
            last = -inf
            for s in SEATS:
                items = a.items[s]
                i = bisect.bisect_left(items, t0 - EPS, key=lambda it: it.t)
                if i:
                    last = max(last, items[i - 1].t)
            at_reset = any(abs(r[0] - t0) < 1e-6 for r in a.resets)
            self.anchored = at_reset or last == -inf or t0 - last >= quiet
            self.quiet_until = last + quiet if not self.anchored else -inf
        if not self.anchored and run.now >= self.quiet_until:
            self.anchored = True
        if self.anchored:
            memo["rk512_anchored"] = True
        return bool(self.anchored)

    def _codes(self, run, probe: Probe) -> None:
        if probe.codes:
            run.events += probe.codes
            probe.codes = []

    # -- what the line shows --------------------------------------------------------------
    def handed_over(self, run, t: float, payload: bytes, partial: bool) -> None:
        """The seat began to send ``payload`` (its STX) at ``t``. ``partial``: the line shows
        only its beginning (the recording, or a case of a run, ended inside the block, or the
        block was cut off): what is there is judged now, for the whole frame never is."""
        if len(self.handed) > 8:
            self.handed.pop(next(iter(self.handed)))
        self.handed[bytes(payload)] = t
        if not partial or not payload or not self._anchor(run):
            return
        frame = bytes(payload)
        p = self.passive
        p.at(t)
        b3 = frame[2] if len(frame) >= 3 else 0
        e = p.first("P")
        if e is not None and (len(frame) < 3 or b3 == 0 or b3 not in K.COMMAND_LETTERS):
            if e.partial_judged:
                return
            e.partial_judged = True
            problem = response_problem(frame, e.frame, partial=True)
            if problem is not None:
                self._alternatives(run, t, t, frame, e, problem, partial=True)
            self._codes(run, self.passive)
        elif len(frame) >= 4 and frame[0] == K.FIRST and (b3 not in K.COMMAND_LETTERS or len(frame) < K.HEADER_LEN):
            # the beginning of a command: bytes 1 to 4 (Table 2-1)
            head = frame[:4] + bytes((1, 0, 0, 1, K.NO_FLAG, 0xFF))
            bad = self.kit.command_problem(self.seat, head)
            if bad is not None and bad[0] in (Code.CMD_BYTE1_INVALID, Code.CMD_BYTE3_INVALID, Code.CMD_BYTE4_INVALID):
                self._finding(run, t, R.FAIL, "wrong", COMMAND_RULE,
                              f"began RK 512 {K.describe(frame)} (its block not on record to its end): {bad[1]}; "
                              f"a CP 341 responder refuses it with {Code(bad[0]).text}: {COMMAND_RULE[0]} "
                              f"({COMMAND_RULE[1]})",
                              expected="a command of Table 2-1", observed=frame.hex(" ").upper())

    def received(self, run, t: float, frame: bytes) -> None:
        """The seat accepted the partner's ``frame`` at ``t``."""
        anchored = self._anchor(run)
        frame = bytes(frame)
        if to_passive(frame, self.active):
            p = self.passive
            p.at(t)
            if p.p_state is PState.IDLE and p.open is None:
                if not anchored and len(frame) >= 1 and frame[0] != K.FIRST:
                    return          # a continuation of a request opened before the analysis joined
                self.plog = []
                self.pvariant = None
                if p.memory is not None:
                    p.memory.running = True
                    flag = (frame[8], frame[9] & 15) if len(frame) >= K.HEADER_LEN else None
                    if flag is not None and flag[0] != K.NO_FLAG and p.memory.flag_exists(*flag):
                        p.memory.set_flag(*flag, 1 - p.readings.amb07_locked_value)
            self.plog.append(("rx", t, frame))
            p.received(t, frame)
            self._codes(run, p)
        else:
            a = self.active
            a.at(t)
            self.alog.append(("rsp", t, frame))
            a.received(t, frame)
            self._codes(run, a)

    def sent(self, run, t: float, frame: bytes) -> None:
        """The partner accepted the seat's ``frame`` at ``t``."""
        anchored = self._anchor(run)
        frame = bytes(frame)
        at = self.handed.get(frame, t)
        p, a = self.passive, self.active
        p.at(t)
        a.at(t)
        b3 = frame[2] if len(frame) >= 3 else 0
        owes = p.first("P") is not None
        if b3 == 0 or (b3 not in K.COMMAND_LETTERS and owes):
            self._response(run, at, t, frame, anchored)
        elif len(frame) >= 1 and frame[0] == K.CONTINUATION:
            self._continuation(run, at, t, frame, anchored)
        else:
            self._command(run, at, t, frame, anchored)
        self._codes(run, self.passive)      # (an alternative may have taken a probe's place)
        self._codes(run, self.active)

    def failed(self, run, t: float, frame: bytes) -> None:
        """The link gave up on the seat's ``frame``: the partner never took it."""
        frame = bytes(frame)
        p, a = self.passive, self.active
        e = p.first("P")
        if e is not None and (len(frame) < 3 or frame[2] == 0 or frame[2] not in K.COMMAND_LETTERS):
            p.take("P")
            p.response_failed(t, e)
            self.plog.append(("fail", t))
        elif a.first("A") is not None and frame[:1] == bytes((K.CONTINUATION,)):
            a.take("A")
            a.continuation_failed(t)
        self._codes(run, p)
        self._codes(run, a)

    def due(self, run, t: float) -> None:
        """A deadline of the frame layer: the probes' timers, a frame the seat owes."""
        anchored = self._anchor(run)
        p, a = self.passive, self.active
        p.at(t, inclusive=True)
        a.at(t, inclusive=True)
        self._codes(run, p)
        self._codes(run, a)
        for probe in (p, a):
            for e in list(probe.expect):
                if e.reported or self._due(e) > t + EPS:
                    continue
                e.reported = True
                end = run.judge.end
                if anchored and (end is None or self._due(e) <= end):     # (else the recording ended first)
                    self._missing(run, e)
                probe.expect.remove(e)
                self.overdue = self.overdue[-3:] + [e]
                if e.origin == "P":
                    p.open, p.p_state, p._t_res_p = None, PState.IDLE, inf
                    self.plog = []
                else:
                    a.drop_job()
