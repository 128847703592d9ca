"""RK 512's part of line analysis (``ptpcert analyze``, ``ptpcert monitor``).

The link below RK 512 is 3964(R) (§2.2.1; §2.2.3: every RK 512 frame is the user data of one
3964(R) block), and it is judged exactly as a stand-alone 3964(R) link is
(:class:`~ptpcert.procedures.p3964.analysis.P3964Analyzer`: blocks, acknowledgements, retries,
timers). On top of it, a *frame layer* judges what the frames say. Every block that a seat's
model station took from the partner (the seat's DLE accepted it) and every block of the seat
that the partner accepted is one RK 512 frame, and the seat's RK 512 layer is followed by two
probes built from the model's own RK 512 layer (:class:`~ptpcert.model.rk512.core.Rk512Core`,
so the analysis and the model cannot disagree):

* the *passive* probe (Fig. 2-19) is fed the partner's commands and continuation commands:
  the response it makes is what the seat owes. The seat's response must be that response:
  first or continuation response (byte 1, Table 2-2), bytes 2 and 3 00h, the REATEL the
  model's header checks give (Table 8-3) and as many data bytes (a FETCH response carries the
  chunk asked for, §2.2.3; every other response none). The data values are not judged: the
  memory behind a seat is not on the line. The response is due within the partner's T_RES
  (Figs. 2-18/2-19); a response nobody asked for, or a missing one, is a finding;
* the *active* probe (Fig. 2-18) takes each command of the seat as a job of the seat and is
  fed the partner's responses: after a response with REATEL 00h and data still to go, the
  seat owes the continuation command (its bytes 3/4 those of the first frame, its data count
  the next chunk, §2.2.3); after an error response it sends none. A command must be one a CP
  341 sends (Table 2-1, its header checked by the model's responder with room for every
  address), and a seat has at most one request of its own open (nesting depth 1, §2.2.3
  "Quasi-full-duplex").

A REATEL that a condition of the seat the line does not show explains (the CPU in STOP: 2Ah,
§7.3; a coordination flag still set: 32h, §6.3.2) is conforming; one that the other reading
of an open point of the manual (AMB-xx, :class:`~ptpcert.model.rk512.readings.Rk512Readings`)
or the seat's T_RES at the edge of its tolerance explains is an informational finding, never
a fail. The STATUS events of classes 05, 06, 09 and 0A the probes raise are what a CP 341 in
the seat raises (reported with every exchange). A command, its continuation frames and their
responses are one exchange (the seat's model is not at rest while a request is open),
labelled e.g. "a SEND DB10 DW0 20 bytes, b REATEL 00".

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
from dataclasses import dataclass, replace
from math import inf
from types import SimpleNamespace
from typing import Any

from ptpcert import results as R
from ptpcert.analysis import OTHER, SEATS, Cause, Finding, clipped
from ptpcert.model.app import Host
from ptpcert.model.codes import Code
from ptpcert.model.events import Delivered, SendDone, SendFailed
from ptpcert.procedures.p3964.analysis import HIGH_KEEPS, P3964Analyzer
from ptpcert.procedures.p3964.model import codec as L
from ptpcert.procedures.p3964.model.readings import READINGS
from ptpcert.procedures.p3964.model.station import Station3964
from ptpcert.procedures.rk512.model import codec as K
from ptpcert.procedures.rk512.model.core import Job, Rk512Core
from ptpcert.procedures.rk512.model.memory import Memory
from ptpcert.procedures.rk512.model.params import Rk512Params
from ptpcert.procedures.rk512.model.readings import RK512_READINGS
from ptpcert.procedures.rk512.model.table import AInput, AState, PInput, PState

_EPS = 1e-9
_WAITING = (AState.WAIT_RESPONSE, AState.WAIT_CONTINUATION_RESPONSE)

#: what a response carries, for people
_RESPONSE_RULE = ("RK 512 answers every command it accepted with exactly one response: byte 1 00h (FFh for a "
                  "continuation command), bytes 2 and 3 00h, byte 4 the error number (REATEL) of the responder's "
                  "checks, and data only in a FETCH response with REATEL 00h, the chunk asked for")
_RESPONSE_REF = "§2.2.3 'Response message frame'; Table 2-2; Fig. 2-19; Table 8-3"
_UNASKED = ("a response answers a command of the partner that is still unanswered: responses are never "
            "themselves answered, and a station sends none it does not owe",
            "§2.2.3 'Response message frame'; Figs. 2-13 to 2-16, 2-19; Table 8-1 16#0A01")
_MISSING = ("the responder answers a command within the requester's response monitoring time T_RES (the "
            "requester then gives up with 16#0A05)",
            "§2.2.3 'Response message frame'; Figs. 2-18, 2-19 'T > T_RES'; Table 8-1 16#0A05")
_CONT_MISSING = ("after a response with REATEL 00h to a frame of its request, the requester sends the next "
                 "continuation command within the responder's T_RES while data are left (the responder aborts "
                 "after T_RES)",
                 "§2.2.3 'Continuation frames'; Fig. 2-18 'send continuation command frame'; Fig. 2-19 'T > T_RES'")
_CONT_UNASKED = ("a continuation command follows only the response with REATEL 00h to the previous frame of "
                 "the same request, while data are left (nesting depth 1)",
                 "§2.2.3 'Quasi-full-duplex', 'Continuation frames'; Fig. 2-18; Table 8-1 16#060E")
_CONT_RULE = ("a continuation command carries the 4-byte header FFh 00h with bytes 3 and 4 of the first "
              "command frame, and the next chunk of the data: 128 bytes, the rest in the last frame (a FETCH "
              "continuation no data)",
              "§2.2.3 'Continuation frames', Table 2-1; Figs. 2-14, 2-16; Table 8-1 16#0603, 16#0605, 16#0611")
_DEPTH = ("a station has at most one request of its own open: it sends its next command only after the "
          "response to the last frame of the previous request (nesting depth 1)",
          "§2.2.3 'Quasi-full-duplex'; §6.3.2 'Parallel processing of requests'; Fig. 2-18")
_COMMAND = ("a command frame is one a CP 341 sends for a valid request: byte 1 00h, byte 2 00h, the command "
            "letter and data type of Table 2-1, a length of 1 to 1024 bytes, a valid flag and CPU number, "
            "and (SEND) the first 128 data bytes, the rest in continuation frames",
            "§2.2.3 Table 2-1, Fig. 2-13; §6.3.2 Tables 6-4 to 6-8")
_FRAME_ID = ("byte 1 of an RK 512 frame is 00h (first frame) or FFh (continuation frame)",
             "§2.2.3 Tables 2-1, 2-2; Table 8-1 16#0601, 16#0A02")

#: the reading alternatives, each with what it says
_READING_WORDS = {
    "AMB-01": "a responder accepts 'C' for counters", "AMB-03": "a responder accepts type 'X' in a SEND",
    "AMB-10": "a too-short frame is handled the other way", "AMB-13": "byte 2 of a command is checked",
    "AMB-14": "byte 5 of a byte or cell address is ignored", "AMB-16": "a SEND may be split into any chunks",
    "AMB-17": "T_RES runs from the hand-over of the command",
    "AMB-18": "the other reading of an aborted partner request",
    "AMB-20": "a CP 341's limits on FETCH of timers, counters and DX", "AMB-22": "the other CPU number readings",
    "AMB-23": "byte 9 FFh needs byte 10's low nibble Fh", "AMB-25": "a request beyond its area is an area error",
    "AMB-31": "responses go before commands", "AMB-32": "an early response ends the request",
    "AMB-33": "an error response with data reports its REATEL", "N1": "a bad byte 1 is answered with FFh",
    "N3": "a continuation's wrong count is 16#060B", "N4": "SEND data are written at the end",
    "N5": "LEN over 1024 is 16#1E41", "N6": "DB 0 is 16#0301", "N7": "a pipelined command does not abort",
}


# ------------------------------------------------------------------ memory geometry


class _Sized:
    """An area of ``n`` bytes whose contents are not known: reads give zeros, writes vanish
    (the analysis never judges data values)."""

    __slots__ = ("n",)

    def __init__(self, n: int):
        self.n = n

    def __len__(self) -> int:
        return self.n

    def __getitem__(self, s: slice) -> bytes:
        return bytes(len(range(*s.indices(self.n))))

    def __setitem__(self, s: slice, data: bytes) -> None:
        pass


class _Geometry(Memory):
    """The memory of a seat as the line sees it: which areas exist and how large they are
    (its profile's [rk512] table), the coordination flags (the application may clear them at
    any time: every first command finds its flag clear), the CPU running."""

    def __init__(self, params: Rk512Params):
        self.params = p = params
        self._db = _Sized(p.db_bytes)
        self._ranges = {K.Area.DB: p.db_range, K.Area.DX: p.dx_range}
        nb, nc = p.byte_area_bytes, 2 * p.cell_area_cells
        self.db, self.dx = {}, {}
        self.areas = {K.Area.E: _Sized(nb), K.Area.A: _Sized(nb), K.Area.M: bytearray(nb),
                      K.Area.T: _Sized(nc), K.Area.Z: _Sized(nc)}
        self.running = True

    def buffer(self, area, number: int = 0):
        if area is K.Area.DB or area is K.Area.DX:
            rng = self._ranges[area]
            return self._db if rng and rng[0] <= number <= rng[1] else None
        return self.areas[area]


def _generous(params: Rk512Params) -> Rk512Params:
    """A responder with every block number and the largest areas: what it refuses, no CP 341
    requests (the header itself is wrong)."""
    return params.with_(db_range=(1, 255), dx_range=(1, 255), db_bytes=65536, byte_area_bytes=65536,
                        cell_area_cells=32768)


# ------------------------------------------------------------------ the probes


@dataclass
class _Expect:
    """A frame the seat owes: ``origin`` "P" (a response) or "A" (a continuation command)."""

    frame: bytes
    origin: str
    owner: Any
    since: float
    code: int | None
    reported: bool = False
    partial_judged: bool = False


class _Probe(Rk512Core):
    """One side of the seat's RK 512 layer, fed what the line shows; what it would send is
    collected in :attr:`expect` instead of going to a link."""

    def __init__(self, params: Rk512Params, readings=RK512_READINGS, *, t_res: float | None = None,
                 name: str = "probe"):
        super().__init__(params, readings, memory=_Geometry(params), name=name)
        if t_res is not None:
            self._t_res = t_res
        self.frame_events = False
        self.powered = True
        self.expect: list[_Expect] = []
        self.codes: list[tuple[float, int]] = []

    def _queue(self, frame, origin, owner, detail=""):
        # the event the frame reports: its row's, or the one a check raised just before it
        row = self._row
        code = row.code if row is not None else None
        if code is None and self.codes and self.codes[-1][0] >= self.now - _EPS:
            code = self.codes[-1][1]
        self.expect.append(_Expect(bytes(frame), origin, owner, self.now, code))

    def _status(self, code, side, final=False):
        self.codes.append((self.now, int(code)))

    def take(self, kind: str) -> _Expect | None:
        for i, e in enumerate(self.expect):
            if e.origin == kind:
                return self.expect.pop(i)
        return None

    def first(self, kind: str) -> _Expect | None:
        return next((e for e in self.expect if e.origin == kind), None)

    def __deepcopy__(self, memo):
        # the parameters and readings are frozen: shared
        memo[id(self.params)] = self.params
        memo[id(self.readings)] = self.readings
        new = self.__class__.__new__(self.__class__)
        memo[id(self)] = new
        for k, v in self.__dict__.items():
            setattr(new, k, copy.deepcopy(v, memo))
        return new

    def at(self, t: float, inclusive: bool = False) -> None:
        """Run the timers due before ``t`` (inputs of an instant go before its deadlines), or
        by ``t`` (``inclusive``)."""
        limit = t + _EPS if inclusive else t - 3 * _EPS
        if self.own_deadline() <= limit:
            self.handle_timer(limit)
        if t > self.now:
            self.now = t

    # -- the passive side -----------------------------------------------------------------
    def acked(self, t: float, e: _Expect) -> None:
        """The seat's response ``e`` was accepted by the partner."""
        self.at(t)
        if e.owner is not None and e.owner is self.open and self.p_state is PState.SEND_RESPONSE:
            self._passive(PInput.RESPONSE_SENT)

    def response_failed(self, t: float, e: _Expect) -> None:
        self.at(t)
        if e.owner is not None and e.owner is self.open and self.p_state is PState.SEND_RESPONSE:
            self._passive(PInput.RESPONSE_NOT_SENT)

    # -- the active side ------------------------------------------------------------------
    def install(self, t: float, frame: bytes, handed: float | None = None) -> None:
        """The seat's first command frame ``frame`` (handed to the link at ``handed``) was
        accepted at ``t``: its job, awaiting the response."""
        self.at(t)
        h = K.decode_header(frame)
        fetch = h.is_fetch
        frames = [bytes(frame)]
        if fetch:
            frames += [h.continuation] * (len(K.chunk_sizes(h.nbytes)) - 1)
        else:
            # the continuations that carry what the first frame did not (however many it did)
            rest = h.nbytes - (len(frame) - K.HEADER_LEN)
            frames += [h.continuation + bytes(n) for n in K.chunk_sizes(rest)] if rest > 0 else []
        req = SimpleNamespace(label=K.describe(frame), length=h.nbytes)
        job = Job(req, h, frames, fetch)
        self.job = job
        self.a_state = AState.SEND_COMMAND
        self._active(AInput.COMMAND_SENT)
        self._handed(t if handed is None else handed)

    def _handed(self, at: float) -> None:
        """T_RES from the hand-over of the frame, where that reading is taken (AMB-17)."""
        if self._tres_at_handover and self.job is not None:
            self._t_res_a = at + self._t_res

    def drop_job(self) -> None:
        self.job = None
        self._t_res_a = inf
        self.a_state = AState.IDLE
        self.expect = [e for e in self.expect if e.origin != "A"]

    def continued(self, t: float, e: _Expect, frame: bytes, handed: float | None = None) -> None:
        """The seat's continuation command was accepted."""
        self.at(t)
        job = self.job
        if job is not None and self.a_state is AState.SEND_CONTINUATION:
            if job.k < len(job.frames):
                job.frames[job.k] = bytes(frame)
            self._active(AInput.COMMAND_SENT)
            self._handed(t if handed is None else handed)

    def continuation_failed(self, t: float) -> None:
        self.at(t)
        if self.a_state is AState.SEND_CONTINUATION:
            self._active(AInput.COMMAND_NOT_SENT)

    @property
    def resting(self) -> bool:
        return (self.a_state is AState.IDLE and self.p_state is PState.IDLE and self.job is None
                and self.open is None and not self.expect)


