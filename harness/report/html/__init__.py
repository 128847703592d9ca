"""The HTML report: one self-contained file (inline CSS, inline SVG, a little inline
JavaScript for the verdict filter; readable without it) rendered from the results object.

Per case it shows the rule, the verdict, the STATUS events expected and observed, and a
sequence diagram of the transcript drawn the way the manual draws its figures: the tester's
lane on the left, the IUT's on the right, time flowing down, one arrow per burst of bytes
with the control characters named, the timer windows the steps watched as bars beside the
IUT's lane, BREAK and character errors marked, and the first divergence in red.

The SVG carries stable classes and data attributes for tests and tools:
``<g class="arrow" data-dir="tester|iut" data-t=".." data-t1=".." data-n="bytes" data-step="..">``
with one ``<text class="label">``; ``<g class="line-condition" data-kind="break|char_error">``;
``<g class="window" data-t0 data-t1 data-step>``; ``<g class="divergence" data-t data-step>``;
``<g class="gap" data-ms>`` where the time axis is compressed; ``<g class="elided">`` where
arrows were left out to keep a long case compact.
"""

from __future__ import annotations

import html as _html
import math
import re
from dataclasses import dataclass, field
from typing import Any, Iterable

from ptpcert import results as R
from ptpcert.model.hexbytes import hexstr
from ptpcert.report import anchor, step_text
from ptpcert.report.html.rules import traceability_section

# ------------------------------------------------------------------ constants
#: The manual's sections, in its order; any other group present follows, sorted.
GROUP_ORDER = ("start-up", "idle", "receive", "send", "release", "repetition", "conflict",
               "break", "character-error", "timing", "regression")
#: Verdicts listed first in the case list.
FAILURES = (R.FAIL, R.XPASS, R.ERROR)
CONTROL = {0x02: "STX", 0x03: "ETX", 0x10: "DLE", 0x15: "NAK"}
STX, ETX, DLE = 0x02, 0x03, 0x10

#: Consecutive bytes of one sender closer than this (and in the same step) make one arrow.
GROUP_GAP = 0.020
#: Labels longer than this many tokens are abbreviated.
MAX_TOKENS = 12

# Diagram geometry (px).
W = 940
AXIS_X = 66          # the time axis; timestamps are right-aligned left of it
TX = 150             # tester lane
IX = 590             # IUT lane
WIN_X = IX + 18      # first window column (right of the IUT's frame brackets)
WIN_COL = 11         # window column pitch
WIN_COLS = 4
TOP = 46             # first row below the lane headers
LABEL_H = 15         # room for an arrow's label above it
SLOPE = 8            # how much lower an arrow ends than it starts (at least)
LIN_MS = 25.0        # gaps up to this are drawn to linear scale...
PX_PER_MS = 2.4      # ...at this scale
ELIDED_H = 40        # the band that stands for arrows left out
MAX_H = 1500         # the most a diagram may take
DIV_WRAP = 62        # characters per line of the divergence text
FRAME_H = 15         # room for a frame's label above the label of its first arrow
FRAME_CHARS = 64     # a frame label longer than this is shortened (the tooltip has it whole)
MAX_FRAME_H = 300    # the most a diagram may grow beyond MAX_H for its frames' labels

_CODE_RE = re.compile(r"16#[0-9A-Fa-f]{4}")
_HEXRUN_RE = re.compile(r"(?:\b[0-9A-F]{2}\b ){16,}\b[0-9A-F]{2}\b")


def esc(s: Any) -> str:
    return _html.escape(str(s), quote=True)


def ms(t: float) -> str:
    v = t * 1000.0
    return f"{v:.1f}" if abs(v) >= 100000 else f"{v:.3f}"


def ms_short(t: float) -> str:
    v = t * 1000.0
    return f"{v:.0f}" if abs(v) >= 100 else f"{v:.1f}"


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


def abbreviate_hex(text: str, keep_head: int = 8, keep_tail: int = 4) -> str:
    """Shorten long runs of hex bytes in a message ("41 41 ... 41 (1027 bytes)")."""
    def sub(m: re.Match) -> str:
        toks = m.group(0).split()
        return " ".join(toks[:keep_head]) + " … " + " ".join(toks[-keep_tail:]) + f" ({len(toks)} bytes)"
    return _HEXRUN_RE.sub(sub, text)


# ------------------------------------------------------------------ transcript -> events
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


# ------------------------------------------------------------------ the time axis
def _dy(dt: float) -> tuple[float, bool]:
    """Height for a gap of ``dt`` seconds, and whether it was compressed."""
    v = max(dt, 0.0) * 1000.0
    if v <= LIN_MS * 1.2:
        return v * PX_PER_MS, False
    return LIN_MS * PX_PER_MS + min(45.0, 11.0 * math.log2(v / LIN_MS)), True


@dataclass
class _Layout:
    keys: list[float]
    ys: list[float]
    gaps: list[tuple[float, float, float]]      # (y0, y1, seconds) of compressed gaps
    elided: list[tuple[float, float, int]]      # (t0, t1, number of events left out)

    def y(self, t: float) -> float:
        k, ys = self.keys, self.ys
        if not k:
            return TOP
        if t <= k[0]:
            return ys[0]
        if t >= k[-1]:
            return ys[-1]
        lo, hi = 0, len(k) - 1
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if k[mid] <= t:
                lo = mid
            else:
                hi = mid
        if k[hi] == k[lo]:
            return ys[lo]
        return ys[lo] + (ys[hi] - ys[lo]) * (t - k[lo]) / (k[hi] - k[lo])


def _r(t: float) -> float:
    return round(t, 7)


