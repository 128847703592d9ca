"""Whether the analysis of a run's capture agrees with the run's recorded verdicts: the one
judgement that ``ptpcert verify`` makes of an evidence bundle and that the tests of the
capture's timing make of a whole suite.

The capture of a run (``run --pcap``) marks where each case began ("case ID (verdict) ...");
the analysis (:func:`~ptpcert.analysis.results.analyze`, both seats judged, seat b switched on
at each case as the run's transport did) places every exchange in the case it falls in. Then:

* a case recorded as failed by the IUT (fail, xfail: :data:`IUT_FAILED`) must show a rule the
  IUT's seat (b) broke, unless the run's failure is one the line does not carry (a STATUS
  event the IUT reported on its standard error) or the run recorded its divergence and the
  line analysis, with its own tolerances, does not confirm it (*unconfirmed*: reported, not
  held against the bundle; a failure without its divergence stands);
* a case recorded as passed (:data:`IUT_PASSED`) must not show the IUT's first deviation in
  the case breaking a rule the case checks (non-strict and informational verdicts grade a
  deviation the suite accepts: the line may show it);
* the tester's seat (a) may deviate only inside the cases (its deviations are the cases'
  deliberate stimuli), never between them;
* every case the results say ran has its mark in the capture, with the same verdict, and the
  capture marks no case the results lack.

One disagreement is known and not yet settled (issue 25, item 12): a pipe (``exec:``) delivers
a station's whole block at once, and a tester's interruption (BREAK, NAK, a timeout) reaches
the IUT after its block was complete; the run sees that, the line analysis takes the block as
still going out at the line's pace and finds the IUT's reaction wrong. A disagreement of that
shape - a case recorded as passed, a capture whose times were taken over a pipe, the IUT's
finding preceded in its case by a deviation of the tester, and the IUT's bytes there coming
faster than the line carries them (a block written whole) - is *unsettled*: reported, not held
against the bundle. Any other shape, and every disagreement of the marks, stands.
"""

from __future__ import annotations

import bisect
import re
from dataclasses import dataclass, field

from ptpcert import results as R
from ptpcert.analysis.results import Analysis

#: verdicts that say the IUT broke the case's rule / followed it
IUT_FAILED = (R.FAIL, R.XFAIL)
IUT_PASSED = (R.PASS, R.XPASS)
#: verdicts of a deviation the suite accepts (another defensible reading, a point where the
#: manual states no wire reaction): the line may show it or not, and neither contradicts them
IUT_ACCEPTED = (R.NON_STRICT, R.INFORMATIONAL)
#: a run's failure that the line does not carry: the STATUS the IUT reported
_STATUS_ONLY = "STATUS: "
_MARK = re.compile(r"^case (\S+) \(([a-z\-]+)\)")


@dataclass(frozen=True)
class Apart:
    """A case where the analysis and the recorded verdict part."""

    case: str
    recorded: str
    found: str          # what the line shows: "a rule the IUT broke: ..." or "no rule the IUT broke"
    unsettled: bool = False

    def text(self) -> str:
        return f"{self.case}: recorded {self.recorded}, the capture shows {self.found}"


@dataclass
class Agreement:
    """The outcome: the cases that agree, those apart (standing or unsettled), and what the
    marks of the capture and the results disagree on."""

    agree: list[str] = field(default_factory=list)
    apart: list[Apart] = field(default_factory=list)
    #: cases the results say ran (they have a transcript) that the capture does not mark
    unmarked: list[str] = field(default_factory=list)
    #: cases the capture marks that the results do not hold
    unknown: list[str] = field(default_factory=list)
    #: (case, the capture's verdict, the results' verdict) where they differ
    verdicts: list[tuple[str, str, str]] = field(default_factory=list)
    #: the tester's deviations outside every case
    tester: list[str] = field(default_factory=list)
    #: cases whose recorded failure the line does not carry (STATUS only): not judged
    status_only: list[str] = field(default_factory=list)
    #: cases recorded as failed with their divergence that the line analysis does not confirm
    unconfirmed: list[str] = field(default_factory=list)

    @property
    def standing(self) -> list[Apart]:
        return [a for a in self.apart if not a.unsettled]

    @property
    def unsettled(self) -> list[Apart]:
        return [a for a in self.apart if a.unsettled]

    @property
    def holds(self) -> bool:
        return not (self.standing or self.unmarked or self.unknown or self.verdicts or self.tester)


def case_marks(an: Analysis) -> list[tuple[float, str, str]]:
    """The cases the capture marks, in time order: (when it began, id, the verdict the mark gives)."""
    out = []
    for m in sorted(an.capture.marks, key=lambda m: m.t):
        hit = _MARK.match(m.text)
        if hit:
            out.append((m.t, hit.group(1), hit.group(2)))
    return out


def _in_case(starts: list[float], ids: list[str], t: float) -> str | None:
    i = bisect.bisect_right(starts, t + 1e-9) - 1
    return ids[i] if i >= 0 else None