def _to_passive(frame: bytes, active: _Probe) -> bool:
    """Does a frame the seat received go to its passive side (a command)? By byte 3, as the
    model classifies (§2.2.3); a frame too short to tell is a response when one is awaited."""
    if len(frame) >= 3:
        return bool(frame[2])
    return active.a_state not in _WAITING


# ------------------------------------------------------------------ one seat's frame layer


class _Frames:
    """The RK 512 layer of one seat as the line reveals it (see the module docstring)."""

    def __init__(self, kit: "Rk512Analyzer", seat: str, *, anchored: bool | None = None):
        self.kit = kit
        self.seat = seat
        self.params = kit.rk[seat]
        self.partner = kit.rk[OTHER[seat]]
        self.passive = _Probe(self.params, name=f"{seat}-passive")
        self.active = _Probe(self.params, name=f"{seat}-active")
        #: what the passive side took since it was last idle, to replay with alternatives
        self.plog: list[tuple] = []
        #: what the active side did since the seat's request began, likewise
        self.alog: list[tuple] = []
        #: the readings, condition or timing the passive probe follows now (None: the model's)
        self.pvariant: tuple | None = None
        self.anchored = anchored
        self.quiet_until = -inf
        self.handed: dict[bytes, float] = {}
        self.overdue: list[_Expect] = []

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

    def _due(self, e: _Expect) -> float:
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
                i = bisect.bisect_left(items, t0 - _EPS, key=lambda it: it.t)
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

    def _codes(self, run, probe: _Probe) -> None:
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
            problem = _response_problem(frame, e.frame, partial=True)
            if problem is not None:
                self._alternatives(run, t, t, frame, e, problem, partial=True)
            self._codes(run, self.passive)
        elif len(frame) >= 4 and frame[0] == K.FIRST and (b3 not in K.COMMAND_LETTERS or len(frame) < K.HEADER_LEN):
            # the beginning of a command: bytes 1 to 4 (Table 2-1)
            head = frame[:4] + bytes((1, 0, 0, 1, K.NO_FLAG, 0xFF))
            bad = self.kit.command_problem(self.seat, head)
            if bad is not None and bad[0] in (Code.CMD_BYTE1_INVALID, Code.CMD_BYTE3_INVALID, Code.CMD_BYTE4_INVALID):
                self._finding(run, t, R.FAIL, "wrong", _COMMAND,
                              f"began RK 512 {K.describe(frame)} (its block not on record to its end): {bad[1]}; "
                              f"a CP 341 responder refuses it with {Code(bad[0]).text}: {_COMMAND[0]} ({_COMMAND[1]})",
                              expected="a command of Table 2-1", observed=frame.hex(" ").upper())

    def received(self, run, t: float, frame: bytes) -> None:
        """The seat accepted the partner's ``frame`` at ``t``."""
        anchored = self._anchor(run)
        frame = bytes(frame)
        if _to_passive(frame, self.active):
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
            p.frame_received(t, frame)
            for e in p.expect:
                if e.since >= t - _EPS:
                    e.since = t
            self._codes(run, p)
        else:
            a = self.active
            a.at(t)
            self.alog.append(("rsp", t, frame))
            a.frame_received(t, frame)
            for e in a.expect:
                if e.since >= t - _EPS:
                    e.since = t
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
                if e.reported or self._due(e) > t + _EPS:
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

    # -- judging the seat's frames --------------------------------------------------------
    def _finding(self, run, t: float, grade: str, kind: str, rule: tuple[str, str], message: str, *,
                 expected: str = "", observed: str = "", codes: tuple[int, ...] = (),
                 readings: tuple[str, ...] = ()) -> None:
        run.findings.append(Finding(self.seat, t, grade, kind, rule[0], rule[1], message, expected=expected,
                                    observed=observed, codes=codes, readings=readings))

    def _missing(self, run, e: _Expect) -> None:
        due = self._due(e)
        t_res = 1000 * self.partner.t_res
        if e.origin == "P":
            what = K.describe(e.frame)
            self._finding(run, due, R.FAIL, "missing", _MISSING,
                          f"RK 512 {what} missing: the partner's command was accepted "
                          f"{1000 * (due - e.since):.0f} ms ago and its T_RES is {t_res:g} ms: "
                          f"{_MISSING[0]} ({_MISSING[1]})",
                          expected=f"{what} within {t_res:g} ms", observed="nothing",
                          codes=(e.code,) if e.code else ())
        else:
            what = K.describe(e.frame)
            self._finding(run, due, R.FAIL, "missing", _CONT_MISSING,
                          f"RK 512 {what} missing: {_CONT_MISSING[0]} ({_CONT_MISSING[1]})",
                          expected=f"{what} within {t_res:g} ms", observed="nothing")

    def _response(self, run, at: float, t: float, frame: bytes, anchored: bool) -> None:
        p = self.passive
        e = p.first("P")
        if e is None:
            late = next((x for x in self.overdue if x.origin == "P"), None)
            if late is not None:
                self.overdue.remove(late)     # the late response, reported missing already
                return
            if anchored:
                self._finding(run, at, R.FAIL, "unexpected", _UNASKED,
                              f"sent RK 512 {K.describe(frame)} where it owes no response: {_UNASKED[0]} "
                              f"({_UNASKED[1]})",
                              expected="no RK 512 frame", observed=K.describe(frame),
                              codes=(Code.RESPONSE_OUT_OF_SEQUENCE,))
            return
        problem = None if e.partial_judged else _response_problem(frame, e.frame)
        if problem is not None:
            self._alternatives(run, at, t, frame, e, problem)   # may follow the seat with another probe
            p = self.passive
            e = p.first("P")
            if e is None:
                return
        p.take("P")
        p.acked(t, e)
        self.plog.append(("ack", t))

    def _alternatives(self, run, at: float, t: float, frame: bytes, e: _Expect, problem: tuple[str, str],
                      partial: bool = False) -> None:
        """The seat's response differs from the model's: a condition the line does not show,
        another reading of an open point, or the seat's T_RES at the edge of its tolerance
        may explain it; else the difference stands."""
        for name, kind, reading, probe in self.kit.passive_alternatives(self, self.plog):
            alt = probe.first("P")
            if alt is None or _response_problem(frame, alt.frame, partial) is not None:
                continue
            if partial:
                alt.partial_judged = True
            # follow the seat with the alternative from here on
            self.passive, self.pvariant = probe, (name, kind)
            text = (f"sent RK 512 {K.describe(frame)} where the model sends {K.describe(e.frame)}: {problem[0]}")
            if kind == "condition":
                run.notes.append((at, f"{text} - {name}, which the line does not show, explains it"))
            else:
                self._finding(run, at, R.INFORMATIONAL, "reading" if kind == "reading" else "timing",
                              (_RESPONSE_RULE, problem[1]),
                              f"{text} - but the model {name} follows the seat ({_RESPONSE_REF})",
                              expected=K.describe(e.frame), observed=K.describe(frame),
                              readings=(reading,) if reading else ())
            return
        codes = (e.code,) if e.code else ()
        partner_code = _partner_sees(frame, e.frame)
        self._finding(run, at, R.FAIL, "wrong", (_RESPONSE_RULE, problem[1]),
                      f"sent RK 512 {K.describe(frame)} where the model sends {K.describe(e.frame)}: {problem[0]} "
                      f"({problem[1]})" + (f"; the model's responder raises {Code(e.code).text}" if e.code else "")
                      + (f"; the partner raises {Code(partner_code).text}" if partner_code else ""),
                      expected=K.describe(e.frame), observed=K.describe(frame), codes=codes)

    def _continuation(self, run, at: float, t: float, frame: bytes, anchored: bool) -> None:
        a = self.active
        e = a.first("A")
        if e is None:
            late = next((x for x in self.overdue if x.origin == "A"), None)
            if late is not None:
                self.overdue.remove(late)     # the late continuation, reported missing already
                return
            text = f"sent RK 512 {K.describe(frame)} where no continuation is due"
            if anchored and not self._active_alternatives(run, at, t, frame, "continuation", text, _CONT_UNASKED):
                self._finding(run, at, R.FAIL, "unexpected", _CONT_UNASKED,
                              f"{text}: {_CONT_UNASKED[0]} ({_CONT_UNASKED[1]})",
                              expected="no continuation command", observed=K.describe(frame))
            if self.active.first("A") is None:
                return
            a = self.active
            e = a.first("A")
        problem = None
        if len(frame) < 4 or frame[:4] != e.frame[:4]:
            problem = (f"its header is {frame[:4].hex(' ').upper()}, not {e.frame[:4].hex(' ').upper()}",)
        elif len(frame) != len(e.frame):
            problem = (f"it carries {len(frame) - 4} data bytes, not {len(e.frame) - 4}",)
        if problem is not None:
            self._finding(run, at, R.FAIL, "wrong", _CONT_RULE,
                          f"sent RK 512 {K.describe(frame)} where the model sends {K.describe(e.frame)}: "
                          f"{problem[0]}: {_CONT_RULE[0]} ({_CONT_RULE[1]})",
                          expected=K.describe(e.frame), observed=K.describe(frame))
        a.take("A")
        a.continued(t, e, frame, at)
        self.alog.append(("cont", t, frame, at))

    def _active_alternatives(self, run, at: float, t: float, frame: bytes, what: str, text: str,
                             rule: tuple[str, str]) -> bool:
        """The seat's request went on (a continuation) or ended (a new command) where the
        model's did not: another reading of an open point, or the seat's T_RES at the edge of
        its tolerance, may explain it. True (and the seat followed with it) when one does."""
        for name, kind, reading, probe in self.kit.active_alternatives(self, self.alog, t):
            if what == "continuation":
                e = probe.first("A")
                if e is None or frame[:4] != e.frame[:4] or len(frame) != len(e.frame):
                    continue
            elif probe.job is not None or probe.a_state is not AState.IDLE:
                continue
            self.active = probe
            self._finding(run, at, R.INFORMATIONAL, "reading" if kind == "reading" else "timing", rule,
                          f"{text} - but the model {name} follows the seat ({rule[1]})",
                          observed=K.describe(frame), readings=(reading,) if reading else ())
            return True
        return False

    def _command(self, run, at: float, t: float, frame: bytes, anchored: bool) -> None:
        a = self.active
        if len(frame) < 1 or frame[0] != K.FIRST:
            if anchored:
                self._finding(run, at, R.FAIL, "wrong", _FRAME_ID,
                              f"sent RK 512 {K.describe(frame)}: {_FRAME_ID[0]} ({_FRAME_ID[1]})",
                              observed=K.describe(frame), codes=())
            return
        if a.job is not None or a.a_state is not AState.IDLE or a.expect:
            text = (f"sent RK 512 {K.describe(frame)} while its request "
                    f"{a.job.label if a.job is not None else ''} is still open")
            if anchored and not self._active_alternatives(run, at, t, frame, "command", text, _DEPTH):
                self._finding(run, at, R.FAIL, "unexpected", _DEPTH, f"{text}: {_DEPTH[0]} ({_DEPTH[1]})",
                              expected="no new command", observed=K.describe(frame))
            a = self.active
            a.drop_job()
        self.alog = [("cmd", t, frame, at)]
        bad = self.kit.command_problem(self.seat, frame)
        if bad is not None:
            code, why = bad
            self._finding(run, at, R.FAIL, "wrong", _COMMAND,
                          f"sent RK 512 {K.describe(frame)}: {why}; a CP 341 responder refuses it with "
                          f"{Code(code).text}: {_COMMAND[0]} ({_COMMAND[1]})",
                          expected="a command of Table 2-1", observed=K.describe(frame))
        if len(frame) >= K.HEADER_LEN and frame[2] in K.COMMAND_LETTERS and K.AREA_BY_CODE.get(frame[3]) is not None:
            a.install(t, frame, at)


