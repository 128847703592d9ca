"""Line analysis: judge both stations of a recorded or live serial link with the model.

A capture (:mod:`ptpcert.capture`) holds what each of two stations put on its transmit line.
For each seat that is judged, a model station with that seat's parameters is fed what the
*other* seat sent, at the times it arrived, and what the model would send is compared, byte
by byte and in time, with what the seat sent. The model is *followed*: a byte the seat sent
later than the model (still in time) delays the rest of the model's schedule, as a UART that
started late would (``delay_output``); a local event the line reveals but no model can
predict - a send job handed over by the station's application, a restart, a receive buffer
that became free - is given to the model when the seat's byte shows it (the procedure's
analyzer says which bytes reveal which events).

A difference is a *finding*: the rule the seat broke (the manual's reference), what the model
sent or would have sent, what the seat sent, and the STATUS events a CP 341 in each seat
raises. Before a difference stands, the stretch since the model was last at rest is judged
again with every alternative the procedure names (the other readings of the manual's open
points, as the fuzzer does) and, where the capture's timestamps are coarse, with the other
seat's bytes as early and as late as the timing resolution allows; an alternative that
follows the seat without a difference turns the finding into an informational one. After a
difference that stands, the seat is not judged again until the line has been quiet long
enough for every conforming station to be at rest (or a case of a ``ptpcert run`` starts).

Timing windows. A byte the model sends in reply to the partner may come as late as the
partner's timer that waits for it allows (e.g. a DLE within the partner's ADT); a byte the
model sends when one of its own timers runs out may come a character time and a twentieth of
the timer early and ``late_ms`` plus a quarter of the timer late. On top of that the
capture's timing *resolution* (how much earlier than its timestamp a byte may really have
been complete): a byte inside a window only because of the resolution is graded
informational, never failed.

Exchanges. The report groups the line into exchanges: an exchange ends where every judged
station's model is at rest (idle, nothing to send, no job) when the next byte begins, at a
case mark, or after a quiet line as long as the longest timer. Each exchange is a
:class:`~ptpcert.results.CaseResult` (pass, or informational), and so is each finding
(fail or informational), so that ``ptpcert report`` and the JUnit/HTML views show them.

Live use (``ptpcert monitor``) feeds chunks as they are read and calls :meth:`LineAnalysis.advance`
with the current time; the analysis judges up to a lag behind it (the longest window), so that
every byte the model predicts has had its chance to arrive. Findings and finished exchanges
are handed to the listener as soon as they stand.

What a procedure brings is a :class:`ProcedureAnalyzer` (``Procedure.analyzer(params_a,
params_b)``): its stations at rest and powered on, when a station is at rest, which local
events the seat's bytes reveal, why the model sends each byte (rule, reference, STATUS code,
timing window), what a byte the model does not send breaks, the alternatives to try, and how
an exchange is labelled. This module knows no protocol.
"""

from __future__ import annotations

import bisect
import copy
import re
from dataclasses import dataclass, field, replace
from math import inf
from typing import Any, Callable, Iterable, NamedTuple

from ptpcert import capture as C
from ptpcert import results as R

SEATS = ("a", "b")
OTHER = {"a": "b", "b": "a"}
_EPS = 1e-9
#: The capture formats hold whole microseconds, so instants that were equal may differ by one:
#: a byte the model begins within a microsecond of the other seat's character counts as begun
#: before it arrived (a sender stops only what it has not begun), and a local event a seat's
#: byte reveals may have happened a microsecond before that byte's estimated start.
QUANTUM = 1e-6
#: what a seat is called in a capture that ``ptpcert run`` wrote
RUN_ROLES = {"a": "tester", "b": "IUT"}


# ------------------------------------------------------------------ what the procedure brings


@dataclass(frozen=True)
class Cause:
    """Why the model sends a byte, and the timing it allows.

    ``early``/``late``: how much earlier/later than the model the byte may be complete and still
    conform (seconds, before the capture's resolution is added). ``kind``: "reply" (to the
    partner), "timer" (one of the station's own timers ran out), "local" (a local event)."""

    kind: str
    rule: str
    reference: str
    early: float
    late: float
    code: int | None = None
    what: str = ""           # the character's name for people, e.g. "DLE" or "the block"
    rules: tuple[str, ...] = ()   # ids of the rules in the procedure's catalogue (ptpcert rules)


@dataclass(frozen=True)
class Explanation:
    """A local event that a seat's byte reveals: ``apply(run, t)`` gives it to the model at
    ``t`` (e.g. a send request). ``note`` is worth telling people (None: routine)."""

    apply: Callable[["SeatRun", float], None]
    note: str | None = None


#: :meth:`ProcedureAnalyzer.explain` needs to see more of the line before it can tell
WAIT = object()


@dataclass(frozen=True)
class Variant:
    """An alternative to try before a difference stands: other readings of the manual's open
    points (``readings``, named ``name``, e.g. "A11"), or the other seat's bytes moved by
    ``shift`` seconds (within the capture's resolution)."""

    name: str
    description: str
    readings: Any = None
    shift: float = 0.0
    #: the local events the seat's bytes reveal (a send job, a free buffer) happened up to
    #: this much earlier than the bytes' timestamps say (within the capture's resolution)
    lead: float = 0.0
    #: what the finding an adopted alternative leaves is called ("reading" or "resolution"
    #: by default; e.g. "buffer": a local condition of the station the line does not show)
    kind: str = ""