def _layout(events: list, extra: list[float], end: float, div_t: float | None, div_h: float,
            elided: list[tuple[float, float, int]], label_h: dict[int, float] | None = None) -> _Layout:
    """Place the key times on the page: linear for short gaps, compressed for long ones,
    with room for every arrow's label (``label_h``: more room above the events, by id,
    that carry a frame's label too) and the divergence text."""
    label_h = label_h or {}
    starts: dict[float, list] = {}
    ends: dict[float, list] = {}
    keys = set(extra)
    keys.add(_r(end))
    for e in events:
        t0, t1 = _r(e.lt0), _r(e.lt1)
        starts.setdefault(t0, []).append(e)
        ends.setdefault(t1, []).append(e)
        keys.update((t0, t1))
    el_bounds = {(_r(a), _r(b)) for a, b, _ in elided}
    for a, b in el_bounds:
        keys.update((a, b))
    if div_t is not None:
        keys.add(_r(div_t))
    # drop keys strictly inside an elided range
    ks = sorted(k for k in keys if not any(a < k < b for a, b in el_bounds))
    ys: list[float] = []
    gaps: list[tuple[float, float, float]] = []
    floor = TOP - LABEL_H + 4.0
    y_start: dict[int, float] = {}
    for i, t in enumerate(ks):
        if i == 0:
            y = TOP + 4.0
            compressed = False
        else:
            if (ks[i - 1], t) in el_bounds:
                dy, compressed = ELIDED_H, False
            else:
                dy, compressed = _dy(t - ks[i - 1])
            y = ys[-1] + dy
        for e in ends.get(t, ()):
            if id(e) in y_start:
                y = max(y, y_start[id(e)] + (12 if isinstance(e, LineBreak) else SLOPE))
        for e in starts.get(t, ()):
            y = max(y, floor + LABEL_H + label_h.get(id(e), 0.0))
        if div_t is not None and _r(div_t) == t:
            y = max(y, floor + 6)
        if i > 0 and compressed:
            gaps.append((ys[-1], y, t - ks[i - 1]))
        ys.append(y)
        for e in starts.get(t, ()):
            y_start[id(e)] = y
            floor = max(floor, y + (22 if isinstance(e, LineBreak) else SLOPE))
        for e in ends.get(t, ()):
            floor = max(floor, y)
        if div_t is not None and _r(div_t) == t:
            floor = max(floor, y + div_h)
    return _Layout(ks, ys, gaps, elided)


# ------------------------------------------------------------------ the diagram
def _wrap(text: str, width: int) -> list[str]:
    words = text.split(" ")
    lines: list[str] = []
    cur = ""
    for w in words:
        while len(w) > width:
            if cur:
                lines.append(cur)
                cur = ""
            lines.append(w[:width])
            w = w[width:]
        if cur and len(cur) + 1 + len(w) > width:
            lines.append(cur)
            cur = w
        else:
            cur = f"{cur} {w}" if cur else w
    if cur:
        lines.append(cur)
    return lines or [""]


def _select(events: list, div_t: float | None, max_events: int) -> tuple[list, list[tuple[float, float, int]]]:
    """Keep the first and last events and those around the divergence; the rest become
    elided ranges."""
    n = len(events)
    if n <= max_events:
        return events, []
    head, tail, around = max_events * 4 // 10, max_events * 3 // 10, max_events * 3 // 20
    keep = set(range(head)) | set(range(n - tail, n))
    if div_t is not None:
        near = min(range(n), key=lambda i: abs(events[i].lt0 - div_t))
        keep |= set(range(max(0, near - around), min(n, near + around + 1)))
    kept, ranges = [], []
    i = 0
    while i < n:
        if i in keep:
            kept.append(events[i])
            i += 1
            continue
        j = i
        while j < n and j not in keep:
            j += 1
        a, b = events[i].lt0, events[j - 1].lt1
        if j < n:
            b = max(events[j - 1].lt0, min(b, events[j].lt0 - 1e-6))
        ranges.append((a, b, j - i))
        i = j
    return kept, ranges