def _response_problem(got: bytes, want: bytes, partial: bool = False) -> tuple[str, str] | None:
    """How the seat's response ``got`` differs from the model's ``want`` (data values aside):
    (what, the manual's reference), or None. ``partial``: only the beginning of the frame is
    on record (the recording, or the case, ended inside its block): what is there is judged."""
    if partial:
        if len(got) > len(want) and (len(got) > 4 or got[:4] != want[:4]):
            return _response_problem(got, want)
        n = min(len(got), 4)
        got, want = got[:n] + want[n:4], want[:4]
        if got == want:
            return None
    if len(got) < 4:
        return (f"a response has 4 bytes at least, this one {len(got)}", "Table 2-2; Table 8-1 16#0610")
    if got[0] != want[0]:
        return (f"byte 1 is {got[0]:02X}h, not {want[0]:02X}h: a {'first' if want[0] == K.FIRST else 'continuation'} "
                f"command gets a {'first' if want[0] == K.FIRST else 'continuation'} response",
                "§2.2.3 Table 2-2; Table 8-1 16#0A01, 16#0A02")
    if got[1] or got[2]:
        return (f"bytes 2 and 3 are {got[1]:02X}h {got[2]:02X}h, not 00h 00h", "§2.2.3 Table 2-2")
    if got[3] != want[3]:
        if got[3] and got[3] not in K.REATEL_STATUS:
            return (f"REATEL {got[3]:02X}h is no error number of Table 8-3 (the partner raises 16#090E); the "
                    f"model's checks give {want[3]:02X}h", "§8.4 Table 8-3; Table 8-1 16#090E")
        return (f"REATEL {got[3]:02X}h, the model's checks give {want[3]:02X}h"
                + (f" (which the requester reports as {K.status_for_reatel(want[3]).text})" if want[3] else ""),
                "§2.2.3 'Response message frame'; Fig. 2-19; §8.4 Table 8-3")
    if len(got) != len(want):
        if got[3]:
            return (f"an error response carries no data, this one {len(got) - 4} bytes",
                    "§2.2.3 'Receiving data'; Table 8-1 16#0A03, 16#0A04")
        if len(want) == 4:
            return (f"a response to a SEND carries no data, this one {len(got) - 4} bytes",
                    "§2.2.3 'SEND message frame'; Table 8-1 16#0A04")
        return (f"it carries {len(got) - 4} data bytes, the FETCH asked for {len(want) - 4} in this frame",
                "§2.2.3 'FETCH message frame', Figs. 2-15, 2-16; Table 8-1 16#0A03")
    return None


