"""The RK 512 layer without its link: both sides of the protocol (§2.2.3, Figs. 2-17 to
2-19), the partner CPU's memory, T_RES on both sides, and the events, over an abstract
lower edge that carries whole frames.

A lower layer (the 3964(R) station in :class:`~.station.Rk512Station`, or the ideal frame
link of :mod:`.framelink`) calls :meth:`Rk512Core.frame_received`, :meth:`frame_sent`
and :meth:`frame_failed`, and the core calls :meth:`_lower_send` to hand it a frame. The
core hands over one frame at a time, in the order the frames became ready (reading
AMB-31), and waits for the lower layer's verdict on it before the next.

Sans-IO, explicit time: every public method takes ``now``; :meth:`next_deadline` and
:meth:`handle_timer` run the core's own timers (T_RES of each side and the application's
wake-ups).

The module is one piece on purpose, although long: it is the core class, with one method per
input of the two transition tables (:mod:`.table`, the active and the passive side) and the
actions they share, all on the state of the open requests; its small job records come first.
"""

from __future__ import annotations

import heapq
from collections import deque
from math import inf

from ptpcert.model.codes import Code
from ptpcert.model.errors import ModelError
from ptpcert.model.events import Status

from . import table as T
from .codec import (
    AREA_BY_CODE,
    CHUNK,
    COMMAND_LETTERS,
    CONTINUATION,
    FETCH,
    FIRST,
    HEADER_LEN,
    MAX_REQUEST_BYTES,
    NO_FLAG,
    SEND_DX,
    STATUS_REATEL,
    WORD_CODES,
    Area,
    fetch_frames,
    response_head,
    send_frames,
    status_for_reatel,
)
from .events import FrameNotSent, FrameReceived, FrameSent, Ready, RequestResult, Served, Wakeup
from .memory import Memory
from .params import Rk512Params
from .readings import CHECKS, RK512_READINGS, Rk512Readings
from .requests import Request, local_check, parse_line, request_header, send_payload

A, P = T.AState, T.PState
AI, PI = T.AInput, T.PInput
_EPS = 1e-9
_DB, _DX = Area.DB.code, Area.DX.code
_COUNTER_C = 0x43
_OK_FIRST = response_head(True, 0)
_OK_CONT = response_head(False, 0)


class Job:
    """The active request in progress: its header and frames (the first and its continuations),
    the frame in flight, and what a FETCH has received and stored so far. Public: the RK 512
    line analysis builds one for a command the line shows (its probe's ``install``)."""

    __slots__ = ("req", "label", "header", "fetch", "frames", "k", "data", "remaining", "store")

    def __init__(self, req: Request, header, frames: list[bytes], fetch: bool):
        self.req = req
        self.label = req.label
        self.header = header
        self.fetch = fetch
        self.frames = frames
        self.k = 0                   # index of the frame in flight / being answered
        self.data = bytearray()      # FETCH: data received so far
        self.remaining = header.nbytes
        self.store = req.length      # FETCH: bytes stored (odd LEN to a word area: one less)


class _Open:
    """The partner request the passive side is serving."""

    __slots__ = ("b3", "b4", "fetch", "area", "number", "start", "nbytes", "done", "flag",
                 "final", "pending", "buf", "letter")

    def __init__(self):
        self.final = True
        self.pending = b""           # SEND data held back until the end (reading n4 False)


