"""One case against an IUT, attempt by attempt (:class:`CaseRunner`): whether the case
applies to the profile and the transport at all, then its attempts until one stands. An
attempt the harness could not time is void and runs again; a failure the machine's timing
may have caused (late only, in a disturbed attempt, close to a timer's edge, over a
network serial server) is reproduced before it stands; a stimulus that found the IUT's
block already ended is tried once more, sooner.

One attempt opens the transport, runs the steps (:class:`ptpcert.runner.steps.CaseRun`),
closes it, and judges what was on record: the IUT's reports (:mod:`ptpcert.runner.grading`)
and, for a failure in real time, the model's view (:mod:`ptpcert.runner.rejudge`). A whole
run of cases is :class:`ptpcert.runner.run.Runner`, built on this.
"""

from __future__ import annotations

import time
from dataclasses import replace
from typing import Any

from ptpcert import results as R
from ptpcert.model.hexbytes import hexstr
from ptpcert.profile import Profile
from ptpcert.scenario import Vector, expand
from ptpcert.transport.base import (
    BREAK,
    CHAR_ERROR,
    NETWORK,
    RESTART,
    SETUPS,
    IUTDied,
    TransportError,
)

from .grading import expected_failure, grade_by_readings, judge_events, mark_divergence_frame
from .options import VIRTUAL, RunOptions, realtime_tolerance
from .pump import Flood, StepFailed
from .rejudge import rejudge
from .steps import CaseRun, RunnerState, TimingFault, earlier_interrupt