def _partner_sees(got: bytes, want: bytes) -> int | None:
    """What a CP 341 requester raises on the seat's response ``got`` where ``want`` was due."""
    if len(got) < 4:
        return Code.FRAME_TOO_SHORT
    if got[0] not in (K.FIRST, K.CONTINUATION):
        return Code.RESPONSE_STRUCTURE
    if got[0] != want[0] or got[2]:
        return Code.RESPONSE_OUT_OF_SEQUENCE
    if got[3]:
        return K.status_for_reatel(got[3])
    if len(got) != len(want):
        return Code.RESPONSE_DATA_LENGTH if len(want) > 4 else Code.RESPONSE_TO_SEND_WITH_DATA
    return None


# ------------------------------------------------------------------ the link station and its host


@dataclass(frozen=True)
class FrameDue:
    """A deadline of the frame layer was reached (an event of the analysis, not of a station)."""

    time: float


class _LinkStation(Station3964):
    """The seat's 3964(R) station, carrying the frame layer's deadlines as its own (the line
    analysis drives every deadline through the station)."""

    frames: _Frames | None = None

    def __init__(self, *args, **kw):
        super().__init__(*args, **kw)
        self._due: list[FrameDue] = []

    def next_deadline(self):
        d = super().next_deadline()
        f = self.frames.deadline() if self.frames is not None else inf
        if f < inf and (d is None or f < d):
            return f
        return d

    def handle_timer(self, now: float) -> None:
        super().handle_timer(now)
        f = self.frames.deadline() if self.frames is not None else inf
        if f <= now + _EPS:
            self._due.append(FrameDue(now))

    @property
    def has_events(self) -> bool:
        return bool(self._due) or super().has_events

    def pop_events(self):
        out = super().pop_events()
        if self._due:
            out = out + self._due
            self._due = []
        return out