class ProcedureAnalyzer:
    """The procedure's part of line analysis (see the module docstring). ``params`` maps a
    seat to its station's parameters; ``apps`` a seat to its application ("echo": it sends
    back every block it receives; "none": what it sends is its own business)."""

    procedure: Any = None
    #: where the manual describes the procedure (the reference of an exchange without findings)
    reference: str = ""

    def __init__(self, procedure: Any, params: dict[str, Any], apps: dict[str, str] | None = None):
        self.procedure = procedure
        self.params = dict(params)
        self.apps = {s: "none" for s in SEATS} | dict(apps or {})
        self._char: dict[str, float] = {}

    # -- timing ---------------------------------------------------------------------------
    def char(self, seat: str) -> float:
        c = self._char.get(seat)
        if c is None:
            c = self._char[seat] = self.procedure.char_time(self.params[seat])
        return c

    def rest_gap(self) -> float:
        """How long the line must be quiet before every conforming station is at rest."""
        raise NotImplementedError

    def early_wait(self, host: Any) -> float:
        """How long after a byte the model does not send the analysis waits for the model to
        send it after all (a timer of the station's own that a conforming station may let run
        out that much sooner), before the byte stands as one the model does not send."""
        raise NotImplementedError

    def late_max(self, seat: str) -> float:
        """The largest ``Cause.late`` of the seat's bytes (the lag of live analysis)."""
        raise NotImplementedError

    # -- stations -------------------------------------------------------------------------
    def fresh(self, seat: str, t: float, readings: Any = None) -> Any:
        """A host (station and application) of ``seat`` that is running and at rest at ``t``."""
        raise NotImplementedError

    def powered(self, seat: str, t: float) -> Any:
        """A host of ``seat`` switched on at ``t`` (what it sends at start-up still to come)."""
        raise NotImplementedError

    def at_rest(self, host: Any) -> bool:
        raise NotImplementedError

    # -- reading the seat's bytes ---------------------------------------------------------
    def explain(self, run: "SeatRun", item: "Item", index: int) -> Explanation | None | object:
        """A local event that the seat's ``item`` (``run.judge.obs[index]``) reveals, the model
        not sending it on its own: an :class:`Explanation`, None, or :data:`WAIT` when more of
        the line must be seen first."""
        return None

    def interjects(self, run: "SeatRun", item: "Item") -> bool:
        """May the seat's ``item`` reveal a local event even where the model is about to send
        a byte of its own (e.g. a flow-control character a station puts between two
        characters of its frame)? Then :meth:`explain` is asked first."""
        return False

    def before(self, item: "Item", inputs: list["Item"]) -> bool:
        """The seat's ``item`` began at the instant (within a microsecond) the other seat's
        ``inputs`` were complete: did what it reveals happen before the station took them in
        (True, e.g. two STXs crossing), or after (False: the station answered them)?"""
        return False

    def event(self, run: "SeatRun", event: Any) -> None:
        """Every event the model raises (STATUS, deliveries, job results), for the
        procedure's own bookkeeping in ``run.memo``."""

    def begins(self, byte: int) -> bool:
        """Does a station's ``byte``, sent for a local event, begin an exchange (e.g. STX)?"""
        return False

    def begins_in(self, host: Any, byte: int) -> bool:
        """Does ``byte``, sent for a local event by the station of ``host`` (as it is when it
        sends the byte), begin an exchange? By default :meth:`begins`; a procedure with a
        layer above its blocks may say no while that layer has an exchange open (e.g. the
        RK 512 response to a command)."""
        return self.begins(byte)

    def resync_at(self, line: "LineAnalysis", k: int) -> int | None:
        """Where the line never goes quiet: does an exchange with both stations at rest begin
        in chunk ``k``, as its bytes and those before it show (a seat that is not followed
        any more is followed again from there)? The index of its first item in the chunk, or
        None."""
        return None

    def startup(self, run: "SeatRun", item: "Item", index: int) -> Explanation | None:
        """The seat was switched on (a case of a restarting IUT began): its first ``item`` is
        its start-up output, or None when it is not."""
        return None

    def startup_rule(self, seat: str) -> tuple[str, str, int | None]:
        """(rule, reference, code) of what a station sends at start-up."""
        return ("a station announces its start-up", "", None)

    def announces_startup(self, seat: str) -> bool:
        """Does the station in ``seat`` send something when it is switched on? (When it does
        not, a power-on only starts its model afresh: there is no start-up output to expect.)"""
        return True

    def startup_name(self, seat: str) -> str:
        """What a station sends at start-up, for people (e.g. "NAK")."""
        return "announcement"

    def entry_start(self, entry: Any) -> float:
        """When the transmission ``entry`` of a station's explanation log (``tx_log``) began."""
        return entry[0]

    def continues(self, prev: Any, entry: Any) -> bool:
        """Is ``entry`` of the explanation log the rest of the transmission ``prev`` (a log
        that records a transmission in parts, e.g. once its schedule was delayed)? Its bytes
        then keep ``prev``'s cause and count on from it."""
        return False

    def cause(self, run: "SeatRun", entry: Any, k: int, byte: int) -> Cause:
        """Why the model (``run.host``) sends ``byte``, the ``k``-th of the transmission
        ``entry`` of its explanation log (``station.tx_log``: [start, end, input, actions]).
        One cause serves every byte of a transmission."""
        raise NotImplementedError

    def unexpected(self, run: "SeatRun", host: Any, item: "Item",
                   later: tuple[float, int, Cause] | None) -> Cause:
        """The rule broken by sending ``item`` where the model ``host`` (as it was when the
        byte began) sends nothing; ``later`` is what the model sends next without further
        input, if anything: (completion, byte, cause)."""
        raise NotImplementedError

    def wrong(self, run: "SeatRun", item: "Item", byte: int, cause: Cause) -> Cause:
        """The rule broken by sending ``item`` where the model sends ``byte`` for ``cause``:
        ``cause`` itself unless the item breaks a rule of its own (e.g. a value no character
        of the seat's frame carries)."""
        return cause

    def name(self, byte: int) -> str:
        return f"{byte:02X}"

    def what(self, host: Any, entry: Any, k: int, byte: int) -> str:
        """The ``k``-th byte of the transmission ``entry`` in words (e.g. "the BCC 10"), or ""."""
        return ""

    def variants(self, seat: str, resolution: float) -> list[Variant]:
        """The alternatives to try before a difference stands."""
        return []

    def label(self, items: list[tuple[str, "Item"]]) -> str:
        """An exchange in a few words, from its bytes ((seat, item) in time order)."""
        return ""



