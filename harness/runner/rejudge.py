"""The re-judgement of a failed real-time attempt: the reference model, fed the line as it
really was (:mod:`ptpcert.replay`), on the timelines the harness's own timing allows (the
tester's bytes as they went out, as late as they may have reached the IUT, as late as a
stalled process may have taken them). A divergence that one of them explains is the
harness's (the attempt is void); one that none explains is the IUT's, and stands, or is
reproduced first where the machine disturbed the attempt (:func:`confirm`).

Called by the case runner (:mod:`ptpcert.runner.attempts`) after an attempt failed; it
reads the attempt's run (:class:`ptpcert.runner.steps.CaseRun`: its log, the bounds of the
IUT's bytes, the disturbances measured) and returns the attempt's outcome.
"""

from __future__ import annotations

from typing import Any

from ptpcert import results as R
from ptpcert.profile import Profile
from ptpcert.scenario import Vector
from ptpcert.transport.base import RESTART, Transport

from .steps import CaseRun, earlier_interrupt


def rejudge(profile: Profile | None, v: Vector, steps, params: Any, tr: Transport, run: CaseRun,
            res: R.CaseResult, outcome: str, may_interrupt_earlier: bool) -> str:
    """A failed real-time attempt, judged again by the model fed the line as it was
    (:mod:`ptpcert.replay`):

    * a stimulus meant to interrupt a block of the IUT went out when the whole block
      was already on the line: the attempt is repeated once with the stimulus after the
      block's first byte; if the block has ended again (an IUT that writes it in one
      piece), the exchange is judged by the rule for the state the IUT was really in:
      the model, fed the same line, must send what the IUT sent and raise what it
      raised;
    * otherwise, if the model fed the tester's bytes as early or as late as they may
      have reached the IUT (the harness reads a byte late when it is descheduled, and
      times its reply from that read) does what the IUT did, the divergence is the
      harness's timing, not the IUT's: the attempt is void (run again; an error if it
      keeps happening)."""
    from ptpcert import replay as RP
    from ptpcert.procedure import ProcedureError
    from ptpcert.transport import sim_factory

    proc = v.proc
    if run.displaced is not None:
        stim, part = run.displaced
        why = (f"the IUT's block (step {part + 1}) was on the line whole before the tester's stimulus (step "
               f"{stim + 1}) went out, so the stimulus reached an IUT whose block had ended")
        if may_interrupt_earlier and earlier_interrupt(steps, stim) is not None:
            res.message = f"{why}; the attempt is repeated with the stimulus after the block's first byte"
            return f"displaced:{stim}"
    elif res.divergence is None and not res.message.startswith("STATUS: "):
        return outcome
    tol = run.tol
    margin = RP.Margin(early=lambda d: tol.early + tol.early_rel * max(d, 0.0),
                       late=lambda d: tol.late(d) + (tol.iut_timer if d > 3 * run.char + 0.001 else 0.0))
    wire = RP.Wire.from_log(run.log, run.lower_bound, run.rel(run.last_look))
    # the procedure's own application unless the profile has none (RK 512: its script)
    options = {} if (profile is None or profile.echo) else {"app": "none"}
    try:
        factory = sim_factory(proc, options)
    except (ValueError, ProcedureError):
        factory = sim_factory(proc, {})
    startup = RESTART in tr.capabilities

    def model(late: bool, stall: float = 0.0):
        return RP.replay(factory(v, params), wire, margin, late=late, startup_on_line=startup,
                         longest=run.longest, char=run.char, stall=stall)

    try:
        if run.displaced is not None:
            rep = model(late=False)
            problems = _status_by_model(v, run, rep.codes) if rep.agrees else []
            if rep.agrees and not problems:
                res.verdict, res.divergence = R.PASS, None
                res.message = (f"{why}; the case's rule could not be exercised, so the exchange was judged by the "
                               "rule for that state (the reference model fed the same line does what the IUT did)")
            else:
                res.verdict = R.FAIL
                res.message = (f"{why}; judged by the rule for that state (the reference model fed the same "
                               "line): " + (rep.why or "STATUS: " + "; ".join(problems)))
                if rep.at is not None:
                    res.divergence = R.Divergence(-1, round(rep.at, 6), "what the reference model does on the "
                                                  "same line", rep.why)
            return "ok"
        worst = max(run.max_stall, run.iut_stall)
        if worst <= tol.stimulus and not run.starved and run.partner_late <= tol.stimulus:
            # the harness kept its own timing in this attempt (no read or write came
            # later than its tolerance), and the IUT's process was not seen kept from a
            # CPU as long: the tester's bytes went out and the IUT's were read as
            # planned, so the divergence is the IUT's; judging it again by a model fed
            # other timings would only explain real defects away (steal time the
            # hypervisor took may still have kept the IUT from its CPU: then the failure
            # is reproduced before it stands)
            return confirm(run, res, outcome)
        if run.iut_stall > run.max_stall or run.starved:
            res.notes.append(f"the IUT's process was kept from a CPU by the machine's load for up to "
                             f"{1000 * run.iut_stall:.1f} ms at a time, and for {1000 * run.iut_wait:.1f} ms in all "
                             f"within {1000 * run.shortest:.0f} ms (its shortest timer), in this attempt (its "
                             "run-queue wait)")
        differences = []
        first_at = None     # where the model fed the line as it was first does otherwise
        # the machine stalled the harness or the IUT noticeably: the IUT process may have
        # been stalled that long (a third timeline); a stall under a character time is noise
        stall = worst + run.look if worst > run.char else 0.0
        timelines = [(False, 0.0), (True, 0.0)] + ([(False, stall)] if stall else [])
        # The tester, as the IUT's conforming partner, replied later than its model had it
        # due: the wire shows the reply within the IUT's timer, but an IUT that starts its
        # timer as its process hands over a block, and writes the block some milliseconds
        # later, whole, had less of that timer left than the wire shows. The harness's
        # lateness and the IUT's add up; the IUT's is not seen, so it is taken as up to its
        # shortest timer (a longer one shows as its process's stall).
        partner = run.partner_late + run.shortest if run.partner_late > tol.stimulus else 0.0
        if partner > stall:
            timelines.append((False, partner))
        for late, stalled in timelines:
            rep = model(late, stalled)
            if not late and not stalled:
                first_at = rep.at
            problems = _status_by_model(v, run, rep.codes) if rep.agrees and res.divergence is None else []
            differences.append(f"{rep.timeline} timeline: " + (rep.why or "STATUS: " + "; ".join(problems)))
            if rep.agrees and not problems:
                whose = ("the IUT's process, kept from a CPU by the machine's load" if run.iut_stall > run.max_stall
                         else "the harness")
                how = (f"up to {1000 * stalled:.1f} ms later than they went out (the tester's reply as the "
                       f"IUT's partner went out {1000 * run.partner_late:.1f} ms later than its model had it "
                       "due, and an IUT that writes a block whole may have started its timer up to its shortest "
                       "timer before the block reached the line)" if stalled and stalled == partner else
                       f"as late as a process stalled for up to {1000 * stalled:.1f} ms (the longest stall "
                       f"measured in this attempt, of {whose}, plus the harness's look period) may have taken "
                       "them, with as many of its own bytes out as a stalled IUT may have had" if stalled else
                       "as late after the IUT's bytes as they may have reached it (the harness read an IUT byte "
                       "late and timed its reply from that read)" if late else
                       "when they really went out (the IUT had acted before the tester's reply reached it)")
                res.notes.append(f"failed attempt: {res.message}")
                res.verdict = R.ERROR
                res.message = ("harness timing fault: the reference model, fed the tester's bytes " + how +
                               ", does what the IUT did; the divergence is the harness's timing, not the IUT's")
                return "timing"
        res.notes.append("the reference model fed the line as it was does not do what the IUT did, however "
                         "late the tester's bytes reached it (" + "; ".join(differences) + ")")
        known = [t for t in (first_at, None if res.divergence is None else res.divergence.time) if t is not None]
        if run.partner_due is not None and known and min(known) >= run.rel(run.partner_due):
            # The tester, as the IUT's partner, sent a reply later than the harness keeps
            # its timing to, and everything the IUT did otherwise than the case and the
            # model came after that reply was due. Once a reply comes late, the IUT may
            # have run out a timer it would have met (its own lag is not on the wire), and
            # what follows from that, its repetitions crossing the partner's late replies,
            # no model can replay. The attempt is void (run again; an error if it keeps
            # happening), never a fail; a divergence before the late reply still fails.
            res.notes.append(f"failed attempt: {res.message}")
            res.verdict = R.ERROR
            res.message = (f"harness timing fault: the tester's reply as the IUT's partner, due at "
                           f"{1000 * run.rel(run.partner_due):.1f} ms, went out later than the harness keeps its "
                           f"timing to ({1000 * tol.stimulus:.1f} ms; up to {1000 * run.partner_late:.1f} ms late in "
                           f"this attempt), and the IUT's divergence came after it (at {1000 * min(known):.1f} ms): "
                           "it cannot be told from the harness's timing")
            return "timing"
    except Exception as exc:   # the re-judgement must never cost the verdict
        res.notes.append(f"re-judging by the model failed: {type(exc).__name__}: {exc}")
    if max(run.max_stall, run.iut_stall) >= run.shortest or run.starved:
        # The machine stalled the harness (and so, as likely, the IUT process) or the IUT
        # process itself as long as the IUT's shortest timer in this attempt: the IUT may
        # then have missed a whole timer window, and what it saw on the line cannot be
        # known well enough to blame it. (A shorter stall is covered by the stalled
        # timeline above.)
        res.notes.append(f"failed attempt: {res.message}")
        res.verdict = R.ERROR
        if run.max_stall >= run.shortest:
            what = f"the harness was stalled for up to {1000 * run.max_stall:.1f} ms"
        elif run.iut_stall >= run.shortest:
            what = f"the IUT's process was kept from a CPU for up to {1000 * run.iut_stall:.1f} ms"
        else:
            what = (f"the IUT's process was kept from a CPU for {1000 * run.iut_wait:.1f} ms in all within "
                    f"{1000 * run.shortest:.0f} ms, its shortest timer")
        res.message = (f"harness timing fault: {what} in this attempt (the harness keeps its own timing to "
                       f"{1000 * tol.stimulus:.1f} ms); the IUT's divergence cannot be told from the machine's "
                       "load")
        return "timing"
    return confirm(run, res, outcome)