class Rk512Core:
    """Both sides of one RK 512 station over an abstract frame carrier."""

    ACTIVE = T.ACTIVE
    PASSIVE = T.PASSIVE

    def __init__(self, params: Rk512Params | None = None, readings: Rk512Readings = RK512_READINGS,
                 *, memory: Memory | None = None, name: str = "station", explain: bool = False,
                 trace: bool = False):
        self.params = params or Rk512Params()
        self.readings = readings
        self.name = name
        self.memory = memory if memory is not None else Memory(self.params)
        self.now = -inf
        self.powered = False
        self.a_state: T.AState = A.IDLE
        self.p_state: T.PState = P.IDLE
        self._events: list = []
        # output: frames waiting for the lower layer, and the one it carries now
        self._out: deque[tuple] = deque()      # (frame, origin, owner, reason)
        self._inflight: tuple | None = None
        # active side
        self._requests: deque[Request] = deque()
        self.job: Job | None = None
        self._t_res_a = inf
        # passive side
        self.open: _Open | None = None
        self._t_res_p = inf
        # application timers
        self._wake: list[tuple[float, int, object]] = []
        self._wake_seq = 0
        self._t_res = self.params.t_res
        r = readings
        if r.amb17_tres_start not in ("acknowledged", "handed_over"):
            raise ValueError(f"amb17_tres_start {r.amb17_tres_start!r}: acknowledged or handed_over")
        self._tres_at_handover = r.amb17_tres_start == "handed_over"
        # readings used on every frame, looked up once
        self._check_b2 = r.amb13_check_byte2
        self._exact = r.amb16_exact_chunks
        self._per_frame = r.n4_write_per_frame
        self._set_flag = r.amb08_set_flag_after_transfer
        unknown = set(r.n2_check_order) - CHECKS
        if unknown:
            raise ValueError(f"n2_check_order: unknown checks {sorted(unknown)}")
        self._checks = [getattr(self, "_c_" + name) for name in r.n2_check_order]
        self._flag_bytes = len(self.memory.areas[Area.M])
        self._send_types = {_DB} | ({_DX} if r.amb03_accept_send_type_x else set())
        fetch_types = set(WORD_CODES - {0x5A}) | {Area.E.code, Area.A.code, Area.M.code, r.amb01_counter_letter}
        if r.amb01_accept_c_for_counters:
            fetch_types.add(_COUNTER_C)
        p = self.params
        serves_dx = r.amb20_serve_dx_fetch if p.serves_dx_fetch is None else p.serves_dx_fetch
        if not serves_dx:
            fetch_types.discard(_DX)
        #: the declared limit of a partner's FETCH of timers/counters, else the reading's
        self._cell_limit = r.amb20_cell_fetch_limit_bytes if p.cell_fetch_limit_bytes is None \
            else p.cell_fetch_limit_bytes
        self._fetch_types = frozenset(fetch_types)
        self._area_of = dict(AREA_BY_CODE)
        self._area_of[r.amb01_counter_letter] = Area.Z
        if r.amb01_accept_c_for_counters:
            self._area_of[_COUNTER_C] = Area.Z
        # every (state, input) resolved once: (row, action, decision or None, target or None)
        self._a_rows = {s: {i: self._resolve(row, "_a_") for i, row in by.items()} for s, by in T.ACTIVE.items()}
        self._p_rows = {s: {i: self._resolve(row, "_p_") for i, row in by.items()} for s, by in T.PASSIVE.items()}
        self._row: T.Row | None = None
        self._timer_set = False
        #: Emit FrameReceived/FrameSent events (a frame carrier that records the frames
        #: itself, like FrameLink, may switch them off for speed).
        self.frame_events = True
        self.trace: list[tuple] | None = [] if trace else None
        #: With ``explain=True``: one entry per frame made ready, (time, frame, side, input,
        #: row reference, STATUS or None, detail): why the station sends what it sends.
        self.frame_log: list[tuple] | None = [] if explain else None

    # ============================================================== application interface
    def power_on(self, now: float) -> None:
        """Start-up complete: the station serves partners and takes requests."""
        self._at(now)
        self.powered = True
        self._events.append(Ready(self.now))

    def request(self, now: float, req: Request | str) -> bool:
        """A SEND or FETCH of the active side (P_SND_RK with REQ). ``req`` may be a script
        line (``"send DB10:DW0:LEN=200"``). Requests run one at a time, in order; the result
        is a :class:`RequestResult` event. Returns False when the request was refused at
        once (before power-on: 16#0502)."""
        self._at(now)
        if isinstance(req, str):
            item = parse_line(req)
            if not isinstance(item, Request):
                raise ValueError(f"{req!r} is not a send or fetch request")
            req = item
        if not self.powered:
            self._fail_now(req, Code.NOT_ALLOWED_IN_MODE)
            return False
        self._requests.append(req)
        self._active(AI.CPU_REQUEST)  # taken at once when idle, else it waits its turn
        return True

    def wake_at(self, t: float, tag: object = None) -> None:
        """An application timer: a :class:`Wakeup` event with ``tag`` at ``t``."""
        self._wake_seq += 1
        heapq.heappush(self._wake, (t, self._wake_seq, tag))

    def restart(self, now: float) -> None:
        """A CP restart of the RK 512 layer: the request in progress and the queued ones end
        with 16#0501, the partner request is dropped, frames not yet handed to the link are
        discarded (the one the link carries cannot be recalled)."""
        self._at(now)
        self._out.clear()
        queued, self._requests = list(self._requests), deque()
        self._passive(PI.RESTART)
        self._active(AI.RESTART)
        for req in queued:
            self._fail_now(req, Code.ABORTED_BY_CP_RESTART)

    @property
    def has_events(self) -> bool:
        """Whether :meth:`pop_events` has anything to return."""
        return bool(self._events)

    def pop_events(self) -> list:
        out, self._events = self._events, []
        return out

    @property
    def idle(self) -> bool:
        """Nothing to do: no request, no partner request, nothing to send."""
        return (self.a_state is A.IDLE and self.p_state is P.IDLE and not self._requests
                and not self._out and self._inflight is None)

    @property
    def pending_jobs(self) -> int:
        """Requests not finished and frames not yet acknowledged."""
        return (len(self._requests) + (self.job is not None) + len(self._out)
                + (self._inflight is not None))

    @property
    def state(self) -> str:
        return f"{self.a_state}/{self.p_state}"

    # ============================================================== time
    def own_deadline(self) -> float:
        t = self._t_res_a if self._t_res_a < self._t_res_p else self._t_res_p
        if self._wake and self._wake[0][0] < t:
            t = self._wake[0][0]
        return t

    def next_deadline(self) -> float | None:
        t = self.own_deadline()
        return None if t == inf else t

    def handle_timer(self, now: float) -> None:
        self._run_timers(now, strict=False)
        self._at(now)

    def _at(self, now: float) -> None:
        if now < self.now - _EPS:
            raise ModelError(f"{self.name}: time went backwards ({now} < {self.now})")
        if now > self.now:
            self.now = now

    def _run_timers(self, now: float, strict: bool) -> None:
        """Fire the own timers due by ``now`` (``strict``: before it) in time order."""
        while True:
            t = self.own_deadline()
            if t == inf or (t >= now - _EPS if strict else t > now + _EPS):
                return
            self._fire(t)

    def _fire(self, t: float) -> None:
        self._at(t)
        ta, tp = self._t_res_a, self._t_res_p
        w = self._wake[0][0] if self._wake else inf
        if ta <= tp and ta <= w:
            self._t_res_a = inf
            self._active(AI.T_RES)
        elif tp <= w:
            self._t_res_p = inf
            self._passive(PI.T_RES)
        else:
            _, _, tag = heapq.heappop(self._wake)
            self._events.append(Wakeup(self.now, tag))

    # ============================================================== lower edge
    def _lower_send(self, now: float, frame: bytes) -> None:  # pragma: no cover - abstract
        raise NotImplementedError

    def frame_received(self, now: float, frame: bytes) -> None:
        """The lower layer delivered a frame (a 3964(R) block received and acknowledged)."""
        if now > self.now:
            self.now = now
        elif now < self.now - _EPS:
            raise ModelError(f"{self.name}: time went backwards ({now} < {self.now})")
        if self.frame_events:
            self._events.append(FrameReceived(self.now, frame))
        # the classification of codec.classify, inline (the hot path)
        n = len(frame)
        if n >= 4:
            b1 = frame[0]
            if frame[2]:
                if b1 == FIRST:
                    self._passive(PI.COMMAND, frame)
                elif b1 == CONTINUATION:
                    self._passive(PI.CONTINUATION, frame)
                else:
                    self._passive(PI.BAD_COMMAND, frame)
            elif b1 == FIRST:
                self._active(AI.RESPONSE, frame)
            elif b1 == CONTINUATION:
                self._active(AI.CONTINUATION_RESPONSE, frame)
            else:
                self._active(AI.BAD_RESPONSE, frame)
        elif n == 3:
            if frame[2]:
                self._passive(PI.SHORT_COMMAND, frame)
            else:
                self._active(AI.SHORT_RESPONSE, frame)
        elif self.a_state is A.WAIT_RESPONSE or self.a_state is A.WAIT_CONTINUATION_RESPONSE:
            # fewer than 3 bytes cannot be told apart: a response if one is awaited
            self._active(AI.SHORT_RESPONSE, frame)
        else:
            self._passive(PI.SHORT_COMMAND, frame)

    def frame_sent(self, now: float) -> None:
        """The lower layer's partner acknowledged the frame in flight."""
        if now > self.now:
            self.now = now
        elif now < self.now - _EPS:
            raise ModelError(f"{self.name}: time went backwards ({now} < {self.now})")
        if self._inflight is None:
            raise ModelError(f"{self.name}: a frame was acknowledged, but none was handed over")
        frame, origin, owner, reason = self._inflight
        self._inflight = None
        if self.frame_events:
            self._events.append(FrameSent(self.now, frame, reason))
        if owner is not None:
            if owner is self.job:
                self._active(AI.COMMAND_SENT)
            elif owner is self.open:
                self._passive(PI.RESPONSE_SENT)
        if self._inflight is None and self._out:
            self._pump(self.now)

    def frame_failed(self, now: float, code: int) -> None:
        """The lower layer gave up on the frame in flight (its final STATUS ``code``)."""
        self._at(now)
        if self._inflight is None:
            raise ModelError(f"{self.name}: a frame was given up, but none was handed over")
        frame, origin, owner, reason = self._inflight
        self._inflight = None
        self._events.append(FrameNotSent(self.now, frame, code))
        if origin == "A":
            if owner is not None and owner is self.job:
                self._active(AI.COMMAND_NOT_SENT)
        elif origin == "P":
            if owner is not None and owner is self.open:
                self._passive(PI.RESPONSE_NOT_SENT)
            else:
                self._status(Code.RESPONSE_NOT_SENT, "receive")
        if self._inflight is None and self._out:
            self._pump(self.now)

    def _queue(self, frame: bytes, origin: str, owner, detail: str = "") -> None:
        row = self._row
        reason = row.ref
        if self.frame_log is not None:
            self.frame_log.append((self.now, frame, origin, self._input, reason, row.code, detail))
        item = (frame, origin, owner, reason)
        if self._inflight is None and not self._out:
            self._inflight = item
            if origin == "A" and self._tres_at_handover:
                self._t_res_a = self.now + self._t_res
            self._lower_send(self.now, frame)
        else:
            self._out.append(item)
            if self._inflight is None:
                self._pump(self.now)

    def _pump(self, now: float) -> None:
        if self._inflight is not None or not self._out:
            return
        out = self._out
        item = None
        if self.readings.amb31_responses_first and len(out) > 1:
            for k, x in enumerate(out):
                if x[1] == "P":
                    item = x
                    del out[k]
                    break
        if item is None:
            item = out.popleft()
        self._inflight = item
        if item[1] == "A" and item[2] is self.job and self._tres_at_handover:
            self._t_res_a = now + self._t_res
        self._lower_send(now, item[0])

    def send_raw(self, now: float, frame: bytes) -> None:
        """Send one frame as it is (a tester's frame): neither side takes note of it."""
        self._at(now)
        self._out.append((bytes(frame), "raw", None, "raw frame"))
        if self._inflight is None:
            self._pump(self.now)

    # ============================================================== dispatch
    _input = None

    def _resolve(self, row: T.Row, prefix: str) -> tuple:
        """(row, action, decision, target) for one table row; an action may return a state
        that overrides the row's target."""
        fn = None if row.action == T.IMPOSSIBLE else getattr(self, prefix + row.action)
        if row.target in T.DECISION_TARGETS:
            return row, fn, getattr(self, "_d_" + row.target.lower()), None
        return row, fn, None, (None if row.target == T.SAME else row.target)

    def _active(self, inp: T.AInput, frame: bytes = b"") -> None:
        old = self.a_state
        row, fn, decide, target = self._a_rows[old][inp]
        if fn is None:
            raise ModelError(f"{self.name}: active input {inp} cannot occur in state {old}")
        self._row = row
        self._input = inp
        new = fn(frame)
        if new is None:
            new = decide(frame) if decide is not None else (target or old)
        if self.trace is not None:
            self.trace.append((self.now, "active", old, inp, row.action, new))
        # T_RES of this side starts with the command (acknowledged or handed over, AMB-17)
        # and stops with the response or the end of the request (_end): no generic rule
        self.a_state = new
        if new is A.IDLE and self._requests and self.powered:
            self._active(AI.CPU_REQUEST)

    def _passive(self, inp: T.PInput, frame: bytes = b"") -> None:
        old = self.p_state
        row, fn, decide, target = self._p_rows[old][inp]
        if fn is None:
            raise ModelError(f"{self.name}: passive input {inp} cannot occur in state {old}")
        self._row = row
        self._input = inp
        self._timer_set = False
        new = fn(frame)
        if new is None:
            new = decide(frame) if decide is not None else (target or old)
        if self.trace is not None:
            self.trace.append((self.now, "passive", old, inp, row.action, new))
        if new is not old and not self._timer_set:
            self._t_res_p = inf
        self.p_state = new

    def _status(self, code: int, side: str, final: bool = False) -> None:
        self._events.append(Status(self.now, code, side, final))

    # ============================================================== active side (Fig. 2-18)
    def _fail_now(self, req: Request, code: int) -> None:
        self._status(code, "send", final=True)
        self._events.append(RequestResult(self.now, req.label, False, int(code)))

    def _a_ignore(self, _f) -> None:
        pass

    def _a_queue_request(self, _f) -> None:
        pass  # request() queued it; it starts when the active side is idle again

    def _a_take_request(self, _f) -> None:
        pass  # LOCAL_CHECK takes it from the queue

    def _d_local_check(self, _f) -> str:
        req = self._requests.popleft()
        code = local_check(req, self.readings)
        if code is not None:
            self._fail_now(req, code)
            return A.IDLE
        h = request_header(req, self.readings)
        if req.op == "send":
            frames = send_frames(h, send_payload(req, h))
        else:
            frames = fetch_frames(h)
        job = Job(req, h, frames, req.op == "fetch")
        if job.fetch and h.area is not None and h.area.words:
            job.store = min(req.length, h.nbytes)
        self.job = job
        self._queue(frames[0], "A", job, req.label)
        return A.SEND_COMMAND

    def _a_command_sent(self, _f) -> None:
        if not self._tres_at_handover:  # "start T_RES" (the hand-over reading started it already)
            self._t_res_a = self.now + self._t_res

    def _a_response_received(self, _f) -> None:
        self._t_res_a = inf  # the response stops T_RES

    def _d_check_response(self, frame: bytes) -> str:
        job = self.job
        n = len(frame)
        reatel = frame[3]
        if reatel:
            if n > 4 and self.readings.amb33_error_response_with_data == "length":
                return self._end(Code.RESPONSE_DATA_LENGTH if job.fetch else Code.RESPONSE_TO_SEND_WITH_DATA)
            return self._end(status_for_reatel(reatel))
        if not job.fetch:
            if n != 4:
                return self._end(Code.RESPONSE_TO_SEND_WITH_DATA)
            job.remaining -= len(job.frames[job.k]) - (HEADER_LEN if job.k == 0 else 4)
        else:
            d = n - 4
            want = CHUNK if job.remaining > CHUNK else job.remaining
            if d != want and (self.readings.amb16_exact_chunks or not 0 < d <= want):
                return self._end(Code.RESPONSE_DATA_LENGTH)
            job.data += frame[4:]
            job.remaining -= d
        job.k += 1
        if job.remaining <= 0:
            return self._end(None)
        if job.fetch and job.k >= len(job.frames):
            job.frames.append(job.header.continuation)  # a partner that sent short chunks (AMB-16)
        self._queue(job.frames[job.k], "A", job, job.label)
        return A.SEND_CONTINUATION

    def _end(self, code: int | None) -> str:
        """The request in progress ends: DONE (code None) or ERROR with ``code``. Its frames
        not yet handed to the link are dropped (the one with the link cannot be recalled)."""
        job, self.job = self.job, None
        self._t_res_a = inf
        if self._out:
            self._out = deque(x for x in self._out if x[2] is not job)
        if code is None:
            data = bytes(job.data[:job.store]) if job.fetch else None
            self._events.append(RequestResult(self.now, job.label, True, None, data))
        else:
            self._status(code, "send", final=True)
            self._events.append(RequestResult(self.now, job.label, False, int(code)))
        return A.IDLE

    def _a_fail_request(self, _f) -> None:
        self._end(self._row.code)

    def _a_abort_for_restart(self, _f) -> None:
        self._end(self._row.code)

    def _a_unsolicited_response(self, _f) -> None:
        self._status(self._row.code, "send")

    def _a_early_response(self, _f) -> None:
        pass  # AFTER_EARLY_RESPONSE decides (AMB-32)

    def _d_after_early_response(self, _f) -> str:
        if self.readings.amb32_early_response_ends_request:
            return self._end(self._row.code)
        self._status(self._row.code, "send")  # an extra response: reported; ours is awaited
        return self.a_state

    def _a_short_response(self, _f) -> None:
        pass  # AFTER_SHORT_RESPONSE decides (AMB-10)

    def _d_after_short_response(self, _f) -> str:
        if self.readings.amb10_short_response_ends_request:
            return self._end(self._row.code)
        self._status(self._row.code, "send")  # reported, and otherwise ignored: T_RES runs on
        return self.a_state

    # ============================================================== passive side (Fig. 2-19)
    def _reply(self, frame: bytes, code: int, owner=None, final_for_owner: bool = False) -> None:
        """Report ``code`` (side "receive") and answer ``frame`` with its REATEL."""
        self._status(code, "receive")
        reatel = STATUS_REATEL.get(code) if code != Code.FRAME_TOO_SHORT else self.readings.amb10_short_command_reatel
        if reatel is None:
            return
        b1 = frame[0] if frame and frame[0] in (FIRST, CONTINUATION) else self.readings.n1_bad_id_reply_frame_id
        self._queue(response_head(b1 == FIRST, reatel), "P", owner, f"REATEL {reatel:02X}h for {Code(code).text}")

    def _reply_with(self, frame: bytes, code: int, reatel: int, owner) -> None:
        self._status(code, "receive")
        self._queue(response_head(frame[0] == FIRST, reatel), "P", owner, f"REATEL {reatel:02X}h for {Code(code).text}")

    def _p_ignore(self, _f) -> None:
        pass

    def _p_refuse_bad_id(self, frame) -> None:
        self._reply(frame, Code.CMD_BYTE1_INVALID)

    def _p_refuse_short(self, frame) -> None:
        self._reply(frame, Code.FRAME_TOO_SHORT)

    def _p_refuse_sequence(self, frame) -> None:
        self._reply(frame, Code.PARTNER_SEQUENCE_ERROR)

    def _p_refuse_pipelined(self, frame) -> None:
        self._reply(frame, Code.PARTNER_SEQUENCE_ERROR)
        if self.readings.n7_pipelined_command_aborts and self.open is not None:
            self.open.final = True

    def _p_drop_partner_request(self, _f) -> None:
        self.open = None

    def _p_take_command(self, _f) -> None:
        pass  # CHECK_COMMAND validates it

    def _p_first_while_waiting(self, _f) -> None:
        self.open = None  # the open request is aborted (Fig. 2-19)

    def _d_first_while_waiting(self, frame) -> str:
        if self.readings.amb18_first_command_while_waiting == "execute":
            self._status(Code.PARTNER_SEQUENCE_ERROR, "receive")
            return self._d_check_command(frame)
        self._reply(frame, Code.PARTNER_SEQUENCE_ERROR)
        return P.IDLE

    def _p_continuation_timeout(self, _f) -> None:
        self.open = None
        self._status(self.readings.amb18_passive_timeout_status, "receive")

    def _p_response_sent(self, _f) -> None:
        pass

    def _d_after_response(self, _f) -> str:
        op = self.open
        if op.final:
            self.open = None
            return P.IDLE
        self._t_res_p = self.now + self._t_res
        self._timer_set = True
        return P.WAIT_CONTINUATION

    def _p_response_not_sent(self, _f) -> None:
        self.open = None
        self._status(self._row.code, "receive")

    # -- the checks of a first command (order: reading n2) ---------------------------------------
    def _d_check_command(self, frame: bytes) -> str:
        op = _Open()
        self.open = op
        n = len(frame)
        op.b3 = b3 = frame[2]
        op.b4 = b4 = frame[3]
        op.fetch = b3 == FETCH
        area = self._area_of.get(b4)
        if area is not None and not op.fetch:
            # the destination of a SEND: 'O' (or, read so, type 'X') a DX, 'A' a DB
            area = Area.DX if b3 == SEND_DX or b4 == _DX else Area.DB
        op.area = area
        if n >= HEADER_LEN:
            length = (frame[6] << 8) | frame[7]
            op.nbytes = 2 * length if area is not None and area.words else length
            if area is not None and area.block:
                op.number = frame[4]
                op.start = 2 * frame[5]
            else:
                op.number = 0
                addr = ((frame[4] << 8) | frame[5]) if self.readings.amb14_address_16bit else frame[5]
                op.start = 2 * addr if area is not None and area.words else addr
            op.flag = None if frame[8] == NO_FLAG else (frame[8], frame[9] & 0x0F)
        op.done = 0
        for check in self._checks:
            bad = check(frame, op)
            if bad is not None:
                code, reatel = bad
                if reatel is None:  # a too-short command left unanswered (AMB-10)
                    self._status(code, "receive")
                    self.open = None
                    return P.IDLE
                self._reply_with(frame, code, reatel, op)
                op.final = True
                return P.SEND_RESPONSE
        op.buf = self.memory.buffer(area, op.number)
        op.letter = area.value
        return self._transfer(frame, op, HEADER_LEN)

    def _c_byte2(self, frame, op):
        if self.readings.amb13_check_byte2 and frame[1] != 0:
            return Code.CMD_BYTE1_INVALID, 0x10
        return None

    def _c_byte3(self, frame, op):
        if op.b3 not in COMMAND_LETTERS:
            return Code.CMD_BYTE3_INVALID, 0x16
        return None

    def _c_byte4(self, frame, op):
        if op.b3 not in COMMAND_LETTERS:
            return None  # byte 3 decides (if it is checked later in the order)
        ok = op.b4 in self._fetch_types if op.fetch else op.b4 in self._send_types
        return None if ok else (Code.CMD_BYTE4_INVALID, 0x10)

    def _c_short(self, frame, op):
        return (Code.FRAME_TOO_SHORT, self.readings.amb10_short_command_reatel) if len(frame) < HEADER_LEN else None

    def _c_cpu_stop(self, frame, op):
        return None if self.memory.running else (Code.CP_NOT_READY, 0x2A)

    def _usable(self, frame, op) -> bool:
        return len(frame) >= HEADER_LEN and op.area is not None and op.b3 in COMMAND_LETTERS

    def _c_block(self, frame, op):
        if self._usable(frame, op) and op.area.block and self.memory.buffer(op.area, op.number) is None:
            return Code.DB_NUMBER_NOT_ALLOWED, 0x14
        return None

    def _size(self, op) -> int | None:
        buf = self.memory.buffer(op.area, op.number)
        return None if buf is None else len(buf)

    def _c_address(self, frame, op):
        if not self._usable(frame, op):
            return None
        size = self._size(op)
        if size is not None and op.start >= size:
            return Code.START_ADDRESS_TOO_HIGH, 0x0C
        return None

    def _c_length(self, frame, op):
        if not self._usable(frame, op):
            return None
        n = op.nbytes
        if n == 0 or n > MAX_REQUEST_BYTES:
            return Code.LENGTH_NOT_ALLOWED, 0x34
        r = self.readings
        if op.fetch and op.area in (Area.T, Area.Z) and self._cell_limit is not None and n > self._cell_limit:
            return Code.LENGTH_NOT_ALLOWED, r.amb20_cell_limit_reatel
        size = self._size(op)
        if size is not None and op.start + n > size:
            if r.amb25_extent_beyond_area == "area":
                return (Code.DB_NUMBER_NOT_ALLOWED, 0x14) if op.area.block else (Code.START_ADDRESS_TOO_HIGH, 0x0C)
            return Code.LENGTH_NOT_ALLOWED, 0x34
        return None

    def _c_flag(self, frame, op):
        if len(frame) < HEADER_LEN:
            return None
        if frame[8] == NO_FLAG:
            if not self.readings.amb23_byte9_ff_means_no_flag and frame[9] & 0x0F != 0x0F:
                return Code.FLAG_INVALID, 0x0C
            return None
        byte, bit = op.flag
        if bit > 7 or byte >= self._flag_bytes:
            return Code.FLAG_INVALID, 0x0C
        return None

    def _c_cpu(self, frame, op):
        if len(frame) >= HEADER_LEN and frame[9] >> 4 not in self.readings.amb22_accepted_cpu_nibbles:
            return Code.CPU_NUMBER_NOT_ALLOWED, 0x0C
        return None

    def _c_data(self, frame, op):
        if len(frame) < HEADER_LEN:
            return None
        d = len(frame) - HEADER_LEN
        if op.fetch:
            return (Code.FETCH_WITH_DATA, 0x34) if d else None
        if op.b3 not in COMMAND_LETTERS:
            return None
        want = CHUNK if op.nbytes > CHUNK else op.nbytes
        if d != want and (self.readings.amb16_exact_chunks or not 0 < d <= want):
            return Code.SEND_LENGTH_DIFFERS, 0x34
        return None

    def _c_lock(self, frame, op):
        if len(frame) >= HEADER_LEN and op.flag is not None:
            byte, bit = op.flag
            if bit <= 7 and byte < self._flag_bytes and self.memory.flag(byte, bit) == self.readings.amb07_locked_value:
                return Code.DB_LOCKED, 0x32
        return None

    # -- continuation commands -------------------------------------------------------------------
    def _p_take_continuation(self, _f) -> None:
        self._t_res_p = inf  # the continuation stops T_RES

    def _d_check_continuation(self, frame: bytes) -> str:
        op = self.open
        bad = None
        if self._check_b2 and frame[1] != 0:
            bad = Code.CMD_BYTE1_INVALID
        elif frame[2] != op.b3:
            bad = Code.CMD_BYTE3_CHANGED
        elif frame[3] != op.b4:
            bad = Code.CMD_BYTE4_CHANGED
        elif not self.memory.running:
            bad = Code.CP_NOT_READY
        elif op.fetch:
            if len(frame) != 4:
                bad = Code.FETCH_WITH_DATA
        else:
            d = len(frame) - 4
            left = op.nbytes - op.done
            want = CHUNK if left > CHUNK else left
            if d != want and (self._exact or not 0 < d <= want):
                bad = self.readings.n3_continuation_count_status
        if bad is not None:
            self._reply(frame, bad, op)
            op.final = True
            return P.SEND_RESPONSE
        return self._transfer(frame, op, 4)

    # -- the transfer to (from) the CPU and the response -----------------------------------------
    def _transfer(self, frame: bytes, op: _Open, head: int) -> str:
        first = head == HEADER_LEN
        mem = self.memory
        if op.fetch:
            left = op.nbytes - op.done
            k = CHUNK if left > CHUNK else left
            start = op.start + op.done
            data = bytes(op.buf[start:start + k])
            op.done += k
            final = op.done >= op.nbytes
            reply = (_OK_FIRST if first else _OK_CONT) + data
        else:
            data = frame[head:]
            start = op.start + op.done
            op.done += len(data)
            final = op.done >= op.nbytes
            if self._per_frame:
                op.buf[start:start + len(data)] = data
            else:
                op.pending += data
                if final:
                    mem.write(op.area, op.number, op.start, op.pending)
                    start, data = op.start, op.pending
                else:
                    data = None
            reply = _OK_FIRST if first else _OK_CONT
        op.final = final
        flag = None
        if final and op.flag is not None and self._set_flag:
            flag = op.flag
            mem.set_flag(flag[0], flag[1], self.readings.amb07_locked_value)
        if data is not None:
            self._events.append(Served(self.now, "read" if op.fetch else "write", op.letter,
                                       op.number, start, data, final, flag))
        else:
            reply = _OK_FIRST if first else _OK_CONT
        self._queue(reply, "P", op, "REATEL 00")
        return P.SEND_RESPONSE
