"""The HTML report's page: one self-contained file (inline CSS, inline SVG, a little inline
JavaScript for the verdict filter; readable without it) rendered from the results object.

It lays out the header (the run and the IUT's profile), the verdict filter, the distinct
deviations, the summary by manual section, the traceability section
(:mod:`~ptpcert.report.html.rules`), each case's section failures first
(:mod:`~ptpcert.report.html.case`) and the legend of the STATUS codes used. The style
sheet and the script are files of the package (``assets/``), inlined as they are.

Part of :mod:`ptpcert.report.html`, whose face re-exports :func:`render` and
:func:`write_html`.
"""

from __future__ import annotations

from functools import cache
from importlib import resources
from typing import Any

from ptpcert import results as R
from ptpcert.report.html.case import FAILURES, case_section
from ptpcert.report.html.markup import abbreviate_hex, badge, esc
from ptpcert.report.html.rules import traceability_section
from ptpcert.report.html.status import legend
from ptpcert.report.text import anchor
from ptpcert.view import NEUTRAL, ReportView

@cache
def asset(name: str) -> str:
    """A file of ``assets/`` (the style sheet, the script) as text."""
    return resources.files("ptpcert.report.html").joinpath("assets", name).read_text("utf-8")


def _profile_rows(p: dict[str, Any], view: ReportView) -> list[tuple[str, str]]:
    """The IUT's profile as (key, value) rows in the profile file's words (the view knows
    which keys are character codes); the expected failures with their reasons."""
    if not p:
        return [("profile", "—")]
    rows = view.settings(p)
    xf = p.get("expected_failures") or {}
    if xf:
        rows.append(("expected failures", "; ".join(f"{k}: {v}" for k, v in xf.items())))
    return rows


def _table(rows: list[tuple[str, str]], raw: bool = False) -> str:
    return "<table>" + "".join(
        f"<tr><th>{esc(k)}</th><td>{v if raw else esc(v)}</td></tr>" for k, v in rows) + "</table>"


def _header(run: R.RunResult, view: ReportView) -> str:
    counts = run.counts()
    n = len(run.cases)
    verdict = run.verdict
    heading = "ptpcert conformance report" + (f" — {run.procedure}" if run.procedure else "")
    out = [f'<header><h1>{esc(heading)}</h1>'
           f'<p>overall verdict {badge(verdict, "overall")} &nbsp; {n} cases: '
           + " ".join(f'{badge(v)} {counts[v]}' for v in R.VERDICTS if counts.get(v)) + "</p>"]
    if run.interrupted:
        out.append('<p class="banner">The run was <b>interrupted</b>; cases not reached are marked not-run.</p>')
    info = [("tool", f"ptpcert {run.tool_version}"),
            ("started", run.started or "—"), ("finished", run.finished or "—"),
            ("wall time", f"{run.wall_time:.1f} s"),
            ("interrupted", "yes" if run.interrupted else "no"),
            ("IUT", run.iut or "—"),
            *((f"IUT {k}", v) for k, v in run.iut_identity.items()),
            ("profile file", run.profile_path or "—"),
            ("vector set", run.vector_set or "—"),
            ("vector set hash", run.vector_set_hash or "—")]
    if run.harness_scheduling:
        info.append(("harness scheduling", run.harness_scheduling))
    if run.shard:
        info.append(("shard", f"{run.shard} (ptpcert run --shard: a part of the selection)"))
    if run.merged_from:
        info.append(("merged from", ", ".join(run.merged_from)))
    out.append('<div class="cols"><div><h2>Run</h2>' + _table(info) + "</div>"
               '<div><h2>IUT profile</h2>' + _table(_profile_rows(run.profile, view)) + "</div></div></header>")
    return "".join(out)


def _filter(run: R.RunResult) -> str:
    counts = run.counts()
    boxes = "".join(f'<label><input type="checkbox" data-v="{esc(v)}" checked> {badge(v)} {counts[v]}</label>'
                    for v in R.VERDICTS if counts.get(v))
    return (f'<nav id="filter" hidden><b>show:</b> {boxes}'
            f'<button type="button" id="expand-all">expand all</button>'
            f'<button type="button" id="collapse-all">collapse all</button></nav>')


