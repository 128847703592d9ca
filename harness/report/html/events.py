"""A transcript as the diagram draws it: consecutive bytes of one sender, close in time and
in one step, become one :class:`Arrow`; a BREAK is a :class:`LineBreak`. An arrow's label
names its bytes; a burst too long to show whole (a flood) is shown by its head and tail.

Part of :mod:`ptpcert.report.html`: the sequence diagram and the text transcript of a case
read the events from here.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from typing import Any, Iterable

from ptpcert import results as R
from ptpcert.report.html.markup import hexstr

CONTROL = {0x02: "STX", 0x03: "ETX", 0x10: "DLE", 0x15: "NAK"}
STX, ETX, DLE = 0x02, 0x03, 0x10

#: Consecutive bytes of one sender closer than this (and in the same step) make one arrow.
GROUP_GAP = 0.020
#: Labels longer than this many tokens are abbreviated.
MAX_TOKENS = 12

_LONE_HEX_RE = re.compile(r"(?<![\w.#-])([0-9A-F]{2})(?![\w.])(?!\s*m?s\b)")


def name_controls(text: str) -> str:
    """'received 02' -> 'received 02 (STX)': name a control character that stands alone
    (not inside a run of hex bytes)."""
    def sub(m: re.Match) -> str:
        a, b = m.start(), m.end()
        before, after = text[max(0, a - 3):a], text[b:b + 3]
        if re.fullmatch(r"[0-9A-F]{2} ", before) or re.fullmatch(r" [0-9A-F]{2}", after):
            return m.group(0)
        name = CONTROL.get(int(m.group(1), 16))
        return f"{m.group(1)} ({name})" if name else m.group(0)
    return _LONE_HEX_RE.sub(sub, text)


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
    dir: str
    t0: float
    duration: float
    step: int = 0
    lt0: float = 0.0
    lt1: float = 0.0

    @property
    def t1(self) -> float:
        return self.t0 + self.duration


def group_events(transcript: Iterable[dict[str, Any]], gap: float = GROUP_GAP) -> list[Arrow | LineBreak]:
    """Bytes, character errors and BREAKs of a transcript (runs, or one entry per byte),
    grouped into arrows, in time order."""
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
    out = _split_trailing_stx(out)
    last = -math.inf
    for ev in out:   # layout times: strictly increasing starts
        ev.lt0 = max(ev.t0, last + 2e-6)
        ev.lt1 = max(ev.t1 + (ev.lt0 - ev.t0), ev.lt0)
        last = ev.lt0
    return out


def _split_trailing_stx(events: list) -> list:
    """A burst that ends in 02 answered by the other side's DLE (or NAK, or its own STX) is
    a block cut short followed by a new STX: draw the STX as its own arrow."""
    out: list = []
    for i, e in enumerate(events):
        nxt = events[i + 1] if i + 1 < len(events) else None
        if (isinstance(e, Arrow) and e.kind == "byte" and len(e.data) > 1 and e.data[-1] == STX
                and e.data[-2] != DLE and isinstance(nxt, Arrow) and nxt.dir != e.dir
                and nxt.data[0] in (DLE, 0x15, STX)):
            head = Arrow(e.dir, e.kind, e.t0, e.times[-2], e.data[:-1], e.step, e.times[:-1])
            tail = Arrow(e.dir, e.kind, e.times[-1], e.times[-1], bytearray([STX]), e.step, e.times[-1:])
            out += [head, tail]
        else:
            out.append(e)
    return out


def tokens(data: bytes, procedure: str = "3964R") -> list[str]:
    """Name the control characters of a burst: a control character that starts a unit (the
    burst, or what follows a block's end) by name, DLE ETX at a block's end, the BCC after
    it in 3964R; data (doubled DLEs included) in hex."""
    out: list[str] = []
    i, n = 0, len(data)
    unit_start = True
    while i < n:
        b = data[i]
        nxt = data[i + 1] if i + 1 < n else None
        if b == DLE and nxt == DLE:
            out += ["10", "10"]
            i += 2
            unit_start = False
            continue
        if b == DLE and nxt == ETX:
            out += ["DLE", "ETX"]
            i += 2
            if procedure == "3964R" and i < n:
                out.append(f"BCC={data[i]:02X}")
                i += 1
            unit_start = True
            continue
        if unit_start and b in CONTROL and (n == 1 or i > 0):
            out.append(CONTROL[b])
            i += 1
            continue
        out.append(f"{b:02X}")
        unit_start = False
        i += 1
    return out


def arrow_label(a: Arrow, procedure: str = "3964R", parity: str = "even") -> str:
    if a.kind == "char_error":
        what = "parity error" if parity != "none" else "framing error"
        if len(a.data) > 1:
            what = what.replace("error", "errors")
        return what + " " + _abbrev_tokens([f"{b:02X}" for b in a.data], len(a.data))
    if len(a.data) > BURST_SHOWN:   # no block is this long (a flood): name only its ends
        head, tail = tokens(bytes(a.data[:32]), procedure), tokens(bytes(a.data[-32:]), procedure)
        return " ".join(head[:6]) + " … " + " ".join(tail[-5:]) + f" ({len(a.data)} bytes)"
    return _abbrev_tokens(tokens(bytes(a.data), procedure), len(a.data))


def _abbrev_tokens(toks: list[str], nbytes: int) -> str:
    if len(toks) <= MAX_TOKENS:
        return " ".join(toks)
    return " ".join(toks[:6]) + " … " + " ".join(toks[-5:]) + f" ({nbytes} bytes)"


#: a burst longer than this (longer than any block with its framing) is shown by its head
#: and tail in the text transcript; the results (JSON) keep every byte
BURST_SHOWN = 4096


def burst_hex(data: bytes, limit: int = BURST_SHOWN) -> str:
    if len(data) <= limit:
        return hexstr(data)
    head, tail = data[: limit // 2], data[-limit // 8:]
    return (f"{hexstr(head)} … {len(data) - len(head) - len(tail)} bytes not shown (see the JSON results) … "
            f"{hexstr(tail)}")

