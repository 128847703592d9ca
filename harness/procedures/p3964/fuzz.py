"""The 3964/3964R fuzz kit, level 2: generated partner behaviour against an IUT, the model as
oracle (the campaign is :mod:`ptpcert.fuzz.campaign`).

For every example, hypothesis draws the tester's behaviour step by step while a model
station plays the IUT in virtual time (co-simulation): what the tester does next depends on
what a conforming IUT has just done (answer its STX with DLE, NAK, another character, a
crossing STX or silence; interrupt its block; send blocks with wrong BCCs, character
errors, gaps over CDT...). The result is an ordinary vector: the tester's stimuli and, as
expectations, what the model did, with windows derived from why it did it. The vector is
run against the IUT; a divergence is a finding, confirmed by a second run, and not a
finding when a model with another defensible reading of the manual (docs/readings.md) would
have done what the IUT did. Hypothesis shrinks every finding to a minimal transcript,
which is written out as a vector (``vectors/regressions/``).

The tester is a reactive partner: before each stimulus it waits until what the IUT has
begun to send (the replies the protocol requires) is complete and written into the vector
as an expectation, so that the runner, too, sends it only after it has seen them; only a
deliberate violation (interrupting the IUT's block) goes out while the IUT is sending, and
the runner then judges what the IUT actually saw. Timing stimuli keep a margin from every
limit that a real process can honour: "just under" a timer is 70 % of it, "just over" 150 %,
and no stimulus lands closer to one of the IUT's deadlines than the runner's real-time
tolerance can tell apart (before the edge: how late the tester's byte may go out plus two
characters; after it: how late the IUT's timer may act and still pass); the exact edges are
fuzzed in virtual time by level 1 (tests/test_fuzz_model.py). Every time in a generated
vector counts forwards: output that began while the tester was still sending is measured
from the step before that stimulus (``since = "mark"``), never with a negative offset.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from hypothesis import strategies as st

from ptpcert.fuzz.kit import FuzzKit, ms, note_rule, send_receive_codes
from ptpcert.model import events as ev
from ptpcert.model.app import Host
from ptpcert.profile import Profile
from ptpcert.registry import by_id
from ptpcert.runner import Tolerance, realtime_tolerance
from ptpcert.scenario import Expected, Expr, StatusSpec, Step, Vector

from .model import codec
from .model import table as T
from .model.params import Params3964
from .model.readings import READINGS, Readings
from .model.station import Station3964

# ------------------------------------------------------------------ rules the expectations stand for
#: every rule an expectation can name: the rows and decision outcomes of the table that send
_RULES = sorted({T.rule_text(e) for e in [r for _, _, r in T.rows()] + [b for _, b in T.branches()] if e.rule},
                key=len, reverse=True)
BLOCK_RULE = T.rule_text(T.TABLE[T.WAIT_SETUP_ACK][T.DLE])
UNEXPLAINED_RULE = "the reference model's behaviour"


def rule_for(actions: list[str], byte: int) -> str:
    """The manual's rule that makes a conforming station send ``byte`` after running
    ``actions`` (the table row's action and the decisions taken, as the station's explain log
    records them): the rule and reference of the row or decision outcome that sends it."""
    element = T.rule_for(actions, byte)
    return UNEXPLAINED_RULE if element is None else T.rule_text(element)


def rule_of_note(note: str) -> tuple[str, str]:
    """The rule an expectation's note names (one of the table's, when a rule of the model
    made it) and the STATUS codes it lists."""
    return note_rule(note, _RULES)


def _note(rule: str, codes) -> str:
    return rule + (" [STATUS " + ", ".join(f"16#{c:04X}" for c in codes) + "]" if codes else "")


# ------------------------------------------------------------------ co-simulation
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
            note = _note(group[0].rule, sorted(set(c for o in group for c in o.codes)))
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


#: every send/receive event of 3964(R): what an example may see raised besides what it expects
_ALL_3964_CODES = send_receive_codes("3964(R)")


# ------------------------------------------------------------------ drawing the tester's behaviour
CONTROL_BIAS = [0x10, 0x02, 0x03, 0x15, 0x00, 0xFF]


def payloads(max_size: int = 64):
    byte = st.one_of(st.sampled_from(CONTROL_BIAS), st.integers(0, 255))
    return st.lists(byte, min_size=1, max_size=max_size).map(bytes)


def _timer_fraction(draw, under_only: bool = False) -> float:
    """Fractions of a timer, as close to its edge as a real process can honour."""
    choices = [0.0, 0.2, 0.5, 0.7] + ([] if under_only else [1.5])
    return draw(st.sampled_from(choices))


class Generator:
    """Draws one example: a sequence of tester behaviours, co-simulated with the model."""

    def __init__(self, profile: Profile, max_actions: int = 6, max_payload: int = 64,
                 readings: Readings = READINGS):
        self.profile = profile
        self.p = profile.params
        self.max_actions = max_actions
        self.max_payload = max_payload
        self.readings = readings
        self.line = profile.line_conditions == "parmrk"

    def __call__(self, data) -> CoSim:
        sim = CoSim(self.p, self.profile.echo, self.readings)
        n = data.draw(st.integers(1, self.max_actions), label="actions")
        self._pol, self._policy_job = {"kind": "random"}, None
        for _ in range(n):
            self._act(sim, data)
        self._finish(sim, data)
        return sim

    def _reply_wait(self) -> float:
        """How long the co-simulation waits for the IUT's next move before the tester acts:
        past the longest timer a reply can depend on here (CDT or ADT), not longer."""
        return 2 * max(self.p.cdt, self.p.adt) + 10 * self.p.char_time

    # -- one action, chosen for the situation the model IUT is in ---------------------
    def _act(self, sim: CoSim, data) -> None:
        s = sim.st.state
        if s == T.WAIT_SETUP_ACK:
            return self._answer_setup(sim, data)
        if s == T.SEND_DATA:
            return self._interrupt_block(sim, data)
        if s == T.WAIT_RELEASE_ACK:
            return self._answer_release(sim, data)
        return self._from_idle(sim, data)

    def _from_idle(self, sim: CoSim, data) -> None:
        p = self.p
        kinds = ["block", "block", "bad-block", "bad-block", "stray", "nak", "wait"]
        if self.profile.echo:
            kinds += ["prime", "prime", "prime-long", "prime-long"]
        if self.line:
            kinds += ["break", "char-error"]
        kind = data.draw(st.sampled_from(kinds), label="idle action")
        if kind == "wait":
            sim.wait(data.draw(st.sampled_from([p.cdt * 0.5, p.cdt * 1.5, p.adt * 0.7, p.adt * 1.5])))
        elif kind == "stray":
            sim.send(bytes([data.draw(st.sampled_from([0x41, 0x10, 0x03, 0x00, 0xFF]), label="stray")]),
                     note="a stray character")
        elif kind == "nak":
            sim.send(b"\x15", note="NAK")
        elif kind == "break":
            sim.brk(20 * max(p.char_time, 0.001))
        elif kind == "char-error":
            sim.send(bytes([0x41]), kind="send_error", note="a character with a parity error")
        else:
            if kind == "prime-long":  # long enough to be interrupted, without 02 or 15 in it
                payload = data.draw(st.lists(st.integers(0x20, 0x7E), min_size=60, max_size=160).map(bytes),
                                    label="long payload")
            else:
                payload = data.draw(payloads(self.max_payload), label="payload")
            self._tester_block(sim, data, payload, mutate=(kind == "bad-block"))
            if kind.startswith("prime"):
                sim.uses_echo = True
        sim.run_until_output(1, limit=self._reply_wait())

    def _tester_block(self, sim: CoSim, data, payload: bytes, mutate: bool) -> None:
        p = self.p
        sim.send(b"\x02", note="STX")
        sim.run_until_output(1, limit=self._reply_wait())
        if not (sim.outs and sim.outs[-1].byte == 0x10):
            return  # not answered with DLE (e.g. the IUT is busy): leave it to the next action
        body = codec.body(payload, p.procedure)
        how = data.draw(st.sampled_from(["wrong-bcc", "char-error", "gap", "dle-other", "cut", "too-long", "stall"]
                                        if mutate else ["none"]), label="mutation")
        if how == "stall":  # nothing after the IUT's DLE: its first-character timeout must run out
            return
        if how == "too-long":
            body = codec.body(payload + bytes([0x5A]) * (1025 - len(payload)), p.procedure)
        if how == "wrong-bcc" and p.has_bcc:
            body = body[:-1] + bytes([body[-1] ^ data.draw(st.integers(1, 255), label="bcc xor")])
        if how == "dle-other":
            # a DLE followed by 41 inside the data, with a BCC that is right for what is
            # sent: only the DLE rule (16#0805) can refuse the block
            stuffed = codec.stuff(payload)
            k = data.draw(st.integers(0, len(stuffed)), label="dle position")
            stuffed = stuffed[:k] + b"\x10\x41" + stuffed[k:]
            body = stuffed + b"\x10\x03" + (bytes([codec.bcc(stuffed)]) if p.has_bcc else b"")
        if how == "cut":
            body = body[: data.draw(st.integers(1, len(body) - 1), label="cut")]
        if how in ("char-error", "gap") and len(body) > 1:
            k = data.draw(st.integers(0, len(body) - 1), label="position")
            sim.send(body[:k], note="block") if k else None
            if how == "char-error" and self.line:
                sim.send(body[k:k + 1], kind="send_error", note="a character with a parity error")
            elif how == "gap":
                sim.send(body[k:k + 1], at=(_timer_fraction(data.draw) or 0.7) * p.cdt, note="after a gap")
            else:
                sim.send(body[k:k + 1])
            if body[k + 1:]:
                sim.send(body[k + 1:], note="rest of the block")
        else:
            sim.send(body, note="block" if how == "none" else f"block ({how})")

    # -- the tester's policy for the IUT's current job ---------------------------------
    def _policy(self, sim: CoSim, data) -> dict:
        """Drawn when the IUT starts a job and kept for all its attempts: answer at random,
        or refuse the first k setups / releases / blocks (k up to the attempt limits, so
        that the limits themselves are reached) and cooperate afterwards."""
        job = sim.st.job
        if job is None:
            return {"kind": "random"}
        if getattr(self, "_policy_job", None) is not job:
            self._policy_job = job
            kind = data.draw(st.sampled_from(["random", "random", "refuse"]), label="job policy")
            pol = {"kind": kind}
            if kind == "refuse":
                where = data.draw(st.sampled_from(["setup", "release", "data"]), label="refuse where")
                limit = self.p.setup_attempts if where == "setup" else self.p.transmission_attempts
                pol.update(where=where, how=data.draw(st.sampled_from(["nak", "silence", "other"]), label="refuse how"),
                           left=data.draw(st.one_of(st.just(limit), st.integers(1, limit)), label="refusals"))
            self._pol = pol
        return self._pol

    def _refusal(self, sim: CoSim, data, where: str) -> str | None:
        pol = self._policy(sim, data)
        if pol["kind"] == "refuse" and pol["where"] == where and pol["left"] > 0:
            pol["left"] -= 1
            return pol["how"]
        if pol["kind"] == "refuse":
            return "dle"
        return None

    def _answer(self, sim: CoSim, data, where: str) -> None:
        p = self.p
        sim.advance(max(sim.t, sim.st.busy_until))  # the IUT's STX / block is completely out
        how = self._refusal(sim, data, where)
        if how is None:
            how = data.draw(st.sampled_from(["dle", "dle", "nak", "other", "silence", "stx"]
                                            + (["char-error", "break"] if self.line else [])), label=f"{where} answer")
        at = _timer_fraction(data.draw, under_only=True) * p.adt if how != "silence" else 0.0
        note = {"dle": "DLE", "nak": "NAK", "other": "another character",
                "stx": "a crossing STX (initialization conflict)" if where == "setup" else "STX"}
        if how in ("dle", "nak", "other", "stx"):
            sim.send({"dle": b"\x10", "nak": b"\x15", "other": b"\x41", "stx": b"\x02"}[how], at=at, note=note[how])
        elif how == "char-error":
            sim.send(b"\x10", at=at, kind="send_error", note="DLE with a parity error")
        elif how == "break":
            sim.brk(20 * max(p.char_time, 0.001), at=at)
        sim.run_until_output(1, limit=self._reply_wait())

    def _answer_setup(self, sim: CoSim, data) -> None:
        self._answer(sim, data, "setup")

    def _interrupt_block(self, sim: CoSim, data) -> None:
        """Interrupt the IUT's block after k of its bytes with NAK, another character or a
        BREAK. What may still come of the block is a partial expectation; so that the byte
        that follows it (a new STX, a NAK) cannot be mistaken for block data, the block must
        not contain those values within the bytes that may still be on their way."""
        p = self.p
        st_ = sim.st
        forced = self._refusal(sim, data, "data")
        if forced in ("nak", "other"):
            how = forced
        elif forced is not None:
            how = "nothing"
        else:
            how = data.draw(st.sampled_from(["nothing", "nak", "other"] + (["break"] if self.line else [])),
                            label="interrupt")
        body = st_.block_body(st_.job.payload) if st_.job else b""
        end = st_.block_done_at
        if how == "nothing" or p.char_time == 0 or len(body) < 16 or end is None:
            sim.advance(end if end is not None else sim.t)
            return
        start = end - len(body) * p.char_time
        done = max(1, int(round((sim.t - start) / p.char_time)))
        if done > len(body) - 12:
            sim.advance(end)
            return
        k = data.draw(st.integers(done, len(body) - 12), label="interrupt after")
        window = body[k:k + 64]
        if 0x02 in window or 0x15 in window:
            sim.advance(end)
            return
        sim.advance(start + k * p.char_time + 1e-9)   # the k-th byte of the block is complete
        sim.flush_expectations()
        # a deliberate violation: it goes out while the IUT is still sending its block
        if how == "break":
            sim.brk(20 * p.char_time, violation=True)
        else:
            sim.send(b"\x15" if how == "nak" else b"\x42", note="NAK" if how == "nak" else "another character",
                     violation=True)
        stim = sim.ref
        sim.advance(max(sim.t, st_.popped_until, st_.busy_until if st_.state is not T.SEND_DATA else sim.t))
        rest_sent = [o for o in sim.outs if o.rule == BLOCK_RULE]
        sim.outs = [o for o in sim.outs if o.rule != BLOCK_RULE]
        # what may still come of the block is measured from its k-th byte (the mark before
        # the interruption): it may be on its way before the interruption has gone out
        mark_ref, _ = sim.since_mark()
        sim.steps.append(Step("expect", body[k:], partial=True, since="mark", after=ms(0.0),
                              within=Expr(f"{ms(max(stim - mark_ref, 0.0)).text} + 4*CHAR"),
                              note="§7.2 items 3-4, §7.6: the IUT stops sending its block"))
        if rest_sent:
            sim.ref = max(sim.ref, rest_sent[-1].t)
        sim.run_until_output(1, limit=self._reply_wait())

    def _answer_release(self, sim: CoSim, data) -> None:
        self._answer(sim, data, "release")

    def _finish(self, sim: CoSim, data=None) -> None:
        """Bring the exchange to rest: the tester goes on answering whatever the IUT still
        wants to send, following the job's policy and then as a conforming partner, until
        the IUT is idle (or waits for a repetition, which looks the same on the line)."""
        st_ = sim.st
        for _ in range(20 * self.p.setup_attempts * self.p.transmission_attempts):
            s = st_.state
            if s in (T.WAIT_SETUP_ACK, T.WAIT_RELEASE_ACK):
                if data is not None:
                    self._answer(sim, data, "setup" if s == T.WAIT_SETUP_ACK else "release")
                else:
                    sim.advance(max(sim.t, st_.busy_until))
                    sim.send(b"\x10", note="DLE (the tester accepts)")
            elif s == T.SEND_DATA and data is not None:
                self._interrupt_block(sim, data)
            elif s in (T.IDLE, T.WAIT_REPETITION) and not st_.transmitting and st_.pending_jobs == 0:
                break
            else:
                d = st_.next_deadline()
                if d is None:
                    break
                sim.advance(max(d, sim.t))


ALTERNATIVE_READINGS = [
    ("A6", dict(a6_second_final_nak=True)),
    ("A7", dict(a7_quiet_wait_retriggered=False)),
    ("A11", dict(a11_deferred_nak_after_dle_other=False)),
    ("A12", dict(a12_release_adt_after_last_byte=False)),
    ("A13", dict(a13_nak_after_invalid_char_in_idle=False)),
    ("A17", dict(a17_accept_zero_length_block=False)),
    ("A19", dict(a19_wait_repetition_code=0x0808)),
    ("A21", dict(a21_conflict_counts_collided_stx=False)),
    ("A23", dict(a23_restart_adt_on_conflict_stx=True)),
    ("A4", dict(a4_reset_setup_counter_per_attempt=False)),
    ("A10", dict(a10_dle_in_end_sequence_too_early=False)),
]



FUZZ_KIT = FuzzKit(Generator, READINGS, tuple(ALTERNATIVE_READINGS), rule_of_note=rule_of_note)