def sequence_svg(c: R.CaseResult, events: list | None = None) -> str:
    """The case's transcript as an SVG sequence diagram ('' when there is no transcript);
    ``events``: its :func:`group_events`, where already at hand."""
    tr = c.transcript or []
    procedure = str(c.params.get("procedure", "3964R"))
    parity = str(c.params.get("parity", "even"))
    all_events = group_events(tr) if events is None else events
    windows = [e for e in tr if e.get("kind") == "window" and "t0" in e and "t1" in e]
    starts = [float(e["t"]) for e in tr if e.get("kind") == "start" and "t" in e]
    div = c.divergence
    if not all_events and not windows and div is None:
        return ""
    frames = _frames(c)
    div_t = float(div.time) if div is not None else None
    div_text = ""
    div_lines: list[str] = []
    if div is not None:
        div_text = (f"✗ {step_text(div.step)}{ms(div.time)} ms: expected "
                    f"{name_controls(abbreviate_hex(div.expected))}; "
                    f"observed {name_controls(abbreviate_hex(div.observed))}")
        div_lines = _wrap(div_text, DIV_WRAP)[:6]
    div_h = 14.0 * len(div_lines) + 18.0

    # where the diagram ends
    ev_end = max([e.lt1 for e in all_events] + [float(w["t0"]) for w in windows] + starts
                 + ([div_t] if div_t is not None else []) + [0.0])
    if c.case_time and c.case_time > 0:
        end = max(float(c.case_time), ev_end)
    else:
        end = max(ev_end, float(windows[-1]["t1"]) if windows else ev_end)
    if div is not None and div.window:
        end = max(end, float(div.window[1]))

    max_events = 60
    while True:
        events, elided = _select(all_events, div_t, max_events)
        wins = [w for w in windows if not any(a < float(w["t0"]) and float(w["t1"]) < b for a, b, _ in elided)]
        extra = [_r(float(w["t0"])) for w in wins] + [_r(min(float(w["t1"]), end)) for w in wins]
        extra += [_r(s) for s in starts]
        if div is not None and div.window:
            extra += [_r(min(float(div.window[0]), end)), _r(min(float(div.window[1]), end))]
        frame_at = _frame_arrows(frames, events)
        label_h = {id(e): FRAME_H for e in frame_at.values()}
        lay = _layout(events, extra, end, div_t, div_h, elided, label_h)
        bottom = (lay.ys[-1] if lay.ys else TOP) + 30
        # the frames' labels take room of their own: up to MAX_FRAME_H more before arrows
        # are left out
        if bottom <= MAX_H + min(MAX_FRAME_H, FRAME_H * len(label_h)) or max_events <= 12:
            break
        max_events = max(12, int(max_events * 0.7))

    y = lay.y
    parts: list[str] = []
    add = parts.append

    # window bars in columns beside the IUT lane, labels in a column to their right
    col_end: list[float] = []
    label_x = WIN_X + WIN_COLS * WIN_COL + 8
    last_label = TOP - 12.0
    win_svg: list[str] = []
    for w in sorted(wins, key=lambda w: (float(w["t0"]), float(w["t1"]))):
        t0, t1 = float(w["t0"]), float(w["t1"])
        clipped = t1 > end + 1e-9
        y0 = y(t0)
        y1 = max(y(min(t1, end)), y0 + 3)
        col = next((k for k, e in enumerate(col_end) if e <= y0), None)
        if col is None:
            if len(col_end) < WIN_COLS:
                col = len(col_end)
                col_end.append(0.0)
            else:
                col = min(range(WIN_COLS), key=lambda k: col_end[k])
        col_end[col] = y1 + 2
        x = WIN_X + col * WIN_COL
        ly = max(y0 + 9, last_label + 12)
        last_label = ly
        label = str(w.get("label", ""))
        full = f"step {int(w.get('step', 0)) + 1}: {label} [{ms(t0)}, {ms(t1)}] ms"
        shown = abbreviate_hex(label, 4, 2)
        if len(shown) > 36:
            shown = shown[:35] + "…"
        shown += f" {ms_short(t0)}–{ms_short(t1)}" + ("…" if clipped else "")
        win_svg.append(
            f'<g class="window" data-t0="{t0:.6f}" data-t1="{t1:.6f}" data-step="{int(w.get("step", 0))}">'
            f'<title>{esc(full)}</title>'
            f'<rect x="{x}" y="{y0:.1f}" width="7" height="{y1 - y0:.1f}"'
            + (' class="clipped"' if clipped else "") + '/>'
            f'<path class="leader" d="M{x + 7} {y0:.1f}L{label_x - 2} {ly - 3:.1f}"/>'
            f'<text x="{label_x}" y="{ly:.1f}">{esc(shown)}</text></g>')

    height = max((lay.ys[-1] if lay.ys else TOP), last_label) + 24
    if div is not None:
        height = max(height, y(div_t) + div_h + 8)
    height = int(math.ceil(height))

    # lanes, axis and headers
    add(f'<text class="lane-h" x="{TX}" y="16">tester (CP 341 seat)</text>')
    add(f'<text class="lane-h" x="{IX}" y="16">IUT</text>')
    add(f'<text class="axis-h" x="{AXIS_X - 4}" y="16">ms</text>')
    add(f'<path class="lane" d="M{TX} 24V{height - 6}M{IX} 24V{height - 6}"/>')
    add(f'<path class="axis" d="M{AXIS_X} 24V{height - 6}"/>')

    # compressed gaps
    for y0, y1, dt in lay.gaps:
        ym = (y0 + y1) / 2
        zig = "".join(f"M{x - 6} {ym - 1:.1f}l12 -5M{x - 6} {ym + 5:.1f}l12 -5" for x in (AXIS_X, TX, IX))
        cut = "".join(f'<rect class="cut" x="{x - 7}" y="{ym - 5:.1f}" width="14" height="8"/>' for x in (AXIS_X, TX, IX))
        add(f'<g class="gap" data-ms="{dt * 1000:.1f}">{cut}<path d="{zig}"/>'
            f'<text x="{AXIS_X - 10}" y="{ym + 4:.1f}">≈ {dt * 1000:.0f} ms</text></g>')

    # elided ranges
    for t0, t1, n in elided:
        y0, y1 = y(t0), y(t1)
        ym = (y0 + y1) / 2
        add(f'<g class="elided" data-t0="{t0:.6f}" data-t1="{t1:.6f}" data-n="{n}">'
            f'<rect x="{TX}" y="{y0 + 4:.1f}" width="{IX - TX}" height="{max(y1 - y0 - 8, 4):.1f}"/>'
            f'<text x="{(TX + IX) // 2}" y="{ym + 4:.1f}">⋮ {n} arrows not drawn ({ms_short(t0)}–{ms_short(t1)} ms; '
            f'see the transcript below)</text></g>')

    # where the steps start
    for s in starts:
        ys_ = y(s)
        add(f'<g class="start" data-t="{s:.6f}"><path d="M{AXIS_X} {ys_:.1f}H{IX}"/>'
            f'<text x="{AXIS_X + 4}" y="{ys_ - 3:.1f}">steps ▾</text></g>')

    add("".join(win_svg))

    # the divergence's window, under the arrows
    if div is not None and div.window:
        w0, w1 = float(div.window[0]), float(div.window[1])
        y0, y1 = y(min(w0, end)), y(min(w1, end))
        add(f'<rect class="div-window" x="{IX + 3}" y="{y0:.1f}" width="9" height="{max(y1 - y0, 3):.1f}">'
            f'<title>{esc(f"the window that applied: [{ms(w0)}, {ms(w1)}] ms")}</title></rect>')

    # frames: a band and a bracket on the sender's side, marks and windows, the label above
    # the label of the frame's first arrow
    add(_frames_svg(frames, frame_at, y, end, elided))

    # arrows and line conditions
    arrows_svg: list[str] = []
    mid = (TX + IX) // 2
    ts_taken: set[float] = set()
    for e in events:
        y0 = y(e.lt0)
        if isinstance(e, LineBreak):
            y1 = max(y(e.lt1), y0 + 12)
            x0 = TX if e.dir == "tester" else IX
            x1 = IX if e.dir == "tester" else TX
            step = 1 if x1 > x0 else -1
            pts = [f"{x0},{y0:.1f}"]
            seg = (abs(x1 - x0)) / 24
            for k in range(1, 24):
                pts.append(f"{x0 + step * seg * k:.0f},{y0 + (5 if k % 2 else -5):.1f}")
            pts.append(f"{x1},{y0:.1f}")
            arrows_svg.append(f'<g class="line-condition" data-kind="break" data-dir="{e.dir}" data-t="{e.t0:.6f}" '
                f'data-step="{e.step}"><title>{esc(f"BREAK from the {e.dir}: {ms(e.t0)} ms, held {e.duration * 1000:.1f} ms")}</title>'
                f'<rect x="{x0 - 4}" y="{y0:.1f}" width="8" height="{y1 - y0:.1f}"/>'
                f'<polyline points="{" ".join(pts)}"/>'
                f'<text class="label" x="{mid}" y="{y0 + 18:.1f}">BREAK ({e.duration * 1000:.1f} ms)</text>'
                f'<text class="ts" x="{AXIS_X - 4}" y="{y0 + 4:.1f}">{ms(e.t0)}</text></g>')
            continue
        y1 = max(y(e.lt1), y0 + SLOPE)
        tester = e.dir == "tester"
        x0, x1 = (TX, IX) if tester else (IX, TX)
        label = arrow_label(e, procedure, parity)
        head = (f"{x1},{y1:.1f} {x1 - 9 if tester else x1 + 9},{y1 - 5:.1f} "
                f"{x1 - 9 if tester else x1 + 9},{y1 + 3:.1f}")
        sender = "tester → IUT" if tester else "IUT → tester"
        data = bytes(e.data)
        tip = (f"{sender}, {len(data)} byte{'s' if len(data) != 1 else ''}, {ms(e.t0)}"
               + (f"–{ms(e.t1)}" if e.t1 > e.t0 else "") + f" ms, step {e.step + 1}: "
               + (hexstr(data) if len(data) <= 48 else hexstr(data[:32]) + " … " + hexstr(data[-12:])))
        attrs = (f'data-dir="{e.dir}" data-t="{e.t0:.6f}" data-t1="{e.t1:.6f}" data-n="{len(data)}" '
                 f'data-step="{e.step}"')
        if div_t is not None and e.t0 - 1e-9 <= div_t <= e.t1 + 1e-9:
            attrs += ' data-diverged="1"'
            ts_taken.add(_r(e.t0))
        body = (f'<title>{esc(tip)}</title>'
                f'<path d="M{x0} {y0:.1f}L{x1} {y1:.1f}"/><polygon points="{head}"/>'
                f'<text class="label" x="{mid}" y="{y0 - 4:.1f}">{esc(label)}</text>'
                f'<text class="ts" x="{AXIS_X - 4}" y="{y0 + 4:.1f}">{ms(e.t0)}</text>')
        if e.kind == "char_error":
            cx = x1 - 16 if tester else x1 + 16
            body += (f'<path class="x" d="M{cx - 5} {y1 - 5:.1f}l10 10M{cx - 5} {y1 + 5:.1f}l10 -10"/>')
            arrows_svg.append(f'<g class="line-condition" data-kind="char_error" {attrs}>{body}</g>')
        else:
            arrows_svg.append(f'<g class="arrow" {attrs}>{body}</g>')

    # the first divergence (under the arrows, so the arrow that diverged stays visible)
    if div is not None:
        yd = y(div_t)
        win = ""
        if div.window:
            win = f' data-t0="{float(div.window[0]):.6f}" data-t1="{float(div.window[1]):.6f}"'
        texts = "".join(f'<text x="{TX + 8}" y="{yd + 17 + 14 * k:.1f}">{esc(line)}</text>'
                        for k, line in enumerate(div_lines))
        add(f'<g class="divergence" data-t="{div_t:.6f}" data-step="{div.step}"{win}>'
            f'<title>{esc(f"first divergence: {step_text(div.step)}{ms(div.time)} ms: expected {div.expected}; observed {div.observed}")}</title>'
            f'<path d="M{AXIS_X} {yd:.1f}H{WIN_X + WIN_COLS * WIN_COL + 2}"/><circle cx="{IX}" cy="{yd:.1f}" r="5"/>'
            f'<rect class="div-box" x="{TX + 3}" y="{yd + 4:.1f}" width="{IX - TX - 6}" height="{14 * len(div_lines) + 6}"/>'
            f'{texts}' + ("" if _r(div_t) in ts_taken else
                           f'<text class="ts" x="{AXIS_X - 4}" y="{yd + 4:.1f}">{ms(div_t)}</text>') + '</g>')

    add("".join(arrows_svg))

    aria = f"sequence diagram of {c.id}"
    return (f'<svg class="seq" width="{W}" height="{height}" '
            f'viewBox="0 0 {W} {height}" role="img" aria-label="{esc(aria)}">' + "".join(parts) + "</svg>")