# ------------------------------------------------------------------ findings


@dataclass
class Finding:
    """A rule a seat broke, or (grade informational) a point the analysis could not settle."""

    seat: str
    t: float                          # capture time of the byte concerned (or where it was due)
    grade: str                        # results.FAIL or results.INFORMATIONAL
    kind: str                         # wrong, missing, early, late, unexpected, start-up, timing, reading, resolution,
    #                                   buffer (a local condition the line does not show)
    rule: str
    reference: str
    message: str
    expected: str = ""
    observed: str = ""
    window: tuple[float, float] | None = None
    codes: tuple[int, ...] = ()
    readings: tuple[str, ...] = ()
    notes: list[str] = field(default_factory=list)
    rules: tuple[str, ...] = ()       # ids of the rules broken, from the procedure's catalogue
    #: the difference does not depend on the order in which the model took the two seats'
    #: characters: a wrong byte inside a transmission the partner kept silent through, up to
    #: and including the read that returned the byte (a monitor reads every port that has
    #: characters waiting, so a partner's character stamped later came later)
    order_free: bool = False

    def text(self, seats: dict[str, str] | None = None) -> str:
        who = f"seat {self.seat}" + (f" ({seats[self.seat]})" if seats and seats.get(self.seat) not in (None, self.seat) else "")
        ids = f" [rule {', '.join(self.rules)}]" if self.rules else ""
        return f"{who}: {self.message}{ids}"


class Item(NamedTuple):
    """One thing a seat put on its line: a byte, a character with an error ("invalid") or a
    BREAK. ``t``: when it was complete; ``start``: when it began (both estimated from the
    chunk's time); ``chunk``: its chunk's index."""

    t: float
    kind: str
    value: Any
    chunk: int
    start: float


def _strip_section(rule: str) -> str:
    """A rule sentence without a leading section number of our own notes."""
    return re.sub(r"^§[\d.\-]+(?: items? [\d\-]+)?:\s*", "", rule)


# ------------------------------------------------------------------ following one seat