def _groups(run: R.RunResult, view: ReportView) -> list[str]:
    """The case groups of the run, in the order the view gives them."""
    present = []
    for c in run.cases:
        if c.group not in present:
            present.append(c.group)
    return view.order(present)


def _deviations(run: R.RunResult) -> str:
    """The distinct deviations (failed cases grouped by root cause), before the cases."""
    groups = run.deviations()
    if not groups:
        return ""
    items = []
    for i, g in enumerate(groups, 1):
        links = ", ".join(f'<a href="#{esc(anchor(cid))}"><code>{esc(cid)}</code></a>' for cid in g.get("cases", []))
        items.append(f'<li id="deviation-{i}"><b>{esc(g["description"])}</b><br><small>{links}</small></li>')
    return (f'<section id="deviations"><h2>Distinct deviations ({len(groups)})</h2>'
            '<p>Failed cases grouped by root cause: cases whose first divergence has the same signature '
            '(what the tester last sent, what was due, what the IUT sent instead) form one group.</p>'
            f'<ol>{"".join(items)}</ol></section>')


def _summary(run: R.RunResult, view: ReportView) -> str:
    out = [_deviations(run), '<section id="summary"><h2>Summary by manual section</h2>']
    for g in _groups(run, view):
        cs = [c for c in run.cases if c.group == g]
        counts: dict[str, int] = {}
        for c in cs:
            counts[c.verdict] = counts.get(c.verdict, 0) + 1
        badges = " ".join(f"{badge(v)} {counts[v]}" for v in R.VERDICTS if counts.get(v))
        rows = "".join(
            f'<tr data-verdict="{esc(c.verdict)}"><td>{badge(c.verdict)}</td>'
            f'<td><a href="#{esc(anchor(c.id))}"><code>{esc(c.id)}</code></a></td><td>{esc(c.title)}</td></tr>'
            for c in sorted(cs, key=_order_key))
        out.append(f'<details class="group" data-group="{esc(g)}">'
                   f'<summary><span class="gname">{esc(g or "(no group)")}</span> {len(cs)} cases: {badges}</summary>'
                   f"<table>{rows}</table></details>")
    bad = [c for c in ordered_cases(run) if c.verdict in FAILURES]
    if bad:
        out.append('<h3>Not passed</h3><table class="bad">' + "".join(
            f'<tr data-verdict="{esc(c.verdict)}"><td>{badge(c.verdict)}</td>'
            f'<td><a href="#{esc(anchor(c.id))}"><code>{esc(c.id)}</code></a></td>'
            f'<td>{esc(abbreviate_hex(c.message)[:300])}</td></tr>' for c in bad) + "</table>")
    out.append("</section>")
    return "".join(out)


def _order_key(c: R.CaseResult) -> int:
    return FAILURES.index(c.verdict) if c.verdict in FAILURES else len(FAILURES)


def ordered_cases(run: R.RunResult) -> list[R.CaseResult]:
    """Failures first (fail, then xpass, then error, each in run order), then the rest in
    run order."""
    bad = sorted((c for c in run.cases if c.verdict in FAILURES), key=_order_key)
    return bad + [c for c in run.cases if c.verdict not in FAILURES]



def render(run: R.RunResult, view: ReportView | None = None) -> str:
    """The report as one HTML string; ``view``: how the run's procedure names its bytes and
    orders its groups (:meth:`ptpcert.procedure.Procedure.report_view`; neutral without)."""
    view = view or NEUTRAL
    used: set[str] = set()
    cases = "".join(case_section(c, used, view) for c in ordered_cases(run))
    title = f"ptpcert report: {run.iut or 'IUT'} — {run.verdict}"
    return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
            f"<title>{esc(title)}</title><style>\n{asset('report.css')}</style></head><body>"
            + _header(run, view) + _filter(run) + _summary(run, view) + traceability_section(run)
            + '<section id="cases"><h2>Cases (failures first)</h2>' + cases + "</section>"
            + legend(used)
            + f"<footer>ptpcert {esc(run.tool_version)} · results schema {esc(run.schema)} · "
              "one self-contained file: no external resources</footer>"
            + f"<script>\n{asset('report.js')}</script></body></html>\n")


def write_html(result: R.RunResult, path, view: ReportView | None = None) -> None:
    """Write the report of ``result`` to ``path`` (whole or not at all); ``view`` as for
    :func:`render`."""
    R.write_atomic(path, render(result, view))
