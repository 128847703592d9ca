"""Reference model of one 3964 / 3964R station: sans-IO, explicit time.

Every public method takes ``now`` (seconds, any monotonic origin). The station never reads
a clock, sleeps, or touches a device; its caller (a driver) feeds it what happened and
drains what it wants to do:

* inputs: :meth:`power_on`, :meth:`receive` (characters received intact),
  :meth:`receive_invalid` (a character with a parity/framing error), :meth:`line_break`,
  :meth:`request_send`, :meth:`set_buffer_free`, and :meth:`handle_timer` once
  :meth:`next_deadline` has been reached;
* outputs: :meth:`pop_output` (bytes with the time each starts on the line),
  :meth:`next_deadline`, :meth:`pop_events` (STATUS events, deliveries, job results).

The station includes its UART transmitter (:class:`~ptpcert.model.output.Transmitter`, the
one every procedure's station uses): bytes are scheduled one character time apart (the
character time follows from baud rate and character frame), so the model knows which bytes
are already on the line when the partner interrupts it. With ``baud_rate=None`` the
character time is zero.

Ordering rule: when an input and a deadline fall on the same instant, the input is handled
first (a character that completed exactly at the deadline started before it). Drivers must
therefore deliver the inputs of an instant before calling :meth:`handle_timer` for it.

What the station does in each state is the transition table in :mod:`.table`; this module
implements its actions (``_a_<name>``) and decisions (``_d_<name>``). An action never picks
the next state: the row's target does, or the decision it names.

Tools that watch a station (the fuzzer, the runner, links) use its public properties
(:attr:`transmitting`, :attr:`busy_until`, :attr:`popped_until`, :attr:`block_done_at`,
:attr:`timer`, :attr:`has_events`) and :meth:`block_body`, never its private fields. A broken
variant (:mod:`ptpcert.procedures.p3964.mutants`) is a subclass that overrides protected
hooks: actions, decisions, :meth:`_body`, :meth:`_durations`, the attempt limits.

The module is one piece on purpose, although long: it is the station class, with one method
for each action and decision of the table (about sixty) besides the interface above. The
sender and the receiver share one state (the job, the reception, the one timer, the
transmitter) and hand over to each other within an input (an initialization conflict turns
a sender into a receiver). The fast path that stores a run of received data at once
(:meth:`quiet_run`, :meth:`receive_run`) must do exactly what the receiver's actions do one
character at a time, and checks, for each subclass, that the table rows and actions it
stands for are still the plain ones. Cutting the class would spread one state machine over
several files and make no part usable alone. What is not the state machine lives elsewhere:
the transmitter in :mod:`ptpcert.model.output`, the table in :mod:`.table`, the block format
in :mod:`.codec`.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass
from math import inf

from ptpcert.model.codes import Code
from ptpcert.model.errors import ModelError
from ptpcert.model.events import Delivered, Event, SendDone, SendFailed, Status
from ptpcert.model.output import EPS, Transmitter, characters

from . import table as T
from .codec import DLE, ETX, MAX_BLOCK, NAK, STX, stuff
from .params import T_BLOCK, T_NAKTIM, Params3964
from .readings import READINGS, Readings

# the method of each action and decision, named once (not built per input)
_ACT = {a: "_a_" + a for a in T.Action}
_DECIDE = {d: "_d_" + d.lower() for d in T.DECISIONS}
_CLASS = [T.OTHER] * 256
_CLASS[STX], _CLASS[DLE], _CLASS[ETX], _CLASS[NAK] = T.STX, T.DLE, T.ETX, T.NAK
_END = bytes((DLE, ETX))
_PAIR, _ONE_DLE = bytes((DLE, DLE)), bytes((DLE,))


def _xor(data: bytes) -> int:
    """XOR of all bytes, folding a big integer in halves (fast for long runs)."""
    n = len(data)
    if n < 16:
        x = 0
        for b in data:
            x ^= b
        return x
    v = int.from_bytes(data, "little")
    width = n
    while width > 1:
        half = (width + 1) // 2
        v = (v & ((1 << (8 * half)) - 1)) ^ (v >> (8 * half))
        width = half
    return v & 0xFF


def _stores_in_receive(cls) -> bool:
    """Whether ``cls`` stores every character but DLE received in state RECEIVE with the
    plain ``store`` action and stays there (the table's rows), so that a run of them can be
    stored at once. A broken variant that changes those rows or the action is driven one
    character at a time."""
    rows = [cls.TABLE[T.RECEIVE][i] for i in (T.STX, T.ETX, T.NAK, T.OTHER)]
    return (all(r.action == "store" and r.target == T.SAME for r in rows)
            and cls._a_store is Station3964._a_store and cls._store is Station3964._store
            and cls._store_run is Station3964._store_run)


def _undoubles_in_receive(cls) -> bool:
    """Whether ``cls`` also takes a doubled DLE in state RECEIVE with the plain table rows
    and actions (DLE: ``dle_received`` to WAIT_ETX; there DLE: ``store_doubled_dle`` back to
    RECEIVE), so that a run of data with DLE pairs in it can be stored at once (one DLE per
    pair kept, both in the BCC). A broken variant that changes any of it is driven one
    character at a time."""
    first, second = cls.TABLE[T.RECEIVE][T.DLE], cls.TABLE[T.WAIT_ETX][T.DLE]
    return (cls._plain_receive
            and first.action == "dle_received" and first.target == T.WAIT_ETX
            and second.action == "store_doubled_dle" and second.target == T.RECEIVE
            and cls._a_dle_received is Station3964._a_dle_received
            and cls._a_store_doubled_dle is Station3964._a_store_doubled_dle
            and cls._start_timer is Station3964._start_timer and cls._input is Station3964._input)


def _plain_end(data: bytes, i: int) -> int:
    """Where the leading characters of ``data[i:]`` that are data other than DLE or DLE DLE
    pairs end: at the first DLE not followed by a second one (or at the end of ``data``)."""
    n = len(data)
    while True:
        j = data.find(DLE, i)
        if j < 0:
            return n
        if j + 1 < n and data[j + 1] == DLE:
            i = j + 2
        else:
            return j


#: Fig. 2-12 "W > 5 / W <= 5": the receptions of one block the figure allows (the alternative of A18)
FIG_2_12_RECEPTIONS = 6


@dataclass
class Job:
    """A send job: the payload and its counters (Fig. 2-10: W, X)."""

    payload: bytes
    w: int = 1          # transmission attempt number, including the first (Table 2-4)
    x: int = 1          # setup attempt number within the current transmission attempt
    first_error: int | None = None
    stx_sent: int = 0   # STX characters sent for this job (for invariants and tests)


class Station3964:
    """One 3964 / 3964R endpoint. See the module docstring for the calling convention."""

    #: the transition table this station follows (:mod:`.table`)
    TABLE = T.TABLE

    def __init_subclass__(cls, **kw):
        super().__init_subclass__(**kw)
        cls._plain_receive = _stores_in_receive(cls)
        cls._plain_pairs = _undoubles_in_receive(cls)

    def __init__(self, params: Params3964 | None = None, readings: Readings = READINGS,
                 *, name: str = "station", trace: bool = False, explain: bool = False):
        self.params = params or Params3964()
        self.readings = readings
        self.name = name
        self.state = T.START_UP
        self.now = -inf
        p = self.params
        self._char = p.char_time
        self._grace = p.char_time if readings.timer_grace_one_character else 0.0
        self._cdt, self._adt = self._durations()
        # timer: one at a time (the flowcharts never run two)
        self._timer: str | None = None
        self._timer_at = inf
        self._timer_started = False
        self._timer_from_tx = False
        # transmitter: what is scheduled to go out, and when (ptpcert.model.output)
        self._tx = Transmitter(p.char_time)
        self._tx_done_at = inf
        self._end_seq_at = inf
        # user side
        self._events: list[Event] = []
        self._jobs: deque[bytes] = deque()
        self.job: Job | None = None          # the job being sent
        self.deferred: Job | None = None     # a job deferred by an initialization conflict
        self.buffer_free = True
        # receiver
        self._buf = bytearray()
        self._x = 0                          # running BCC of the block being received
        self._overflow = False
        self._noted: int | None = None       # first error noted in the current reception
        self.w_r = 0                         # reception attempt number (Fig. 2-12 W)
        self._rx_first_error: int | None = None
        self._bcc_in = 0
        self._nak_just_sent = False
        self._cdt_timeout = False
        self._in_end_sequence = False
        self._dle_etx_done_at = inf
        self.trace: list[tuple] | None = [] if trace else None
        #: A real-time driver that wakes up after a deadline sets this: the station then acts
        #: at the time it is told (when its bytes really go out), not at the deadline, so a
        #: late wake-up delays what follows instead of shortening the next interval.
        self.late_timers_act_now = False
        #: With ``trace=True`` every input is recorded as (now, state, input, action, new
        #: state, ((decision, outcome), ...)) and every timer start as (now, "timer", name, at).
        #: With ``explain=True`` the station records why it sends what it sends: one entry
        #: per transmission, [start, end, input, actions] (the table row's action and the
        #: decisions taken), for tools that explain a transcript (the fuzzer, reports).
        self.tx_log: list[list] | None = [] if explain else None
        self._why: tuple[str, list[str]] = ("", [])

    # ================================================================== public API
    def power_on(self, now: float) -> None:
        """Switch-on (Fig. 2-9): the station sends its start-up NAK and becomes idle."""
        self._at(now, strict=True)
        self._input(T.POWER_ON)

    def receive(self, now: float, data: bytes | bytearray | int) -> None:
        """Characters received intact, all completed at ``now``."""
        self._at(now, strict=True)
        if isinstance(data, int):
            data = bytes((data,))
        cls = _CLASS
        i, n = 0, len(data)
        fast = self.trace is None and self._plain_receive
        pairs = fast and self._plain_pairs
        while i < n:
            if fast and self.state is T.RECEIVE:
                # TABLE[RECEIVE][STX/ETX/NAK/OTHER] = store, for a whole run without DLE,
                # and with DLE DLE pairs in it where the DLE rows are the plain ones too
                if pairs and self._tx_done_at == inf:
                    j = _plain_end(data, i)
                else:
                    j = data.find(DLE, i)
                    if j < 0:
                        j = n
                if j > i:
                    self._store_stuffed(data[i:j])
                    i = j
                    continue
            b = data[i]
            if i and self._tx_done_at <= now + EPS:
                # a zero-time transmission started by the previous character has ended
                # before this one, as it has between two receive() calls of one instant
                self._at(now, strict=True)
            self._input(cls[b], b)
            i += 1

    def quiet_run(self, now: float, data: bytes, spacing: float) -> int:
        """How many leading characters of ``data`` (the first complete at ``now``, each next
        one ``spacing`` later) this station would only store: no output, no event, no change
        of state, and none of its own deadlines between them. In state RECEIVE (Fig. 2-12
        "wait to receive") that is every character up to the first DLE that is not doubled
        (a DLE DLE pair is stored as one DLE, "dual DLE"), as long as they come closer
        together than CDT. A query: nothing changes. Links use it, with
        :meth:`receive_run`, to hand over a block at 9600 baud in one call instead of one
        event per character."""
        if (self.state is not T.RECEIVE or not self._plain_receive or self.trace is not None or self._tx.runs
                or self._events or now < self.now - EPS or self._tx_done_at != inf
                or self._timer_at <= now + EPS):
            return 0
        if self._plain_pairs:
            n = _plain_end(data, 0)     # a DLE DLE pair is stored as one DLE
        else:
            n = data.find(DLE)
            n = len(data) if n < 0 else n
        # the character timer restarts with each character; the next one must come first
        return n if spacing < self._cdt + self._grace - EPS else min(n, 1)

    def receive_run(self, now: float, data: bytes, spacing: float) -> None:
        """Characters received intact, the first complete at ``now`` and each next one
        ``spacing`` later: the same as ``receive(now + i * spacing, data[i])`` for each
        ``i``, in one call where :meth:`quiet_run` says they are only stored."""
        n = len(data)
        if n and self.quiet_run(now, data, spacing) == n:
            self._at(now, strict=True)
            self.now = max(self.now, now + (n - 1) * spacing)
            self._store_stuffed(bytes(data))
            return
        for i, b in enumerate(data):
            self.receive(now + i * spacing, b)

    def output_stream(self) -> tuple[float, bytes, float] | None:
        """The characters this station has scheduled to send back to back from the next one
        not yet handed out, if no input interrupts them: (start of the first, the bytes,
        the time of its next own deadline other than pacing them: a timer or the end of
        its block). None when nothing is scheduled. A query, for links."""
        runs = self._tx.runs
        if not runs:
            return None
        run = runs[0]
        return run[0], run[1], min(self._timer_at, self._tx_done_at)

    def receive_invalid(self, now: float, value: int = 0) -> None:
        """A character with a parity, framing or overrun error (an "invalid character")."""
        self._at(now, strict=True)
        self._input(T.INVALID, value)

    def line_break(self, now: float) -> None:
        """A BREAK condition on the receive line (§2.2.2 Error handling)."""
        self._at(now, strict=True)
        self._input(T.BREAK)

    def line_event(self, now: float, kind: str, value=0) -> None:
        """One event from the line, as drivers and links carry them: ``"byte"`` (a
        character, or ``"bytes"``, several at one instant), ``"invalid"`` (a character with a
        parity/framing error) or ``"break"``."""
        if kind == "byte" or kind == "bytes":
            self.receive(now, value)
        elif kind == "invalid":
            self.receive_invalid(now, value)
        elif kind == "break":
            self.line_break(now)
        else:
            raise ModelError(f"{self.name}: unknown line event {kind!r}")

    def request_send(self, now: float, payload: bytes) -> bool:
        """Hand over a send job (P_SND_RK with REQ). Returns False, raising 16#1E41, when
        the length is outside 1..1024; a 7-bit character frame cannot carry bytes > 7F."""
        self._at(now, strict=True)
        payload = bytes(payload)
        if not 1 <= len(payload) <= MAX_BLOCK:
            self._emit(Status(self.now, Code.LEN_ILLEGAL, "send", final=True))
            self._emit(SendFailed(self.now, payload, Code.LEN_ILLEGAL, None))
            return False
        if self.params.data_bits == 7 and any(b > 0x7F for b in payload):
            raise ValueError("a payload byte above 7F cannot be sent with 7 data bits")
        self._jobs.append(payload)
        self._input(T.SEND_REQUEST)
        return True

    def set_buffer_free(self, now: float, free: bool) -> None:
        """The application frees (or fills) the receive buffer (Fig. 2-11)."""
        self._at(now, strict=True)
        self.buffer_free = free
        if free and self.state is T.WAIT_BUFFER:
            self._input(T.BUFFER_FREE)

    def next_deadline(self) -> float | None:
        """The earliest time at which the station wants :meth:`handle_timer` (a timer, the
        end of a transmission, or the start of a byte to transmit); None when it waits
        only for input."""
        t, done = self._timer_at, self._tx_done_at
        if done < t:
            t = done
        tx = self._tx.runs
        if tx and tx[0][0] < t:
            t = tx[0][0]
        return None if t == inf else t

    def handle_timer(self, now: float) -> None:
        """Advance to ``now``, handling every deadline that has been reached."""
        self._at(now, strict=False)

    def pop_output(self, now: float | None = None) -> list[tuple[float, int]]:
        """Bytes whose transmission has started by ``now`` (all scheduled bytes when
        ``now`` is None), as (start time, byte) pairs, in order."""
        return characters(self.pop_output_runs(now), self._char)

    def pop_output_runs(self, now: float | None = None) -> list[tuple[float, bytes]]:
        """Like :meth:`pop_output`, as runs (start of the first byte, bytes) of characters
        sent back to back."""
        tx = self._tx
        return tx.pop(now) if tx.runs else []

    def pop_events(self) -> list[Event]:
        out, self._events = self._events, []
        return out

    @property
    def idle(self) -> bool:
        """Idle with nothing to do: no job, nothing scheduled to transmit."""
        return (self.state is T.IDLE and not self._tx.runs and self.job is None
                and self.deferred is None and not self._jobs)

    @property
    def pending_jobs(self) -> int:
        return len(self._jobs) + (self.job is not None) + (self.deferred is not None)

    @property
    def transmitting(self) -> bool:
        """Bytes are scheduled that :meth:`pop_output` has not handed out yet."""
        return bool(self._tx.runs)

    @property
    def busy_until(self) -> float:
        """When the transmitter will have sent everything scheduled so far (-inf before the
        first transmission)."""
        return self._tx.free_at

    @property
    def popped_until(self) -> float:
        """When the last byte handed out by :meth:`pop_output` has left the line."""
        return self._tx.popped_end

    @property
    def block_done_at(self) -> float | None:
        """While a block is being sent (state SEND_DATA): when its last byte will have left
        the transmitter (the TX_DONE input); otherwise None."""
        t = self._tx_done_at
        return None if t == inf else t

    @property
    def timer(self) -> tuple[str, float] | None:
        """The running timer (the flowcharts never run two) as (name, deadline), or None."""
        return None if self._timer is None else (self._timer, self._timer_at)

    @property
    def has_events(self) -> bool:
        """Events are waiting for :meth:`pop_events`."""
        return bool(self._events)

    def block_body(self, payload: bytes) -> bytes:
        """What this station sends after the partner's DLE for ``payload``: the data with
        every DLE doubled, DLE ETX and, for 3964R, the BCC (a broken variant's own, if any)."""
        return self._body(bytes(payload))

    # ================================================================== time
    def _at(self, now: float, strict: bool) -> None:
        """Move the clock to ``now`` and handle the deadlines before it (``strict``) or up
        to and including it."""
        if now < self.now - EPS:
            raise ModelError(f"{self.name}: time went backwards ({now} < {self.now})")
        while True:
            done_at, timer_at = self._tx_done_at, self._timer_at
            is_done = done_at <= timer_at
            t = done_at if is_done else timer_at
            if t == inf:
                break
            if strict:
                # Inputs at `now` go before deadlines at `now` (see the module docstring);
                # only a zero-time transmission has ended by the instant it started.
                due = t < now - EPS or (is_done and self._char == 0 and t <= now + EPS)
            else:
                due = t <= now + EPS
            if not due:
                break
            self.now = max(self.now, now if self.late_timers_act_now else t)
            if is_done:
                self._tx_done_at = inf
                self._input(T.TX_DONE)
            else:
                name, self._timer, self._timer_at = self._timer, None, inf
                self._input(name)
        if now > self.now:
            self.now = now

    def _start_timer(self, name: str, duration: float, since: float | None = None) -> None:
        # a timer measured from the end of our own transmission moves with it (delay_output)
        self._timer_from_tx = since is not None
        since = self.now if since is None else since
        grace = 0.0 if name is T.T_NAKTIM else self._grace
        self._timer, self._timer_at = name, since + duration + grace
        self._timer_started = True
        if self.trace is not None:
            self.trace.append((self.now, "timer", name, self._timer_at))

    def _stop_timer(self) -> None:
        self._timer, self._timer_at = None, inf

    def delay_output(self, delta: float) -> None:
        """The line took ``delta`` seconds longer than scheduled to carry what the station
        sent (a real-time driver that wrote late): what is still scheduled, the end of the
        transmission, and any timer measured from it move by ``delta``, as they would with a
        UART that started late."""
        if delta > 0:
            self._shift_output(delta)

    def advance_output(self, delta: float) -> float:
        """The line carried what the station sent up to ``delta`` seconds sooner than
        scheduled (an analysis that learns the station's transmission began earlier than it
        thought): what is still scheduled, the end of the transmission and any timer measured
        from it move earlier, but nothing before the present. Returns the move made."""
        if delta <= 0:
            return 0.0
        now = self.now
        runs = self._tx.runs
        if runs:
            delta = min(delta, runs[0][0] - now)
        if self._tx_done_at != inf:
            delta = min(delta, self._tx_done_at - now)
        if self._timer is not None and self._timer_from_tx:
            delta = min(delta, self._timer_at - now)
        if delta <= 0:
            return 0.0
        self._shift_output(-delta)
        return delta

    def _shift_output(self, delta: float) -> None:
        """Move what is still scheduled to transmit, the end of the transmission and a timer
        measured from it by ``delta`` seconds (later when positive)."""
        self._tx.shift(delta)
        if self._tx_done_at != inf:
            self._tx_done_at += delta
            self._end_seq_at += delta
            self._dle_etx_done_at += delta
        if self._timer is not None and self._timer_from_tx:
            self._timer_at += delta

    # ================================================================== transmitter
    def _send(self, data: bytes) -> float:
        """Schedule ``data`` on the line; return when its last byte has been sent."""
        start, end = self._tx.schedule(self.now, data)  # A8: no guard time before any character
        if self.tx_log is not None:
            self.tx_log.append([start, end, self._why[0], list(self._why[1])])
        return end

    def _cancel_tx(self) -> None:
        """Stop transmitting at once: bytes not yet started are dropped."""
        tx = self._tx
        tx.cut(self.now, EPS)     # a byte that starts now has started
        if self.tx_log:
            free = tx.free_at
            for entry in reversed(self.tx_log):
                if entry[1] <= free:
                    break
                entry[1] = max(entry[0], free)
        self._tx_done_at = inf
        self._end_seq_at = inf

    # ================================================================== dispatch
    def _input(self, inp: str, value: int = 0) -> None:
        old = self.state
        row = self.TABLE[old][inp]
        if row.action is T.IMPOSSIBLE:
            raise ModelError(f"{self.name}: input {inp} cannot occur in state {old}")
        self._timer_started = False
        if self.tx_log is not None:
            self._why = (inp, [row.action])
        action = row.action
        getattr(self, _ACT.get(action) or "_a_" + action)(value)
        target = row.target
        decided = None
        while target in _DECIDE:
            if self.tx_log is not None:
                self._why[1].append(target)
            outcome = getattr(self, _DECIDE[target])()
            if self.trace is not None:
                decided = (decided or ()) + ((target, outcome),)
            target = outcome
        new = old if target is T.SAME else target
        if self.trace is not None:
            self.trace.append((self.now, old, inp, row.action, new, decided or ()))
        if new is not old and not self._timer_started:
            self._stop_timer()
        self.state = new
        if new is T.IDLE and (self.deferred is not None or self._jobs):
            self._input(T.SEND_REQUEST)

    def _emit(self, event: Event) -> None:
        self._events.append(event)

    # ================================================================== start-up / idle
    def _a_send_startup_nak(self, _v: int) -> None:
        self._send(bytes((NAK,)))

    def _a_ignore(self, _v: int) -> None:
        pass

    def _a_queue_job(self, _v: int) -> None:
        pass  # request_send has queued it; it starts when the station is next idle

    def _a_start_quiet_wait(self, _v: int) -> None:
        self._start_timer(T.T_CDT, self._cdt)

    def _a_restart_quiet_wait(self, _v: int) -> None:
        if self.readings.a7_quiet_wait_retriggered or self._timer is None:
            self._start_timer(T.T_CDT, self._cdt)
        else:
            self._timer_started = True  # keep the running wait

    def _a_quiet_nak(self, _v: int) -> None:
        self._send(bytes((NAK,)))
        self._emit(Status(self.now, Code.RX_SETUP_ERROR, "receive"))

    def _a_report_break(self, _v: int) -> None:
        self._emit(Status(self.now, Code.LINE_BREAK, "receive"))

    def _a_report_invalid_in_idle(self, _v: int) -> None:
        self._emit(Status(self.now, Code.CHARACTER_ERROR, "receive"))

    def _d_idle_char_error(self) -> str:
        if self.readings.a13_nak_after_invalid_char_in_idle:
            self._start_timer(T.T_CDT, self._cdt)
            return T.IDLE_JUNK
        return T.IDLE

    # ================================================================== sender
    def _a_start_job(self, _v: int) -> None:
        if self.deferred is not None:
            job, self.deferred = self.deferred, None
            if self.readings.a21_conflict_counts_collided_stx:
                job.x += 1  # the collided STX was setup attempt 1 (Fig. 2-8, A21)
        else:
            job = Job(self._jobs.popleft())
        self.job = job

    def _d_start_check(self) -> str:
        # only a deferred job can start with X > 1 (A21); a new one has X = 1
        if self.job.x > 1 and self.job.x > self._setup_limit():
            return T.SETUP_CHECK
        self._send_stx()
        return T.WAIT_SETUP_ACK

    def _send_stx(self) -> None:
        self.job.stx_sent += 1
        self._start_timer(T.T_ADT, self._adt, self._send(bytes((STX,))))

    def _note_send_error(self, code: int) -> None:
        job = self.job
        if job.first_error is None:
            job.first_error = code
        if self.readings.a9_report_each_error:
            self._emit(Status(self.now, code, "send"))

    def _fail_job(self, code: int) -> None:
        job = self.job
        self._emit(Status(self.now, code, "send", final=True))
        self._emit(SendFailed(self.now, job.payload, code, job.first_error))
        self.job = None

    def _a_setup_refused(self, _v: int) -> None:
        self._note_send_error(Code.SETUP_REFUSED)
        self.job.x += 1

    def _a_setup_invalid_character(self, _v: int) -> None:
        self._note_send_error(Code.CHARACTER_ERROR)
        self.job.x += 1

    def _a_setup_timeout(self, _v: int) -> None:
        self._note_send_error(Code.SETUP_TIMEOUT)
        self.job.x += 1

    def _setup_limit(self) -> int:
        return self.params.setup_attempts

    def _tx_limit(self) -> int:
        return self.params.transmission_attempts

    def _d_setup_check(self) -> str:
        if self.job.x <= self._setup_limit():
            self._send_stx()
            return T.WAIT_SETUP_ACK
        self._send(bytes((NAK,)))
        self._fail_job(Code.SETUP_ATTEMPTS_EXCEEDED)
        return T.IDLE

    def _a_initialization_conflict(self, _v: int) -> None:
        if self.params.priority == "high":
            if self.readings.a23_restart_adt_on_conflict_stx:
                self._start_timer(T.T_ADT, self._adt)
            else:
                self._timer_started = True  # T_ADT keeps running
            return
        self._stop_timer()
        self.deferred, self.job = self.job, None
        self._a_begin_reception(0)

    def _d_priority(self) -> str:
        return T.WAIT_SETUP_ACK if self.params.priority == "high" else T.RECEIVE_ENTRY

    def _durations(self) -> tuple[float, float]:
        """The CDT and ADT this station applies: the parameters' (Table 2-4)."""
        return self.params.cdt, self.params.adt

    def _body(self, payload: bytes) -> bytes:
        """What follows the partner's DLE: the data with every DLE doubled, DLE ETX and, for
        3964R, the BCC over all of it (§2.2.2 Control characters, Block check character)."""
        stuffed = stuff(payload)
        body = stuffed + _END
        if self.params.has_bcc:
            body += bytes((_xor(stuffed) ^ DLE ^ ETX,))
        return body

    def _a_setup_acknowledged(self, _v: int) -> None:
        self._stop_timer()
        end = self._send(self._body(self.job.payload))
        n_end = 3 if self.params.has_bcc else 2
        self._end_seq_at = end - n_end * self._char
        self._tx_done_at = end
        self._dle_etx_done_at = self._end_seq_at + 2 * self._char

    def _a_send_refused(self, _v: int) -> None:
        self._cancel_tx()
        self._note_send_error(Code.SEND_INTERRUPTED)
        self.job.w += 1

    def _a_send_interrupted(self, _v: int) -> None:
        self._cancel_tx()
        self._note_send_error(Code.SEND_INTERRUPTED)
        self._start_timer(T.T_CDT, self._cdt)

    def _a_dle_during_send(self, _v: int) -> None:
        self._in_end_sequence = (self.readings.a10_dle_in_end_sequence_too_early
                                 and self.now >= self._end_seq_at - EPS)
        self._cancel_tx()

    def _d_in_end_sequence(self) -> str:
        if self._in_end_sequence:
            self._note_send_error(Code.RELEASE_REFUSED)  # "DLE too early" (A10)
            self.job.w += 1
            return T.TX_CHECK
        self._note_send_error(Code.SEND_INTERRUPTED)
        self._start_timer(T.T_CDT, self._cdt)
        return T.ABORT_QUIET

    def _a_abort_nak(self, _v: int) -> None:
        self._send(bytes((NAK,)))
        self._nak_just_sent = True
        self.job.w += 1

    def _a_block_sent(self, _v: int) -> None:
        since = self.now if self.readings.a12_release_adt_after_last_byte else self._dle_etx_done_at
        self._start_timer(T.T_ADT, self._adt, since)

    def _a_release_acknowledged(self, _v: int) -> None:
        job, self.job = self.job, None
        self._emit(SendDone(self.now, job.payload, job.w))

    def _a_release_refused(self, _v: int) -> None:
        self._note_send_error(Code.RELEASE_REFUSED)
        self.job.w += 1

    def _a_release_invalid_character(self, _v: int) -> None:
        self._note_send_error(Code.CHARACTER_ERROR)
        self.job.w += 1

    def _a_release_timeout(self, _v: int) -> None:
        self._note_send_error(Code.RELEASE_TIMEOUT)
        self.job.w += 1

    def _d_tx_check(self) -> str:
        nak_sent, self._nak_just_sent = self._nak_just_sent, False
        job = self.job
        if job.w <= self._tx_limit():
            if job.w == 2:
                self._emit(Status(self.now, Code.FIRST_REPETITION, "send"))
            if self.readings.a4_reset_setup_counter_per_attempt:
                job.x = 1
            self._send_stx()
            return T.WAIT_SETUP_ACK
        if not nak_sent or self.readings.a6_second_final_nak:
            self._send(bytes((NAK,)))
        self._fail_job(Code.TX_ATTEMPTS_EXCEEDED)
        return T.IDLE

    def _a_abort_job(self, _v: int) -> None:
        self._cancel_tx()
        self._fail_job(self.readings.a15_break_status_on_send)

    # ================================================================== receiver
    def _a_begin_reception(self, _v: int) -> None:
        self.w_r = 1
        self._rx_first_error = None
        self._clear_reception()

    def _clear_reception(self) -> None:
        self._buf = bytearray()
        self._x = 0
        self._overflow = False
        self._noted = None

    def _d_receive_entry(self) -> str:
        if self.buffer_free:
            self._start_timer(T.T_CDT, self._cdt, self._send(bytes((DLE,))))
            return T.RECEIVE
        self._start_timer(T.T_NAKTIM, T_NAKTIM)
        return T.WAIT_BUFFER

    def _a_buffer_freed(self, _v: int) -> None:
        self._start_timer(T.T_CDT, self._cdt, self._send(bytes((DLE,))))

    def _a_no_buffer(self, _v: int) -> None:
        self._emit(Status(self.now, Code.NO_RECEIVE_BUFFER, "receive"))
        self._send(bytes((NAK,)))

    def _a_setup_garbage(self, _v: int) -> None:
        pass  # what follows is the A16 decision

    def _d_abandon_setup(self) -> str:
        if self.readings.a16_garbage_during_buffer_wait_quiet_nak:
            # give up the setup; IDLE_JUNK sends the NAK and raises 16#0802
            self._start_timer(T.T_CDT, self._cdt)
            return T.IDLE_JUNK
        self._emit(Status(self.now, Code.RX_SETUP_ERROR, "receive"))
        self._timer_started = True  # T_NAKTIM keeps running
        return T.WAIT_BUFFER

    def _note(self, code: int) -> None:
        if self._noted is None:
            self._noted = code

    def _store(self, b: int, in_bcc: bool = True) -> None:
        """Keep one received data byte (``in_bcc``: and count it in the running BCC)."""
        if len(self._buf) < MAX_BLOCK:
            self._buf.append(b)
        elif not self._overflow:
            self._overflow = True
            self._note(Code.FRAME_TOO_LONG)
        if in_bcc:
            self._x ^= b
        self._timer, self._timer_at = T.T_CDT, self.now + self._cdt + self._grace

    def _store_run(self, run: bytes) -> None:
        room = MAX_BLOCK - len(self._buf)
        if len(run) > room:
            self._buf += run[:max(room, 0)]
            if not self._overflow:
                self._overflow = True
                self._note(Code.FRAME_TOO_LONG)
        else:
            self._buf += run
        self._x ^= _xor(run)
        self._timer, self._timer_at = T.T_CDT, self.now + self._cdt + self._grace

    def _store_stuffed(self, run: bytes) -> None:
        """Store a run received in state RECEIVE: data other than DLE, and DLE DLE pairs
        where the station takes them with the plain rows (``_plain_pairs``). A pair is what
        ``_a_dle_received`` then ``_a_store_doubled_dle`` make of it: one DLE kept, both in
        the BCC, the character timer restarted (not measured from a transmission)."""
        if DLE not in run:
            self._store_run(run)
            return
        x = self._x ^ _xor(run)
        self._store_run(run.replace(_PAIR, _ONE_DLE))
        self._x = x
        self._timer_from_tx = False

    def _a_store(self, v: int) -> None:
        self._store(v)
        self._timer_started = True

    def _a_dle_received(self, _v: int) -> None:
        self._x ^= DLE
        self._start_timer(T.T_CDT, self._cdt)

    def _a_store_doubled_dle(self, _v: int) -> None:
        self._store(DLE)          # XORs the second DLE; the first was XORed on arrival
        self._timer_started = True

    def _a_dle_followed_by_other(self, v: int) -> None:
        self._note(Code.RX_LOGICAL_ERROR)
        self._x ^= v

    def _d_nak_at_once(self) -> str:
        if self.readings.a11_deferred_nak_after_dle_other:
            self._start_timer(T.T_CDT, self._cdt)  # keep receiving
            return T.RECEIVE
        return T.NAK_CHECK

    def _a_note_invalid_character(self, _v: int) -> None:
        self._note(Code.CHARACTER_ERROR)
        self._start_timer(T.T_CDT, self._cdt)

    def _a_character_timeout(self, _v: int) -> None:
        self._note(Code.CDT_EXCEEDED)
        self._cdt_timeout = True

    def _a_end_of_text(self, _v: int) -> None:
        self._x ^= ETX
        if self.params.has_bcc:
            self._start_timer(T.T_CDT, self._cdt)  # Fig. 2-12: wait for the BCC

    def _d_after_etx(self) -> str:
        return T.WAIT_BCC if self.params.has_bcc else T.EVALUATE

    def _a_bcc_received(self, v: int) -> None:
        self._bcc_in = v

    def _d_bcc_check(self) -> str:
        if self._bcc_in == self._x:
            return T.EVALUATE
        self._note(Code.BCC_ERROR)
        return T.NAK_CHECK

    def _a_bcc_invalid_character(self, _v: int) -> None:
        self._note(Code.CHARACTER_ERROR)

    def _d_evaluate(self) -> str:
        if self._noted is None and (self._buf or self.readings.a17_accept_zero_length_block):
            self._send(bytes((DLE,)))
            self._emit(Delivered(self.now, bytes(self._buf)))
            self._clear_reception()
            return T.IDLE
        if self._noted is None:
            self._noted = Code.RX_LOGICAL_ERROR  # zero-length block refused (alternative of A17)
        return T.NAK_CHECK

    def _d_nak_check(self) -> str:
        self._send(bytes((NAK,)))
        code = self._noted
        self._emit(Status(self.now, code, "receive"))
        if self.w_r == 1:
            self._rx_first_error = code
            self._emit(Status(self.now, Code.EXPECT_REPETITION, "receive"))
        timeout, self._cdt_timeout = self._cdt_timeout, False
        self._clear_reception()
        limit = (self.params.transmission_attempts if self.readings.a18_receiver_uses_own_attempt_limit
                 else FIG_2_12_RECEPTIONS)
        if self.w_r >= limit or (timeout and not self.readings.a2_cdt_timeout_awaits_repetition):
            self._emit(Status(self.now, self._rx_first_error, "receive", final=True))
            return T.IDLE
        self._start_timer(T.T_BLOCK, T_BLOCK, self._tx.free_at)
        return T.WAIT_REPETITION

    def _a_repetition_begins(self, _v: int) -> None:
        self.w_r += 1
        self._clear_reception()

    def _a_partner_gave_up(self, _v: int) -> None:
        self._emit(Status(self.now, self.readings.a19_wait_repetition_code, "receive", final=True))

    def _a_repetition_timeout(self, _v: int) -> None:
        self._emit(Status(self.now, self.readings.a19_wait_repetition_code, "receive", final=True))

    def _a_abandon_reception(self, _v: int) -> None:
        self._clear_reception()
        self._emit(Status(self.now, Code.LINE_BREAK, "receive"))


Station3964._plain_receive = _stores_in_receive(Station3964)
Station3964._plain_pairs = _undoubles_in_receive(Station3964)