def confirm(run: CaseRun, res: R.CaseResult, outcome: str) -> str:
    """A failure that stands in an attempt the machine disturbed (the harness or the IUT's
    process stalled or kept waiting for a CPU, a partner reply late, the hypervisor
    taking a CPU away) is reproduced before it is reported: "disturbed", which runs the
    case once more. A defect fails again; a divergence that the machine caused, in a way
    no measurement here could pin on it, does not come back. It never turns a failure
    into a pass or an error by itself."""
    if outcome != "ok" or res.verdict != R.FAIL:
        return outcome
    what = run.disturbance()
    if what is None:
        return outcome
    res.notes.append(f"the machine disturbed this failed attempt: {what}")
    return "disturbed"


def _status_by_model(v: Vector, run: CaseRun, model_codes: list[int]) -> list[str]:
    """STATUS judged by the model's own events on the same line: everything the IUT
    raised is allowed by the case or raised by the model, and every event the case
    requires is raised unless the model does not raise it either."""
    if run.status_codes is None:
        return []
    spec = v.expected.iut_status
    seen, model = set(run.status_codes), set(model_codes)
    problems = ["missing " + " or ".join(f"16#{c:04X}" for c in sorted(g))
                for g in spec.required if not g & seen and g & model]
    extra = sorted(c for c in seen if c not in spec.allowed and c not in model)
    if extra:
        problems.append("unexpected " + ", ".join(f"16#{c:04X}" for c in extra))
    return problems
