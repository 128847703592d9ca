"""The certificate of an evidence bundle: one printable, self-contained page (no script, no
external resource) with the IUT's identity, the verdict, the counts per group, the rules of
the procedure's catalogue covered (checked, untestable, not run for this profile), the open
points of the manual with the readings the cases applied, the tool's identity, the date, and
the bundle's digest (which ``ptpcert verify`` checks against the manifest).

It reads the results object, the rules catalogue and the facts handed in.
"""

from __future__ import annotations

import re
from typing import Any

from ptpcert import results as R
from ptpcert.report.html.markup import esc
from ptpcert.report.html.rules import NOT_APPLICABLE, NOT_CHECKED, UNTESTABLE, catalogue_for, rule_verdicts

_CSS = """body{font:14px/1.4 system-ui,sans-serif;max-width:48em;margin:2em auto;color:#111}
h1{font-size:1.6em;margin:0 0 .2em}h2{font-size:1.1em;margin:1.2em 0 .3em;border-bottom:1px solid #999}
table{border-collapse:collapse;width:100%}td,th{border:1px solid #bbb;padding:.2em .4em;text-align:left;
vertical-align:top}th{background:#eee}.verdict{font-size:1.4em;font-weight:bold;padding:.2em .6em;display:inline-block}
.pass{background:#d4f4d4}.fail{background:#f8d0d0}.error{background:#f8ecc0}code{font-size:.95em;word-break:break-all}
@media print{body{margin:0;max-width:none;font-size:11px}h2{break-after:avoid}table{break-inside:auto}}"""

#: the groups of verdicts shown per group of cases
_COLUMNS = (R.PASS, R.NON_STRICT, R.INFORMATIONAL, R.FAIL, R.XFAIL, R.XPASS, R.ERROR, R.UNSUPPORTED, R.NOT_RUN)


def _point_order(point: str) -> tuple:
    """An open point's id in its natural order: A2 before A10, MB-01 before MB-02."""
    return tuple(int(p) if p.isdigit() else p for p in re.split(r"(\d+)", point))


def _rows(pairs) -> str:
    return "".join(f"<tr><th>{esc(k)}</th><td>{v}</td></tr>" for k, v in pairs)


def rule_counts(run: R.RunResult) -> tuple[str, dict[str, int]]:
    """The catalogue's title and how many of its rules were checked (a case ran on them),
    are untestable, and were not run for this profile (deselected, or not for its settings)."""
    cat = catalogue_for(run)
    if cat is None:
        return "", {}
    out = {"checked": 0, "untestable": 0, "not run for this profile": 0}
    for verdict, _ in rule_verdicts(run, cat).values():
        if verdict == UNTESTABLE:
            out["untestable"] += 1
        elif verdict in (NOT_CHECKED, NOT_APPLICABLE, R.NOT_RUN, R.UNSUPPORTED):
            out["not run for this profile"] += 1
        else:
            out["checked"] += 1
    return f"{cat.title} ({cat.manual})", out


def render_certificate(run: R.RunResult, *, tool: dict[str, Any], digest: str) -> str:
    verdict = run.verdict
    ident = run.iut_identity or {}
    who = " ".join(ident.get(k, "") for k in ("vendor", "product", "version") if ident.get(k)) or run.iut or "IUT"
    identity = [(k, esc(v)) for k, v in ident.items()] or [("identity", "not declared ([iut.identity] of the profile)")]
    identity += [("procedure", esc(run.procedure or "—")), ("IUT reached as", f"<code>{esc(run.iut)}</code>"),
                 ("profile", esc(run.profile_path or "—"))]
    groups: dict[str, dict[str, int]] = {}
    for c in run.cases:
        g = groups.setdefault(c.group, {})
        g[c.verdict] = g.get(c.verdict, 0) + 1
    cols = [v for v in _COLUMNS if any(g.get(v) for g in groups.values())]
    table = ("<table><tr><th>group</th>" + "".join(f"<th>{esc(v)}</th>" for v in cols) + "<th>total</th></tr>"
             + "".join(f"<tr><td>{esc(g)}</td>" + "".join(f"<td>{n.get(v, 0)}</td>" for v in cols)
                       + f"<td>{sum(n.values())}</td></tr>" for g, n in groups.items())
             + "</table>")
    title, rules = rule_counts(run)
    rules_html = (f"<p>{esc(title)}: " + ", ".join(f"{n} {esc(k)}" for k, n in rules.items()) + "</p>"
                  if rules else "<p>no rules catalogue for this procedure</p>")
    cat = catalogue_for(run)
    applied = sorted({r for c in run.cases for r in c.readings}, key=_point_order)
    points = ", ".join(sorted(cat.readings, key=_point_order)) if cat is not None and cat.readings else "none"
    readings = (f"<p>open points of the manual: {esc(points)}</p><p>readings the cases applied: "
                + (esc("; ".join(applied)) if applied else "none") + "</p>")
    devs = run.deviations()
    dev_html = ("<ol>" + "".join(f"<li>{esc(g['description'])}</li>" for g in devs) + "</ol>") if devs else ""
    cats = "; ".join(f"{c['title']} ({c['rules']} rules, {c['digest'][:16]})" for c in tool.get("rules_catalogues", []))
    tool_rows = [("ptpcert", esc(tool.get("ptpcert", run.tool_version))),
                 ("Python", esc(f"{tool.get('implementation', '')} {tool.get('python', '')}".strip())),
                 ("platform", esc(tool.get("platform", ""))),
                 ("suite", f"{tool.get('cases', len(run.cases))} cases, digest <code>{esc(tool.get('suite_digest', ''))}</code>"),
                 ("rules catalogues", esc(cats or "none")),
                 ("run", esc(f"{run.started} to {run.finished}" + (" (interrupted)" if run.interrupted else "")))]
    n = run.counts()
    return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            f"<title>{esc(f'ptpcert certificate: {who} — {verdict}')}</title><style>{_CSS}</style></head><body>"
            f"<h1>Conformance certificate</h1><p>{esc(who)} — {esc(run.procedure)}</p>"
            f'<p>overall verdict <span class="verdict {esc(verdict)}">{esc(verdict.upper())}</span> '
            f"{len(run.cases)} cases: " + ", ".join(f"{n[v]} {esc(v)}" for v in R.VERDICTS if n.get(v)) + "</p>"
            + "<h2>Implementation under test</h2><table>" + _rows(identity) + "</table>"
            + "<h2>Cases per group</h2>" + table
            + ("<h2>Distinct deviations</h2>" + dev_html if dev_html else "")
            + "<h2>Rules covered</h2>" + rules_html
            + "<h2>Open points and readings</h2>" + readings
            + "<h2>Tool</h2><table>" + _rows(tool_rows) + "</table>"
            + f"<h2>Bundle</h2><p>bundle digest (SHA-256 of the manifest's lines but this page's): "
              f'<code id="bundle-digest">{esc(digest)}</code></p><p>Check it with '
              "<code>ptpcert verify BUNDLE.zip</code>.</p></body></html>\n")
