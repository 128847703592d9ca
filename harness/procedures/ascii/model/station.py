"""Reference model of one CP 341 ASCII driver: sans-IO, explicit time.

Every public method takes ``now`` (seconds, any monotonic origin). The station never reads a
clock, sleeps or touches a device. Its caller (a driver) feeds it what happened and drains
what it wants to do, through the same interface as the 3964(R) station:

* inputs: :meth:`power_on`, :meth:`line_event` (``"byte"``/``"bytes"`` received intact,
  ``"invalid"`` a character with a parity/framing/overrun error, ``"break"``, and the modem
  inputs ``"cts"``, ``"dsr"``, ``"dcd"``, ``"ri"`` with value 0/1), :meth:`request_send`
  (P_SND_RK), :meth:`read_frame` (P_RCV_RK), and :meth:`handle_timer` once
  :meth:`next_deadline` has been reached;
* outputs: :meth:`pop_output` / :meth:`pop_output_runs` (characters with the time each
  starts on the line), :meth:`pop_signals` (RTS and DTR changes, for a port that carries
  modem lines), :meth:`pop_events` (STATUS events, frames stored/read/discarded, job
  results).

The station includes its UART transmitter (:class:`~ptpcert.model.output.Transmitter`, the
one every procedure's station uses): characters go out one character time apart, so the
model knows what is already on the line when an XOFF or CTS OFF stops it, and an XON or XOFF
it sends itself goes out at the next character boundary, between two characters of a frame
if need be (full duplex, §2.1).

Ordering rule: the inputs of an instant are handled before the deadlines of that instant (a
character that completed exactly at a deadline started before it). Drivers deliver the
inputs of an instant before calling :meth:`handle_timer` for it.

What the station does is the three tables of :mod:`.table` (receiver per end criterion,
sender, receive-side flow control); this module implements their actions and decisions.
With ``explain=True`` it records why it sent each character (:attr:`tx_log`) and switched
each signal (:attr:`signal_log`), naming the table row, the decisions and the manual's
reference, for tools that explain a transcript.

The module is one piece on purpose, although long: it is the station class, with one method
for each action and decision of the three tables besides the interface above. The three
machines share one state (the frame coming in, the receive buffer, the send job, the modem
lines, the deadlines, the transmitter) and act on one another within a single input: a
stored character fills the buffer and flow control sends XOFF, a received XOFF stops the
sender. Cutting the class along the tables would spread that state over several files and
make no part usable alone. What is not the state machine lives elsewhere: the transmitter
in :mod:`ptpcert.model.output`, the send job and the explanation records in
:mod:`.records`, the tables in :mod:`.table`, what goes on the line for a job in
:mod:`.codec`.
"""

from __future__ import annotations

from collections import deque
from enum import StrEnum
from math import inf
from typing import Any, Mapping

from ptpcert.model.codes import Code
from ptpcert.model.errors import ModelError, ParameterError
from ptpcert.model.events import Delivered, SendDone, SendFailed, Status
from ptpcert.model.output import EPS, Transmitter, characters

from . import events as aev
from . import table as T
from .codec import send_bytes
from .events import FrameDiscarded, FrameStored
from .params import BUFFER_BYTES, MAX_FRAME, AsciiParams
from .readings import READINGS, AsciiReadings
from .records import AsciiJob, SignalRecord, TxRecord, Why
from .table import FcInput, FcState, RxInput, RxState, TxInput, TxState


class Timer(StrEnum):
    """The station's deadlines; at one instant they run out in this order."""

    TX_DONE = "TX_DONE"        # the last stop bit of the frame being sent
    T_CDT = "T_CDT"            # receiver: character delay time
    T_PAUSE = "T_PAUSE"        # sender: pause between frames
    T_DOW = "T_DOW"            # sender: data output waiting time (automatic V.24)
    T_RTS_OFF = "T_RTS_OFF"    # sender: time to RTS OFF (automatic V.24)
    T_XON_WAIT = "T_XON_WAIT"  # sender: wait time for XON / CTS = ON
    WAKE = "WAKE"              # the application asked to be woken (see wake_at)


_ORDER = {t: i for i, t in enumerate(Timer)}
_TX_TIMERS = {Timer.TX_DONE: TxInput.TX_DONE, Timer.T_PAUSE: TxInput.T_PAUSE,
              Timer.T_DOW: TxInput.T_DOW, Timer.T_RTS_OFF: TxInput.T_RTS_OFF,
              Timer.T_XON_WAIT: TxInput.T_XON_WAIT}
#: timers measured from the end of the station's own transmission: they move with it
_FROM_TX = (Timer.TX_DONE, Timer.T_PAUSE, Timer.T_RTS_OFF)


_POWER_ON = Why("station", "START_UP", "POWER_ON", "start_up", "§7.2; §2.2.4")