def _whole_block(an: Analysis, t: float) -> bool:
    """Whether the IUT's bytes around ``t`` came faster than the line carries them (closer
    than half a character time): a block written whole into a pipe."""
    timing = an.capture.timing
    if timing is None or not timing.char_time:
        return False
    times = [ch.t for ch in an.capture.chunks if ch.seat == "b" and ch.data]
    i = bisect.bisect_left(times, t - 1e-7)
    near = [b - a for a, b in zip(times[max(i - 1, 0):i + 1], times[max(i, 1):i + 2])]
    return bool(near) and min(near) < timing.char_time / 2


def _bears_on(f, c: R.CaseResult) -> bool:
    """Whether the IUT's finding ``f`` contradicts a pass of case ``c``: it is not of the IUT's
    start-up (which every case of an IUT restarted per case sees, and only the start-up cases
    check), and it breaks one of the rules the case checks where both name rules."""
    if f.kind == "start-up":
        return False
    if c.rules and f.rules:
        return bool(set(f.rules) & set(c.rules))
    return True


def agreement(run: R.RunResult, an: Analysis) -> Agreement:
    """Judge the agreement of ``run`` (the recorded results) with ``an`` (its capture
    analysed, both seats judged). A case checks its own rules: where a case cites rule ids,
    only a finding of one of them contradicts a recorded pass (a broken variant that breaks
    one rule everywhere fails the cases of that rule, not every case, and so does the run),
    and only the IUT's first deviation in the case (the later ones may be its consequences)."""
    out = Agreement()
    marked = case_marks(an)
    marks = {cid: v for _, cid, v in marked}
    starts, ids = [t for t, _, _ in marked], [cid for _, cid, _ in marked]
    recorded = {c.id: c for c in run.cases}
    for c in run.cases:
        if c.transcript and c.id not in marks:
            out.unmarked.append(c.id)
    for cid, verdict in marks.items():
        if cid not in recorded:
            out.unknown.append(cid)
        elif recorded[cid].verdict != verdict:
            out.verdicts.append((cid, verdict, recorded[cid].verdict))
    piped = an.capture.timing is not None and an.capture.timing.transport == "pipe"
    iut: dict[str, list] = {}           # case id -> the IUT's failing findings
    tester: dict[str, list] = {}        # case id -> the tester's failing findings
    for f in an.findings:
        if f.grade != R.FAIL:
            continue
        cid = _in_case(starts, ids, f.t)
        if cid is None:
            if f.seat == "a":
                out.tester.append(f"{f.t:.6f} s: {f.message}")
            continue
        (iut if f.seat == "b" else tester).setdefault(cid, []).append(f)
    for c in run.cases:
        if c.id not in marks:
            continue
        found = sorted(iut.get(c.id, []), key=lambda f: f.t)
        if c.verdict in IUT_FAILED:
            if found:
                out.agree.append(c.id)
            elif c.message.startswith(_STATUS_ONLY):
                out.status_only.append(c.id)
            elif c.divergence is not None:
                # the run recorded where the IUT diverged, and the line analysis, which judges
                # only what the line shows with its own tolerances, does not confirm it
                out.unconfirmed.append(c.id)
            else:
                out.apart.append(Apart(c.id, c.verdict, "no rule the IUT broke"))
        elif c.verdict in IUT_PASSED:
            # the first of the IUT's deviations in the case: after it the model follows the IUT
            # again from where it stands, and what it finds then may be its consequence
            own = [f for f in found[:1] if _bears_on(f, c)]
            if not own:
                out.agree.append(c.id)
                continue
            f = own[0]
            tester_first = any(x.t <= f.t for x in tester.get(c.id, []))
            out.apart.append(Apart(c.id, c.verdict, f"a rule the IUT broke at {f.t:.6f} s: {f.message}",
                                   unsettled=piped and tester_first and _whole_block(an, f.t)))
    return out


def judge_run_capture(cap, profile, *, tolerance_ms: float = 50.0, url: str | None = None) -> Analysis:
    """Analyse the capture of a run against ``profile`` (the IUT's, seat b; seat a its
    conforming partner, as ``ptpcert analyze`` takes it), both seats judged, seat b switched
    on at each case where the run's transport restarted the IUT, with the timing resolution
    the capture says its times were taken with."""
    from ptpcert.analysis.results import analyze

    proc = profile.procedure
    params = {"b": profile.params, "a": proc.tester_params(profile.params)}
    kit = proc.analyzer(params["a"], params["b"], apps={"b": "echo" if profile.echo else "none", "a": "none"},
                        late_ms=tolerance_ms)
    if kit is None:
        raise ValueError(f"line analysis of {proc.title} is not available")
    resolution = cap.timing.resolution if cap.timing is not None else 0.0
    restart = {"b"} if url and url.startswith(("exec:", "pty:", "sim:")) else set()
    return analyze(cap, kit, judge="ab", resolution=resolution, restart_at_cases=restart)