class SeatRun:
    """One attempt to follow a seat with a model from a point where it was at rest."""

    def __init__(self, judge: "SeatJudge", host: Any, t0: float, i_in: int, i_obs: int, *,
                 variant: Variant | None = None, expect_startup: bool = False):
        self.judge = judge
        self.kit = judge.kit
        self.host = host
        self.st = host.station
        self.t0 = self.now = t0
        self.i_in, self.i_obs = i_in, i_obs
        self.start_pos = (i_in, i_obs)
        self.variant = variant
        self.shift = variant.shift if variant is not None else 0.0
        self.lead = variant.lead if variant is not None else 0.0
        #: the shift applies to the other seat's characters up to here (the difference an
        #: alternative is to explain); later ones keep their times
        self.shift_until = inf
        self.expect_startup = expect_startup
        self.failed: Finding | None = None
        # provisional until the next rest point (a later difference may replace them)
        self.findings: list[Finding] = []
        self.events: list[tuple[float, int]] = []
        self.notes: list[tuple[float, str]] = []
        self.flags: dict[int, bool] = {}
        self.stage = 0
        self._applied = -1
        #: the seat's byte whose explanation last waited for more of the line
        self._waited, self._waited_at = -1, -inf
        self._tied = -inf
        self._snapshot: tuple | None = None
        self._held: list[tuple] = []
        #: the procedure's own notes about this run (e.g. the send jobs the line revealed)
        self.memo: dict[str, Any] = {}
        self.rest = (t0, i_in, i_obs, expect_startup, {})
        self._log_pos = -1
        self._log_k = 0
        self._log_cause: Cause | None = None
        self.char = self.kit.char(judge.seat)
        self.res = judge.analysis.resolution
        self.early_wait = 0.0

    # -- the model ------------------------------------------------------------------------
    def replace_host(self, host: Any) -> None:
        """A restart: a new station takes over (its explanation log starts afresh)."""
        self.host, self.st = host, host.station
        self._log_pos, self._log_k, self._log_cause = -1, 0, None

    def _cause_of(self, s: float, b: int) -> tuple[Cause, Any, int]:
        """Why the model sends the byte it began at ``s``: (cause, log entry, index in it)."""
        log = self.st.tx_log
        if not log:
            return self.kit.cause(self, None, 0, b), None, 0
        pos = old = self._log_pos
        n = len(log)
        moved = pos < 0
        start = self.kit.entry_start
        while pos + 1 < n and start(log[pos + 1]) <= s + 1e-9:
            pos += 1
            moved = True
        if moved:
            if old >= 0 and pos > old and self.kit.continues(log[pos - 1], log[pos]):
                self._log_pos = pos     # the same transmission, logged in two parts
            else:
                self._log_pos, self._log_k = max(pos, 0), 0
                self._log_cause = None
        k = self._log_k
        self._log_k += 1
        entry = log[self._log_pos]
        cause = self._log_cause
        if cause is None:
            # one cause per transmission: the bytes of a block share it
            cause = self._log_cause = self.kit.cause(self, entry, k, b)
        return cause, entry, k

    def _name(self, cause: Cause, entry: Any, k: int, b: int) -> str:
        """The byte the model sends, for people (e.g. "the BCC 10")."""
        return self.kit.what(self.host, entry, k, b) or cause.what or self.kit.name(b)

    def _trim_log(self) -> None:
        log = self.st.tx_log
        if log and self._log_pos > 0:
            del log[:self._log_pos]
            self._log_pos = 0

    def _at_rest(self) -> bool:
        return self.kit.at_rest(self.host)

    # -- stepping -------------------------------------------------------------------------
    def step(self, until: float, rest_after: float | None = None) -> str:
        """Follow the seat up to ``until``. Returns "fail" (see :attr:`failed`), "rest" (at
        rest after ``rest_after``), "wait" (the procedure must see more of the line) or
        "until"."""
        inputs, obs = self.judge.inputs, self.judge.obs
        kit = self.kit
        until_shift = self.shift_until
        shift_ = self.shift

        def at(it: Item) -> float:
            return it.t + shift_ if it.t <= until_shift else it.t

        flags = self.flags
        while True:
            if self._held:
                r = self._release()
                if r is not None:
                    return "wait" if r is WAIT else r
            if rest_after is not None and self.now > rest_after and self._rested(self.now):
                return "rest"
            st = self.st
            n_in = len(inputs)
            t_in = at(inputs[self.i_in]) if self.i_in < n_in else inf
            d = st.next_deadline()
            t_dl = inf if d is None else d
            # the next event of the seat's own next byte (see _obs_time)
            if self.i_obs < len(obs):
                o = obs[self.i_obs]
                stage = self.stage
                if stage == 0:
                    t_ob = o.start - QUANTUM
                    if self.lead and o.t <= until_shift:
                        t_ob -= self.lead
                elif stage == 1:
                    t_ob = o.start + QUANTUM
                    if self._tied + _EPS > t_ob:
                        t_ob = self._tied + _EPS
                else:
                    t_ob = o.t + self.early_wait
            else:
                o, t_ob, stage = None, inf, -1
            t = t_in if t_in < t_dl else t_dl
            if t_ob < t:
                t = t_ob
            if t > until or t == inf:
                return "until"
            if t > self.now:
                self.now = t
            if t_ob == t and stage == 0:
                # a local event the seat's byte reveals goes before the inputs of its instant
                # (two stations whose STXs cross both decided to send before hearing the other)
                if (st.transmitting and t_dl <= o.start + QUANTUM and not (self.lead and t < o.start - QUANTUM)
                        and not kit.interjects(self, o)):
                    self.stage, self._tied = 1, -inf   # the model is about to send a byte: compare
                    continue
                idx = self.i_obs
                k = self.i_in
                while k < n_in and at(inputs[k]) <= o.start + QUANTUM:
                    k += 1
                if k > self.i_in and not kit.before(o, inputs[self.i_in:k]):
                    self.stage = 1      # the other seat's characters of the same instant came first
                    self._tied = at(inputs[k - 1])
                    continue
                if self._explain(idx, o, t) is WAIT:
                    return "wait"
                if self.failed:
                    return "fail"
                if self.i_obs == idx:
                    self.stage, self._tied = 1, -inf
                continue
            if t_in == t:
                while self.i_in < n_in and at(inputs[self.i_in]) <= t:
                    it = inputs[self.i_in]
                    self.i_in += 1
                    if it.chunk not in flags:
                        flags[it.chunk] = kit.at_rest(self.host) and (
                            self.i_obs >= len(obs) or obs[self.i_obs].start >= t - QUANTUM)
                    if st.transmitting:
                        # a byte begun at the same instant was on the line before the input
                        r = self._compare_all(st.pop_output(t + QUANTUM))
                        if r is not None:
                            self.i_in -= 1      # taken in once the byte is settled
                            return r
                    st.line_event(t if t > st.now else st.now, it.kind, it.value)
                    r = self._collect(t)
                    if r is not None:
                        return r
                if self.stage and self._retry(t) is WAIT:
                    return "wait"
                if self.failed:
                    return "fail"
                continue
            if t_dl == t:
                st.handle_timer(t)
                r = self._collect(t)
                if r is not None:
                    return r
                if self.stage and self._retry(t) is WAIT:
                    return "wait"
                if self.failed:
                    return "fail"
                continue
            if stage == 1:
                # the instant of the seat's byte has passed: try once more, then keep the model
                # as it is now to say which rule the byte broke if nothing explains it
                if self._retry(t) is WAIT:
                    return "wait"
                if self.failed:
                    return "fail"
                if self.stage == 1:
                    self._pending(t)
                continue
            if self._waited == self.i_obs:
                # what the byte reveals waited for more of the line (live): ask once more
                # before the byte stands as one the model does not send
                self._waited = -1
                idx = self.i_obs
                # at the instant it waited (what it reveals happened then, as with the whole line)
                r = self._retry(max(self._waited_at, self.st.now))
                if r is WAIT:
                    return "wait"
                if self.failed:
                    return "fail"
                if self._applied == idx or self.i_obs != idx:
                    continue
            # the seat's byte is due and neither the model nor a local event sends it
            self._unexpected(o, t)
            return "fail"

    def _retry(self, t: float) -> Any:
        """The seat's next byte is waiting: what the model just did may let a local event
        explain it now."""
        if self.stage == 0 or self.i_obs >= len(self.judge.obs):
            return None
        idx = self.i_obs
        r = None
        if self._applied != idx:
            r = self._explain(idx, self.judge.obs[idx], t)
        if self.i_obs != idx:
            self.stage = 0
        return r

    def _pending(self, t: float) -> None:
        """Nothing explains the seat's byte yet: the model as it is now says, if the byte stays
        unexplained, which rule it broke."""
        self.stage = 2
        self.early_wait = self.kit.early_wait(self.host) + self.res
        self._snapshot = (copy.deepcopy(self.host), self._log_pos, self._log_k)
        o = self.judge.obs[self.i_obs]
        if o.chunk not in self.flags:
            self.flags[o.chunk] = self._at_rest()

    def _nothing_due(self, t: float) -> bool:
        obs = self.judge.obs
        return self.i_obs >= len(obs) or obs[self.i_obs].start > t + _EPS

    def _rested(self, t: float) -> bool:
        return self.stage == 0 and not self._held and self._at_rest() and self._nothing_due(t)

    def _explain(self, idx: int, o: Item, t: float) -> Any:
        if self._applied == idx:
            return None      # what the byte revealed is with the model already
        kit = self.kit
        if self.expect_startup:
            self.expect_startup = False
            e = kit.startup(self, o, idx)
            if e is None:
                rule, ref, code = kit.startup_rule(self.judge.seat)
                self.failed = Finding(self.judge.seat, o.t, R.FAIL, "start-up", rule, ref,
                                      f"no start-up {kit.startup_name(self.judge.seat)}: the station's first "
                                      f"character after it was switched on "
                                      f"is {self._show(o)}; {rule} ({ref})",
                                      expected=rule, observed=self._show(o), codes=(code,) if code else ())
                return None
        else:
            e = kit.explain(self, o, idx)
            if e is WAIT:
                self._waited, self._waited_at = idx, t
            if e is WAIT or e is None:
                return e
        self._applied = idx
        at = max(t, self.st.now)
        e.apply(self, at)
        if e.note:
            self.notes.append((o.t, e.note))
        r = self._collect(at)
        return r if r is WAIT else True

    def _collect(self, t: float) -> Any:
        """After the model acted at ``t``: its events, and its bytes compared with the seat's.
        Returns None, "fail", or WAIT (a byte's window is still open on a live line)."""
        st = self.st
        if st.has_events:
            for e in self.host.drain(t if t > st.now else st.now):
                code = getattr(e, "code", None)
                if code is not None and hasattr(e, "side"):
                    self.events.append((e.time, code))
                self.kit.event(self, e)
        if st.transmitting:
            r = self._compare_all(st.pop_output(t))
            if r is not None:
                return r
        if self.stage == 0 and not st.transmitting and self._rested(t):
            self.rest = (t, self.i_in, self.i_obs, self.expect_startup, dict(self.memo))
            self.judge.committed(self)
            self._trim_log()
        return None

    def _compare_all(self, popped: list) -> Any:
        for s, b in popped:
            if self._held:
                self._held.append((s, b) + self._cause_of(s, b))
                continue
            cause, entry, k = self._cause_of(s, b)
            r = self._compare(s, b, cause, entry, k)
            if r is True:
                return "fail"
            if r is WAIT:
                self._held.append((s, b, cause, entry, k))
        return WAIT if self._held else None

    def _release(self) -> Any:
        """Bytes the model sent while their windows were open: compare them now."""
        while self._held:
            r = self._compare(*self._held[0])
            if r is WAIT:
                return WAIT
            self._held.pop(0)
            if r is True:
                return "fail"
        return None

    # -- comparing ------------------------------------------------------------------------
    def _show(self, o: Item | None) -> str:
        if o is None:
            return "nothing"
        if o.kind == "break":
            return "a BREAK"
        if o.kind == "invalid":
            return f"{self.kit.name(o.value)} with a parity/framing error"
        return self.kit.name(o.value)

    def _compare(self, s: float, b: int, cause: Cause, entry: Any, k: int) -> Any:
        """The model has begun to send ``b`` at ``s``: compare with the seat's next byte.
        False: it matches; True: a difference (see :attr:`failed`); WAIT: its window is still
        open and the seat has sent nothing since."""
        j = self.judge
        obs = j.obs
        p = s + self.char
        r = self.res
        lo, hi = p - cause.early - r, p + cause.late + r
        o = obs[self.i_obs] if self.i_obs < len(obs) else None
        if o is not None and o.chunk not in self.flags:
            # a byte the model sends for a local event (its application's send job) may begin
            # an exchange though a job was waiting (the first of its transmission: a frame's
            # other characters continue the exchange it began)
            self.flags[o.chunk] = cause.kind == "local" and k == 0 and self.kit.begins_in(self.host, b)
        if o is not None and o.kind == "byte" and o.value == b and lo <= o.t <= hi:
            # the usual case: the byte the model sends, in its window
            d = o.t - p
            if (d < -cause.early - _EPS and cause.kind == "timer") or d > cause.late + _EPS:
                self._timing(cause, self._name(cause, entry, k, b), p, o, d, lo, hi)
            self.i_obs += 1
            self.stage = 0
            self._snapshot = None
            # follow the seat: what it sends next starts later too - but only by as much as
            # the byte was certainly late. Its timestamp may lag its completion by up to the
            # resolution, so it may have been that much earlier; a model that followed the
            # stamp would run behind the seat, and the other seat's answer to the seat's last
            # byte would reach it "during" a byte it had long finished (a monitor that read a
            # block's tail in one go stamps it late).
            follow = d - r
            if follow > 1e-7:
                self.st.delay_output(follow)
            elif d < -1e-7 and r > 0 and hasattr(self.st, "advance_output"):
                # earlier than the model: the seat's byte was complete by its timestamp, so
                # the model (its start held back by the other seat's late-stamped bytes) runs
                # behind the seat; its schedule moves up, within the resolution
                self.st.advance_output(min(-d, r))
            return False
        if o is None and hi > j.analysis.known_until:
            return WAIT
        name = self._name(cause, entry, k, b)
        codes = (cause.code,) if cause.code else ()
        if o is None or o.t > hi:
            if j.end is not None and hi > j.end:
                # the recording ended before the byte was due: nothing to judge
                self.failed = Finding(j.seat, p, R.INFORMATIONAL, "end", cause.rule, cause.reference,
                                      f"the recording ends before {name} was due", rules=cause.rules)
                return True
            if o is not None and o.kind == "byte" and o.value == b and o.t - hi < j.analysis.rest:
                # (what a live analysis, deciding when the window closes, calls missing)
                self.failed = Finding(
                    j.seat, p, R.FAIL, "missing", cause.rule, cause.reference,
                    f"{name} {1000 * (o.t - p):.3f} ms late (it may be {1000 * cause.late:.3f} ms late): "
                    f"{cause.rule} ({cause.reference})",
                    expected=f"{name} by {self._at(hi)}", observed=f"{name} at {self._at(o.t)}",
                    window=(lo, hi), codes=codes, rules=cause.rules)
                return True
            got = "nothing" if o is None else f"{self._show(o)} only {1000 * (o.t - p):.3f} ms later"
            self.failed = Finding(
                j.seat, p, R.FAIL, "missing", cause.rule, cause.reference,
                f"{name} missing: {cause.rule} ({cause.reference}); due by {self._at(hi)}, "
                f"the seat sent {got}",
                expected=f"{name} at {self._at(p)}", observed=got, window=(lo, hi), codes=codes, rules=cause.rules)
            return True
        if o.kind != "byte" or o.value != b:
            cause = self.kit.wrong(self, o, b, cause)
            codes = (cause.code,) if cause.code else ()
            self.failed = Finding(
                j.seat, o.t, R.FAIL, "wrong", cause.rule, cause.reference,
                f"sent {self._show(o)} where the model sends {name}: {cause.rule} ({cause.reference})",
                expected=f"{name} at {self._at(p)}", observed=f"{self._show(o)} at {self._at(o.t)}",
                window=(lo, hi), codes=codes, rules=cause.rules,
                order_free=k > 0 and entry is not None and not self._partner_between(self.kit.entry_start(entry), o.t))
            return True
        if o.t < lo:
            self.failed = Finding(
                j.seat, o.t, R.FAIL, "early", cause.rule, cause.reference,
                f"{name} {1000 * (p - o.t):.3f} ms too early: {cause.rule} ({cause.reference})",
                expected=f"{name} at {self._at(p)}", observed=f"{name} at {self._at(o.t)}",
                window=(lo, hi), codes=codes, rules=cause.rules)
            return True
        raise AssertionError("unreachable")   # pragma: no cover

    def _partner_between(self, lo: float, hi: float) -> bool:
        """Did the other seat send anything stamped after ``lo`` and by ``hi``?"""
        inputs = self.judge.inputs
        i = bisect.bisect_right(inputs, lo, key=lambda it: it.t)
        return i < len(inputs) and inputs[i].t <= hi

    def _timing(self, cause: Cause, name: str, p: float, o: Item, d: float, lo: float, hi: float) -> None:
        """In its window only because of the capture's timing resolution: informational. (A
        byte that answers the other seat cannot be too early: it came after what it
        answers, only the timestamps say otherwise.)"""
        side = "early" if d < 0 else "late"
        self.findings.append(Finding(
            self.judge.seat, o.t, R.INFORMATIONAL, "timing", cause.rule, cause.reference,
            f"{name} {1000 * abs(d):.3f} ms {side}, within the capture's timing resolution "
            f"({1000 * self.res:.3f} ms) of its window: {cause.rule} ({cause.reference})",
            expected=f"{name} at {self._at(p)}", observed=f"{name} at {self._at(o.t)}", window=(lo, hi), rules=cause.rules))

    @staticmethod
    def _at(t: float) -> str:
        return f"{t * 1000:.3f} ms"

    def _unexpected(self, o: Item, t: float) -> None:
        """The seat sent ``o`` and the model does not send it: say what the model does next."""
        later = self._peek(o)
        host = self._snapshot[0] if self._snapshot is not None else self.host
        cause = self.kit.unexpected(self, host, o, later)
        shown = self._show(o)
        if later is not None and o.kind == "byte" and later[1] == o.value:
            msg = f"{shown} {1000 * (later[0] - o.t):.3f} ms too early: {cause.rule} ({cause.reference})"
            kind, expected = "early", f"{shown} at {self._at(later[0])}"
        else:
            msg = f"sent {shown} where the model sends nothing: {cause.rule} ({cause.reference})"
            kind = "unexpected"
            expected = ("nothing" if later is None
                        else f"nothing, then {self.kit.name(later[1])} at {self._at(later[0])}")
        self.failed = Finding(self.judge.seat, o.t, R.FAIL, kind, cause.rule, cause.reference, msg,
                              expected=expected, observed=f"{shown} at {self._at(o.t)}",
                              codes=(cause.code,) if cause.code else (), rules=cause.rules)

    def _peek(self, o: Item) -> tuple[float, int, Cause] | None:
        """What the model (as it was when the seat's byte began) sends next without further
        input: a copy of it runs ahead."""
        horizon = o.t + self.judge.analysis.horizon
        probe = copy.copy(self)
        if self._snapshot is not None:
            host, probe._log_pos, probe._log_k = self._snapshot
            probe.host = copy.deepcopy(host)
        else:
            probe.host = copy.deepcopy(self.host)
        probe.st = st = probe.host.station
        for _ in range(10_000):
            out = st.pop_output(st.now)
            if out:
                s, b = out[0]
                return (s + self.char, b, probe._cause_of(s, b)[0])
            d = st.next_deadline()
            if d is None or d > horizon:
                return None
            st.handle_timer(d)
            probe.host.drain(d)
        return None


