"""The 3964 / 3964R state machine, drawn from the transition table (:mod:`ptpcert.procedures.p3964.model.table`).

:func:`svg` returns a self-contained SVG picture: the states as boxes, the decisions (the
flowcharts' diamonds) as diamonds, every row and decision outcome as an arrow labelled with
its input (or condition) and the STATUS code it raises; hovering an arrow shows the action
and the manual reference. The layout is computed here (layers from the start-up state,
ordered to keep arrows short), so a row added to the table shows up without touching this
module. :func:`table_text` prints the same table as text.

Imports only the model and the standard library.
"""

from __future__ import annotations

import math
from collections import defaultdict
from dataclasses import dataclass, field
from xml.sax.saxutils import escape

from .model import table as T

#: rows that change nothing are listed by table_text() but not drawn
_NOT_DRAWN = {T.Action.IMPOSSIBLE, T.Action.IGNORE, T.Action.QUEUE_JOB}


# ---------------------------------------------------------------------------------- text
def table_text() -> str:
    """The table as text: one line per row that can occur (state, input, action, target,
    STATUS code, reference and the ids of the rules it implements), then the decisions'
    outcomes."""
    rows = [(str(s), str(i), str(r.action), str(r.target), _code(r), r.ref + _rules(r))
            for s, i, r in T.rows() if r.action != T.IMPOSSIBLE]
    outs = [(str(d), b.when, "", str(b.target), _code(b), b.ref + _rules(b)) for d, b in T.branches()]
    impossible = sum(1 for _, _, r in T.rows() if r.action == T.IMPOSSIBLE)
    lines = []

    def block(title, head, items):
        widths = [max(len(x[k]) for x in items + [head]) for k in range(5)]
        lines.append(title)
        for item in [head] + items:
            lines.append("  ".join(v.ljust(w) for v, w in zip(item, widths)) + "  " + item[5])
        lines.append("")

    block(f"Transition table: {len(rows)} rows ({impossible} state/input pairs cannot occur and are left out)",
          ("STATE", "INPUT", "ACTION", "TARGET", "CODE", "REFERENCE"), rows)
    block(f"Decisions: {len(T.DECISIONS)} (flowchart diamonds), {len(outs)} outcomes",
          ("DECISION", "WHEN", "", "TARGET", "CODE", "REFERENCE"), outs)
    return "\n".join(lines).rstrip() + "\n"


def _rules(e) -> str:
    return f"  [{', '.join(e.rules)}]" if e.rules else ""


def _code(e) -> str:
    if e.code is None:
        return ""
    return e.code.text + (" (noted)" if e.noted else "")


# ---------------------------------------------------------------------------------- graph
@dataclass
class _Node:
    name: str
    decision: bool
    w: float
    h: float
    rank: int = 0
    x: float = 0.0
    y: float = 0.0


@dataclass
class _Edge:
    src: str
    dst: str
    lines: list[str] = field(default_factory=list)   # visible label, one line per row/outcome
    tips: list[str] = field(default_factory=list)    # hover text: action and reference
    only_break: bool = True


def _graph() -> tuple[dict[str, _Node], list[_Edge]]:
    nodes: dict[str, _Node] = {}
    for s in T.STATES:
        nodes[s] = _Node(s, False, max(120.0, 8.2 * len(s) + 28), 36.0)
    for d in T.DECISIONS:
        nodes[d] = _Node(d, True, max(130.0, 7.6 * len(d) + 70), 54.0)
    edges: dict[tuple[str, str], _Edge] = {}

    def edge(src, dst) -> _Edge:
        return edges.setdefault((src, dst), _Edge(src, dst))

    # rows: one label line per (action, code), naming all the inputs that share it
    grouped: dict[tuple, list[str]] = defaultdict(list)
    for s, i, r in T.rows():
        if r.action in _NOT_DRAWN:
            continue
        dst = s if r.target == T.SAME else r.target
        grouped[(s, dst, r.action, r.code, r.noted, r.ref)].append(str(i))
    for (s, dst, action, code, noted, ref), inputs in grouped.items():
        e = edge(s, dst)
        e.lines.append(_label(", ".join(inputs), code, noted))
        e.tips.append(f"{s} on {', '.join(inputs)}: {action} -> {dst}; {ref}")
        e.only_break = e.only_break and inputs == [T.BREAK]
    for d, b in T.branches():
        e = edge(d, b.target)
        e.lines.append(_label(b.when, b.code, b.noted))
        e.tips.append(f"{d}: {b.when} -> {b.target}; {b.ref}")
        e.only_break = False
    return nodes, list(edges.values())


