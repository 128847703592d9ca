"""The step interpreter: one vector run once against an open transport. The tester's side
of the vector's steps goes out with the timing they ask for (each byte paced as on the
line, a late one near an IUT timer a harness timing fault), and every ``expect`` step
watches its window, with the tolerance of the attempt, for the bytes it names.

:class:`CaseRun` is the top layer of a case's run: the prologue (the IUT idle before the
first step), the steps, the epilogue (the IUT's echo, then a quiet line). It builds on the
partner play (:mod:`ptpcert.runner.partner`), the case's line
(:mod:`ptpcert.runner.pump`) and the machine watch (:mod:`ptpcert.runner.disturbance`); the
case runner (:mod:`ptpcert.runner.attempts`) makes one per attempt and judges what it
leaves. :func:`earlier_interrupt` rewrites the steps for an attempt that interrupts an
IUT's block sooner.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any, Callable

from ptpcert import results as R
from ptpcert.model.hexbytes import hexstr
from ptpcert.scenario import Expr, Step, Vector, brief_hex, names_in, timer_env
from ptpcert.transport.base import RESTART, Transport

from .options import RunOptions, Tolerance
from .partner import PartnerPlay


class TimingFault(RuntimeError):
    """The harness could not keep the timing a stimulus needs (machine too loaded)."""


@dataclass
class RunnerState:
    """What the runner learns across cases of one run (read and set by the prologue)."""

    startup_nak_seen: bool | None = None
    persistent_settled: bool = False


def earlier_interrupt(steps: tuple[Step, ...], stim: int) -> tuple[Step, ...] | None:
    """The steps with the stimulus of step ``stim`` sent after the first byte of the block
    it interrupts instead of after several: the expect step before it keeps only its first
    byte, the partial expectation after it takes the rest. None when the steps around it
    are not an expected block, the stimulus and the rest of that block."""
    if stim < 1 or stim + 1 >= len(steps):
        return None
    before, after = steps[stim - 1], steps[stim + 1]
    if before.kind != "expect" or before.partial or before.optional or before.alternatives or len(before.data) < 2:
        return None
    if after.kind != "expect" or not after.partial:
        return None
    return (steps[:stim - 1] + (replace(before, data=before.data[:1]), steps[stim],
                                replace(after, data=before.data[1:] + after.data)) + steps[stim + 2:])


class CaseRun(PartnerPlay):
    """Executes one vector once against an open transport."""

    def __init__(self, vector: Vector, steps: tuple[Step, ...], tr: Transport,
                 params: Any, tol: Tolerance, opts: RunOptions):
        super().__init__(vector, steps, tr, params, tol, opts)
        self.env = timer_env(vector, params, opts.startup_timeout)
        #: (ref, floor): when ``ref`` was set from a received byte, the earliest that byte
        #: may have left the IUT - how long before its own reply the IUT's timer may have run
        self._ref_floor: tuple[float, float] = (self.t0, self.t0)
        self.grade = R.PASS
        self.notes: list[str] = []
        self.sent_end = self.t0
        self.mark_time = self.t0
        #: (data, bytes received) of the last partial expect step, for a step that resumes it
        self.last_partial: tuple[bytes, int] | None = None
        names = self.proc.iut_timers if self.proc.iut_timers is not None else self.proc.time_names
        self.iut_timers = frozenset(names)
        #: per stimulus (a send, character error or BREAK step): (step, IUT bytes read
        #: before its first byte went out)
        self.stimuli: list[tuple[int, int]] = []
        #: (stimulus step, partial step) when an IUT block that a stimulus was meant to
        #: interrupt had ended before the stimulus went out
        self.displaced: tuple[int, int] | None = None
        #: the STATUS events the IUT reported (None: not collected)
        self.status_codes: list[int] | None = None
        self.skipping = 0

    def ev(self, e: Expr) -> float:
        """A time of the vector (e.g. ``0.8 * CDT``) in seconds, with the case's timers."""
        return e.eval(self.env)

    #: how long a process IUT that sent nothing in a window is given to show it has ended
    DEATH_GRACE = 0.1

    def _look_for_death(self) -> None:
        """Nothing came in the window: an IUT process that has ended, or ends within
        DEATH_GRACE (a crash on a loaded machine takes a while), is reported as ended
        (IUTDied) rather than as silence. The verdict is a fail either way."""
        if self.realtime and RESTART in self.tr.capabilities:
            # the grace comes after the window that decided: what the machine does to either
            # process meanwhile does not touch the verdict's footing
            kept = self.max_stall, self.iut_stall, self.iut_wait, self.stolen
            end = self.tr.now() + self.DEATH_GRACE
            while self.tr.now() < end:
                self.pump(end)
            self.max_stall, self.iut_stall, self.iut_wait, self.stolen = kept

    # -- steps -------------------------------------------------------------------------
    def run_steps(self) -> None:
        """The vector's steps in order, each by the handler of its kind (``_send``,
        ``_expect``, ...)."""
        skip = 0
        self.ending: int | None = None
        for i, step in enumerate(self.steps):
            if self.ending is not None:
                if self.ending == 0:
                    break       # an alternative that ends the case came (or_end)
                self.ending -= 1
            if skip:
                skip -= 1   # the rest of a block the IUT did not send (an optional expect's skip)
                continue
            self.step_index = i
            self.skipping = 0
            getattr(self, "_" + step.kind)(step)
            if step.mark:
                self.mark_time = self.ref
            skip = self.skipping

    def _send_bytes(self, step: Step, data: bytes, writer: Callable[[int], float], kind: str) -> None:
        """Send characters paced as on the line: the k-th starts at ref + at + k*(CHAR+gap)
        and is handed over when it is complete, one character time later."""
        at, gap = self.ev(step.at), self.ev(step.gap)
        char = self.tester_char
        start = self.ref + at
        t = start
        # A late byte matters only where one of the IUT's timers could have run out because
        # of it: when the time since the previous event nears the shortest timer. Where that
        # event is the IUT's byte, its timer may have started as early as the byte may have
        # left it (a block written in one piece and read late, then handled for a while).
        prev = self._ref_floor[1] if self._ref_floor[0] == self.ref else self.ref
        critical = 0.9 * self.shortest
        for k, b in enumerate(data):
            target = start + k * (char + gap) + char
            self.wait_until(target)
            if k == 0:
                self._stimulus()
            t = writer(b)
            self.record({"t": self.rel(t), "dir": "tester", "kind": kind, "byte": b, "step": self.step_index})
            late = t - target
            self.max_stall = max(self.max_stall, late)
            if late > self.tol.stimulus and t - prev > critical:
                raise TimingFault(f"step {self.step_index + 1}: the tester's byte {k + 1} went out "
                                  f"{late * 1000:.1f} ms late (allowed {self.tol.stimulus * 1000:.1f} ms)")
            prev = t
        self.ref = self.sent_end = t
        self.forced += at + len(data) * char + max(0, len(data) - 1) * gap

    def _stimulus(self) -> None:
        """A stimulus is about to go out: take in what the IUT has sent by now (the state
        it is in when the stimulus reaches it) and note it."""
        if self.realtime:
            self.pump(self.tr.now())
        self.stimuli.append((self.step_index, len(self.rx)))

    def _send(self, step: Step) -> None:
        self._send_bytes(step, step.data, lambda b: self.tr.write(bytes([b])), "byte")

    def _send_error(self, step: Step) -> None:
        self._send_bytes(step, step.data, self.tr.send_char_error, "char_error")

    def _break(self, step: Step) -> None:
        at, dur = self.ev(step.at), self.ev(step.duration)
        target = self.ref + at
        self.wait_until(target)
        self._stimulus()
        t = self.tr.send_break(dur)
        if t - target > self.tol.stimulus and t - self.ref > 0.9 * self.shortest:
            raise TimingFault(f"step {self.step_index + 1}: BREAK went out {1000 * (t - target):.1f} ms late")
        self.record({"t": self.rel(t), "dir": "tester", "kind": "break", "duration": dur, "step": self.step_index})
        self.ref = self.sent_end = t + dur
        self.wait_until(self.ref)
        self.forced += at + dur

    def _wait(self, step: Step) -> None:
        d = self.ev(step.duration)
        self.ref += d
        self.wait_until(self.ref)
        self.forced += d

    def _silence(self, step: Step) -> None:
        d = self.ev(step.duration)
        end = self.ref + d
        self.mark("window", t0=self.rel(self.ref), t1=self.rel(end), label=f"silence {step.duration}")
        self.wait_until(end)
        if self.pos < len(self.rx) and self.rx[self.pos][0] <= end:
            t, b = self.rx[self.pos]
            self.fail(f"silence for {step.duration}", f"received {b:02X} at {1000 * (t - self.ref):.1f} ms",
                      t, (self.ref, end))
        self.ref = end
        self.forced += d

    def _expect(self, step: Step) -> None:
        last_partial, self.last_partial = self.last_partial, None
        if step.resume and last_partial is not None and last_partial[0] == step.data:
            rest = step.data[last_partial[1]:]
            if not rest:
                return  # the interrupted step received everything already
            step = replace(step, data=rest, alternatives=())
        if step.since == "sent":
            self.ref = self.sent_end
        elif step.since == "mark":
            self.ref = self.mark_time
        lo_nom, hi_nom = self.ev(step.after), self.ev(step.within)
        lo = self.ref + lo_nom - self.tol.early - self.tol.early_rel * max(lo_nom, 0.0)
        hi = self.ref + hi_nom + self.tol.late(hi_nom) + self.lead
        if self.tol.iut_timer and self._ends_on_iut_timer(step):
            hi += self.tol.iut_timer
        what = brief_hex(step.data)
        if step.alternatives:
            what += " (or " + " or ".join(brief_hex(a) for a in step.alternatives) + ")"
        label = f"expect {what} in [{step.after}, {step.within}]"
        self.mark("window", t0=self.rel(self.ref + lo_nom), t1=self.rel(self.ref + hi_nom), label=label)
        cands = [step.data] + list(step.alternatives)
        first = self.next_wanted(hi, {c[0] for c in cands})
        if first is None or first[0] > hi:
            if step.partial:
                self.last_partial = (step.data, 0)
            if step.optional or step.partial:
                if step.optional:
                    self._grade(step.absent_grade, f"step {self.step_index + 1}: optional {what} not sent")
                    # the next step follows the window watched in vain (its tolerance included)
                    self.ref = max(self.ref + hi_nom, min(self.tr.now(), hi))
                    self.skipping = step.skip
                self.forced += max(hi_nom, 0.0)  # the whole window had to be watched
                return
            if first is None:
                self._look_for_death()
                self.fail(what + f" within {step.within}", "nothing received", hi, (self.ref + lo_nom, self.ref + hi_nom))
            t, b = first
            self.fail(what + f" within {step.within}",
                      f"{b:02X} came {1000 * (t - self.ref):.1f} ms after the reference, too late",
                      t, (self.ref + lo_nom, self.ref + hi_nom), late_only=(b == step.data[0]))
        t, b = first
        live = [c for c in cands if c[0] == b]
        if not live:
            if step.partial:
                self.last_partial = (step.data, 0)
                return
            if step.optional:
                self._grade(step.absent_grade, f"step {self.step_index + 1}: optional {what} not sent")
                self.skipping = step.skip
                return
            self.fail(what, f"received {b:02X}", t, (self.ref + lo_nom, self.ref + hi_nom))
        # the rest of a block the stimulus interrupts may have been on the line before the
        # stimulus went out: those bytes are not a reaction to it, early or not
        before = step.partial and bool(self.stimuli) and self.pos < self.stimuli[-1][1]
        if t < lo and not before:
            self.fail(f"{what} no earlier than {step.after}",
                      f"{b:02X} came {1000 * (t - self.ref):.1f} ms after the reference, too early",
                      t, (self.ref + lo_nom, self.ref + hi_nom), late_only=True)
        got = bytearray([b])
        self.consume()
        last_t = t
        gap_expr = step.max_gap if step.max_gap is not None else Expr(self.proc.max_gap)
        gap_nom = self.ev(gap_expr)
        gap_lim = gap_nom + self.tol.late(gap_nom)
        while True:
            done = [c for c in live if len(c) == len(got)]
            longer = [c for c in live if len(c) > len(got)]
            if not longer:
                break
            nxt = self.next_wanted(last_t + gap_lim, {c[len(got)] for c in longer})
            if nxt is None or nxt[0] > last_t + gap_lim:
                if done or step.partial:
                    break
                self.fail(f"{what} with gaps of at most {gap_expr}",
                          f"got {brief_hex(bytes(got))}, then nothing for {1000 * gap_lim:.0f} ms",
                          last_t + gap_lim, late_only=nxt is not None)
            nt, nb = nxt
            still = [c for c in longer if c[len(got)] == nb]
            if not still:
                if done or step.partial:
                    break
                self.fail(what, f"byte {len(got) + 1} is {nb:02X} (after {brief_hex(bytes(got))})", nt)
            if step.partial and nt > hi:
                self.fail(f"the IUT to stop sending within {step.within}",
                          f"it still sent {nb:02X} {1000 * (nt - self.ref):.1f} ms after the reference", nt,
                          (self.ref, self.ref + hi_nom))
            live = still
            got.append(nb)
            self.consume()
            last_t = nt
        matched = bytes(got)
        if step.partial:
            self.last_partial = (step.data, len(matched))
        if matched != step.data and not step.partial:
            if matched in step.alternatives:
                self._grade(step.alt_grade, f"step {self.step_index + 1}: the IUT sent {hexstr(matched)}")
                if step.or_end is not None:
                    self.ending = step.or_end
        if (step.partial and matched == step.data and self.stimuli and self.pos <= self.stimuli[-1][1]
                and self.displaced is None):
            # the whole block was on the line before the stimulus went out: the stimulus
            # reached an IUT whose block had ended (e.g. written in one piece over a pipe)
            self.displaced = (self.stimuli[-1][0], self.step_index)
        # the rest of a block a stimulus interrupts may have come while the stimulus (a long
        # BREAK, say) was still going out: the next step cannot follow a time already passed
        # before the stimulus ended, so the reference does not go back behind it
        self.ref = max(last_t, self.sent_end) if step.partial else last_t
        if got and self.ref == last_t:
            self._ref_floor = (last_t, min(last_t, self.rx_floor[self.pos - 1]))
        self.forced += max(lo_nom, 0.0) + len(matched) * self.char

    def _ends_on_iut_timer(self, step: Step) -> bool:
        """The window waits for what one of the IUT's own timers causes: its lower bound
        names one (e.g. ``after = "CDT"``: a NAK due when the IUT's CDT runs out)."""
        return bool(names_in(step.after) & self.iut_timers)

    def _grade(self, grade: str, why: str) -> None:
        """The case passes no better than ``grade`` (a note says why, below a pass)."""
        if grade != R.PASS:
            self.notes.append(f"{grade}: {why}")
        self.grade = R.worse_grade(self.grade, grade)

    def _prime(self, step: Step) -> None:  # pragma: no cover - expanded before running
        raise AssertionError("a procedure's own steps are expanded before the run")

    _receive = _prime

    def _partner(self, step: Step) -> None:
        """The tester plays a conforming partner for the step's duration."""
        t0 = self.tr.now()
        limit = self.ref + self.ev(step.duration)
        self.play_partner(self.tp, limit, want=None, label="the tester plays a conforming partner")
        self.forced += self.tr.now() - t0  # the protocol's own retries decide how long this takes

    # -- before and after the steps ----------------------------------------------------
    def prologue(self, state: RunnerState) -> None:
        """Wait for what a freshly started IUT sends on its own (3964's start-up NAK;
        bounded), so the steps start with the IUT idle; on a persistent IUT, wait for the
        line to be quiet."""
        if self.v.start == "power-on":
            return
        if RESTART in self.tr.capabilities:
            startup = self.proc.startup_bytes(self.p)
            if startup:
                limit = self.opts.startup_timeout if state.startup_nak_seen is not False else 0.1
                first = self.next_byte(self.tr.now() + limit)
                if first is not None and first[1] == startup[0]:
                    self.consume()
                    for b in startup[1:]:
                        nxt = self.next_byte(self.tr.now() + limit)
                        if nxt is None or nxt[1] != b:
                            break
                        self.consume()
                    state.startup_nak_seen = True
                elif first is None and state.startup_nak_seen is None:
                    state.startup_nak_seen = False
            else:
                self._await_ready()
            self.ref = max(self.tr.now(), self.rx[self.pos - 1][0] if self.pos else self.tr.now())
        else:
            quiet = self.longest + self.tol.late(0)
            if not state.persistent_settled:
                # the first case on a persistent line: the IUT may still be starting up
                quiet = max(quiet, self.opts.startup_timeout / 2)
                state.persistent_settled = True
            end = self.tr.now() + 10 * quiet + 5.0
            last = self.tr.now()
            while self.tr.now() < min(last + quiet, end):
                n = len(self.rx)
                self.pump(min(last + quiet, end))
                if len(self.rx) > n:
                    last = self.rx[-1][0]
            self.pos = len(self.rx)
            self.ref = self.tr.now()
        self.mark("start", t=self.rel(self.ref))

    def _await_ready(self) -> None:
        """An IUT that announces nothing at start-up: before the first stimulus, wait until
        it waits for input (a stimulus written earlier would sit in a pipe and lose its
        timing), at most the start-up timeout."""
        if self.tr.virtual:
            return
        end = self.tr.now() + self.opts.startup_timeout
        while True:
            ready = self.tr.ready()
            if ready is None or ready:
                return
            if self.tr.now() >= end:
                self.notes.append(f"the IUT did not wait for input within {self.opts.startup_timeout:g} s of its start")
                return
            self.pump(min(end, self.tr.now() + 0.01))

    def epilogue(self) -> None:
        """After the steps: an echo IUT sends back the blocks the vector names; the tester
        receives them as a conforming partner would. Then the line must stay quiet."""
        self.step_index = len(self.steps)
        echo = list(self.v.expected.echo_after) if self.opts.echo else []
        if echo:
            self.receive_echoes(echo)
        quiet = self.longest + self.char * 4
        end = self.ref + quiet
        self.mark("window", t0=self.rel(self.ref), t1=self.rel(end), label="no further bytes")
        self.wait_until(end)
        self.forced += quiet  # silence is proven only by watching for the longest timer
        if self.pos < len(self.rx):
            t, b = self.rx[self.pos]
            rest = hexstr(bytes(x[1] for x in self.rx[self.pos:self.pos + 16]))
            self.fail("nothing more from the IUT" + (" after its echo" if echo else ""),
                      f"it sent {rest}", t, (self.ref, end))
        self.ref = end