# ------------------------------------------------------------------ frames
def _frames(c: R.CaseResult) -> list[dict[str, Any]]:
    """The case's frames that can be drawn (a sender and a time span), the divergence's
    frame marked ``diverged`` also in results written before runs marked it."""
    hit = R.divergence_frame(c)
    out = []
    for f in c.frames:
        try:
            t0, t1 = float(f["t0"]), float(f["t1"])
        except (KeyError, TypeError, ValueError):
            continue
        if f.get("dir") not in ("tester", "iut"):
            continue
        g = dict(f, t0=t0, t1=max(t0, t1), label=str(f.get("label", "")))
        g["diverged"] = bool(f.get("diverged")) or f is hit
        out.append(g)
    return out


def _frame_arrows(frames: list[dict[str, Any]], events: list) -> dict[int, Any]:
    """The arrow each frame's label goes with (by the frame's index): the first arrow of
    its sender that overlaps its span."""
    out: dict[int, Any] = {}
    for i, f in enumerate(frames):
        for e in events:
            if (isinstance(e, Arrow) and e.dir == f["dir"] and e.t1 >= f["t0"] - 1e-9
                    and e.t0 <= f["t1"] + 1e-9):
                out[i] = e
                break
    return out


def _frames_svg(frames: list[dict[str, Any]], frame_at: dict[int, Any], y, end: float,
                elided: list[tuple[float, float, int]]) -> str:
    out: list[str] = []

    def hidden(f: dict[str, Any]) -> bool:   # partly left out of the diagram: not drawn
        return any(a < min(f["t1"], end) and f["t0"] < b for a, b, _ in elided)

    labels: dict[int, list[int]] = {}     # arrow id -> the frames labelled above it
    for i, e in frame_at.items():
        if not hidden(frames[i]):
            labels.setdefault(id(e), []).append(i)
    mid = (TX + IX) // 2
    named = {"tester": -1e9, "iut": -1e9}   # where the last name of a mark or window went, per side
    for i, f in enumerate(frames):
        t0, t1 = f["t0"], min(f["t1"], end)
        # a frame's windows are drawn up to where its sender's next frame begins (the CDT
        # runs from each character: the next one stops it); their times are in the tooltip
        nxt = min((g["t0"] for g in frames[i + 1:] if g["dir"] == f["dir"] and g["t0"] >= f["t1"] - 1e-9),
                  default=math.inf)
        if hidden(f):
            continue
        tester = f["dir"] == "tester"
        y0 = y(t0)
        y1 = max(y(t1), y0 + 4)
        # the band hugs the sender's lane on its outer side; the bracket closes it
        bx = TX - 9 if tester else IX + 2
        kx = TX - 12 if tester else IX + 13
        ex = TX - 5 if tester else IX + 8
        tip = [f"frame from the {'tester' if tester else 'IUT'}, {ms(f['t0'])}–{ms(f['t1'])} ms: {f['label']}"]
        if f.get("frame"):
            fr = str(f["frame"])
            tip.append("content: " + (fr if len(fr) <= 150 else fr[:120] + " …"))
        if f.get("expected") and f.get("expected") != f["label"]:
            tip.append(f"expected: {f['expected']}")
        body = [f'<rect class="band" x="{bx}" y="{y0:.1f}" width="7" height="{y1 - y0:.1f}"/>',
                f'<path class="bracket" d="M{ex} {y0:.1f}H{kx}V{y1:.1f}H{ex}"/>']
        nx, anchor_ = (TX - 15, "end") if tester else (IX - 5, "end")
        for m in f.get("marks") or []:
            try:
                tm, name = float(m["t"]), str(m.get("name", ""))
            except (KeyError, TypeError, ValueError):
                continue
            if tm > end + 1e-9:
                continue
            ym = y(tm)
            lx0, lx1 = (TX - 14, TX + 4) if tester else (IX - 4, IX + 14)
            text = ""
            if ym + 3 - named[f["dir"]] >= 10:   # names that would overlap: the tooltip has them
                named[f["dir"]] = ym + 3
                text = f'<text x="{nx}" y="{ym + 3:.1f}" text-anchor="{anchor_}">{esc(name)}</text>'
            body.append(f'<g class="mark" data-t="{tm:.6f}" data-name="{esc(name)}"><path d="M{lx0} {ym:.1f}H{lx1}"/>'
                        f'{text}</g>')
            tip.append(f"{name} at {ms(tm)} ms")
        for w in f.get("windows") or []:
            try:
                w0, w1, name = float(w["t0"]), float(w["t1"]), str(w.get("name", ""))
            except (KeyError, TypeError, ValueError):
                continue
            tip.append(f"{name} {ms(w0)}–{ms(w1)} ms")
            shown_to = min(w1, end, max(nxt, w0))
            if w0 > end + 1e-9 or y(shown_to) - y(w0) < 3:
                continue
            wy0, wy1 = y(w0), y(shown_to)
            text = ""
            ty = max(wy0 + 10, named[f["dir"]] + 10)   # below a name already there, if it fits
            if ty <= wy1 + 2:
                named[f["dir"]] = ty
                text = f'<text x="{nx}" y="{ty:.1f}" text-anchor="{anchor_}">{esc(name)}</text>'
            body.append(f'<g class="fwindow" data-t0="{w0:.6f}" data-t1="{w1:.6f}" data-name="{esc(name)}"'
                        + (' data-cut="1"' if shown_to < min(w1, end) else "") + '>'
                        f'<rect x="{bx - 1}" y="{wy0:.1f}" width="9" height="{wy1 - wy0:.1f}"/>{text}</g>')
        attrs = (f'data-dir="{f["dir"]}" data-t0="{f["t0"]:.6f}" data-t1="{f["t1"]:.6f}"'
                 + (' data-diverged="1"' if f["diverged"] else ""))
        e = frame_at.get(i)
        if e is not None:
            ids = labels[id(e)]
            if ids[0] == i:   # one label line per arrow: the frames that start in it, joined
                text = " | ".join(frames[k]["label"] for k in ids)
                if len(text) > FRAME_CHARS:
                    text = text[:FRAME_CHARS - 1] + "…"
                ly = y(e.lt0) - 4 - LABEL_H + 1
                wpx = 6.6 * len(text) + 10
                body.append(f'<rect class="pill" x="{mid - wpx / 2:.0f}" y="{ly - 11:.1f}" width="{wpx:.0f}" '
                            f'height="14" rx="7"/><text class="flabel" x="{mid}" y="{ly:.1f}">{esc(text)}</text>')
        out.append(f'<g class="frame" {attrs}><title>{esc(chr(10).join(tip))}</title>{"".join(body)}</g>')
    return "".join(out)