class _Rk512LinkHost(Host):
    """The seat's link station with its RK 512 frame layer (``frames``)."""

    def __init__(self, station: _LinkStation, frames: _Frames):
        super().__init__(station, "none")
        self.frames = frames
        station.frames = frames


# ------------------------------------------------------------------ the analyzer


class Rk512Analyzer(P3964Analyzer):
    """Line analysis of an RK 512 link: the 3964(R) link and the RK 512 frames (module docstring).
    ``rk_params`` maps each seat to its :class:`~ptpcert.model.rk512.Rk512Params`."""

    reference = "§2.2.3; Figs. 2-13 to 2-19; Tables 2-1, 2-2, 8-3"

    def __init__(self, link_procedure: Any, rk_params: dict[str, Rk512Params], late_ms: float = 50.0):
        super().__init__(link_procedure, {s: rk_params[s].line for s in SEATS}, {"a": "none", "b": "none"}, late_ms)
        self.rk = dict(rk_params)
        self._checker: dict[str, _Probe] = {}
        self._alts: list | None = None
        self._cut: bytes | None = None
        #: per seat, the latest block whose end the line does not show
        self._partial: dict[str, bytes] = {}

    def quiet(self) -> float:
        """How long a quiet line must be before no RK 512 request can be open."""
        return 1.25 * max(p.t_res for p in self.rk.values()) + self.late_abs

    # -- stations -------------------------------------------------------------------------
    def _station(self, seat: str, readings: Any = None) -> Station3964:
        return _LinkStation(self.params[seat], readings or READINGS, name=seat, explain=True)

    def fresh(self, seat: str, t: float, readings: Any = None) -> Host:
        host = super().fresh(seat, t, readings)
        return _Rk512LinkHost(host.station, _Frames(self, seat))

    def powered(self, seat: str, t: float) -> Host:
        host = super().powered(seat, t)
        return _Rk512LinkHost(host.station, _Frames(self, seat, anchored=True))

    def at_rest(self, host: Host) -> bool:
        return host.station.idle and host.frames.resting

    def begins_in(self, host: Host, byte: int) -> bool:
        """An STX begins an exchange only while no RK 512 request is open on the seat: a
        response, a continuation command belong to the exchange of their request."""
        return self.begins(byte) and host.frames.resting

    def wrong(self, run, item, byte: int, cause: Cause) -> Cause:
        """A high-priority station that answers the partner's crossing STX with DLE, where
        the model sends its block after the partner's DLE, breaks the initialization
        conflict's rule (Fig. 2-8), not the block's."""
        inputs, k = run.judge.inputs, run.i_in
        if (item.kind == "byte" and item.value == L.DLE and run.st.params.priority == "high" and k >= 2
                and [(x.kind, x.value) for x in inputs[k - 2:k]] == [("byte", L.STX), ("byte", L.DLE)]):
            return Cause("reply", *HIGH_KEEPS, 0.0, 0.0, rules=("3964.CONFLICT.HIGH-WAITS",))
        return super().wrong(run, item, byte, cause)

    # -- the frame layer's inputs ---------------------------------------------------------
    def _seen(self, best: bytes, data: bytearray) -> bytes | None:
        out = super()._seen(best, data)
        self._cut = out         # the line shows no end of this block
        return out

    def _payload(self, run, index: int) -> Any:
        self._cut = None
        out = super()._payload(run, index)
        if isinstance(out, bytes) and out == self._cut:
            self._partial[run.judge.seat] = out
        return out

    def _request(self, run, t: float, payload: bytes) -> None:
        frames = getattr(run.host, "frames", None)
        if frames is not None:
            seat = run.judge.seat
            frames.handed_over(run, t, payload, self._partial.get(seat) == payload)
        super()._request(run, t, payload)

    def event(self, run, e) -> None:
        super().event(run, e)
        frames = getattr(run.host, "frames", None)
        if frames is None:
            return
        cls = type(e)
        if cls is Delivered:
            frames.received(run, e.time, e.payload)
        elif cls is SendDone:
            frames.sent(run, e.time, e.payload)
        elif cls is SendFailed:
            frames.failed(run, e.time, e.payload)
        elif cls is FrameDue:
            frames.due(run, e.time)

    # -- the model's decisions, reused ----------------------------------------------------
    def command_problem(self, seat: str, frame: bytes) -> tuple[int, str] | None:
        """Why no CP 341 sends the command ``frame``: (the STATUS a responder raises, what is
        wrong), or None. Byte 2 is checked first (Table 2-1: 00h), then the model's responder,
        with every block number and the largest areas, judges the header: what it refuses is
        the header's fault, not the partner's memory."""
        if frame[1:2] != b"\x00":
            return (Code.CMD_BYTE1_INVALID, f"byte 2 is {frame[1]:02X}h, not 00h")
        probe = self._checker.get(seat)
        if probe is None:
            probe = self._checker[seat] = _Probe(_generous(self.rk[seat]), name="checker")
        probe = copy.deepcopy(probe)
        probe.frame_received(0.0, bytes(frame))
        e = probe.first("P")
        code = next((c for _, c in probe.codes), None)
        if e is None or len(e.frame) < 4 or e.frame[3] == 0 or code is None:
            return None
        return (code, f"a responder with every area refuses its header with REATEL {e.frame[3]:02X}h")

    def passive_alternatives(self, frames: _Frames, log: list[tuple]):
        """The passive side replayed with each alternative: (description, kind, reading, probe)."""
        seat = frames.seat
        params = frames.params
        first = next((x[2] for x in log if x[0] == "rx"), b"")
        out = []
        conditions = [("with the CPU in STOP (§7.3; Table 8-1 16#060D)", "stop")]
        if len(first) >= K.HEADER_LEN and first[8] != K.NO_FLAG:
            conditions.append((f"with coordination flag {first[8]}.{first[9] & 15} still set by the "
                               "application (§6.3.2 'Using interprocessor communication flags')", "lock"))
        for name, cond in conditions:
            out.append((name, "condition", "", self._replay(params, RK512_READINGS, None, log, cond)))
        t_res = params.t_res
        for factor, words in ((0.95, "early"), (1.25, "late")):
            tr = factor * t_res + (self.late_abs if factor > 1 else 0.0)
            out.append((f"with its T_RES running out {1000 * abs(tr - t_res):.0f} ms {words} (within the "
                        "tolerance of a timer)", "timing", "", self._replay(params, RK512_READINGS, tr, log, None)))
        for name, change in self._alternatives():
            out.append((f"with the other reading of the manual's open point {name} "
                        f"({_READING_WORDS.get(name, 'see ptpcert.model.rk512.readings')})", "reading", name,
                        self._replay(params, replace(RK512_READINGS, **change), None, log, None)))
        return out

    def active_alternatives(self, frames: _Frames, log: list[tuple], t: float):
        """The active side replayed up to ``t`` with each alternative: (description, kind,
        reading, probe)."""
        params = frames.params
        out = []
        t_res = params.t_res
        for factor in (0.95, 1.25):
            tr = factor * t_res + (self.late_abs if factor > 1 else 0.0)
            words = "early" if factor < 1 else "late"
            out.append((f"with its T_RES running out {1000 * abs(tr - t_res):.0f} ms {words} (within the "
                        "tolerance of a timer)", "timing", "", self._replay_active(params, RK512_READINGS, tr, log, t)))
        for name, change in self._alternatives():
            out.append((f"with the other reading of the manual's open point {name} "
                        f"({_READING_WORDS.get(name, 'see ptpcert.model.rk512.readings')})", "reading", name,
                        self._replay_active(params, replace(RK512_READINGS, **change), None, log, t)))
        return out

    @staticmethod
    def _replay_active(params, readings, t_res, log, t: float) -> _Probe:
        p = _Probe(params, readings, t_res=t_res)
        for kind, at, frame, *handed in log:
            if kind == "cmd":
                if len(frame) >= K.HEADER_LEN and frame[2] in K.COMMAND_LETTERS and K.AREA_BY_CODE.get(frame[3]):
                    p.install(at, frame, *handed)
            elif kind == "rsp":
                p.at(at)
                p.frame_received(at, frame)
            elif kind == "cont":
                e = p.take("A")
                if e is not None:
                    p.continued(at, e, frame, *handed)
        p.at(t)
        p.codes = []
        return p

    def _alternatives(self) -> list:
        if self._alts is None:
            from ptpcert.procedures.rk512.fuzz import ALTERNATIVE_READINGS
            self._alts = list(ALTERNATIVE_READINGS)
        return self._alts

    @staticmethod
    def _replay(params, readings, t_res, log, condition) -> _Probe:
        p = _Probe(params, readings, t_res=t_res)
        last = max((i for i, x in enumerate(log) if x[0] == "rx"), default=-1)
        for i, x in enumerate(log):
            if x[0] == "rx":
                _, t, frame = x
                p.at(t)
                if condition == "stop" and i == last:
                    p.memory.running = False      # the CPU went to STOP before this frame
                if condition == "lock" and len(frame) >= K.HEADER_LEN and frame[0] == K.FIRST and frame[8] != K.NO_FLAG \
                        and p.memory.flag_exists(frame[8], frame[9] & 15):
                    p.memory.set_flag(frame[8], frame[9] & 15, p.readings.amb07_locked_value)
                p.frame_received(t, frame)
                for e in p.expect:
                    if e.since >= t - _EPS:
                        e.since = t
            elif x[0] == "ack":
                e = p.take("P")
                if e is not None:
                    p.acked(x[1], e)
            elif x[0] == "fail":
                e = p.take("P")
                if e is not None:
                    p.response_failed(x[1], e)
        p.codes = []
        return p

    # -- reports --------------------------------------------------------------------------
    def label(self, items) -> str:
        """The RK 512 frames of an exchange, e.g. "a SEND DB10 DW0 20 bytes, b REATEL 00"."""
        frames = _frames_of(items, {s: self.params[s].has_bcc for s in SEATS})
        if not frames:
            return super().label(items)
        words = []
        for seat, f in frames:
            kind = K.classify(f)
            if kind in (K.Kind.RESPONSE, K.Kind.CONTINUATION_RESPONSE) and len(f) >= 4:
                text = ("REATEL 00" if f[3] == 0 else f"REATEL {f[3]:02X}h") + (
                    f" + {len(f) - 4} bytes" if len(f) > 4 else "")
                if kind is K.Kind.CONTINUATION_RESPONSE:
                    text = "continuation " + text
            else:
                text = K.describe(f)
            words.append(f"{seat} {text}")
        return clipped(", ".join(words), 240)


