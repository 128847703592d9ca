"""Grading a case's result beyond the steps: what the IUT reported (STATUS events, the
procedure's other reports, in virtual time the model's deliveries and jobs), the grade of
another reading of an open point of the manual that explains a failure, and an expected
failure the profile lists. Also the frame a divergence falls in, marked for the reports.

The case runner (:mod:`ptpcert.runner.attempts`) calls these on each attempt's result and
on the case's final one; they read the attempt's run (:class:`ptpcert.runner.steps.CaseRun`)
and never wait on the line.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

from ptpcert import results as R
from ptpcert.model.events import status_text
from ptpcert.model.hexbytes import hexstr
from ptpcert.profile import Profile
from ptpcert.scenario import Step, Vector
from ptpcert.transport.base import STATUS, Transport

from .options import RunOptions
from .steps import CaseRun


def judge_events(opts: RunOptions, v: Vector, tr: Transport, res: R.CaseResult, run: CaseRun) -> None:
    """What the IUT reported in this attempt against what the case expects (also for a
    failed attempt: the report shows what the IUT raised); keeps the STATUS codes on the
    run for the re-judgement."""
    if STATUS in tr.capabilities and opts.check_status:
        codes = [c for _, c in tr.status_reports()]
        run.status_codes = codes
        res.observed_status = [status_text(c) for c in codes]
        res.status_checked = True
        problems = v.expected.iut_status.judge(codes)
        if problems and res.verdict != R.FAIL:
            res.verdict = R.FAIL
            res.message = "STATUS: " + "; ".join(problems) + (f" (reported: {', '.join(res.observed_status) or 'none'})")
        soft = v.expected.iut_status.soft_missing(codes)
        if soft and res.verdict in R.GRADE_ORDER:
            res.verdict = R.worse_grade(res.verdict, R.INFORMATIONAL)
            res.message = "; ".join(x for x in (res.message, "STATUS: the IUT took another reading of an open "
                                                "point: " + ", ".join(soft) + " not reported (reported: "
                                                + (", ".join(res.observed_status) or "none") + ")") if x)
        # what the procedure's IUT reports beyond STATUS (e.g. RK 512 request results)
        lines = [text for _, text in tr.report_lines()]
        more = v.proc.judge_reports(v, lines)
        if more and res.verdict != R.FAIL:
            res.verdict = R.FAIL
            res.message = "reported: " + "; ".join(more)
    if opts.check_model_events and hasattr(tr, "delivered") and res.verdict != R.FAIL:
        want = list(v.expected.delivered)
        have = tr.delivered()
        if have != want:
            res.verdict = R.FAIL
            res.message = ("delivered " + (", ".join(hexstr(x) for x in have) or "nothing")
                           + "; the vector says " + (", ".join(hexstr(x) for x in want) or "nothing"))
        elif v.expected.sent and tr.sent()[: len(v.expected.sent)] != list(v.expected.sent):
            res.verdict = R.FAIL
            res.message = "completed send jobs differ from the vector's 'sent'"


def grade_by_readings(runner: Any, v: Vector, res: R.CaseResult) -> None:
    """A failed case tagged with open points of the manual: when the model with the
    other reading of one of them (through the one ``sim:`` builder, in virtual time)
    diverges from the case as the IUT did (the same step and the same bytes, or the
    same complaint about what the IUT reported), the IUT takes that reading, and the
    case gets the grade the procedure gives it. ``runner`` is the case's runner: one of
    its kind, with its profile and options, runs the case against that model."""
    from ptpcert.transport import sim_factory
    proc = v.proc
    profile = runner.profile
    app = "echo" if (profile is None or profile.echo) else "none"
    if app not in proc.apps():
        app = proc.apps()[0]
    opts = replace(runner.opts, grade_readings=False, rejudge=False)
    for name in v.readings:
        grade = proc.reading_grade(name)
        other = proc.other_reading(name) if grade is not None else None
        if other is None:
            continue
        alt = type(runner)(sim_factory(proc, {"app": app}, readings=other), profile, opts).run_case(v)
        d, mine = alt.divergence, res.divergence
        if mine is None:   # a divergence in what the IUT reported, not on the wire
            same = d is None and alt.verdict == R.FAIL and alt.message == res.message
        else:
            same = d is not None and d.step == mine.step and d.observed == mine.observed
        if not same:
            continue
        res.notes.append(f"failed: {res.message}")
        res.verdict = grade
        res.message = (f"the IUT takes the other reading of open point {name} (docs/readings.md), which "
                       f"the procedure grades {grade}: the model with that reading does the same "
                       f"({res.message})")
        return


def expected_failure(profile: Profile | None, v: Vector, res: R.CaseResult) -> None:
    """A case the profile lists as an expected failure: a fail is an xfail, a pass an
    xpass."""
    xf = (profile.expected_failures if profile else {}).get(v.id)
    if xf is not None:
        if res.verdict == R.FAIL:
            res.verdict, res.message = R.XFAIL, f"expected failure ({xf}): {res.message}"
        elif res.verdict in (R.PASS, R.NON_STRICT, R.INFORMATIONAL):
            res.verdict, res.message = R.XPASS, f"listed as an expected failure ({xf}) but passed"


def mark_divergence_frame(proc: Any, res: R.CaseResult, log: list[dict], steps: tuple[Step, ...],
                          params: Any) -> None:
    """Mark the frame the first divergence falls in (``diverged``) and, where the step that
    diverged expected bytes from the IUT, name the frame expected in its place
    (``expected``): the procedure decodes the transcript with those bytes put in for what
    came at that step."""
    f = R.divergence_frame(res)
    if f is None:
        return
    f["diverged"] = True
    div = res.divergence
    if f.get("dir") != "iut" or not 0 <= div.step < len(steps):
        return
    step = steps[div.step]
    if step.kind != "expect" or not step.data:
        return
    before = [e for e in log if e.get("dir") in ("tester", "iut") and e.get("step", -1) < div.step]
    # the expected bytes take the times of the bytes that came instead (so that a decoder
    # that splits by pauses splits alike), those beyond them follow at once
    came = [float(e["t"]) for e in log if e.get("dir") == "iut" and e.get("step") == div.step
            and e.get("kind") in ("byte", "char_error") and "t" in e]
    t = max([float(e.get("t", 0.0)) for e in before] + came + [float(f["t0"])])
    synth = before + [{"t": came[k] if k < len(came) else round(t + (k - len(came) + 1) * 1e-6, 7),
                       "dir": "iut", "kind": "byte", "byte": b, "step": div.step}
                      for k, b in enumerate(step.data)]
    try:
        frames = proc.describe_frames(synth, params)
    except Exception:  # a decoder's fault must not cost the verdict
        return
    same = [g for g in frames if g.get("dir") == "iut" and abs(float(g["t0"]) - float(f["t0"])) < 1e-6]
    if same:
        f["expected"] = same[0]["label"]