# ------------------------------------------------------------------ STATUS events
def status_name(code: str) -> tuple[str, str]:
    """(short name, catalogue text) of a STATUS code; tolerant of unknown ones."""
    from ptpcert.status import UnknownStatus, lookup
    try:
        ev = lookup(code)
    except (UnknownStatus, ValueError):
        return "not in the catalogue", ""
    return ev.short, ev.text


def _norm(code: str) -> str:
    return "16#" + code[3:].upper() if code[:3] == "16#" else code.upper()


def _status_html(code: str, used: set[str], cls: str = "") -> str:
    short, text = status_name(code)
    used.add(_norm(code))
    c = f' class="st {cls}"' if cls else ' class="st"'
    return f'<span{c} title="{esc(text)}"><code>{esc(code)}</code> {esc(short)}</span>'


def _codes_in_text(text: str, used: set[str]) -> str:
    """Escape ``text``, annotating each 16#XXXX with its short name."""
    out, pos = [], 0
    for m in _CODE_RE.finditer(text):
        out.append(esc(text[pos:m.start()]))
        code = "16#" + m.group(0)[3:].upper()
        short, full = status_name(code)
        used.add(code)
        out.append(f'<span class="st" title="{esc(full)}"><code>{esc(code)}</code> <i>{esc(short)}</i></span>')
        pos = m.end()
    out.append(esc(text[pos:]))
    return "".join(out)


