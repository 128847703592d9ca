"""The 3964(R) fuzz kit's co-simulation (:class:`CoSim`): a model station plays the IUT in
virtual time while the generator (:mod:`.generator`) acts as its partner, and the vector
being written grows with every stimulus and every reply.

The tester's stimuli (bytes, character errors, BREAKs, waits) go in as the runner will send
them; before each one the co-simulation waits until what the IUT has begun to send is
complete and turns it into expectations, so the runner, too, sends the stimulus only after
it has seen them (only a deliberate violation goes out while the IUT sends). No stimulus
lands closer to one of the IUT's deadlines than the runner's real-time tolerance can tell
apart. The model's output becomes ``expect`` steps whose windows follow from why the model
sent it (a reply: up to the partner's timer; a timer's output: where it fell), each noted
with the table rule that made it (:mod:`.rules`); output that began while a stimulus was
still going out is measured from a mark before it, so no offset is negative.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from ptpcert.fuzz.kit import ms, send_receive_codes
from ptpcert.model import events as ev
from ptpcert.model.app import Host
from ptpcert.registry import by_id
from ptpcert.runner import Tolerance, realtime_tolerance
from ptpcert.scenario import Expected, Expr, StatusSpec, Step, Vector

from ..model import table as T
from ..model.params import Params3964
from ..model.readings import READINGS, Readings
from ..model.station import Station3964
from .rules import BLOCK_RULE, expectation_note, rule_for

#: every send/receive event of 3964(R): what an example may see raised besides what it expects
_ALL_3964_CODES = send_receive_codes("3964(R)")


@dataclass
class _Out:
    t: float            # completion time of the byte (when the tester sees it)
    byte: int
    cause: str          # "reply" or "timer"
    rule: str
    codes: tuple[int, ...]


class CoSim:
    """A model IUT in virtual time and the vector being written while it runs."""

    def __init__(self, params: Params3964, echo: bool, readings: Readings = READINGS,
                 tolerance: Tolerance | None = None):
        self.p = params
        self.char = params.char_time
        self.st = Station3964(params, readings, name="iut", explain=True)
        self.echo = echo
        self.host = Host(self.st, "echo" if echo else "none")
        # how far a stimulus keeps from the IUT's deadlines (see _start): before an edge, as
        # far as the tester's byte may go out late plus two characters; after it, as far as
        # the runner lets the IUT's timer act late (for the longer of CDT and ADT)
        if tolerance is None:
            tolerance = realtime_tolerance(by_id("p3964"), params)   # this procedure, as registered
        self.tol = tolerance
        floor = 0.15 * min(params.cdt, params.adt) + 2 * params.char_time
        self.edge_before = max(floor, tolerance.stimulus + tolerance.early + 2 * params.char_time)
        self.edge_after = max(floor, tolerance.late(max(params.cdt, params.adt)) + 2 * params.char_time)
        self.edge_margin = max(self.edge_before, self.edge_after)
        #: steps that are deliberate violations (sent while the IUT was sending)
        self.violations: set[int] = set()
        #: (arrival of a stimulus's first character, the IUT's deadlines at that moment)
        self.stimuli: list[tuple[float, tuple[float, ...]]] = []
        # the reference point before the last stimulus and the step that set it (-1: the
        # start of the case), for output that began while the stimulus was going out
        self.mark_ref = 0.0
        self.mark_idx = -1
        self.stim_end = 0.0
        self.st.power_on(0.0)
        self.st.pop_output()
        self.host.drain()

        self.t = 0.0
        self.ref = 0.0            # the runner's reference point
        self.sent_end = 0.0
        self.steps: list[Step] = []
        self.outs: list[_Out] = []   # model output not yet turned into expectations
        self.delivered: list[bytes] = []
        self.sent: list[bytes] = []
        self.codes: list[int] = []
        self.uses_echo = False

    # -- running the model -------------------------------------------------------
    def _collect(self, cause: str) -> None:
        events = self.host.drain()
        codes = tuple(e.code for e in events if isinstance(e, ev.Status))
        self.codes += codes
        for e in events:
            if isinstance(e, ev.Delivered):
                self.delivered.append(e.payload)
            elif isinstance(e, ev.SendDone):
                self.sent.append(e.payload)
        log = self.st.tx_log
        for start, data in self.st.pop_output_runs(self.t):   # only what has started by now
            for i, b in enumerate(data):
                t0 = start + i * self.char
                why = next((x for x in reversed(log) if x[0] - 1e-12 <= t0 <= max(x[1], x[0]) + 1e-12), None)
                inp, actions = (why[2], why[3]) if why else ("", [])
                kind = "timer" if inp in (T.T_ADT, T.T_CDT, T.T_NAKTIM, T.T_BLOCK) else "reply"
                self.outs.append(_Out(t0 + self.char, b, kind, rule_for(actions, b), codes if why is log[-1] else ()))

    def advance(self, until: float) -> None:
        """Run the model (no input) up to ``until``."""
        while True:
            d = self.st.next_deadline()
            if d is None or d > until:
                break
            self.t = max(self.t, d)
            self.st.handle_timer(self.t)
            self._collect("timer")
        self.t = max(self.t, until)

    def _input(self, at: float, kind: str, value: int = 0) -> None:
        self.advance(at)
        if kind == "byte":
            self.st.receive(at, value)
        elif kind == "invalid":
            self.st.receive_invalid(at, value)
        else:
            self.st.line_break(at)
        self._collect("reply")

    def settle(self, quiet: float | None = None, limit: float = 60.0) -> None:
        """Run until the model has been quiet for ``quiet`` (default max(CDT, ADT) + 4 chars)."""
        quiet = quiet if quiet is not None else max(self.p.cdt, self.p.adt) + 4 * self.char
        end = self.t + limit
        while self.t < end:
            last = max([o.t for o in self.outs], default=self.ref)
            d = self.st.next_deadline()
            horizon = max(last, self.t) + quiet
            if d is None or d > horizon:
                self.advance(horizon)
                if not self.st.transmitting:
                    return
            else:
                self.advance(d)

    # -- the tester's side --------------------------------------------------------
    def _start(self, at: float, violation: bool = False) -> tuple[float, float]:
        """When a stimulus ``at`` after the reference starts: never before the model's
        present (the co-simulation may have run ahead looking for output); unless it is a
        deliberate ``violation``, never before what the IUT has begun to send is complete
        (the partner reacts to the replies the protocol requires: they become expectations
        first, so the runner waits for them too); and never so close to one of the IUT's
        deadlines (a timer, the end of its transmission) that a real process could see the
        two in either order: then the deadline runs out first and the stimulus follows what
        it caused. Returns the start and the delay the vector states."""
        for _ in range(10_000):
            if not violation:
                pending = max([o.t for o in self.outs], default=self.t)
                if self.st.transmitting or self.st.busy_until > self.t:
                    pending = max(pending, self.st.busy_until)
                if pending > self.t + 1e-12:
                    self.advance(pending)
                    self._collect("reply")
                    continue
            self.flush_expectations()
            start = max(self.ref + at, self.t)
            arrival = start + self.char
            timer, done = self.st.timer, self.st.block_done_at
            edges = tuple(d for d in (timer[1] if timer else None, done) if d is not None)
            near = [d for d in edges if arrival - self.edge_after < d < arrival + self.edge_before]
            if not near:
                self.stimuli.append((arrival, edges))
                self.mark_ref, self.mark_idx = self.ref, len(self.steps) - 1
                return start, start - self.ref
            self.advance(max(near) + self.edge_after)
            self._collect("reply")
            at = 0.0
        raise RuntimeError("the co-simulated IUT never stops sending")

    def _stimulus(self, step: Step, violation: bool) -> None:
        if violation:
            self.violations.add(len(self.steps))
        self.steps.append(step)
        self.stim_end = self.ref

    def send(self, data: bytes, at: float = 0.0, gap: float = 0.0, note: str = "", kind: str = "send",
             violation: bool = False) -> None:
        start, at = self._start(at, violation)
        for k, b in enumerate(data):
            arrive = start + k * (self.char + gap) + self.char
            self._input(arrive, "invalid" if kind == "send_error" else "byte", b)
        self.ref = self.sent_end = arrive
        self._stimulus(Step(kind, bytes(data), at=ms(at), gap=ms(gap), note=note), violation)

    def brk(self, duration: float, at: float = 0.0, violation: bool = False) -> None:
        t, at = self._start(at, violation)
        self._input(t, "break")
        self.advance(t + duration)
        self.ref = self.sent_end = t + duration
        self._stimulus(Step("break", duration=ms(duration), at=ms(at), note="BREAK"), violation)

    def wait(self, d: float) -> None:
        end, d = self._start(d)
        self.advance(end)
        self.ref = end
        self.steps.append(Step("wait", duration=ms(d)))

    def since_mark(self) -> tuple[float, int]:
        """The reference point before the last stimulus, marked in the vector (a zero wait
        at the start when the stimulus was the first step): what output that began while
        the stimulus was going out is measured from."""
        if self.mark_idx < 0:
            self.steps.insert(0, Step("wait", duration=ms(0.0), mark=True))
            self.violations = {i + 1 for i in self.violations}
            self.mark_idx = 0
        elif not self.steps[self.mark_idx].mark:
            self.steps[self.mark_idx] = replace(self.steps[self.mark_idx], mark=True)
        return self.mark_ref, self.mark_idx

    def run_until_output(self, n: int = 1, limit: float | None = None) -> list[_Out]:
        """Let the model run until it has produced ``n`` more bytes (or ``limit``)."""
        end = self.t + (limit if limit is not None else 2 * max(self.p.adt, self.p.cdt) + 10 * self.char)
        while len(self.outs) < n and self.t < end:
            d = self.st.next_deadline()
            if d is None or d > end:
                self.advance(end)
                break
            self.advance(d)
        return self.outs[:n]

    # -- expectations -------------------------------------------------------------
    def flush_expectations(self, interrupted_rest: bytes | None = None) -> None:
        """Turn the model's output so far into expect steps, relative to the runner's
        reference point; ``interrupted_rest``: the block the IUT was sending when the tester
        interrupted it (what may still come of it is a partial expectation). Output that
        began before the reference (while the tester's last stimulus was going out) is
        measured from the mark before that stimulus, so no offset is negative."""
        # only characters that have arrived by now; one still on the line stays for later
        outs = [o for o in self.outs if o.t <= self.t + 1e-12]
        self.outs = [o for o in self.outs if o.t > self.t + 1e-12]
        i = 0
        char, cdt = self.char, self.p.cdt
        while i < len(outs):
            j = i + 1
            while j < len(outs) and outs[j].t - outs[j - 1].t <= cdt and outs[j].cause == outs[i].cause \
                    and outs[j].rule == outs[i].rule:
                j += 1
            group = outs[i:j]
            d = group[0].t - self.ref
            data = bytes(o.byte for o in group)
            note = expectation_note(group[0].rule, sorted(set(c for o in group for c in o.codes)))
            since = "previous"
            timed = group[0].cause == "timer" or d > 3 * char + 1e-9
            reply_within = Expr("CDT") if group[0].rule == BLOCK_RULE else Expr("ADT")
            if d < -1e-9:
                # it began while the tester's stimulus was still going out (a reply to a
                # BREAK's start, a NAK in the middle of an over-long block)
                mark_ref, _ = self.since_mark()
                dm, stim = group[0].t - mark_ref, max(self.ref - mark_ref, 0.0)
                since = "mark"
                after = ms(max(0.0, dm - 2 * char))
                within = ms(dm + 2 * char) if timed else Expr(f"{ms(stim).text} + {reply_within.text}")
            elif timed:
                after, within = ms(max(0.0, d - 2 * char)), ms(d + 2 * char)
            else:
                # a reply: any time up to the partner's timer (CDT for the first character of
                # a block after the partner's DLE)
                after, within = ms(0.0), reply_within
            self.steps.append(Step("expect", data, after=after, within=within, note=note, since=since))
            self.ref = group[-1].t
            i = j
        if interrupted_rest:
            mark_ref, _ = self.since_mark()
            self.steps.append(Step("expect", interrupted_rest, partial=True, since="mark", after=ms(0.0),
                                   within=Expr(f"{ms(max(self.ref - mark_ref, 0.0)).text} + 4*CHAR"),
                                   note="the IUT stops sending its block"))

    # -- the result ---------------------------------------------------------------
    def vector(self, vid: str, title: str, rule: str) -> Vector:
        self.settle()
        self.flush_expectations()
        requires = {"echo"} if (self.uses_echo or self.delivered) and self.echo else set()
        codes = frozenset(self.codes) | {0x0701, 0x0801, 0x0815, 0x080C, 0x0802, 0x1E0D}
        return Vector(
            procedure="p3964", id=vid, title=title, reference="§2.2; Figs. 2-5 to 2-12 (generated by ptpcert fuzz)", rule=rule,
            group="regression", iut_role="both", params=self.p, steps=tuple(self.steps),
            expected=Expected(StatusSpec((), codes | _ALL_3964_CODES), StatusSpec(), tuple(self.delivered),
                              tuple(self.sent), ()),
            requires=frozenset(requires), provenance="[fuzz]",
            binds=("procedure", "priority", "cdt_ms", "adt_ms", "setup_attempts", "transmission_attempts",
                   "baud_rate", "data_bits", "parity", "stop_bits"),
        )
