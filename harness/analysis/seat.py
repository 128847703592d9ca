"""The seat run: one attempt to follow a seat with its model, from a point where it was at rest.

A :class:`SeatRun` feeds a model station with that seat's parameters what the *other* seat
sent, at the times it arrived, and compares what the model sends, byte by byte and in time,
with what the seat sent. The model is *followed*: a byte the seat sent later than the model
(still in time) delays the rest of the model's schedule, as a UART that started late would
(``delay_output``); a local event the line reveals but no model can predict - a send job
handed over by the station's application, a restart, a receive buffer that became free - is
given to the model when the seat's byte shows it (the procedure's analyzer,
:class:`~ptpcert.analysis.interface.ProcedureAnalyzer`, says which bytes reveal which events).
The first difference ends the run (:attr:`SeatRun.failed`); what to make of it is the seat
judge's business (:mod:`ptpcert.analysis.judge`), which also runs the alternatives as runs of
their own.

Timing windows. A byte the model sends in reply to the partner may come as late as the
partner's timer that waits for it allows (e.g. a DLE within the partner's ADT); a byte the
model sends when one of its own timers runs out may come a character time and a twentieth of
the timer early and ``late_ms`` plus a quarter of the timer late (the procedure's
:class:`~ptpcert.analysis.interface.Cause` says which). On top of that the capture's timing
*resolution* (how much earlier than its timestamp a byte may really have been complete): a
byte inside a window only because of the resolution is graded informational, never failed;
characters of both seats stamped within it of each other may be taken in either order
(:mod:`ptpcert.analysis.order`).

One class, one piece: the stepping loop, the explanations and the comparison all move the
same position in both seats' items and the same model, and hand each other the run's state
(the stage of the seat's next byte, the bytes held while their windows are open), so they are
not split. ``judge`` is the :class:`~ptpcert.analysis.judge.SeatJudge` that owns the run
(imported for type checkers only: the judge imports this module).
"""

from __future__ import annotations

import copy
from math import inf
from typing import TYPE_CHECKING, Any

from ptpcert import results as R
from ptpcert.analysis import ahead
from ptpcert.analysis import order as O
from ptpcert.analysis.interface import (EPS, QUANTUM, WAIT, Cause, Finding, Item, Variant, at_ms, resolution_finding,
                                       show_item)

