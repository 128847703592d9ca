"""The HTML report's traceability section: every rule of the procedure's catalogue with this
run's verdict (the worst verdict of the cases that cite it), the cases, and the rules that
cannot be checked on the line with the reason; then the manual's open points with the
reading the reference model takes and how the cases grade the others.

It reads only the results object (each case carries the ids of the rules it checks) and the
rules catalogue (:mod:`ptpcert.rules`); the page (:mod:`ptpcert.report.html.page`) calls
:func:`traceability_section`.
"""

from __future__ import annotations

import re

from ptpcert import results as R
from ptpcert.registry import by_id
from ptpcert.report.html.markup import esc
from ptpcert.report.text import anchor
from ptpcert.rules import Catalogue, catalogues, for_rule

#: worst first: the verdict a rule gets from the cases that cite it
_WORST = (R.FAIL, R.XPASS, R.ERROR, R.NON_STRICT, R.INFORMATIONAL, R.PASS, R.XFAIL, R.UNSUPPORTED, R.NOT_RUN)
NOT_CHECKED = "not run"
UNTESTABLE = "untestable"
NOT_APPLICABLE = "does not apply"


def rule_anchor(rule_id: str) -> str:
    """The HTML anchor of a rule's row in the traceability section."""
    return "rule-" + "".join(c if c.isalnum() else "-" for c in rule_id)


def rule_links(rule_ids: list[str]) -> str:
    """A case's rule ids as links to their rows of the traceability section (an id of no
    catalogue stays plain text)."""
    return ", ".join(f'<a href="#{esc(rule_anchor(r))}"><code>{esc(r)}</code></a>' if for_rule(r) is not None
                     else f"<code>{esc(r)}</code>" for r in rule_ids)


def _natural(name: str) -> tuple:
    """A sort key that puts A2 before A10 and AMB-02 before N1 (open points' names)."""
    return tuple(int(x) if x.isdigit() else x for x in re.split(r"(\d+)", name))


def _badge(verdict: str) -> str:
    cls = verdict if verdict in R.VERDICTS else "not-run"
    return f'<span class="v v-{esc(cls)}">{esc(verdict)}</span>'


def catalogue_for(run: R.RunResult) -> Catalogue | None:
    """The catalogue whose rules the run's cases cite (or, when none cites any, the one of the
    run's procedure)."""
    cited = {r for c in run.cases for r in c.rules}
    for cat in catalogues():
        if any(r.startswith(cat.prefix + ".") for r in cited):
            return cat
    for cat in catalogues():
        if run.procedure and cat.title == run.procedure:
            return cat
    return None


def rule_verdicts(run: R.RunResult, catalogue: Catalogue) -> dict[str, tuple[str, list[R.CaseResult]]]:
    """Each rule's verdict in this run and the cases that cite it: the worst verdict of those
    cases; "untestable"; "does not apply" (to the profile's procedure, priority or frame); or
    "not run" (no case of this run cites it)."""
    by_rule: dict[str, list[R.CaseResult]] = {r.id: [] for r in catalogue}
    for c in run.cases:
        for rid in c.rules:
            if rid in by_rule:
                by_rule[rid].append(c)
    setting = by_id(catalogue.procedure).setting_from_profile(run.profile or {}, catalogue.dimensions)
    out = {}
    for rule in catalogue:
        cases = by_rule[rule.id]
        if not rule.testable:
            out[rule.id] = (UNTESTABLE, cases)
        elif not rule.applies_to(setting) and all(c.verdict in (R.UNSUPPORTED, R.NOT_RUN) for c in cases):
            out[rule.id] = (NOT_APPLICABLE, cases)
        elif not cases:
            out[rule.id] = (NOT_CHECKED, cases)
        else:
            out[rule.id] = (min((c.verdict for c in cases), key=lambda v: _WORST.index(v) if v in _WORST else 99),
                            cases)
    return out


def traceability_section(run: R.RunResult) -> str:
    """The section as HTML ("" when the run's procedure has no rules catalogue)."""
    cat = catalogue_for(run)
    if cat is None:
        return ""
    verdicts = rule_verdicts(run, cat)
    counts: dict[str, int] = {}
    for verdict, _ in verdicts.values():
        counts[verdict] = counts.get(verdict, 0) + 1
    order = list(_WORST) + [NOT_CHECKED, NOT_APPLICABLE, UNTESTABLE]
    summary = " ".join(f"{_badge(v)} {counts[v]}" for v in order if counts.get(v))
    rows = []
    for rule in cat:
        verdict, cases = verdicts[rule.id]
        scope = f" <i>({esc(rule.scope())})</i>" if rule.scope() else ""
        if verdict == UNTESTABLE:
            checked = f"<i>untestable: {esc(rule.untestable)}</i>"
        elif verdict == NOT_APPLICABLE:
            checked = f"<i>does not apply to this IUT's settings (only {esc(rule.scope())})</i>"
        elif not cases:
            checked = "<i>no case of this run cites it (deselected, or not for this IUT's settings)</i>"
        else:
            checked = "<br>".join(
                f'{_badge(c.verdict)} <a href="#{esc(anchor(c.id))}"><code>{esc(c.id)}</code></a> {esc(c.title)}'
                for c in sorted(cases, key=lambda c: (_WORST.index(c.verdict) if c.verdict in _WORST else 99, c.id)))
        rows.append(f'<tr id="{esc(rule_anchor(rule.id))}" data-verdict="{esc(verdict)}"><td>{_badge(verdict)}</td>'
                    f'<td><code>{esc(rule.id)}</code>{scope}</td><td>{esc(rule.text)}<br><small>{esc(rule.ref)}'
                    + (f"; open points {esc(', '.join(rule.readings))}" if rule.readings else "")
                    + f"</small></td><td>{checked}</td></tr>")
    readings = "".join(
        f"<tr><td><code>{esc(a.id)}</code></td><td>{esc(a.question)}</td><td>{esc(a.model)}</td>"
        f"<td>{esc(a.grade)}</td></tr>"
        for a in sorted(cat.readings.values(), key=lambda a: _natural(a.id)))
    return (f'<section id="traceability"><h2>Traceability: the manual\'s rules in this run</h2>'
            f"<p>{len(cat)} rules of {esc(cat.title)} ({esc(cat.manual)}): {summary}. A rule's verdict is the "
            "worst verdict of the cases that check it; untestable rules cannot be seen on the line.</p>"
            '<details class="group"><summary>the rules, with the cases that check them</summary>'
            "<table><tr><th>verdict</th><th>rule</th><th>what the manual says</th><th>checked by</th></tr>"
            + "".join(rows) + "</table></details>"
            '<details class="group"><summary>the manual\'s open points and how the cases grade them '
            "(docs/readings.md has the full text)</summary>"
            "<table><tr><th>point</th><th>question</th><th>the reference model's reading</th>"
            "<th>another defensible reading is graded</th></tr>" + readings + "</table></details></section>")