# ------------------------------------------------------------------ the page
CSS = """
:root{--fail:#c62828;--xpass:#ad1457;--error:#e65100;--nonstrict:#b58900;--info:#1565c0;--pass:#2e7d32;
--xfail:#607d8b;--unsup:#8d8d8d;--notrun:#bdbdbd}
body{font:14px/1.45 system-ui,-apple-system,"Segoe UI",Roboto,sans-serif;margin:0 auto;max-width:1180px;padding:0 18px 40px;color:#1d1d1d}
h1{font-size:22px;margin:18px 0 6px}h2{font-size:18px;margin:26px 0 8px;border-bottom:1px solid #ddd}
table{border-collapse:collapse}td,th{padding:2px 10px 2px 0;text-align:left;vertical-align:top}
th{font-weight:600;color:#444;white-space:nowrap}
code,pre{font-family:ui-monospace,"DejaVu Sans Mono",Menlo,Consolas,monospace;font-size:12.5px}
pre{background:#f6f6f6;padding:6px 8px;white-space:pre-wrap;word-break:break-all;margin:4px 0}
.v{display:inline-block;padding:0 7px;border-radius:9px;color:#fff;font-weight:600;font-size:12px;white-space:nowrap}
.v-fail{background:var(--fail)}.v-xpass{background:var(--xpass)}.v-error{background:var(--error)}
.v-non-strict{background:var(--nonstrict)}.v-informational{background:var(--info)}.v-pass{background:var(--pass)}
.v-xfail{background:var(--xfail)}.v-unsupported{background:var(--unsup)}.v-not-run{background:var(--notrun);color:#333}
.overall{font-size:16px;padding:2px 12px}
.banner{background:#fff3e0;border:1px solid var(--error);padding:6px 10px;margin:8px 0}
.cols{display:grid;grid-template-columns:minmax(0,1fr) minmax(0,1.3fr);gap:36px}
#filter{position:sticky;top:0;background:#fff;border-bottom:1px solid #ddd;padding:6px 0;z-index:2}
#filter label{margin-right:12px;white-space:nowrap}#filter button{margin-left:6px}
details.group{margin:3px 0}details.group>summary{cursor:pointer}
.gname{display:inline-block;min-width:150px;font-weight:600}
.case{scroll-margin-top:44px;border:1px solid #ddd;border-left:6px solid var(--unsup);margin:10px 0;padding:0 10px;border-radius:3px}
.case.c-fail{border-left-color:var(--fail)}.case.c-xpass{border-left-color:var(--xpass)}.case.c-error{border-left-color:var(--error)}
.case.c-pass{border-left-color:var(--pass)}.case.c-non-strict{border-left-color:var(--nonstrict)}
.case.c-informational{border-left-color:var(--info)}.case.c-xfail{border-left-color:var(--xfail)}
.case>details>summary{cursor:pointer;padding:6px 0;font-weight:600}
.case .title{font-weight:400;color:#333}.case .ref{color:#666;font-weight:400;font-size:12.5px}
.case dl{display:grid;grid-template-columns:190px 1fr;gap:2px 10px;margin:6px 0}.case dt{font-weight:600;color:#444}.case dd{margin:0}
.divbox{border:1px solid var(--fail);background:#fdecea;padding:6px 10px;margin:6px 0}
.st{white-space:nowrap;margin-right:8px}.st.missing{color:var(--fail);font-weight:600}.st.unexpected{color:var(--fail)}
.diagram{overflow-x:auto}
svg.seq{display:block;margin:6px 0;background:#fff}
svg.seq text{font:11px ui-monospace,"DejaVu Sans Mono",Menlo,monospace;fill:#222}
svg.seq .lane-h{font:600 12px system-ui,sans-serif;text-anchor:middle}
svg.seq .axis-h,svg.seq .ts{text-anchor:end;fill:#555;font-size:10px}
svg.seq .lane{stroke:#333;stroke-width:2}svg.seq .axis{stroke:#aaa}
svg.seq .arrow path{stroke:#1d1d1d;stroke-width:1.3;fill:none}svg.seq .arrow polygon{fill:#1d1d1d}
svg.seq .arrow[data-dir=iut] path{stroke:#0d47a1}svg.seq .arrow[data-dir=iut] polygon{fill:#0d47a1}
svg.seq .arrow[data-dir=iut] .label{fill:#0d47a1}
svg.seq .arrow[data-diverged] path{stroke:var(--fail);stroke-width:2.2}svg.seq .arrow[data-diverged] polygon{fill:var(--fail)}
svg.seq .arrow[data-diverged] .label{fill:var(--fail);font-weight:700}
svg.seq .label{text-anchor:middle}
svg.seq .line-condition path,svg.seq .line-condition polyline{stroke:var(--fail);stroke-width:1.5;fill:none}
svg.seq .line-condition polygon{fill:var(--fail)}svg.seq .line-condition .label{fill:var(--fail);font-weight:700}
svg.seq .line-condition[data-kind=char_error]>path:first-of-type{stroke-dasharray:5 3}
svg.seq .line-condition rect{fill:var(--fail);opacity:.35}svg.seq .x{stroke-width:2.5}
svg.seq .window rect{fill:#5c85d6;fill-opacity:.35;stroke:#3b64b3}svg.seq .window rect.clipped{stroke-dasharray:3 2}
svg.seq .window text{font:10px system-ui,sans-serif;fill:#3b64b3}svg.seq .leader{stroke:#b5c6e6;fill:none}
svg.seq .gap path{stroke:#555;fill:none}svg.seq .gap .cut{fill:#fff}svg.seq .gap text{text-anchor:end;font-size:10px;fill:#555}
svg.seq .elided rect{fill:#f2f2f2}svg.seq .elided text{text-anchor:middle;fill:#666;font-style:italic}
svg.seq .start path{stroke:#999;stroke-dasharray:2 3}svg.seq .start text{font-size:9px;fill:#777}
svg.seq .frame .band{fill:#2e7d32;fill-opacity:.22}svg.seq .frame[data-dir=iut] .band{fill:#0d47a1}
svg.seq .frame .bracket{stroke:#2e7d32;stroke-width:1.4;fill:none}svg.seq .frame[data-dir=iut] .bracket{stroke:#0d47a1}
svg.seq .frame .pill{fill:#e8f5e9;stroke:#a5d6a7}svg.seq .frame[data-dir=iut] .pill{fill:#e3f2fd;stroke:#90caf9}
svg.seq .flabel{text-anchor:middle;font-weight:600;fill:#1b5e20}svg.seq .frame[data-dir=iut] .flabel{fill:#0d47a1}
svg.seq .frame .mark path{stroke:#6a1b9a;stroke-width:1.6}
svg.seq .frame .mark text,svg.seq .frame .fwindow text{font-size:9px;fill:#6a1b9a;paint-order:stroke;stroke:#fff;stroke-width:3px}
svg.seq .frame .fwindow rect{fill:#ff9800;fill-opacity:.3;stroke:#ef6c00;stroke-dasharray:2 2}
svg.seq .frame[data-diverged] .band{fill:var(--fail);fill-opacity:.35}svg.seq .frame[data-diverged] .bracket{stroke:var(--fail);stroke-width:2.2}
svg.seq .frame[data-diverged] .pill{fill:#fdecea;stroke:var(--fail)}svg.seq .frame[data-diverged] .flabel{fill:var(--fail)}
svg.seq .divergence path{stroke:var(--fail);stroke-width:1.5;stroke-dasharray:6 3}svg.seq .divergence circle{fill:var(--fail)}
svg.seq .divergence text{fill:var(--fail);font-weight:700;font-family:system-ui,sans-serif}
svg.seq .divergence .ts{fill:var(--fail)}svg.seq .div-box{fill:#fdecea;fill-opacity:.92}
svg.seq .div-window{fill:var(--fail);fill-opacity:.3;stroke:var(--fail)}
.steps td{font-family:ui-monospace,monospace;font-size:12px}.steps tr.div-step{background:#fdecea}
footer{margin-top:30px;color:#777;font-size:12px}
"""

