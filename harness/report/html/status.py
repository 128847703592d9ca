"""STATUS codes in the HTML report: each 16#XXXX annotated with its short name from the CP
341 catalogue (:mod:`ptpcert.status`), expected and observed codes marked where they are
missing or unexpected, and the legend of every code the page used.

Part of :mod:`ptpcert.report.html`: a case's section and the page call it, handing a set in
which the codes used are collected for the legend.
"""

from __future__ import annotations

import re

from ptpcert.report.html.markup import esc
from ptpcert.status import UnknownStatus, lookup

#: a STATUS code in a text
CODE_RE = re.compile(r"16#[0-9A-Fa-f]{4}")


def status_name(code: str) -> tuple[str, str]:
    """(short name, catalogue text) of a STATUS code; tolerant of unknown ones."""
    try:
        ev = lookup(code)
    except (UnknownStatus, ValueError):
        return "not in the catalogue", ""
    return ev.short, ev.text


def _norm(code: str) -> str:
    return "16#" + code[3:].upper() if code[:3] == "16#" else code.upper()


def status_html(code: str, used: set[str], cls: str = "") -> str:
    """A STATUS code with its short name (the catalogue's text as its tooltip), added to
    ``used``; ``cls``: "missing" or "unexpected"."""
    short, text = status_name(code)
    used.add(_norm(code))
    c = f' class="st {cls}"' if cls else ' class="st"'
    return f'<span{c} title="{esc(text)}"><code>{esc(code)}</code> {esc(short)}</span>'


def codes_in_text(text: str, used: set[str]) -> str:
    """Escape ``text``, annotating each 16#XXXX with its short name."""
    out, pos = [], 0
    for m in CODE_RE.finditer(text):
        out.append(esc(text[pos:m.start()]))
        code = "16#" + m.group(0)[3:].upper()
        short, full = status_name(code)
        used.add(code)
        out.append(f'<span class="st" title="{esc(full)}"><code>{esc(code)}</code> <i>{esc(short)}</i></span>')
        pos = m.end()
    out.append(esc(text[pos:]))
    return "".join(out)


def legend(used: set[str]) -> str:
    """The section that explains every STATUS code in ``used`` ("" when there is none)."""
    if not used:
        return ""
    rows = []
    for code in sorted(used):
        try:
            ev = lookup(code)
            rows.append(f"<tr><td><code>{esc(ev.notation)}</code></td><td>{esc(ev.short)}</td>"
                        f"<td>{esc(ev.event_class)} {esc(ev.class_name)}</td><td>{esc(ev.text)}</td>"
                        f"<td>{esc(ev.reference)}</td></tr>")
        except (UnknownStatus, ValueError):
            rows.append(f"<tr><td><code>{esc(code)}</code></td><td colspan=4>not in the CP 341 catalogue</td></tr>")
    return ('<section id="status"><h2>STATUS events in this report</h2><table><tr><th>code</th><th>event</th>'
            '<th>class</th><th>text</th><th>source</th></tr>' + "".join(rows) + "</table></section>")