# ------------------------------------------------------------------ one seat


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
            first = a._chunk_items[k][0] + j
            start = a.items[seat_k][first].start
            if self.lost_at is None or self.lost_at == -inf or a.items[seat_k][first].t > self.lost_at:
                break
            # a chunk read after the difference whose bytes, stamped back from its read, began
            # before it: the exchange that departed, not a new one
            self.resumed_in = k
        t0 = start - 2 * self.kit.char(self.seat) - 1e-6
        prev = a.items[seat_k][first - 1].t if j else (a.chunks[k - 1].t if k > 0 else -inf)
        t0 = max(t0, prev + _EPS)
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
        if cand._rested(cand.now):
            self._take(cand)


# ------------------------------------------------------------------ the whole line


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
    :meth:`close`) or from a whole capture (:func:`analyze`). ``judge``: the seats to
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
        self._chunk_items: list[tuple[int, int]] = []   # (the seat's first item index, count) per chunk
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
        while prev_k >= 0 and not self._chunk_items[prev_k][1]:
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
            for i, b in enumerate(data):
                t = ct - (n - 1 - i) * c
                if t < prev:
                    t = prev
                start = t - c
                items.append(Item(t, kind, b, k, start if start > prev else prev))
                prev = t
        elif chunk.condition is C.Cond.BREAK:
            t = max(prev, chunk.t)
            items.append(Item(t, "break", chunk.duration, k, max(prev, t - c)))
        elif chunk.condition in C.GAPS:
            self.gaps.append((chunk.t, seat, chunk.condition.value))
        self._chunk_items.append((first, len(items) - first))
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
            if items[mid].start < t - _EPS:
                lo = mid + 1
            else:
                hi = mid
        return lo

    def chunk_start(self, k: int) -> float:
        first, n = self._chunk_items[k]
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
            if not self._chunk_items[k][1]:
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
        first, m = self._chunk_items[k]
        seat = self.chunks[k].seat
        out: list[tuple[str, Item]] = [(seat, it) for it in self.items[seat][first:first + within]]
        j = k - 1
        while j >= 0 and len(out) < n:
            first, m = self._chunk_items[j]
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
            first, n = self._chunk_items[k]
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
        first, n = self._chunk_items[k]
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
        nxt = self.chunks[e.last + 1].t if e.last + 1 < len(self.chunks) else inf
        lo = -inf if e.index == 1 else e.t0
        cur, slack = self._cursors, self.horizon
        for j in self.judges.values():
            e.findings += _between(j.findings, lo, nxt, _time_of, cur, slack)
            e.events[j.seat] = [c for _, c in _between(j.events, lo, nxt, _first, cur, slack)]
        e.findings.sort(key=_time_of)
        e.notes = [f"seat {s}: {text}" for t, s, text in _between(self.notes, lo, nxt, _first, cur, slack)]
        cases = [m.text for m in self.marks if m.t <= e.t0 + _EPS and m.text.lower().startswith("case ")]
        e.case = cases[-1] if cases else ""
        if self.listener is not None and hasattr(self.listener, "exchange"):
            self.listener.exchange(self, e)

    def exchange_items(self, e: Exchange) -> list[tuple[str, Item]]:
        out = []
        for k in range(e.first, e.last + 1):
            seat = self.chunks[k].seat
            first, n = self._chunk_items[k]
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