JS = """
(function(){
var nav=document.getElementById('filter');if(!nav)return;nav.hidden=false;
function apply(){var on={};nav.querySelectorAll('input[data-v]').forEach(function(i){on[i.getAttribute('data-v')]=i.checked;});
document.querySelectorAll('[data-verdict]').forEach(function(el){el.hidden=!on[el.getAttribute('data-verdict')];});}
nav.addEventListener('change',apply);
function all(open){document.querySelectorAll('.case>details,details.group').forEach(function(d){d.open=open;});}
document.getElementById('expand-all').addEventListener('click',function(){all(true);});
document.getElementById('collapse-all').addEventListener('click',function(){all(false);});
function openHash(){var id=decodeURIComponent(location.hash.slice(1));var el=id&&document.getElementById(id);
if(!el)return;el.hidden=false;var d=el.querySelector('details');if(d)d.open=true;el.scrollIntoView();}
window.addEventListener('hashchange',openHash);openHash();
})();
"""


def _badge(verdict: str, extra: str = "") -> str:
    return f'<span class="v v-{esc(verdict)}{(" " + extra) if extra else ""}">{esc(verdict)}</span>'


def _profile_rows(p: dict[str, Any]) -> list[tuple[str, str]]:
    if not p:
        return [("profile", "—")]
    rows: list[tuple[str, str]] = []
    seen = set()

    def take(*keys):
        seen.update(keys)
        return [p.get(k) for k in keys]

    proc, prio = take("procedure", "priority")
    rows.append(("procedure", f"{proc if proc is not None else '?'}, priority {prio if prio is not None else '?'}"))
    cdt, adt = take("character_delay_ms", "acknowledgement_delay_ms")
    rows.append(("timers", f"character delay time CDT {cdt} ms, acknowledgement delay time ADT {adt} ms"))
    sa, ta = take("setup_attempts", "transmission_attempts")
    rows.append(("attempts", f"{sa} connection set-up, {ta} transmission"))
    baud, db, par, sb = take("baud_rate", "data_bits", "parity", "stop_bits")
    rows.append(("character frame", f"{baud} baud, {db} data bits, parity {par}, {sb} stop bit{'s' if sb != 1 else ''}"))
    st, lc, sfs = take("send_trigger", "line_conditions", "status_from_stderr")
    rows.append(("send trigger", str(st)))
    rows.append(("line conditions", str(lc)))
    rows.append(("STATUS from stderr", str(sfs).lower() if isinstance(sfs, bool) else str(sfs)))
    (tt,) = take("timer_tolerance_ms")
    rows.append(("IUT timer tolerance", f"{tt or 0:g} ms " + ("(declared: widens the late side of windows that "
                                                             "end on an IUT timer)" if tt else "(none declared)")))
    xf = p.get("expected_failures") or {}
    seen.add("expected_failures")
    if xf:
        rows.append(("expected failures", "; ".join(f"{k}: {v}" for k, v in xf.items())))
    for k, v in p.items():
        if k not in seen:
            rows.append((k.replace("_", " "), str(v)))
    return rows


def _table(rows: list[tuple[str, str]], raw: bool = False) -> str:
    return "<table>" + "".join(
        f"<tr><th>{esc(k)}</th><td>{v if raw else esc(v)}</td></tr>" for k, v in rows) + "</table>"


def _header(run: R.RunResult) -> str:
    counts = run.counts()
    n = len(run.cases)
    verdict = run.verdict
    out = [f'<header><h1>ptpcert conformance report — {esc(run.procedure or "3964/3964R")}</h1>'
           f'<p>overall verdict {_badge(verdict, "overall")} &nbsp; {n} cases: '
           + " ".join(f'{_badge(v)} {counts[v]}' for v in R.VERDICTS if counts.get(v)) + "</p>"]
    if run.interrupted:
        out.append('<p class="banner">The run was <b>interrupted</b>; cases not reached are marked not-run.</p>')
    info = [("tool", f"ptpcert {run.tool_version}"),
            ("started", run.started or "—"), ("finished", run.finished or "—"),
            ("wall time", f"{run.wall_time:.1f} s"),
            ("interrupted", "yes" if run.interrupted else "no"),
            ("IUT", run.iut or "—"),
            ("profile file", run.profile_path or "—"),
            ("vector set", run.vector_set or "—"),
            ("vector set hash", run.vector_set_hash or "—")]
    if run.harness_scheduling:
        info.append(("harness scheduling", run.harness_scheduling))
    out.append('<div class="cols"><div><h2>Run</h2>' + _table(info) + "</div>"
               '<div><h2>IUT profile</h2>' + _table(_profile_rows(run.profile)) + "</div></div></header>")
    return "".join(out)


def _filter(run: R.RunResult) -> str:
    counts = run.counts()
    boxes = "".join(f'<label><input type="checkbox" data-v="{esc(v)}" checked> {_badge(v)} {counts[v]}</label>'
                    for v in R.VERDICTS if counts.get(v))
    return (f'<nav id="filter" hidden><b>show:</b> {boxes}'
            f'<button type="button" id="expand-all">expand all</button>'
            f'<button type="button" id="collapse-all">collapse all</button></nav>')


def _groups(run: R.RunResult) -> list[str]:
    present = []
    for c in run.cases:
        if c.group not in present:
            present.append(c.group)
    ordered = [g for g in GROUP_ORDER if g in present]
    return ordered + sorted(g for g in present if g not in GROUP_ORDER)


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


