"""A transcript as the diagram draws it: consecutive bytes of one sender, close in time and
in one step, become one :class:`Arrow`; a BREAK is a :class:`LineBreak`. An arrow's label
names its bytes as the procedure's view says (:class:`~ptpcert.view.ReportView`);
a burst too long to show whole (a flood) is shown by its head and tail.

Part of :mod:`ptpcert.report.html`: the sequence diagram and the text transcript of a case
read the events from here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable, Iterable, Mapping

from ptpcert import results as R
from ptpcert.report.html.markup import hexstr
from ptpcert.view import NEUTRAL, ReportView

#: Consecutive bytes of one sender closer than this (and in the same step) make one arrow.
GROUP_GAP = 0.020
#: Labels longer than this many tokens are abbreviated.
MAX_TOKENS = 12


@dataclass
class Arrow:
    """Consecutive bytes of one sender, close in time, in one step: one arrow."""

    dir: str                      # "tester" | "iut"
    kind: str                     # "byte" | "char_error"
    t0: float
    t1: float
    data: bytearray = field(default_factory=bytearray)
    step: int = 0
    times: list[float] = field(default_factory=list)
    lt0: float = 0.0              # times for the layout: events that start together are
    lt1: float = 0.0              # drawn one below the other


@dataclass
class LineBreak:
    """A BREAK on the line: its sender, when it began and how long it was held."""

    dir: str
    t0: float
    duration: float
    step: int = 0
    lt0: float = 0.0
    lt1: float = 0.0

    @property
    def t1(self) -> float:
        return self.t0 + self.duration


def group_events(transcript: Iterable[dict[str, Any]], gap: float = GROUP_GAP,
                 view: ReportView | None = None) -> list[Arrow | LineBreak]:
    """Bytes, character errors and BREAKs of a transcript (runs, or one entry per byte),
    grouped into arrows, in time order; a burst whose last byte starts anew
    (:attr:`ReportView.cut_last`) as two."""
    out: list[Arrow | LineBreak] = []
    cur: Arrow | None = None
    for t, d, kind, value, step in R.wire_runs(transcript):
        if kind == "break":
            out.append(LineBreak(d, t, value, step))
            cur = None
            continue
        if (cur is not None and cur.dir == d and cur.kind == kind and cur.step == step
                and t - cur.t1 < gap):
            cur.data += value
            cur.times += [t] * len(value)
            cur.t1 = t
        else:
            cur = Arrow(d, kind, t, t, bytearray(value), step, [t] * len(value))
            out.append(cur)
    out = _cut_last(out, (view or NEUTRAL).cut_last)
    last = -math.inf
    for ev in out:   # layout times: strictly increasing starts
        ev.lt0 = max(ev.t0, last + 2e-6)
        ev.lt1 = max(ev.t1 + (ev.lt0 - ev.t0), ev.lt0)
        last = ev.lt0
    return out


def _cut_last(events: list, cut_last: Callable[[bytes, bytes], bool]) -> list:
    """Each burst whose last byte starts anew (``cut_last`` of its bytes and the other
    side's answer right after it) as two arrows: the last byte drawn as its own."""
    out: list = []
    for i, e in enumerate(events):
        nxt = events[i + 1] if i + 1 < len(events) else None
        if (isinstance(e, Arrow) and e.kind == "byte" and len(e.data) > 1 and isinstance(nxt, Arrow)
                and nxt.dir != e.dir and cut_last(bytes(e.data), bytes(nxt.data))):
            head = Arrow(e.dir, e.kind, e.t0, e.times[-2], e.data[:-1], e.step, e.times[:-1])
            tail = Arrow(e.dir, e.kind, e.times[-1], e.times[-1], e.data[-1:], e.step, e.times[-1:])
            out += [head, tail]
        else:
            out.append(e)
    return out


def arrow_label(a: Arrow, view: ReportView | None = None, params: Mapping[str, Any] | None = None) -> str:
    """The label of an arrow: its bytes as the view names them (``params``: the case's, for
    the view and the parity); a character error as a parity or framing error."""
    params = params or {}
    tokens = (view or NEUTRAL).tokens
    parity = str(params.get("parity", "even"))
    if a.kind == "char_error":
        what = "parity error" if parity != "none" else "framing error"
        if len(a.data) > 1:
            what = what.replace("error", "errors")
        return what + " " + _abbrev_tokens([f"{b:02X}" for b in a.data], len(a.data))
    if len(a.data) > BURST_SHOWN:   # no block is this long (a flood): name only its ends
        head, tail = tokens(bytes(a.data[:32]), params), tokens(bytes(a.data[-32:]), params)
        return " ".join(head[:6]) + " … " + " ".join(tail[-5:]) + f" ({len(a.data)} bytes)"
    return _abbrev_tokens(tokens(bytes(a.data), params), len(a.data))


def _abbrev_tokens(toks: list[str], nbytes: int) -> str:
    if len(toks) <= MAX_TOKENS:
        return " ".join(toks)
    return " ".join(toks[:6]) + " … " + " ".join(toks[-5:]) + f" ({nbytes} bytes)"


#: a burst longer than this (longer than any block with its framing) is shown by its head
#: and tail in the text transcript; the results (JSON) keep every byte
BURST_SHOWN = 4096


def burst_hex(data: bytes, limit: int = BURST_SHOWN) -> str:
    """A burst in hex for the text transcript; one longer than ``limit`` by its head and tail."""
    if len(data) <= limit:
        return hexstr(data)
    head, tail = data[: limit // 2], data[-limit // 8:]
    return (f"{hexstr(head)} … {len(data) - len(head) - len(tail)} bytes not shown (see the JSON results) … "
            f"{hexstr(tail)}")