# ------------------------------------------------------------------ whole captures


@dataclass
class Analysis:
    """The outcome of judging a capture: its exchanges and findings, ready for the reports."""

    line: LineAnalysis
    capture: C.Capture
    kit: ProcedureAnalyzer
    source: str = ""

    @property
    def exchanges(self) -> list[Exchange]:
        return self.line.exchanges

    @property
    def findings(self) -> list[Finding]:
        return self.line.findings()


def analyze(cap: C.Capture, kit: ProcedureAnalyzer, *, judge: Iterable[str] = SEATS, resolution: float = 0.0,
            restart_at_cases: Iterable[str] = (), source: str = "", listener: Any = None) -> Analysis:
    """Judge a whole capture."""
    line = LineAnalysis(kit, judge=judge, resolution=resolution, restart_at_cases=restart_at_cases,
                        listener=listener)
    marks = sorted(cap.marks, key=lambda m: m.t)
    mi = 0
    for ch in cap.chunks:
        while mi < len(marks) and marks[mi].t <= ch.t:
            line.mark(marks[mi])
            mi += 1
        line.feed(ch)
    while mi < len(marks):
        line.mark(marks[mi])
        mi += 1
    line.close(cap.end)
    return Analysis(line, cap, kit, source)


# ------------------------------------------------------------------ reports