def _summary(run: R.RunResult) -> str:
    out = [_deviations(run), '<section id="summary"><h2>Summary by manual section</h2>']
    for g in _groups(run):
        cs = [c for c in run.cases if c.group == g]
        counts: dict[str, int] = {}
        for c in cs:
            counts[c.verdict] = counts.get(c.verdict, 0) + 1
        badges = " ".join(f"{_badge(v)} {counts[v]}" for v in R.VERDICTS if counts.get(v))
        rows = "".join(
            f'<tr data-verdict="{esc(c.verdict)}"><td>{_badge(c.verdict)}</td>'
            f'<td><a href="#{esc(anchor(c.id))}"><code>{esc(c.id)}</code></a></td><td>{esc(c.title)}</td></tr>'
            for c in sorted(cs, key=_order_key))
        out.append(f'<details class="group" data-group="{esc(g)}">'
                   f'<summary><span class="gname">{esc(g or "(no group)")}</span> {len(cs)} cases: {badges}</summary>'
                   f"<table>{rows}</table></details>")
    bad = [c for c in ordered_cases(run) if c.verdict in FAILURES]
    if bad:
        out.append('<h3>Not passed</h3><table class="bad">' + "".join(
            f'<tr data-verdict="{esc(c.verdict)}"><td>{_badge(c.verdict)}</td>'
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


def _steps_table(c: R.CaseResult) -> str:
    if not c.steps:
        return ""
    div_step = c.divergence.step if c.divergence is not None else None
    rows = []
    for i, s in enumerate(c.steps):
        kind = str(s.get("kind", ""))
        rest = {k: v for k, v in s.items() if k not in ("kind", "data", kind, "note")}
        what = str(s.get(kind, s.get("data", "")))
        what = abbreviate_hex(what)
        detail = ", ".join(f"{k} {v}" for k, v in rest.items())
        cls = ' class="div-step"' if i == div_step else ""
        rows.append(f"<tr{cls}><td>{i + 1}</td><td>{esc(kind)}</td><td>{esc(what)}</td>"
                    f"<td>{esc(detail)}</td><td>{esc(s.get('note', ''))}</td></tr>")
    return ('<details><summary>steps</summary><table class="steps"><tr><th>#</th><th>kind</th>'
            '<th>bytes / duration</th><th>timing</th><th>note</th></tr>' + "".join(rows) + "</table></details>")


def _transcript_text(c: R.CaseResult, events: list | None = None) -> str:
    """The whole transcript, one line per burst, window or mark (compact: full bytes, no
    line per byte)."""
    lines = []
    items: list[tuple[float, int, str]] = []
    for e in group_events(c.transcript) if events is None else events:
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
    for f in _frames(c):   # each frame on a line of its own, before the bytes it spans
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
        if isinstance(m, dict) and _is_num(m.get("t")):
            extra.append(f"{m.get('name', '?')} at {ms(float(m['t']))} ms")
    for w in f.get("windows") or []:
        if isinstance(w, dict) and _is_num(w.get("t0")) and _is_num(w.get("t1")):
            extra.append(f"{w.get('name', '?')} {ms(float(w['t0']))}–{ms(float(w['t1']))} ms")
    if extra:
        line += "  [" + "; ".join(extra) + "]"
    if f["diverged"] and f.get("expected") and f.get("expected") != f["label"]:
        line += f"  (expected: {f['expected']})"
    return line


def _is_num(x: Any) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool)


def _case(c: R.CaseResult, used: set[str]) -> str:
    a = anchor(c.id)
    failing = c.verdict in FAILURES
    rows: list[tuple[str, str]] = []
    rows.append(("manual reference", _codes_in_text(c.reference, used)))
    rows.append(("rule", _codes_in_text(c.rule, used)))
    rows.append(("verdict", _badge(c.verdict) + (f" {esc(abbreviate_hex(c.message))}" if c.message else "")))
    rows.append(("IUT role", esc(c.iut_role)))
    # STATUS
    exp = _codes_in_text(c.expected_status or "none", used)
    groups = c.expected_status_codes or []
    observed = list(c.observed_status or [])
    obs_set = {o.upper() for o in observed}
    if groups:
        parts = []
        for g in groups:
            alts = " or ".join(_status_html(code, used, "" if not c.status_checked or code.upper() in obs_set
                                                     else "missing") for code in g)
            parts.append(alts)
        exp += "<br>required: " + "; ".join(parts)
    rows.append(("STATUS expected at the IUT", exp))
    allowed = {code.upper() for g in groups for code in g} | {m.upper() for m in _CODE_RE.findall(c.expected_status or "")}
    if c.status_checked:
        obs = " ".join(_status_html(o, used, "" if o.upper() in allowed else "unexpected") for o in observed) or "none"
    else:
        obs = (" ".join(_status_html(o, used) for o in observed) + " " if observed else "") + \
            "<i>not checked (the IUT does not report STATUS, or the check was off)</i>"
    rows.append(("STATUS observed", obs))
    rows.append(("a CP 341 in the tester's seat raises", _codes_in_text(c.tester_status or "none", used)))
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
                    f"<br>expected {esc(name_controls(abbreviate_hex(d.expected)))}"
                    f"<br>observed {esc(name_controls(abbreviate_hex(d.observed)))}"
                    + (f"<br>{esc(where)}" if (where := R.divergence_frame_text(c)) else "") + "</div>")
    events = group_events(c.transcript)
    svg = sequence_svg(c, events)
    if svg:
        body.append(f'<div class="diagram">{svg}</div>')
    else:
        body.append("<p><i>no transcript (the case did not reach the line)</i></p>")
    body.append(_steps_table(c))
    body.append(_transcript_text(c, events))
    if c.stderr_tail:
        body.append("<b>IUT stderr (tail)</b><pre>" + esc(c.stderr_tail[-2000:]) + "</pre>")
    return (f'<section class="case c-{esc(c.verdict)}" id="{esc(a)}" data-verdict="{esc(c.verdict)}">'
            f'<details{" open" if failing else ""}><summary>{_badge(c.verdict)} <code>{esc(c.id)}</code> '
            f'<span class="title">{esc(c.title)}</span> <span class="ref">[{esc(c.reference)}]</span></summary>'
            + "".join(body) + "</details></section>")


def _legend(used: set[str]) -> str:
    if not used:
        return ""
    from ptpcert.status import UnknownStatus, lookup
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


def render(run: R.RunResult) -> str:
    """The report as one HTML string."""
    used: set[str] = set()
    cases = "".join(_case(c, used) for c in ordered_cases(run))
    title = f"ptpcert report: {run.iut or 'IUT'} — {run.verdict}"
    return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
            f"<title>{esc(title)}</title><style>{CSS}</style></head><body>"
            + _header(run) + _filter(run) + _summary(run) + traceability_section(run)
            + '<section id="cases"><h2>Cases (failures first)</h2>' + cases + "</section>"
            + _legend(used)
            + f"<footer>ptpcert {esc(run.tool_version)} · results schema {esc(run.schema)} · "
              "one self-contained file: no external resources</footer>"
            + f"<script>{JS}</script></body></html>\n")


def write_html(result: R.RunResult, path) -> None:
    R.write_atomic(path, render(result))