def _frames_of(items, bcc: dict[str, bool]) -> list[tuple[str, bytes]]:
    """The blocks of an exchange's items as (seat, user data), in the order they ended: a
    block begins after the other seat's DLE answers an STX and ends with DLE ETX (the BCC
    after it skipped)."""
    out = []
    state = {s: None for s in SEATS}       # None, "stx", or a bytearray being received
    esc = {s: False for s in SEATS}
    skip = {s: 0 for s in SEATS}
    for seat, it in items:
        other = OTHER[seat]
        if it.kind != "byte":
            state[seat] = None
            continue
        b = it.value
        if skip[seat]:
            skip[seat] -= 1
            continue
        blk = state[seat]
        if isinstance(blk, bytearray):
            if esc[seat]:
                esc[seat] = False
                if b == 0x10:
                    blk.append(b)
                elif b == 0x03:
                    out.append((seat, bytes(blk)))
                    state[seat] = None
                    skip[seat] = 1 if bcc[seat] else 0
                else:
                    blk += bytes((0x10, b))
            elif b == 0x10:
                esc[seat] = True
            else:
                blk.append(b)
            continue
        if b == 0x02:
            state[seat] = "stx"
        elif b == 0x10 and state[other] == "stx":
            state[other], esc[other] = bytearray(), False
    return out