def _codes(codes: Iterable[int]) -> str:
    out = list(dict.fromkeys(f"16#{c:04X}" for c in codes))
    return ", ".join(out) if out else "none"


def _transcript(line: LineAnalysis, e: Exchange, t0: float) -> list[dict[str, Any]]:
    cap = C.Capture([line.chunks[k] for k in range(e.first, e.last + 1)])
    tr = C.to_transcript(cap)
    for x in tr:
        if "t" in x:
            x["t"] = round(x["t"] - t0, 6)
    return tr


def exchange_cases(line: LineAnalysis, e: Exchange, seats: dict[str, str], source: str = "",
                   notes: Iterable[str] = ()) -> list[R.CaseResult]:
    """The cases of one exchange: one per finding, or one (pass) when it has none. Times in
    a case are seconds since the exchange began (less one character)."""
    kit = line.kit
    proc = kit.procedure
    label = line.label(e)
    width = max(4, len(str(len(line.exchanges))))
    base = f"EX{e.index:0{width}d}"
    where = (f"exchange {e.index}: {e.t0:.6f} s to {e.t1:.6f} s of the capture"
             + (f", in {e.case}" if e.case else ""))
    raised = {s: _codes(e.events.get(s, [])) for s in SEATS}
    common = [where] + list(e.notes) + list(notes)
    t0 = e.t0 - max(kit.char("a"), kit.char("b"))
    out = []
    if not e.findings:
        c = R.CaseResult(base, label, kit.reference,
                         "both stations follow the procedure" if line.judged else "not judged",
                         "exchanges", "", verdict=R.PASS if line.judged else R.NOT_RUN)
        c.expected_status = "; ".join(f"seat {s}: {raised[s]}" for s in line.judged) or "not judged"
        c.tester_status = c.expected_status
        c.transcript = _transcript(line, e, t0)
        c.params = proc.params_table(kit.params["b"])
        c.notes = common
        c.case_time = round(e.t1 - t0, 6)
        c.source = source
        return [c]
    count: dict[str, int] = {}
    for f in e.findings:
        count[f.seat] = count.get(f.seat, 0) + 1
        n = count[f.seat]
        cid = f"{base}.{f.seat}" + (str(n) if n > 1 else "")
        c = R.CaseResult(cid, f"seat {f.seat}: {label}", f.reference, _strip_section(f.rule),
                         f"seat {f.seat}", f"seat {f.seat} ({seats.get(f.seat, f.seat)})", verdict=f.grade,
                         message=f.text(seats))
        c.divergence = R.Divergence(-1, round(f.t - t0, 6), f.expected or f.rule, f.observed or "",
                                    None if f.window is None else (round(f.window[0] - t0, 6),
                                                                   round(f.window[1] - t0, 6)))
        other = OTHER[f.seat]
        c.expected_status = f"{raised[f.seat]} (what a CP 341 in seat {f.seat} raises here)"
        c.expected_status_codes = [[f"16#{x:04X}"] for x in f.codes]
        c.tester_status = f"{raised[other]} (what a CP 341 in seat {other} raises here)"
        c.readings = list(f.readings)
        c.rules = list(f.rules)
        c.transcript = _transcript(line, e, t0)
        if f.window is not None:
            c.transcript.append({"kind": "window", "dir": "note", "step": -1,
                                 "t0": round(f.window[0] - t0, 6), "t1": round(f.window[1] - t0, 6),
                                 "label": f"seat {f.seat}: {f.expected}"})
        c.params = proc.params_table(kit.params[f.seat])
        c.notes = common + list(f.notes)
        c.case_time = round(e.t1 - t0, 6)
        c.source = source
        out.append(c)
    return out


def to_results(an: Analysis, *, started: str = "", profile: dict[str, Any] | None = None,
               notes: Iterable[str] = ()) -> R.RunResult:
    """The analysis as a results object: one case per finding, one per exchange without."""
    from ptpcert import __version__

    line, kit, cap = an.line, an.kit, an.capture
    seats = dict(cap.seats)
    run = R.RunResult(tool_version=__version__, started=started or (C.iso_time(cap.start) or ""),
                      iut=f"seat a: {seats['a']}, seat b: {seats['b']}", procedure=kit.procedure.title,
                      profile=dict(profile or {}), vector_set=f"capture {an.source}".strip())
    notes = list(notes)
    for e in line.exchanges:
        run.cases += exchange_cases(line, e, seats, an.source, notes)
    return run


def summary_line(line: LineAnalysis, e: Exchange, seats: dict[str, str] | None = None) -> str:
    """One console line for an exchange: when it began, its number, verdict and bytes, and
    its first finding."""
    extra = ""
    if e.findings:
        f = next((x for x in e.findings if x.grade == R.FAIL), e.findings[0])
        extra = "  " + f.text(seats)
    return f"{e.t0:11.6f} s  EX{e.index:04d} {e.verdict:<13} {line.label(e)}{extra}"