def _label(what: str, code, noted: bool) -> str:
    if code is None:
        return what
    return f"{what} · {code.text}" + (" noted" if noted else "")


def _layout(nodes: dict[str, _Node], edges: list[_Edge]) -> tuple[float, float]:
    """Layers by distance from START_UP; within a layer, an order that keeps arrows short
    (barycentres of the neighbours, a few sweeps). Returns the drawing's size."""
    succ: dict[str, list[str]] = defaultdict(list)
    nbrs: dict[str, list[str]] = defaultdict(list)
    for e in edges:
        if e.src != e.dst:
            succ[e.src].append(e.dst)
            nbrs[e.src].append(e.dst)
            nbrs[e.dst].append(e.src)
    rank = {T.START_UP: 0}
    todo = [T.START_UP]
    while todo:
        nxt = []
        for u in todo:
            for v in succ[u]:
                if v not in rank:
                    rank[v] = rank[u] + 1
                    nxt.append(v)
        todo = nxt
    deepest = max(rank.values())
    layers: dict[int, list[str]] = defaultdict(list)
    for n in nodes:   # table order first: sender before receiver
        nodes[n].rank = rank.get(n, deepest + 1)
        layers[nodes[n].rank].append(n)
    pos = {n: float(k) for layer in layers.values() for k, n in enumerate(layer)}
    order = sorted(layers)
    for sweep in range(8):
        for r in (order if sweep % 2 == 0 else reversed(order)):
            layer = layers[r]
            key = {n: (sum(pos[m] for m in nbrs[n]) / len(nbrs[n]) if nbrs[n] else pos[n]) for n in layer}
            layer.sort(key=lambda n: (key[n], pos[n]))
            # spread positions to the scale of the widest layer so barycentres compare
            scale = max(len(v) for v in layers.values()) / max(len(layer), 1)
            for k, n in enumerate(layer):
                pos[n] = (k + 0.5) * scale
    gap_x, gap_y, margin, top = 90.0, 170.0, 60.0, 110.0
    width = max(sum(nodes[n].w for n in layer) + gap_x * (len(layer) - 1) for layer in layers.values()) + 2 * margin
    for r, layer in layers.items():
        total = sum(nodes[n].w for n in layer) + gap_x * (len(layer) - 1)
        x = (width - total) / 2
        for n in layer:
            nodes[n].x = x + nodes[n].w / 2
            nodes[n].y = top + r * gap_y
            x += nodes[n].w + gap_x
    height = top + max(layers) * gap_y + 140
    return width, height


# ---------------------------------------------------------------------------------- drawing
def _clip(n: _Node, dx: float, dy: float) -> tuple[float, float]:
    """Where a ray from the node's centre in direction (dx, dy) leaves its outline."""
    if dx == 0 and dy == 0:
        return n.x, n.y
    if n.decision:   # diamond: |x|/(w/2) + |y|/(h/2) = 1
        t = 1.0 / (abs(dx) / (n.w / 2) + abs(dy) / (n.h / 2))
    else:
        t = min((n.w / 2) / abs(dx) if dx else math.inf, (n.h / 2) / abs(dy) if dy else math.inf)
    return n.x + dx * t, n.y + dy * t


def _bezier(p0, p1, p2, p3, t):
    u = 1 - t
    return tuple(u ** 3 * a + 3 * u * u * t * b + 3 * u * t * t * c + t ** 3 * d
                 for a, b, c, d in zip(p0, p1, p2, p3))