if TYPE_CHECKING:
    from ptpcert.analysis.judge import SeatJudge


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
        #: the shift applies to the other seat's characters stamped after ``shift_from`` up to
        #: ``shift_until`` (the difference an alternative is to explain); others keep their times
        self.shift_from, self.shift_until = -inf, inf
        #: the ordering rule's state (:mod:`ptpcert.analysis.order`)
        self.order_floor, self.moved_for = -inf, -1
        #: the other seat's last character that came while the model was sending: its stamp,
        #: the bytes the model then had yet to send, and until when they may still come
        #: (:func:`ptpcert.analysis.order.cut`)
        self.cut_at, self.tail, self.tail_until = -inf, [], -inf
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
        until_shift, from_shift, shift_ = self.shift_until, self.shift_from, self.shift
        local = self.variant is not None and self.variant.local

        def at(it: Item) -> float:
            if not from_shift < it.t <= until_shift:
                return it.t
            return O.taken_at(self, it) if local else it.t + shift_

        flags = self.flags
        while True:
            if self._held:
                r = self._release()
                if r is not None:
                    return "wait" if r is WAIT else r
            if rest_after is not None and self.now > rest_after and self.rested(self.now):
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
                    if self._tied + EPS > t_ob:
                        t_ob = self._tied + EPS
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
            if t_in == t and stage == 2 and t_dl < inf and O.timer_first(self, o, t, t_dl):
                continue    # the seat's byte came before the input, on a timer of the model's
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
                    if st.transmitting:
                        O.cut(self, it)         # the input came while the model was sending
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
        obs = self.judge.obs    # no byte of the seat may have begun by t (resolution: order.py)
        if self.i_obs >= len(obs):
            return True
        start = obs[self.i_obs].start
        return start > t + EPS and start - self.res > self.cut_at + EPS

    def rested(self, t: float) -> bool:
        """Is the run at rest at ``t``: no byte of the seat being settled or held, the model at
        rest, and no byte of the seat begun by then?"""
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
                                      f"is {show_item(self.kit, o)}; {rule} ({ref})",
                                      expected=rule, observed=show_item(self.kit, o), codes=(code,) if code else ())
                return None
        elif O.tail_explains(self, o):
            return True
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
        if self.stage == 0 and not st.transmitting and self.rested(t):
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
            if (d < -cause.early - EPS and cause.kind == "timer") or d > cause.late + EPS:
                self.findings.append(resolution_finding(j.seat, cause, self._name(cause, entry, k, b), p, o.t, d,
                                                        self.res, (lo, hi)))
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
                    expected=f"{name} by {at_ms(hi)}", observed=f"{name} at {at_ms(o.t)}",
                    window=(lo, hi), codes=codes, rules=cause.rules)
                return True
            got = "nothing" if o is None else f"{show_item(self.kit, o)} only {1000 * (o.t - p):.3f} ms later"
            self.failed = Finding(
                j.seat, p, R.FAIL, "missing", cause.rule, cause.reference,
                f"{name} missing: {cause.rule} ({cause.reference}); due by {at_ms(hi)}, "
                f"the seat sent {got}",
                expected=f"{name} at {at_ms(p)}", observed=got, window=(lo, hi), codes=codes, rules=cause.rules)
            return True
        if o.kind != "byte" or o.value != b:
            cause = self.kit.wrong(self, o, b, cause)
            codes = (cause.code,) if cause.code else ()
            self.failed = Finding(
                j.seat, o.t, R.FAIL, "wrong", cause.rule, cause.reference,
                f"sent {show_item(self.kit, o)} where the model sends {name}: {cause.rule} ({cause.reference})",
                expected=f"{name} at {at_ms(p)}", observed=f"{show_item(self.kit, o)} at {at_ms(o.t)}",
                window=(lo, hi), codes=codes, rules=cause.rules,
                order_free=k > 0 and entry is not None and not j.partner_sent_between(self.kit.entry_start(entry), o.t))
            return True
        if o.t < lo:
            self.failed = Finding(
                j.seat, o.t, R.FAIL, "early", cause.rule, cause.reference,
                f"{name} {1000 * (p - o.t):.3f} ms too early: {cause.rule} ({cause.reference})",
                expected=f"{name} at {at_ms(p)}", observed=f"{name} at {at_ms(o.t)}",
                window=(lo, hi), codes=codes, rules=cause.rules)
            return True
        raise AssertionError("unreachable")   # pragma: no cover

    def _unexpected(self, o: Item, t: float) -> None:
        """The seat sent ``o`` and the model does not send it: say what the model does next."""
        later = ahead.peek(self, o)
        host = self._snapshot[0] if self._snapshot is not None else self.host
        cause = self.kit.unexpected(self, host, o, later)
        shown = show_item(self.kit, o)
        if later is not None and o.kind == "byte" and later[1] == o.value:
            msg = f"{shown} {1000 * (later[0] - o.t):.3f} ms too early: {cause.rule} ({cause.reference})"
            kind, expected = "early", f"{shown} at {at_ms(later[0])}"
        else:
            msg = f"sent {shown} where the model sends nothing: {cause.rule} ({cause.reference})"
            kind = "unexpected"
            expected = ("nothing" if later is None
                        else f"nothing, then {self.kit.name(later[1])} at {at_ms(later[0])}")
        self.failed = Finding(self.judge.seat, o.t, R.FAIL, kind, cause.rule, cause.reference, msg,
                              expected=expected, observed=f"{shown} at {at_ms(o.t)}",
                              codes=(cause.code,) if cause.code else (), rules=cause.rules)
