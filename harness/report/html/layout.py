"""The geometry of the sequence diagram and its time axis: where the lanes and window
columns are, how time maps to height (linear for short gaps, compressed for long ones, with
room for every label and the divergence's text), and which events a long case keeps (the
first, the last and those around the divergence; the rest become elided ranges).

Part of :mod:`ptpcert.report.html`: :mod:`~ptpcert.report.html.diagram` draws with it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ptpcert.report.html.events import LineBreak

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


def _dy(dt: float) -> tuple[float, bool]:
    """Height for a gap of ``dt`` seconds, and whether it was compressed."""
    v = max(dt, 0.0) * 1000.0
    if v <= LIN_MS * 1.2:
        return v * PX_PER_MS, False
    return LIN_MS * PX_PER_MS + min(45.0, 11.0 * math.log2(v / LIN_MS)), True


@dataclass
class Layout:
    """Times placed on the page: the key times and their heights, the compressed gaps and
    the elided ranges; :meth:`y` interpolates between key times."""

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


def key_time(t: float) -> float:
    """A time rounded as the layout keys it (so that equal times meet)."""
    return round(t, 7)


def place(events: list, extra: list[float], end: float, div_t: float | None, div_h: float,
            elided: list[tuple[float, float, int]], label_h: dict[int, float] | None = None) -> Layout:
    """Place the key times on the page: linear for short gaps, compressed for long ones,
    with room for every arrow's label (``label_h``: more room above the events, by id,
    that carry a frame's label too) and the divergence text."""
    label_h = label_h or {}
    starts: dict[float, list] = {}
    ends: dict[float, list] = {}
    keys = set(extra)
    keys.add(key_time(end))
    for e in events:
        t0, t1 = key_time(e.lt0), key_time(e.lt1)
        starts.setdefault(t0, []).append(e)
        ends.setdefault(t1, []).append(e)
        keys.update((t0, t1))
    el_bounds = {(key_time(a), key_time(b)) for a, b, _ in elided}
    for a, b in el_bounds:
        keys.update((a, b))
    if div_t is not None:
        keys.add(key_time(div_t))
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
        if div_t is not None and key_time(div_t) == t:
            y = max(y, floor + 6)
        if i > 0 and compressed:
            gaps.append((ys[-1], y, t - ks[i - 1]))
        ys.append(y)
        for e in starts.get(t, ()):
            y_start[id(e)] = y
            floor = max(floor, y + (22 if isinstance(e, LineBreak) else SLOPE))
        for e in ends.get(t, ()):
            floor = max(floor, y)
        if div_t is not None and key_time(div_t) == t:
            floor = max(floor, y + div_h)
    return Layout(ks, ys, gaps, elided)


def wrap(text: str, width: int) -> list[str]:
    """``text`` in lines of at most ``width`` characters (a longer word is cut)."""
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


def select(events: list, div_t: float | None, max_events: int) -> tuple[list, list[tuple[float, float, int]]]:
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