class AsciiStation:
    """One CP 341 ASCII driver (one interface). See the module docstring for the calling
    convention.

    ``params`` is an :class:`AsciiParams`, or a mapping of settings as a user would
    assign them: a mapping that breaks a rule of Tables 2-7..2-10 does not raise; the
    station then starts in STOP, as a CP does with a bad parameter set (§7.1): it reports
    16#020F at power-on, drives no output, receives nothing and refuses every send request
    (16#0502). ``cts``/``dsr``: the modem inputs before the line reports them (reading
    d_start_up: ON, as on a port without modem lines).
    """

    RX_TABLES = T.RX_TABLES
    TX_TABLE = T.TX_TABLE
    FC_TABLE = T.FC_TABLE

    def __init__(self, params: AsciiParams | Mapping[str, Any] | None = None,
                 readings: AsciiReadings = READINGS, *, name: str = "station",
                 trace: bool = False, explain: bool = False, cts: bool = True, dsr: bool = True):
        self.parameter_error: ParameterError | None = None
        if params is None:
            params = AsciiParams()
        elif not isinstance(params, AsciiParams):
            try:
                params = AsciiParams.from_dict(params)
            except ParameterError as e:
                self.parameter_error = e
                params = _fallback_params(params)
        self.params: AsciiParams = params
        self.readings = readings
        self.name = name
        self.now = -inf
        p = params
        self._char = p.char_time
        self._cdt_window = p.cdt + (p.char_time if readings.q4_cdt_grace_one_character else 0.0)
        self._rx_table = self.RX_TABLES[p.end_criterion]
        self._end = p.end_sequence if p.end_criterion == "end_chars" else b""
        self._xonxoff = p.flow_control == "xon_xoff"
        self._flow_active = p.flow_control in ("xon_xoff", "rts_cts")
        self._v24 = p.flow_control == "auto_v24"
        #: "START_UP" until power_on, then "RUN", or "STOP" after a parameter error
        self.mode = "START_UP"
        self.rx_state = RxState.WAIT_CHAR
        self.tx_state = TxState.IDLE
        self.fc_state = FcState.OPEN
        self._timers: dict[Timer, float] = {}
        self._line = Transmitter(self._char)   # runs of kind "data" (a job's frame) or "control" (XON/XOFF)
        self._events: list = []
        self._signals: list[tuple[float, str, int]] = []
        # modem lines (§2.2.4 "RS 232C secondary signals"): outputs OFF at power-on
        self.rts = 0
        self.dtr = 0
        self.cts = int(bool(cts))
        self.dsr = int(bool(dsr))
        self.dcd = 0
        self.ri = 0
        # sender
        self._jobs: deque[AsciiJob] = deque()
        self.job: AsciiJob | None = None
        self.partner_stopped = False     # XOFF received / CTS OFF (flow control)
        self._last_frame_end = -inf      # last stop bit of the last frame sent (the pause)
        # receiver: the frame coming in
        self._cur = bytearray()          # its characters received intact
        self._count = 0                  # its characters, errors included (fixed length)
        self._prev: int | None = None    # its last character, if intact (end sequence)
        self._spoil: int | None = None   # the first error that spoiled it (a STATUS code)
        self._spoil_reason = ""
        self._trailing = False           # it began within the CDT after a complete frame
        self._last_complete_at = -inf
        # receive buffer (Table 2-10)
        self._stored: deque[tuple[float, bytes]] = deque()
        self._stored_bytes = 0
        self._fc_source = ""             # what freed room: "read" or "discard" (Q15)
        self._override: str | None = None
        self._why: Why = _POWER_ON
        self.trace: list[tuple] | None = [] if trace else None
        #: A real-time driver that wakes up after a deadline sets this: the station then acts
        #: at the time it is told, not at the deadline (see Station3964).
        self.late_timers_act_now = False
        self.tx_log: list[TxRecord] | None = [] if explain else None
        self.signal_log: list[SignalRecord] | None = [] if explain else None

    # ================================================================== public API
    def power_on(self, now: float) -> None:
        """The driver has its parameters (§7.2): flow control announces itself (XON, or RTS
        ON), automatic V.24 sets DTR ON; a bad parameter set reports 16#020F instead."""
        self._at(now, strict=True)
        if self.mode != "START_UP":
            raise ModelError(f"{self.name}: power_on twice")
        self._why = _POWER_ON
        if self.parameter_error is not None:
            self.mode = "STOP"
            self._emit(Status(self.now, Code.PARAMS_REJECTED, "diag"))
            return
        self.mode = "RUN"
        if self._v24 or self.readings.d_dtr_on_outside_auto_v24:
            self._set_signal("dtr", 1)
        if self._v24 and not self.dsr:
            self.rx_state = RxState.OFF
        if self.params.flow_control == "rts_cts":
            self.partner_stopped = not self.cts
        if self._flow_active:
            self._fc(FcInput.START)
        if self._jobs:
            self._tx(TxInput.SEND_REQUEST)

    def receive(self, now: float, data: bytes | bytearray | int) -> None:
        """Characters received intact, all completed at ``now``."""
        self._at(now, strict=True)
        if isinstance(data, int):
            data = (data,)
        for b in data:
            self._char_in(b)

    def receive_invalid(self, now: float, value: int = 0) -> None:
        """A character with a parity, framing or overrun error."""
        self._at(now, strict=True)
        if self.mode != "RUN":
            return
        count = 0 if self.rx_state is RxState.WAIT_CHAR else self._count
        if self.params.end_criterion == "fixed_length" and count + 1 == self.params.fixed_length \
                and self.rx_state is not RxState.OFF:
            inp = RxInput.INVALID_END
        else:
            inp = RxInput.INVALID
        self._rx(inp, value)

    def line_break(self, now: float) -> None:
        """The receive line is interrupted (BREAK, wire break)."""
        self._at(now, strict=True)
        if self.mode == "RUN":
            self._rx(RxInput.BREAK)
            # the other reading of d_break: the BREAK ends the running send job as well
            # (outside the sender's table, which has no BREAK input)
            if self.readings.d_break_aborts_send and self.job is not None:
                self._abort(Code.LINE_BREAK)
                self.tx_state = TxState.IDLE
                self._next_job()

    def set_line(self, now: float, name: str, value: int) -> None:
        """A modem input changed: ``cts``, ``dsr``, ``dcd`` or ``ri`` (0/1)."""
        self._at(now, strict=True)
        value = int(bool(value))
        if name not in ("cts", "dsr", "dcd", "ri"):
            raise ModelError(f"{self.name}: {name!r} is not a modem input")
        if getattr(self, name) == value:
            return
        setattr(self, name, value)
        if self.mode != "RUN":
            return
        mode = self.params.flow_control
        if name == "cts":
            if mode == "rts_cts":
                self._tx(TxInput.GO if value else TxInput.STOP)
            elif mode == "auto_v24":
                self._tx(TxInput.CTS_ON if value else TxInput.CTS_OFF)
        elif name == "dsr" and mode == "auto_v24":
            self._rx(RxInput.DSR_ON if value else RxInput.DSR_OFF)
            self._tx(TxInput.DSR_ON if value else TxInput.DSR_OFF)

    def line_event(self, now: float, kind: str, value=0) -> None:
        """One event from the line, as drivers and links carry them."""
        if kind == "byte" or kind == "bytes":
            self.receive(now, value)
        elif kind == "invalid":
            self.receive_invalid(now, value)
        elif kind == "break":
            self.line_break(now)
        elif kind in ("cts", "dsr", "dcd", "ri"):
            self.set_line(now, kind, value)
        else:
            raise ModelError(f"{self.name}: unknown line event {kind!r}")

    def request_send(self, now: float, payload: bytes) -> bool:
        """Hand over a send job (P_SND_RK with REQ, LEN = len(payload)). Returns False when
        it is refused at once: LEN outside 1..1024 (16#1E41), or the driver in STOP
        (16#0502). A 7-bit character frame cannot carry bytes above 7F (a harness error)."""
        self._at(now, strict=True)
        payload = bytes(payload)
        if self.mode == "STOP":
            return self._refuse(payload, Code.NOT_ALLOWED_IN_MODE)
        if not 1 <= len(payload) <= MAX_FRAME:
            return self._refuse(payload, Code.LEN_ILLEGAL)
        if self.params.data_bits == 7 and any(b > 0x7F for b in payload):
            raise ValueError("a payload byte above 7F cannot be sent with 7 data bits")
        wire = send_bytes(payload, self.params, self.readings)
        if wire is None:
            return self._refuse(payload, Code.LEN_ILLEGAL)
        self._jobs.append(AsciiJob(payload, wire))
        if self.mode == "RUN":
            self._tx(TxInput.SEND_REQUEST)
        return True

    def read_frame(self, now: float) -> bytes | None:
        """P_RCV_RK: take the oldest frame out of the receive buffer (NDR = 1, LEN); None
        when the buffer is empty. Frees room, which may lift an XOFF / RTS OFF."""
        self._at(now, strict=True)
        if not self._stored:
            return None
        _, frame = self._stored.popleft()
        self._stored_bytes -= len(frame)
        self._emit(Delivered(self.now, frame))
        self._room_check("read")
        return frame

    def wake_at(self, t: float) -> None:
        """The application wants to act at ``t`` (a user program that reads later): the
        station adds ``t`` to its deadlines, so every driver wakes up for it, and does
        nothing when it is reached."""
        if t > self.now + EPS:
            cur = self._timers.get(Timer.WAKE, inf)
            self._timers[Timer.WAKE] = min(cur, t)

    def next_deadline(self) -> float | None:
        """The earliest time at which the station wants :meth:`handle_timer` (a timer, the
        end of a transmission, or the start of a character to send)."""
        t = min(self._timers.values(), default=inf)
        if self._line.runs:
            t = min(t, self._line.runs[0][0])
        return None if t == inf else t

    def handle_timer(self, now: float) -> None:
        """Advance to ``now``, handling every deadline that has been reached."""
        self._at(now, strict=False)

    def pop_output(self, now: float | None = None) -> list[tuple[float, int]]:
        """Characters whose transmission has started by ``now`` (all scheduled ones when
        ``now`` is None), as (start time, byte) pairs, in order."""
        return characters(self.pop_output_runs(now), self._char)

    def pop_output_runs(self, now: float | None = None) -> list[tuple[float, bytes]]:
        """Like :meth:`pop_output`, as runs (start of the first character, bytes) sent back
        to back."""
        out = []
        log = self.tx_log
        for start, data, kind, why in self._line.pop(now, labelled=True):
            out.append((start, data))
            if log is not None:
                end = start + len(data) * self._char
                last = log[-1] if log else None
                if last is not None and last.why is why and abs(last.end - start) < EPS:
                    log[-1] = TxRecord(last.start, end, last.data + data, kind, why)
                else:
                    log.append(TxRecord(start, end, data, kind, why))
        return out

    def pop_signals(self, now: float | None = None) -> list[tuple[float, str, int]]:
        """Changes of the station's modem outputs (``rts``, ``dtr``) up to ``now``, as
        (time, name, value)."""
        if now is None:
            out, self._signals = self._signals, []
            return out
        out = [s for s in self._signals if s[0] <= now + EPS]
        self._signals = [s for s in self._signals if s[0] > now + EPS]
        return out

    def pop_events(self) -> list:
        out, self._events = self._events, []
        return out

    def explain(self, t: float) -> TxRecord | None:
        """The record of the character that started at ``t`` (``explain=True``)."""
        for rec in reversed(self.tx_log or ()):
            if rec.start - EPS <= t < rec.end - EPS:
                return rec
        return None

    def delay_output(self, delta: float) -> None:
        """The line took ``delta`` seconds longer than scheduled to carry what the station
        sent: what is still scheduled, and the timers measured from the end of its
        transmission, move by ``delta``."""
        if delta <= 0:
            return
        before = self._line.popped_end
        self._line.shift(delta)
        for t in _FROM_TX:
            if t in self._timers:
                self._timers[t] += delta
        if self._last_frame_end != -inf and self._last_frame_end >= before - self._char - EPS:
            self._last_frame_end += delta

    # -- state for drivers, hosts and tests --------------------------------------------
    @property
    def idle(self) -> bool:
        """Nothing to do: no job, nothing to send, no frame coming in."""
        return (self.tx_state is TxState.IDLE and self.job is None and not self._jobs
                and not self._line.runs and self.rx_state in (RxState.WAIT_CHAR, RxState.OFF))

    @property
    def pending_jobs(self) -> int:
        return len(self._jobs) + (self.job is not None)

    @property
    def transmitting(self) -> bool:
        """Characters are scheduled that :meth:`pop_output` has not handed out yet."""
        return bool(self._line.runs)

    @property
    def has_events(self) -> bool:
        """Events are waiting for :meth:`pop_events`."""
        return bool(self._events)

    @property
    def frames_stored(self) -> int:
        return len(self._stored)

    @property
    def stored_frames(self) -> tuple[bytes, ...]:
        return tuple(f for _, f in self._stored)

    @property
    def oldest_stored_at(self) -> float | None:
        return self._stored[0][0] if self._stored else None

    @property
    def buffer_fill(self) -> int:
        """Bytes in the receive buffer: the stored frames and the intact frame coming in
        (a spoiled frame's characters are thrown away as they come)."""
        coming = len(self._cur) if self._spoil is None else 0
        return self._stored_bytes + coming

    @property
    def holding_partner(self) -> bool:
        """The station has sent XOFF (or set RTS OFF) and not lifted it yet."""
        return self.fc_state is FcState.HELD

    # ================================================================== time
    def _at(self, now: float, strict: bool) -> None:
        if now < self.now - EPS:
            raise ModelError(f"{self.name}: time went backwards ({now} < {self.now})")
        timers = self._timers
        while timers:
            name = min(timers, key=lambda k: (timers[k], _ORDER[k]))
            t = timers[name]
            due = t < now - EPS if strict else t <= now + EPS
            if not due:
                break
            del timers[name]
            self.now = max(self.now, now if self.late_timers_act_now else t)
            if name is Timer.T_CDT:
                self._rx(RxInput.T_CDT)
            elif name is Timer.WAKE:
                pass
            else:
                self._tx(_TX_TIMERS[name])
        self.now = max(self.now, now)

    def _start(self, timer: Timer, at: float) -> None:
        self._timers[timer] = at

    def _stop(self, *timers: Timer) -> None:
        for t in timers:
            self._timers.pop(t, None)

    # ================================================================== dispatch
    def _dispatch(self, machine: str, table: dict, decisions: dict, state: str, inp: str,
                  value: int) -> str:
        row = table[state][inp]
        if row.action == T.IMPOSSIBLE:
            raise ModelError(f"{self.name}: {machine} input {inp} cannot occur in state {state}")
        # a dispatch may run inside another (a stored character fills the buffer: XOFF);
        # the outer one's explanation and override are kept apart from the inner one's
        outer, outer_override, self._override = self._why, self._override, None
        self._why = why = Why(machine, str(state), str(inp), row.action, row.ref)
        getattr(self, f"_{machine}_{row.action}")(value)
        target = self._override or row.target
        while target in decisions:
            why.decisions.append(str(target))
            target = getattr(self, "_d_" + target.lower())()
        new = state if target == T.SAME else target
        if self.trace is not None:
            self.trace.append((self.now, machine, state, inp, row.action, new))
        self._why, self._override = outer, outer_override
        return new

    def _rx(self, inp: RxInput, value: int = 0) -> None:
        new = self._dispatch("rx", self._rx_table, T.RX_DECISION_TARGETS, self.rx_state, inp, value)
        self.rx_state = new
        if new is RxState.WAIT_CHAR or new is RxState.OFF:
            self._stop(Timer.T_CDT)

    def _tx(self, inp: TxInput) -> None:
        new = self._dispatch("tx", self.TX_TABLE, T.TX_DECISION_TARGETS, self.tx_state, inp, 0)
        self.tx_state = new
        if new is TxState.IDLE:
            self._next_job()

    def _next_job(self) -> None:
        if self.tx_state is TxState.IDLE and self.job is None and self._jobs:
            self._tx(TxInput.SEND_REQUEST)

    def _fc(self, inp: FcInput, source: str = "") -> None:
        self._fc_source = source
        self.fc_state = self._dispatch("fc", self.FC_TABLE, {}, self.fc_state, inp, 0)

    def _emit(self, event) -> None:
        self._events.append(event)

    def _refuse(self, payload: bytes, code: int) -> bool:
        self._emit(Status(self.now, code, "send", final=True))
        self._emit(SendFailed(self.now, payload, code, None))
        return False

    # ================================================================== characters in
    def _char_in(self, b: int) -> None:
        if self.mode != "RUN":
            return  # START_UP / STOP: the interface is not running
        if self.params.data_bits == 7:
            b &= 0x7F
        p = self.params
        if self._xonxoff and (b == p.xon or b == p.xoff):
            # flow control, never data (§2.2.4); it goes to the sender
            if self.readings.q16_flow_char_restarts_cdt and self.rx_state in (RxState.RECEIVE, RxState.DISCARD):
                self._restart_cdt()
            self._tx(TxInput.STOP if b == p.xoff else TxInput.GO)
            return
        self._rx(self._classify(b), b)

    def _classify(self, b: int) -> RxInput:
        if self.rx_state is RxState.OFF:
            return RxInput.CHAR
        crit = self.params.end_criterion
        if crit == "end_chars":
            end = self._end
            if len(end) == 1:
                return RxInput.END if b == end[0] else RxInput.CHAR
            prev = None if self.rx_state is RxState.WAIT_CHAR else self._prev
            return RxInput.END if (b == end[1] and prev == end[0]) else RxInput.CHAR
        if crit == "fixed_length":
            count = 0 if self.rx_state is RxState.WAIT_CHAR else self._count
            return RxInput.END if count + 1 == self.params.fixed_length else RxInput.CHAR
        return RxInput.CHAR

    # ================================================================== receiver actions
    def _new_frame(self) -> None:
        self._cur = bytearray()
        self._count = 0
        self._prev = None
        self._spoil = None
        self._spoil_reason = ""
        self._trailing = self.now - self._last_complete_at <= self._cdt_window + EPS

    def _restart_cdt(self) -> None:
        if self._cdt_suspended():
            self._stop(Timer.T_CDT)
            return
        self._start(Timer.T_CDT, self.now + self._cdt_window)

    def _cdt_suspended(self) -> bool:
        """Reading d_hold: no CDT for an intact frame while the partner is held."""
        return (self.fc_state is FcState.HELD and self._spoil is None
                and self.readings.d_cdt_suspended_while_holding)

    def _spoil_with(self, code: int, reason: str) -> None:
        if self._spoil is None:
            self._spoil, self._spoil_reason = code, reason

    def _put_char(self, b: int) -> None:
        """Store one intact character of the frame coming in, unless it does not fit: a
        frame longer than 1024 bytes (reading Q13) or no room left in the buffer (Q17)."""
        self._count += 1
        self._prev = b
        if self._spoil is not None:
            self._cur.append(b)   # kept only to show what was discarded
            return
        if len(self._cur) >= MAX_FRAME:
            self._spoil_with(self.readings.q13_overlong_frame_code, aev.TOO_LONG)
            self._cur.append(b)
            return
        room = BUFFER_BYTES - len(self._cur) - (self._stored_bytes if self.params.prevent_overwrite else 0)
        if room <= 0:
            self._spoil_with(self.readings.q17_overflow_code, aev.NO_ROOM)
            self._cur.append(b)
            return
        self._cur.append(b)
        self._full_check()

    def _rx_ignore(self, _v: int) -> None:
        pass

    def _rx_begin_frame(self, v: int) -> None:
        self._new_frame()
        self._put_char(v)
        self._restart_cdt()

    def _rx_store(self, v: int) -> None:
        self._put_char(v)
        self._restart_cdt()

    def _d_room(self) -> RxState:
        return RxState.RECEIVE if self._spoil is None else RxState.DISCARD

    def _rx_begin_spoiled(self, _v: int) -> None:
        self._new_frame()
        self._count = 1
        self._spoil_with(Code.CHARACTER_ERROR, aev.CHARACTER_ERROR)
        self._restart_cdt()

    def _rx_spoil(self, _v: int) -> None:
        self._count += 1
        self._prev = None
        self._spoil_with(Code.CHARACTER_ERROR, aev.CHARACTER_ERROR)
        self._restart_cdt()

    def _rx_discard(self, v: int) -> None:
        # an intact character of a spoiled frame: counted, kept for the record and for
        # finding the end sequence
        self._count += 1
        self._cur.append(v)
        self._prev = v
        self._restart_cdt()

    def _rx_discard_invalid(self, _v: int) -> None:
        self._count += 1
        self._prev = None
        self._restart_cdt()

    def _rx_complete_frame(self, v: int) -> None:
        """END: the end character (sequence) or the N-th character completes the frame."""
        if self.rx_state is RxState.WAIT_CHAR:
            self._new_frame()
        self._put_char(v)
        self._last_complete_at = self.now
        if self._spoil is not None:
            self._report_spoiled(cdt=False)
            return
        frame, self._cur = bytes(self._cur), bytearray()
        self._store_frame(frame)

    def _rx_frame_complete(self, _v: int) -> None:
        """CDT criterion: the CDT expired after the last character, the frame is complete."""
        frame, self._cur = bytes(self._cur), bytearray()
        self._store_frame(frame)

    def _rx_fragment_timeout(self, _v: int) -> None:
        """End-character and fixed-length criteria: the CDT expired inside a frame."""
        code = self.readings.q10_trailing_discard_code if self._trailing else Code.CDT_EXCEEDED
        if code is not None:
            self._emit(Status(self.now, code, "receive"))
        self._emit(FrameDiscarded(self.now, bytes(self._cur), aev.CDT_EXPIRED, code))
        self._cur = bytearray()
        self._room_check("discard")

    def _rx_report_spoiled(self, _v: int) -> None:
        """The CDT expired in a spoiled frame."""
        self._report_spoiled(cdt=True)

    def _rx_end_spoiled(self, v: int) -> None:
        """The end character (sequence) or the N-th character ends a spoiled frame."""
        self._count += 1
        self._cur.append(v)
        self._last_complete_at = self.now
        self._report_spoiled(cdt=False)

    def _rx_end_spoiled_invalid(self, _v: int) -> None:
        """Fixed length: the N-th character of a spoiled frame, itself with an error."""
        self._count += 1
        self._last_complete_at = self.now
        self._report_spoiled(cdt=False)

    def _rx_report_spoiled_at_once(self, _v: int) -> None:
        # fixed length: the N-th character of the frame has an error
        if self.rx_state is RxState.WAIT_CHAR:
            self._new_frame()
        self._count += 1
        self._spoil_with(Code.CHARACTER_ERROR, aev.CHARACTER_ERROR)
        self._last_complete_at = self.now
        self._report_spoiled(cdt=False)

    def _report_spoiled(self, cdt: bool) -> None:
        code = self._spoil
        self._emit(Status(self.now, code, "receive"))
        if cdt and self.params.end_criterion != "cdt" and self.readings.q12_cdt_also_reports_0806 \
                and code != Code.CDT_EXCEEDED:
            self._emit(Status(self.now, Code.CDT_EXCEEDED, "receive"))
        self._emit(FrameDiscarded(self.now, bytes(self._cur), self._spoil_reason, code))
        self._cur = bytearray()
        self._spoil = None
        self._room_check("discard")

    def _rx_report_break(self, _v: int) -> None:
        self._emit(Status(self.now, Code.LINE_BREAK, "receive"))

    def _rx_abandon_frame(self, _v: int) -> None:
        self._emit(Status(self.now, Code.LINE_BREAK, "receive"))
        self._emit(FrameDiscarded(self.now, bytes(self._cur), aev.LINE_BREAK, Code.LINE_BREAK))
        self._cur = bytearray()
        self._spoil = None
        self._room_check("discard")

    def _rx_receiver_off(self, _v: int) -> None:
        pass

    def _rx_receiver_on(self, _v: int) -> None:
        pass

    def _rx_abort_reception(self, _v: int) -> None:
        code = self.readings.q19_v24_code
        self._emit(Status(self.now, code, "receive"))
        self._emit(FrameDiscarded(self.now, bytes(self._cur), aev.DSR_OFF, code))
        self._cur = bytearray()
        self._spoil = None
        self._room_check("discard")

    # ================================================================== receive buffer
    def _store_frame(self, frame: bytes) -> None:
        """A complete frame goes into the receive buffer (§2.2.4 "receive buffer";
        Table 2-10)."""
        p = self.params
        if len(self._stored) < p.buffer_frames:
            pass
        elif not p.prevent_overwrite:
            _, old = self._stored.popleft()
            self._stored_bytes -= len(old)
            self._emit(FrameDiscarded(self.now, old, aev.OVERWRITTEN, None))
        else:
            code = self.readings.q18_full_buffer_code
            self._emit(Status(self.now, code, "receive"))
            self._emit(FrameDiscarded(self.now, frame, aev.BUFFER_FULL, code))
            return
        self._stored.append((self.now, frame))
        self._stored_bytes += len(frame)
        self._emit(FrameStored(self.now, frame))
        self._full_check()

    def _is_full(self) -> bool:
        r = self.readings
        frames = max(1, self.params.buffer_frames + r.q14_xoff_frame_offset)
        return len(self._stored) >= frames or self.buffer_fill >= r.q14_xoff_fill_bytes

    def _full_check(self) -> None:
        if self._flow_active and self.mode == "RUN" and self.fc_state is FcState.OPEN and self._is_full():
            self._fc(FcInput.FULL)

    def _room_check(self, source: str) -> None:
        if self._flow_active and self.mode == "RUN" and not self._is_full():
            self._fc(FcInput.ROOM, source)

    # ================================================================== receive flow control
    def _fc_let_partner_send(self, _v: int) -> None:
        if self.fc_state is FcState.HELD and self._fc_source == "discard" \
                and not self.readings.q15_xon_after_discard:
            self._override = T.SAME
            return
        self._announce(ready=True)

    def _fc_room_while_open(self, _v: int) -> None:
        # Q15: XON only to lift an XOFF; the other reading sends one after every read
        if self._fc_source == "read" and not self.readings.q15_xon_only_after_xoff:
            self._announce(ready=True)

    def _fc_hold_partner(self, _v: int) -> None:
        self._announce(ready=False)

    def _fc_ignore(self, _v: int) -> None:
        pass

    def _announce(self, ready: bool) -> None:
        heard = self.now
        if self._xonxoff:
            heard = self._send_control(self.params.xon if ready else self.params.xoff)
        else:
            self._set_signal("rts", 1 if ready else 0)
        if self.readings.d_cdt_suspended_while_holding and self.rx_state is RxState.RECEIVE \
                and self._spoil is None:
            if ready:   # the CDT of the interrupted frame runs again from the XON
                self._start(Timer.T_CDT, heard + self._cdt_window)
            else:
                self._stop(Timer.T_CDT)

    # ================================================================== transmitter
    def _send_control(self, b: int) -> float:
        """XON/XOFF go out at the next character boundary, ahead of any data waiting.
        Returns when the character is out."""
        removed = self._line.cut(self.now)
        for data, kind, why in removed:
            if kind == "control":
                self._line.schedule(self.now, data, kind, why)
        _, out = self._line.schedule(self.now, bytes((b,)), "control", self._why)
        for data, kind, why in removed:
            if kind == "data":
                _, end = self._line.schedule(self.now, data, kind, why)
                if Timer.TX_DONE in self._timers:
                    self._timers[Timer.TX_DONE] = end
        return out

    def _set_signal(self, name: str, value: int) -> None:
        if getattr(self, name) == value:
            return
        setattr(self, name, value)
        self._signals.append((self.now, name, value))
        if self.signal_log is not None:
            self.signal_log.append(SignalRecord(self.now, name, value, self._why))

    def _transmit(self) -> None:
        """Hand what is left of the job's frame to the transmitter."""
        job = self.job
        rest = job.wire[job.pos:]
        _, end = self._line.schedule(self.now, rest, "data", self._why)
        job.pos = len(job.wire)
        self._start(Timer.TX_DONE, end)

    def _take_back(self, extra: int = 0) -> int:
        """Stop sending the job's frame: characters not started by now (plus ``extra``)
        are taken back; returns how many."""
        removed = self._line.cut(self.now + extra * self._char)
        n = 0
        for data, kind, why in removed:
            if kind == "control":
                self._line.schedule(self.now, data, kind, why)
            else:
                n += len(data)
        if self.job is not None:
            self.job.pos -= n
        if n:
            self._stop(Timer.TX_DONE)
        return n

    def _finish_job(self) -> None:
        job, self.job = self.job, None
        self._emit(SendDone(self.now, job.payload, 1))

    def _abort(self, code: int) -> None:
        job = self.job
        self._take_back()
        self._stop(Timer.TX_DONE, Timer.T_PAUSE, Timer.T_DOW, Timer.T_RTS_OFF, Timer.T_XON_WAIT)
        if job.pos > 0:
            self._last_frame_end = max(self._last_frame_end, self._line.last_end("data"))
        if self._v24:
            self._set_signal("rts", 0)
        self._emit(Status(self.now, code, "send", final=True))
        self._emit(SendFailed(self.now, job.payload, code, None))
        self.job = None

    # ================================================================== sender actions
    def _tx_ignore(self, _v: int) -> None:
        pass

    def _tx_queue_job(self, _v: int) -> None:
        pass  # request_send queued it; it starts when the sender is next idle

    def _tx_start_job(self, _v: int) -> None:
        self.job = self._jobs.popleft()

    def _d_start(self) -> TxState:
        p, r = self.params, self.readings
        if p.pauses_between_frames:
            ready = self._last_frame_end + p.cdt + r.q5_send_pause_extra_chars * self._char
            if self.now < ready - EPS:
                self._start(Timer.T_PAUSE, ready)
                return TxState.PAUSE
        if self._v24:
            if r.q19_send_needs_dsr and not self.dsr:
                self._abort(r.q19_v24_code)
                return TxState.IDLE
            self._set_signal("rts", 1)
            self._start(Timer.T_DOW, self.now + p.data_output_wait)
            return TxState.RTS_ON_WAIT
        if self.partner_stopped:
            self._start(Timer.T_XON_WAIT, self.now + p.xon_wait)
            return TxState.STOPPED
        self._transmit()
        return TxState.SEND

    def _tx_pause_over(self, _v: int) -> None:
        pass

    def _tx_output_wait_over(self, _v: int) -> None:
        pass

    def _d_cts_check(self) -> TxState:
        if self.cts:
            self._transmit()
            return TxState.SEND
        self._abort(self.readings.q19_v24_code)
        return TxState.IDLE

    def _tx_frame_sent(self, _v: int) -> None:
        self._last_frame_end = self.now

    def _d_after_send(self) -> TxState:
        if self._v24:
            self._start(Timer.T_RTS_OFF, self.now + self.params.rts_off_delay)
            if not self.readings.q19_done_at_rts_off:
                self._finish_job()
            return TxState.RTS_OFF_WAIT
        self._finish_job()
        return TxState.IDLE

    def _tx_rts_off(self, _v: int) -> None:
        self._set_signal("rts", 0)
        if self.job is not None:
            self._finish_job()

    def _tx_partner_stopped(self, _v: int) -> None:
        if self._xonxoff and not self.readings.q16_xoff_while_idle_holds:
            return
        self.partner_stopped = True

    def _tx_partner_ready(self, _v: int) -> None:
        self.partner_stopped = False

    def _tx_interrupt(self, _v: int) -> None:
        self.partner_stopped = True
        if self._take_back(self.readings.q15_chars_after_xoff) == 0:
            self._override = T.SAME   # the whole frame is on the line already
            return
        self._start(Timer.T_XON_WAIT, self.now + self.params.xon_wait)

    def _tx_resume(self, _v: int) -> None:
        self.partner_stopped = False
        self._stop(Timer.T_XON_WAIT)
        self._transmit()

    def _tx_wait_expired(self, _v: int) -> None:
        self._abort(Code.XON_CTS_WAIT_EXPIRED)

    def _tx_abort_on_cts(self, _v: int) -> None:
        self._abort(self.readings.q19_v24_code)

    def _tx_abort_on_dsr(self, _v: int) -> None:
        self._abort(self.readings.q19_v24_code)


def _fallback_params(settings: Mapping[str, Any]) -> AsciiParams:
    """Parameters for a station in STOP: the character frame of ``settings`` if it is
    valid on its own (so that the silent line is timed right), else the defaults."""
    frame = {k: settings[k] for k in ("baud_rate", "data_bits", "parity", "stop_bits", "interface")
             if k in settings}
    try:
        return AsciiParams(**frame)
    except (ParameterError, TypeError):
        return AsciiParams()
