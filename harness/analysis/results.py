"""Whole captures: judge one, and turn the outcome into run results.

:func:`analyze` feeds a whole capture, marks included, to a
:class:`~ptpcert.analysis.line.LineAnalysis` and returns an :class:`Analysis`.
:func:`to_results` makes that a :class:`~ptpcert.results.RunResult` for ``ptpcert report`` and
the JUnit/HTML views: each exchange is a case (pass, or informational), and so is each finding
(fail or informational), with the exchange's bytes as its transcript, times in seconds since
the exchange began (:func:`exchange_cases` does it for one exchange).
:func:`summary_line` is an exchange's console line, which ``ptpcert analyze`` and ``ptpcert
monitor`` print as each exchange stands.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Iterable

from ptpcert import capture as C
from ptpcert import results as R
from ptpcert.analysis.interface import OTHER, SEATS, Finding, ProcedureAnalyzer, strip_section
from ptpcert.analysis.line import Exchange, LineAnalysis


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
        c = R.CaseResult(cid, f"seat {f.seat}: {label}", f.reference, strip_section(f.rule),
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
