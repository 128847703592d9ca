"""One case's section of the HTML report: its rule, verdict, STATUS expected and observed,
the first divergence, the sequence diagram, the expanded steps and the whole transcript as
text (one line per burst, window, mark and frame), and the IUT's stderr.

Part of :mod:`ptpcert.report.html`: the page (:mod:`~ptpcert.report.html.page`) puts the
sections in order; the diagram is :mod:`~ptpcert.report.html.diagram`.
"""

from __future__ import annotations

from typing import Any

from ptpcert import results as R
from ptpcert.report.html.diagram import sequence_svg
from ptpcert.report.html.events import LineBreak, burst_hex, group_events
from ptpcert.report.html.frames import drawable_frames
from ptpcert.report.html.markup import abbreviate_hex, badge, esc, is_num, ms
from ptpcert.report.html.rules import rule_links
from ptpcert.report.html.status import CODE_RE, codes_in_text, status_html
from ptpcert.report.text import anchor, step_text
from ptpcert.view import NEUTRAL, ReportView

#: Verdicts listed first in the case list, their cases shown open.
FAILURES = (R.FAIL, R.XPASS, R.ERROR)


def _steps_table(c: R.CaseResult) -> str:
    """The expanded steps as a table, the divergence's step marked."""
    if not c.steps:
        return ""
    div_step = c.divergence.step if c.divergence is not None else None
    rows = []
    for i, s in enumerate(c.steps):
        kind = str(s.get("kind", ""))
        rest = {k: v for k, v in s.items() if k not in ("kind", "data", kind, "note")}
        what = str(s.get(kind, s.get("data", "")))
        what = abbreviate_hex(what)
        # as a vector writes a step: a flag alone where it is set, numbers and words as they are
        detail = ", ".join(k if v is True else f"{k} = {str(v).lower()}" if isinstance(v, bool) else f"{k} {v}"
                           for k, v in rest.items())
        cls = ' class="div-step"' if i == div_step else ""
        rows.append(f"<tr{cls}><td>{i + 1}</td><td>{esc(kind)}</td><td>{esc(what)}</td>"
                    f"<td>{esc(detail)}</td><td>{esc(s.get('note', ''))}</td></tr>")
    return ('<details><summary>steps</summary><table class="steps"><tr><th>#</th><th>kind</th>'
            '<th>bytes / duration</th><th>timing</th><th>note</th></tr>' + "".join(rows) + "</table></details>")


def transcript_section(c: R.CaseResult, events: list | None = None, view: ReportView | None = None) -> str:
    """The whole transcript, one line per burst, window or mark (compact: full bytes, no
    line per byte); ``events``: its :func:`group_events` (by ``view``), where at hand."""
    lines = []
    items: list[tuple[float, int, str]] = []
    for e in group_events(c.transcript, view=view) if events is None else events:
        if isinstance(e, LineBreak):
            items.append((e.t0, 0, f"{ms(e.t0):>10} ms  {e.dir:<6} BREAK held {e.duration * 1000:.1f} ms  (step {e.step + 1})"))
        else:
            what = "char-error " if e.kind == "char_error" else ""
            items.append((e.t0, 0, f"{ms(e.t0):>10} ms  {e.dir:<6} {what}{burst_hex(bytes(e.data))}"
                                   f"  ({len(e.data)} byte{'s' if len(e.data) != 1 else ''}, step {e.step + 1})"))
    for e in c.transcript:
        if e.get("kind") == "dropped" and "t" in e:
            items.append((float(e["t"]), 1, f"{ms(float(e['t'])):>10} ms  {R.dropped_note(e)}"))
        elif e.get("kind") == "window" and "t0" in e:
            items.append((float(e["t0"]), 1, f"{ms(float(e['t0'])):>10} ms  window step {int(e.get('step', 0)) + 1}: "
                                             f"{e.get('label', '')} until {ms(float(e['t1']))} ms"))
        elif e.get("kind") == "start" and "t" in e:
            items.append((float(e["t"]), 1, f"{ms(float(e['t'])):>10} ms  the steps start"))
    for f in drawable_frames(c):   # each frame on a line of its own, before the bytes it spans
        items.append((f["t0"], -1, _frame_line(f)))
    items.sort(key=lambda x: (x[0], x[1]))
    lines = [x[2] for x in items]
    if not lines:
        return ""
    return "<details><summary>transcript</summary><pre>" + esc("\n".join(lines)) + "</pre></details>"