class CaseRunner:
    """Runs single cases against the IUTs a transport factory makes, with a profile (None:
    the vectors' own parameters) and options."""

    def __init__(self, factory, profile: Profile | None = None,
                 options: RunOptions | None = None):
        self.factory = factory
        self.profile = profile
        self.opts = options or RunOptions()
        self.state = RunnerState()
        #: the last attempt's case driver (its log and what it noted), for tools and tests
        self.last_run: CaseRun | None = None

    # -- applicability -------------------------------------------------------------
    def effective_params(self, v: Vector) -> Any:
        """The vector's parameters, with the profile's where the vector does not bind them."""
        if self.profile is None:
            return v.params
        p = self.profile.params
        fixed = {name: getattr(v.params, name) for name in v.binds}
        try:
            return v.proc.params_with(p, **fixed) if fixed else p
        except ValueError:
            return v.params  # no such IUT: the bound values do not go with the profile's (unsupported)

    def unsupported_reason(self, v: Vector, caps: frozenset[str]) -> str | None:
        """Why the case cannot run against the profile's IUT over a transport that carries
        ``caps`` (None: it can)."""
        if self.profile is not None:
            if v.procedure != self.profile.procedure.id:
                return (f"the vector is for {v.proc.title}; the IUT profile is for "
                        f"{self.profile.procedure.title}")
            for name in v.binds:
                want, have = getattr(v.params, name), getattr(self.profile.params, name)
                if want != have:
                    return f"the vector is for {name} = {want}; the IUT profile has {have}"
            if "echo" in v.needs and not self.profile.echo:
                return "needs an IUT that sends back what it receives (profile send_trigger = \"none\")"
            # a transport with real line conditions (a UART, RFC 2217) needs no marking by the
            # IUT; which of them it carries is checked below, kind by kind
            if "line_conditions" in v.needs and self.profile.line_conditions == "none" and \
                    "native_line_conditions" not in caps:
                return "needs BREAK / character errors; the profile says the IUT reads no line conditions"
        if "line_conditions" in v.needs:
            kinds = {s.kind for s in v.steps}
            if "break" in kinds and BREAK not in caps:
                return "needs BREAK, which this transport cannot carry"
            if "send_error" in kinds and CHAR_ERROR not in caps:
                return "needs characters with parity/framing errors, which this transport cannot carry"
        if "restart" in v.needs and RESTART not in caps:
            return "needs to see the IUT start up; this transport does not start the IUT"
        if v.setup is not None and not getattr(self.factory, "virtual", False):
            name = v.setup[0]
            if self.profile is None or name not in self.profile.setups:
                return (f"needs the IUT in the state of setup {name!r}, which the profile's [iut.setups] "
                        "does not name")
            if SETUPS not in caps:
                return f"needs the IUT started with setup {name!r}; this transport does not start the IUT"
        return v.proc.unsupported_reason(v, self.profile, caps, self.factory)

    def nothing_to_test(self, cases: list[Vector]) -> str | None:
        """Why none of ``cases`` can run against the profile's IUT over this transport (one
        line: how many cases, the commonest reason), or None where at least one can. A run in
        which every case is unsupported judged nothing, and a gate must not read it as a
        pass."""
        if not cases:
            return "no case at all"
        reasons: dict[str, int] = {}
        caps = self.factory.capabilities
        for v in cases:
            why = self.unsupported_reason(v, caps)
            if not why:
                return None
            reasons[why] = reasons.get(why, 0) + 1
        ranked = sorted(reasons.items(), key=lambda kv: -kv[1])
        said = "; ".join(f"{n} case(s): {why}" for why, n in ranked[:3])
        also = f"; {len(ranked) - 3} more reason(s)" if len(ranked) > 3 else ""
        return (f"nothing to test: every one of the {len(cases)} cases is unsupported for this profile and "
                f"IUT ({said}{also})")

    # -- one case ------------------------------------------------------------------
    def run_case(self, v: Vector) -> R.CaseResult:
        """The case's result: unsupported, or the verdict of the attempt that stood."""
        res = R.CaseResult(id=v.id, title=v.title, reference=v.reference, rule=v.rule, group=v.group,
                           iut_role=v.iut_role, readings=list(v.readings), source=v.source, rules=list(v.rules))
        res.expected_status = v.expected.iut_status.describe()
        res.expected_status_codes = [sorted(f"16#{c:04X}" for c in g) for g in v.expected.iut_status.required]
        res.tester_status = v.expected.tester_status.describe()
        params = self.effective_params(v)
        res.params = v.proc.params_table(params)
        steps = expand(replace(v, params=params))
        res.steps = [{"kind": s.kind, "data": hexstr(s.data), **s.to_toml()} for s in steps]
        wall0 = time.monotonic()
        reason = self.unsupported_reason(v, self.factory.capabilities)
        if reason:
            res.verdict, res.message = R.UNSUPPORTED, reason
            return res
        attempts = voided = reruns = 0
        realtime = not getattr(self.factory, "virtual", False)
        earlier_tried = False
        while True:
            attempts += 1
            outcome = self._attempt(v, steps, params, res, may_interrupt_earlier=not earlier_tried)
            if outcome.startswith("displaced:"):
                # the stimulus found the IUT's block ended: once more, interrupting earlier
                earlier_tried = True
                steps = earlier_interrupt(steps, int(outcome.split(":")[1]))
                res.notes.append(f"attempt {attempts} voided: {res.message}")
                continue
            if outcome == "timing" and voided < self.opts.timing_retries:
                voided += 1
                res.notes.append(f"attempt {attempts} voided: {res.message}")
                self._pause(voided + reruns, realtime)
                continue
            if res.verdict == R.FAIL and reruns < self._rerun_budget(v, outcome, realtime):
                reruns += 1
                why = ("failed by timing only" if outcome == "late" else
                       "failed in an attempt the machine disturbed (see the note before); a failure is reproduced "
                       "before it stands, so it runs again" if outcome == "disturbed" else
                       "failed; the case works close to a timer's edge, so it runs again" if v.timing_sensitive else
                       "failed over a network serial server, whose delays can stretch a gap on the line; "
                       "it runs again")
                res.notes.append(f"attempt {attempts} {why}: {res.message}")
                self._pause(voided + reruns, realtime)
                continue
            break
        if res.verdict == R.FAIL and v.readings and self.opts.grade_readings:
            grade_by_readings(self, v, res)
        if res.verdict in (R.PASS, R.NON_STRICT, R.INFORMATIONAL) and reruns:
            res.message = "; ".join(x for x in (res.message, f"passed on attempt {attempts} after {reruns} failed "
                                                              f"attempt(s) (see notes)") if x)
        res.attempts = attempts
        res.duration = round(time.monotonic() - wall0, 4)
        expected_failure(self.profile, v, res)
        return res

    def _rerun_budget(self, v: Vector, outcome: str, realtime: bool) -> int:
        """How many times a failed case runs again before its failure stands. A failure is
        reproduced before it is reported where the machine's own timing could have caused
        it: a case that failed only by a late reply, or in an attempt the machine disturbed
        (CaseRun.disturbance), runs once more; a case close to a timer's
        edge (an acceptance at 80 % of CDT or ADT, an initialization conflict) runs up to
        ``edge_attempts`` times in all over a real-time transport, and passes if any attempt
        passes: one acceptance proves the IUT waits long enough, while a refusal may come
        from a process that was scheduled a few milliseconds late. A deterministic early
        timeout fails every attempt. Over a network serial server (rfc2217://, socket://)
        every failed case runs once more: a server that stalls longer than CDT puts a gap on
        the line that the harness never sent."""
        if not self.opts.confirm_late:
            return 0
        budget = 1 if outcome in ("late", "disturbed") else 0
        if v.timing_sensitive and realtime:
            budget = max(budget, self.opts.edge_attempts - 1)
        if NETWORK in self.factory.capabilities and realtime:
            budget = max(budget, 1)   # a server that stalls longer than CDT puts a gap on the line
        return budget

    def _pause(self, n: int, realtime: bool) -> None:
        """Before the n-th repeated attempt, let a burst of load on the machine pass."""
        if realtime and self.opts.retry_pause:
            time.sleep(self.opts.retry_pause[min(n, len(self.opts.retry_pause)) - 1])

    def _attempt(self, v: Vector, steps, params: Any, res: R.CaseResult, may_interrupt_earlier: bool = False) -> str:
        """Run once; fill ``res``; return "ok", "timing" (voided), "late" (failed by
        lateness only), "disturbed" (failed in an attempt the machine disturbed: reproduce
        it) or "displaced:N" (the stimulus of step N was meant to interrupt a block that had
        ended; run again interrupting earlier)."""
        try:
            tr = self.factory(v, params)
        except TransportError as exc:
            res.verdict, res.message = R.ERROR, f"transport: {exc}"
            return "ok"
        tol = self.opts.tolerance or (VIRTUAL if tr.virtual else realtime_tolerance(v.proc, params, self.opts.late_ms))
        if self.profile is not None and self.profile.timer_tolerance_ms:
            tol = replace(tol, iut_timer=self.profile.timer_tolerance_ms / 1000.0)
        outcome = "ok"
        run: CaseRun | None = None
        info = None
        res.divergence = None
        try:
            tr.open()
            run = self.last_run = CaseRun(v, steps, tr, params, tol, self.opts)
            run.prologue(self.state)
            try:
                run.run_steps()
                run.epilogue()
            except StepFailed:
                if run.displaced is not None and run.realtime and self.opts.rejudge and not (
                        may_interrupt_earlier and earlier_interrupt(steps, run.displaced[0]) is not None):
                    try:    # the case will be judged by the model: get the rest of the exchange
                        run.observe_rest()
                    except (StepFailed, Flood):
                        pass
                raise
            res.verdict, res.message = run.grade, "; ".join(run.notes)
        except StepFailed as exc:
            res.verdict, res.message, res.divergence = R.FAIL, exc.message, exc.div
            outcome = "late" if exc.late_only else "ok"
        except TimingFault as exc:
            res.verdict, res.message = R.ERROR, f"harness timing fault: {exc}"
            outcome = "timing"
        except Flood as exc:
            res.verdict, res.message = R.FAIL, str(exc)
        except IUTDied as exc:
            res.verdict, res.message = R.FAIL, f"{exc} during step {run.step_index + 1 if run else 0}"
            res.stderr_tail = exc.stderr_tail
        except TransportError as exc:
            res.verdict, res.message = R.ERROR, f"transport: {exc}"
        except (KeyboardInterrupt, SystemExit):
            raise
        except Exception as exc:  # a harness bug: an error, never blamed on the IUT
            import traceback
            res.verdict = R.ERROR
            res.message = f"harness fault: {type(exc).__name__}: {exc}"
            res.notes.append(traceback.format_exc(limit=6))
        finally:
            try:
                info = tr.close()
            except Exception as exc:  # never lose the result because closing failed
                res.notes.append(f"closing the transport failed: {exc}")
        if info is not None:
            if info.stderr:
                res.stderr_tail = info.stderr[-2000:]
            res.notes.extend(info.notes)
        if run is not None:
            res.transcript = run.transcript()
            try:
                res.frames = v.proc.describe_frames(run.log, params)
                mark_divergence_frame(v.proc, res, run.log, steps, params)
            except Exception as exc:  # a decoder's fault must not cost the verdict
                res.notes.append(f"frames could not be decoded: {type(exc).__name__}: {exc}")
            res.origin = run.t0
            res.forced_wait = round(run.forced, 6)
            res.case_time = round(tr.now() - run.t0, 6) if tr.virtual else 0.0
            if res.verdict != R.ERROR:  # also for a failed attempt: the report shows what the IUT raised
                judge_events(self.opts, v, tr, res, run)
            if res.verdict == R.FAIL and run.realtime and self.opts.rejudge:
                outcome = rejudge(self.profile, v, steps, params, tr, run, res, outcome, may_interrupt_earlier)
        return outcome