@dataclass
class _Box:
    x: float
    y: float
    w: float
    h: float

    def hits(self, o: "_Box") -> bool:
        return not (self.x + self.w <= o.x or o.x + o.w <= self.x or self.y + self.h <= o.y or o.y + o.h <= self.y)


def _free(box: _Box, placed: list[_Box]) -> _Box:
    """Move a label down until it overlaps no node and no label placed before it."""
    for _ in range(40):
        if not any(box.hits(o) for o in placed):
            break
        box.y += 7
    placed.append(box)
    return box


def svg() -> str:
    """The state machine as a self-contained SVG document."""
    nodes, edges = _graph()
    width, height = _layout(nodes, edges)
    out: list[str] = []
    labels: list[str] = []
    placed: list[_Box] = [_Box(n.x - n.w / 2, n.y - n.h / 2, n.w, n.h) for n in nodes.values()]
    pairs = {(e.src, e.dst) for e in edges}
    for e in edges:
        a, b = nodes[e.src], nodes[e.dst]
        cls = "edge break" if e.only_break else "edge"
        tip = escape("\n".join(e.tips))
        if e.only_break and b.name == T.IDLE and a is not b:
            # BREAK returns every state to idle: a short arrow that says so, not a line across
            x0, y0 = a.x - a.w / 2, a.y + a.h / 4
            out.append(f'<path class="{cls}" d="M{x0:.1f},{y0:.1f} l-26,14" marker-end="url(#arrow)">'
                       f'<title>{tip}</title></path>')
            text = f"{e.lines[0]} → IDLE"
            box = _free(_Box(x0 - 30 - len(text) * 5.6, y0 + 14, len(text) * 5.6 + 4, 14), placed)
            labels.append(f'<g class="label"><title>{tip}</title><text x="{box.x + box.w:.1f}" '
                          f'y="{box.y + 10:.1f}" text-anchor="end">{escape(text)}</text></g>')
            continue
        if a is b:   # a loop on the node's right-hand side
            x0, y0 = a.x + a.w / 2, a.y - 8
            x1, y1 = a.x + a.w / 2, a.y + 8
            path = f"M{x0:.1f},{y0:.1f} C{x0 + 60:.1f},{y0 - 40:.1f} {x1 + 60:.1f},{y1 + 40:.1f} {x1:.1f},{y1:.1f}"
            mid = (x0 + 48, a.y)
            anchor = "start"
        else:
            dx, dy = b.x - a.x, b.y - a.y
            dist = math.hypot(dx, dy)
            # bow every arrow to its left; arrows both ways between two nodes then part,
            # and arrows that go back up or sideways keep clear of the nodes between
            bow = 0.12 * dist + (40 if (e.dst, e.src) in pairs else 0) + (60 if b.rank <= a.rank else 0)
            nx, ny = -dy / dist, dx / dist
            c1 = (a.x + dx / 3 + nx * bow, a.y + dy / 3 + ny * bow)
            c2 = (a.x + 2 * dx / 3 + nx * bow, a.y + 2 * dy / 3 + ny * bow)
            p0 = _clip(a, c1[0] - a.x, c1[1] - a.y)
            p3 = _clip(b, c2[0] - b.x, c2[1] - b.y)
            path = (f"M{p0[0]:.1f},{p0[1]:.1f} C{c1[0]:.1f},{c1[1]:.1f} {c2[0]:.1f},{c2[1]:.1f} "
                    f"{p3[0]:.1f},{p3[1]:.1f}")
            # labels sit nearer the source, so that the many arrows into one node keep theirs apart
            mid = _bezier(p0, c1, c2, p3, 0.4)
            anchor = "middle"
        out.append(f'<path class="{cls}" d="{path}" marker-end="url(#arrow)"><title>{tip}</title></path>')
        # the label: a white box behind the text, moved down until it overlaps nothing
        lh, cw = 12.0, 5.6
        w = max(len(s) for s in e.lines) * cw + 6
        h = lh * len(e.lines) + 4
        x = mid[0] - (w / 2 if anchor == "middle" else 0)
        y = mid[1] - h / 2
        box = _free(_Box(x, y, w, h), placed)
        tx = box.x + (w / 2 if anchor == "middle" else 3)
        text = "".join(f'<tspan x="{tx:.1f}" y="{box.y + 2 + lh * (k + 1) - 2.5:.1f}">{escape(s)}</tspan>'
                       for k, s in enumerate(e.lines))
        labels.append(f'<g class="label"><title>{tip}</title>'
                      f'<rect x="{box.x:.1f}" y="{box.y:.1f}" width="{w:.1f}" height="{h:.1f}"/>'
                      f'<text text-anchor="{anchor}">{text}</text></g>')
    shapes = []
    for n in nodes.values():
        if n.decision:
            pts = f"{n.x:.1f},{n.y - n.h / 2:.1f} {n.x + n.w / 2:.1f},{n.y:.1f} {n.x:.1f},{n.y + n.h / 2:.1f} " \
                  f"{n.x - n.w / 2:.1f},{n.y:.1f}"
            shapes.append(f'<g class="decision" id="{n.name}"><polygon points="{pts}"/>'
                          f'<text x="{n.x:.1f}" y="{n.y + 4:.1f}">{escape(n.name)}</text></g>')
        else:
            shapes.append(f'<g class="state" id="{n.name}"><rect x="{n.x - n.w / 2:.1f}" y="{n.y - n.h / 2:.1f}" '
                          f'width="{n.w:.1f}" height="{n.h:.1f}" rx="8"/>'
                          f'<text x="{n.x:.1f}" y="{n.y + 5:.1f}">{escape(n.name)}</text></g>')
    style = (
        "text{font-family:DejaVu Sans,Arial,sans-serif}"
        ".state rect{fill:#e8f0fb;stroke:#2b5797;stroke-width:1.6}"
        ".state text{font-size:13px;font-weight:bold;text-anchor:middle;fill:#16325c}"
        ".decision polygon{fill:#fff6e0;stroke:#b07d12;stroke-width:1.4}"
        ".decision text{font-size:11px;text-anchor:middle;fill:#5c3f00}"
        ".edge{fill:none;stroke:#555;stroke-width:1.1}"
        ".edge.break{stroke:#aaa;stroke-dasharray:4 3}"
        ".label rect{fill:#fff;fill-opacity:.85}"
        ".label text{font-size:10px;fill:#222}"
        ".title{font-size:16px;font-weight:bold}.legend{font-size:11px;fill:#444}"
    )
    head = [
        f'<text class="title" x="20" y="28">3964 / 3964R transition table (Figs. 2-9 to 2-12)</text>',
        '<text class="legend" x="20" y="48">Boxes: states. Diamonds: decisions (the flowcharts\' branch points). '
        'Arrows: input, or a decision\'s condition, and the STATUS code it raises (Table 8-1; '
        '"noted": raised with the NAK at the end of the block).</text>',
        '<text class="legend" x="20" y="64">Dashed: BREAK (immediate return to idle, no NAK). Not drawn: inputs that '
        'cannot occur, that a state ignores, or send requests it keeps until idle. '
        'Hover an arrow for the action and the manual reference.</text>',
    ]
    return "\n".join([
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0f}" height="{height:.0f}" '
        f'viewBox="0 0 {width:.0f} {height:.0f}">',
        f"<style>{style}</style>",
        '<defs><marker id="arrow" viewBox="0 0 10 10" refX="9" refY="5" markerWidth="7" markerHeight="7" '
        'orient="auto-start-reverse"><path d="M0,0 L10,5 L0,10 z" fill="#555"/></marker></defs>',
        f'<rect width="{width:.0f}" height="{height:.0f}" fill="#fff"/>',
        *head, *out, *shapes, *labels,
        "</svg>",
    ]) + "\n"
