"""A case's transcript as an SVG sequence diagram, drawn the way the manual draws its
figures: the tester's lane on the left, the IUT's on the right, time flowing down, one arrow
per burst of bytes with its bytes named, the timer windows the steps watched as bars beside
the IUT's lane, BREAK and character errors marked, the frames the procedure found, and the
first divergence in red.

The SVG carries stable classes and data attributes for tests and tools:
``<g class="arrow" data-dir="tester|iut" data-t=".." data-t1=".." data-n="bytes" data-step="..">``
with one ``<text class="label">``; ``<g class="line-condition" data-kind="break|char_error">``;
``<g class="window" data-t0 data-t1 data-step>``; ``<g class="divergence" data-t data-step>``;
``<g class="gap" data-ms>`` where the time axis is compressed; ``<g class="elided">`` where
arrows were left out to keep a long case compact.

Part of :mod:`ptpcert.report.html`: the events come from :mod:`~ptpcert.report.html.events`,
the geometry from :mod:`~ptpcert.report.html.layout`, the frames from
:mod:`~ptpcert.report.html.frames`. One function: the diagram's parts share its layout and
are drawn in one pass.
"""

from __future__ import annotations

import math

from ptpcert import results as R
from ptpcert.report.html.events import LineBreak, arrow_label, group_events
from ptpcert.report.html.frames import drawable_frames, frame_arrows, frames_svg
from ptpcert.report.html.layout import (
    AXIS_X,
    DIV_WRAP,
    FRAME_H,
    IX,
    MAX_FRAME_H,
    MAX_H,
    SLOPE,
    TOP,
    TX,
    WIN_COL,
    WIN_COLS,
    WIN_X,
    W,
    key_time,
    place,
    select,
    wrap,
)
from ptpcert.report.html.markup import abbreviate_hex, esc, hexstr, ms, ms_short
from ptpcert.report.text import step_text
from ptpcert.view import NEUTRAL, ReportView


def sequence_svg(c: R.CaseResult, events: list | None = None, view: ReportView | None = None) -> str:
    """The case's transcript as an SVG sequence diagram ('' when there is no transcript);
    ``events``: its :func:`group_events`, where already at hand; ``view``: how the case's
    procedure names its bytes (neutral: in hex)."""
    tr = c.transcript or []
    view = view or NEUTRAL
    all_events = group_events(tr, view=view) if events is None else events
    windows = [e for e in tr if e.get("kind") == "window" and "t0" in e and "t1" in e]
    starts = [float(e["t"]) for e in tr if e.get("kind") == "start" and "t" in e]
    div = c.divergence
    if not all_events and not windows and div is None:
        return ""
    frames = drawable_frames(c)
    div_t = float(div.time) if div is not None else None
    div_text = ""
    div_lines: list[str] = []
    if div is not None:
        div_text = (f"✗ {step_text(div.step)}{ms(div.time)} ms: expected "
                    f"{view.words(abbreviate_hex(div.expected), c.params)}; "
                    f"observed {view.words(abbreviate_hex(div.observed), c.params)}")
        div_lines = wrap(div_text, DIV_WRAP)[:6]
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
        events, elided = select(all_events, div_t, max_events)
        wins = [w for w in windows if not any(a < float(w["t0"]) and float(w["t1"]) < b for a, b, _ in elided)]
        extra = [key_time(float(w["t0"])) for w in wins] + [key_time(min(float(w["t1"]), end)) for w in wins]
        extra += [key_time(s) for s in starts]
        if div is not None and div.window:
            extra += [key_time(min(float(div.window[0]), end)), key_time(min(float(div.window[1]), end))]
        frame_at = frame_arrows(frames, events)
        label_h = {id(e): FRAME_H for e in frame_at.values()}
        lay = place(events, extra, end, div_t, div_h, elided, label_h)
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
    add(frames_svg(frames, frame_at, y, end, elided))

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
        label = arrow_label(e, view, c.params)
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
            ts_taken.add(key_time(e.t0))
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
            f'{texts}' + ("" if key_time(div_t) in ts_taken else
                           f'<text class="ts" x="{AXIS_X - 4}" y="{yd + 4:.1f}">{ms(div_t)}</text>') + '</g>')

    add("".join(arrows_svg))

    aria = f"sequence diagram of {c.id}"
    return (f'<svg class="seq" width="{W}" height="{height}" '
            f'viewBox="0 0 {W} {height}" role="img" aria-label="{esc(aria)}">' + "".join(parts) + "</svg>")
