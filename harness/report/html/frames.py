"""The frames a procedure found in a case's transcript, drawn in the sequence diagram: a
band and a bracket on the sender's side, the end characters and other marks as ticks, the
frame's windows as shaded spans, the decoded label in a pill above the frame's first arrow,
and the divergence's frame in red.

Part of :mod:`ptpcert.report.html`: :mod:`~ptpcert.report.html.diagram` draws the frames
with it, and the case's text transcript lists :func:`drawable_frames`.
"""

from __future__ import annotations

import math
from typing import Any

from ptpcert import results as R
from ptpcert.report.html.events import Arrow
from ptpcert.report.html.layout import FRAME_CHARS, IX, LABEL_H, TX
from ptpcert.report.html.markup import esc, ms


def drawable_frames(c: R.CaseResult) -> list[dict[str, Any]]:
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


def frame_arrows(frames: list[dict[str, Any]], events: list) -> dict[int, Any]:
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


def frames_svg(frames: list[dict[str, Any]], frame_at: dict[int, Any], y, end: float,
               elided: list[tuple[float, float, int]]) -> str:
    """The frames as SVG: ``frame_at`` is :func:`frame_arrows`' answer, ``y`` the layout's
    time to height, ``end`` where the diagram ends; a frame that reaches into an elided
    range is left out."""
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