def _frame_line(f: dict[str, Any]) -> str:
    """A frame as one line of the text transcript: "▸ frame IUT  21.771–26.354 ms: label
    [ETX at ..; CDT ..–.. ms]"."""
    who = "tester" if f["dir"] == "tester" else "iut"
    mark = "✗" if f["diverged"] else "▸"
    line = f"{ms(f['t0']):>10} ms  {who:<6} {mark} frame {ms(f['t0'])}–{ms(f['t1'])} ms: {f['label']}"
    extra = []
    for m in f.get("marks") or []:
        if isinstance(m, dict) and is_num(m.get("t")):
            extra.append(f"{m.get('name', '?')} at {ms(float(m['t']))} ms")
    for w in f.get("windows") or []:
        if isinstance(w, dict) and is_num(w.get("t0")) and is_num(w.get("t1")):
            extra.append(f"{w.get('name', '?')} {ms(float(w['t0']))}–{ms(float(w['t1']))} ms")
    if extra:
        line += "  [" + "; ".join(extra) + "]"
    if f["diverged"] and f.get("expected") and f.get("expected") != f["label"]:
        line += f"  (expected: {f['expected']})"
    return line


def case_section(c: R.CaseResult, used: set[str], view: ReportView | None = None) -> str:
    """The case's section (open when it failed), its bytes named as ``view`` says; the
    STATUS codes it shows are added to ``used``."""
    view = view or NEUTRAL
    a = anchor(c.id)
    failing = c.verdict in FAILURES
    rows: list[tuple[str, str]] = []
    rows.append(("manual reference", codes_in_text(c.reference, used)))
    rows.append(("rule", codes_in_text(c.rule, used)))
    rows.append(("verdict", badge(c.verdict) + (f" {esc(abbreviate_hex(c.message))}" if c.message else "")))
    rows.append(("IUT role", esc(c.iut_role)))
    # STATUS
    exp = codes_in_text(c.expected_status or "none", used)
    groups = c.expected_status_codes or []
    observed = list(c.observed_status or [])
    obs_set = {o.upper() for o in observed}
    if groups:
        parts = []
        for g in groups:
            alts = " or ".join(status_html(code, used, "" if not c.status_checked or code.upper() in obs_set
                                                     else "missing") for code in g)
            parts.append(alts)
        exp += "<br>required: " + "; ".join(parts)
    rows.append(("STATUS expected at the IUT", exp))
    allowed = {code.upper() for g in groups for code in g} | {m.upper() for m in CODE_RE.findall(c.expected_status or "")}
    if c.status_checked:
        obs = " ".join(status_html(o, used, "" if o.upper() in allowed else "unexpected") for o in observed) or "none"
    else:
        obs = (" ".join(status_html(o, used) for o in observed) + " " if observed else "") + \
            "<i>not checked (the IUT does not report STATUS, or the check was off)</i>"
    rows.append(("STATUS observed", obs))
    rows.append(("a CP 341 in the tester's seat raises", codes_in_text(c.tester_status or "none", used)))
    if c.rules:
        rows.append(("rules checked", rule_links(c.rules)))
    if c.readings:
        rows.append(("open points (readings)", esc(", ".join(c.readings))))
    if c.device:
        rows.append(("device", esc(c.device)))
    rows.append(("attempts", esc(c.attempts)))
    dur = f"{c.duration:.3f} s wall"
    if c.case_time:
        dur += f", {c.case_time * 1000:.1f} ms case time"
    rows.append(("duration", esc(dur)))
    if c.source:
        rows.append(("source", f"<code>{esc(c.source)}</code>"))
    body = [f"<dl>{''.join(f'<dt>{k}</dt><dd>{v}</dd>' for k, v in rows)}</dl>"]
    if c.notes:
        body.append("<b>notes</b>" + "".join(f"<pre>{esc(n)}</pre>" for n in c.notes))
    if c.divergence is not None:
        d = c.divergence
        win = (f"; the window that applied: [{ms(float(d.window[0]))}, {ms(float(d.window[1]))}] ms"
               if d.window else "")
        body.append(f'<div class="divbox"><b>first divergence</b> at {step_text(d.step)}{ms(d.time)} ms{esc(win)}:'
                    f"<br>expected {esc(view.words(abbreviate_hex(d.expected), c.params))}"
                    f"<br>observed {esc(view.words(abbreviate_hex(d.observed), c.params))}"
                    + (f"<br>{esc(where)}" if (where := R.divergence_frame_text(c)) else "") + "</div>")
    events = group_events(c.transcript, view=view)
    svg = sequence_svg(c, events, view)
    if svg:
        body.append(f'<div class="diagram">{svg}</div>')
    else:
        body.append("<p><i>no transcript (the case did not reach the line)</i></p>")
    body.append(_steps_table(c))
    body.append(transcript_section(c, events))
    if c.stderr_tail:
        body.append("<b>IUT stderr (tail)</b><pre>" + esc(c.stderr_tail[-2000:]) + "</pre>")
    return (f'<section class="case c-{esc(c.verdict)}" id="{esc(a)}" data-verdict="{esc(c.verdict)}">'
            f'<details{" open" if failing else ""}><summary>{badge(c.verdict)} <code>{esc(c.id)}</code> '
            f'<span class="title">{esc(c.title)}</span> <span class="ref">[{esc(c.reference)}]</span></summary>'
            + "".join(body) + "</details></section>")
