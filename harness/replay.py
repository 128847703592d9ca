"""Re-judging an attempt by the reference model, fed the line as it really was.

A real-time case can go wrong for reasons that are not the IUT's: a stimulus meant to land
inside the IUT's block reached it after the block had ended (the IUT wrote it whole), or
the harness, descheduled on a loaded machine, read an IUT byte late and timed its reply
from that late read, so the reply reached the IUT after one of its timers although the
harness thinks it was on time. The runner then asks the model what a conforming IUT does
with the line the IUT really had: the tester's bytes, character errors and BREAKs go to the
model (the procedure's station, through the one ``sim:`` builder) in their order relative
to the IUT's output, each delayed from the IUT byte (or tester event) before it as it was
on the line. Every IUT byte is known only within an interval: the harness read it at ``r``,
and had looked at the line without seeing it at ``lb`` (its previous look), so it left the
IUT somewhere in [lb, r]. Two timelines bound what the IUT can have seen:

* **observed**: each IUT byte left when the harness read it (the tester's replies reached
  the IUT as soon after it as the harness saw them go out);
* **late**: each IUT byte left at the earliest it can have (its ``lb``), so the tester's
  replies reached the IUT as late after it as they can have.

The model *agrees* with the IUT when, fed one timeline, it sends the bytes the IUT sent, in
their order, with its own delays inside the intervals the harness observed (within the
case's tolerance), and sends nothing the IUT did not send before the observation ended.
This module only computes; the runner decides what agreement means for the verdict.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass, field
from typing import Any, Callable

from ptpcert.model.hexbytes import hexstr

#: kinds of the tester's entries in a runner log, as line events
_TESTER_KINDS = {"byte": "byte", "char_error": "invalid", "break": "break"}


@dataclass
class IutByte:
    r: float     # when the harness read it (case time)
    lb: float    # when the harness last looked at the line without it
    b: int


@dataclass
class TesterEvent:
    t: float         # when it went out (case time)
    kind: str        # "byte", "invalid" (a character error) or "break"
    value: int = 0
    duration: float = 0.0
    seen: int = 0    # IUT bytes the harness had read before it went out


@dataclass
class Wire:
    """What was on the line in one attempt, as the harness observed it."""

    iut: list[IutByte] = field(default_factory=list)
    tester: list[TesterEvent] = field(default_factory=list)
    end: float = 0.0   # the end of the observation (case time)

    @classmethod
    def from_log(cls, log: list[dict[str, Any]], lower_bounds: dict[int, float], end: float) -> "Wire":
        """From a runner log (one entry per byte, times relative to the case start) and the
        lower bounds of the IUT bytes, by log index."""
        w = cls(end=end)
        for i, e in enumerate(log):
            d, kind = e.get("dir"), e.get("kind")
            if d == "iut" and kind == "byte":
                t = float(e["t"])
                w.iut.append(IutByte(t, min(t, lower_bounds.get(i, t)), int(e["byte"])))
            elif d == "tester" and kind in _TESTER_KINDS:
                w.tester.append(TesterEvent(float(e["t"]), _TESTER_KINDS[kind], int(e.get("byte", 0)),
                                            float(e.get("duration", 0.0)), len(w.iut)))
        return w


@dataclass
class Margin:
    """How far the IUT's delays may stray from the model's: ``early(d)`` and ``late(d)``
    for a model delay ``d`` (seconds)."""

    early: Callable[[float], float]
    late: Callable[[float], float]


@dataclass
class Replay:
    agrees: bool
    why: str = ""                       # the first difference, in words ("" when it agrees)
    at: float | None = None             # the case time of the first difference
    model: bytes = b""                  # what the model sent before the observation ended
    codes: list[int] = field(default_factory=list)   # STATUS events the model raised
    timeline: str = "observed"


def replay(transport, wire: Wire, margin: Margin, *, late: bool, startup_on_line: bool,
           longest: float, char: float, stall: float = 0.0) -> Replay:
    """Feed ``wire``'s tester events to the model IUT behind ``transport`` (a ``sim:``
    transport for the case, not yet opened) on the observed or the ``late`` timeline, and
    compare what it sends with what the IUT sent. ``startup_on_line``: the IUT was started
    for the case, so its start-up bytes are in ``wire``; else the model's are left out.
    ``longest``: the IUT's longest timer (how long the model may take to send a byte);
    ``char``: its character time.

    ``stall`` > 0 (the **stalled** timeline): the machine stalled processes for up to
    ``stall`` seconds in this attempt (the harness measured its own), so the IUT process
    may have taken a tester event up to ``stall`` after it went out, or, having written its
    bytes late and in a burst, with fewer of its own bytes out than the harness had read
    before. Each tester event then reaches the model at the moment, between the model's
    completing the bytes the harness had read before it and ``stall`` after the observed
    time, at which the model (without the event) has sent the most of the bytes the IUT
    sent before the next tester event, the last of them still on the line; and the IUT's
    delays may stray ``stall`` further from the model's."""
    name = "late" if late else "observed"
    if stall > 0:
        name = "stalled"
        margin = Margin(early=lambda d, m=margin: m.early(d) + stall, late=lambda d, m=margin: m.late(d) + stall)
    tr = transport
    tr.open()
    out: list[tuple[float, int]] = []     # the model's bytes: (completion time, byte)
    codes: list[int] = []

    def run_until(t: float) -> None:
        while True:
            items = tr.read(t)
            out.extend(items)
            codes.extend(c for _, c in tr.status_reports())
            if not items and tr.now() >= t - 1e-12:
                return

    def run_until_count(n: int, limit: float) -> None:
        while len(out) < n:
            items = tr.read(limit)
            out.extend(items)
            codes.extend(c for _, c in tr.status_reports())
            if not items and tr.now() >= limit - 1e-12:
                return

    if not startup_on_line:   # the IUT was already running: its start-up is not in the wire
        run_until(tr.now() + 1e-3 + 4 * char)
        out.clear()
        codes.clear()
    iut = wire.iut
    model_at: list[float] = []            # the model time of each tester event delivered
    prev_real, prev_model = 0.0, tr.now()
    patience = 2 * longest + 1.0          # how long the model may take for a byte the IUT sent

    def differ(j: int) -> Replay | None:
        """Compare the model's and the IUT's first ``j`` bytes."""
        for i in range(min(j, len(out), len(iut))):
            if out[i][1] != iut[i].b:
                return Replay(False, f"the IUT's byte {i + 1} is {iut[i].b:02X}; the model sends {out[i][1]:02X} "
                                     f"(after {hexstr(bytes(b for _, b in out[max(0, i - 4):i])) or 'nothing'})",
                              iut[i].r, bytes(b for _, b in out), codes, name)
        if len(out) < j:
            i = len(out)
            return Replay(False, f"the IUT sent {iut[i].b:02X} where the model sends nothing "
                                 f"(after {hexstr(bytes(b for _, b in out[-4:])) or 'nothing'})",
                          iut[i].r, bytes(b for _, b in out), codes, name)
        return None

    def flexible(target: float, upto: int) -> float:
        """When the event reaches the model on the stalled timeline (see above): a copy of
        the model runs on without it to see what it sends; ``upto``: the IUT bytes read
        before the next tester event."""
        probe = copy.deepcopy(tr)
        horizon = target + stall
        ahead: list[tuple[float, int]] = []
        while True:
            items = probe.read(horizon + char)
            ahead.extend(items)
            if not items and probe.now() >= horizon + char - 1e-12:
                break
        m0 = len(out)
        best = None
        for i, (done, b) in enumerate(ahead):
            m = m0 + i + 1
            if m > upto or m > len(iut) or iut[m - 1].b != b:
                break
            at = done - char / 2      # byte m still on the line
            if at > horizon:
                break
            best = at
        if best is not None:
            return max(best, tr.now())
        if ahead:                     # before the model's next byte starts
            return max(tr.now(), min(target, ahead[0][0] - char - 1e-6))
        return target

    for idx, e in enumerate(wire.tester):
        k = e.seen
        if k > len(out):   # the model paces its bytes: give it their line time too
            run_until_count(k, tr.now() + max(0.0, iut[k - 1].r - prev_real) + patience + (k - len(out)) * char)
        bad = differ(k)
        if bad is not None:
            return bad
        if k > 0 and iut[k - 1].r >= prev_real and (not model_at or out[k - 1][0] >= prev_model):
            base_real = iut[k - 1].lb if late else iut[k - 1].r
            base_model = out[k - 1][0]
        else:
            base_real, base_model = prev_real, prev_model
        target = max(base_model + (e.t - base_real), tr.now())
        if stall > 0:
            upto = wire.tester[idx + 1].seen if idx + 1 < len(wire.tester) else len(iut)
            target = flexible(target, upto)
        run_until(target)
        if e.kind == "byte":
            tr.write(bytes([e.value]))
        elif e.kind == "invalid":
            tr.send_char_error(e.value)
        else:
            tr.send_break(e.duration)
        prev_real, prev_model = e.t, target
        model_at.append(target)
    end_model = prev_model + (wire.end - prev_real)
    run_until(max(end_model, tr.now()) + margin.late(longest))
    # an IUT that sends faster than the model paces (a block written at once) is ahead of it
    # when the observation ends: let the model catch up (the delays are compared below)
    run_until_count(len(iut), tr.now() + patience + (len(iut) - len(out)) * char)
    bad = differ(len(iut))
    if bad is not None:
        return bad
    # when each byte was sent, compared with the intervals the harness observed: the delay
    # from the line event before it (a tester event, or the IUT's previous byte)
    order = _log_order(wire)
    prev: tuple[str, int] | None = None
    for kind, idx in order:
        if kind == "tester":
            prev = ("tester", idx)
            continue
        j = idx
        m_j = out[j][0]
        if prev is None:
            prev = ("iut", j)
            continue
        if prev[0] == "tester":
            e = wire.tester[prev[1]]
            lo, hi, dm = max(0.0, iut[j].lb - e.t), iut[j].r - e.t, m_j - model_at[prev[1]]
        else:
            p = iut[prev[1]]
            lo, hi, dm = max(0.0, iut[j].lb - p.r), iut[j].r - p.lb, m_j - out[prev[1]][0]
        if hi < dm - margin.early(dm) or lo > dm + margin.late(dm):
            what = "the tester's last stimulus" if prev[0] == "tester" else "its byte before"
            return Replay(False, f"the IUT's byte {j + 1} ({iut[j].b:02X}) came {_ms(lo)}..{_ms(hi)} after {what}; "
                                 f"the model sends it {_ms(dm)} after", iut[j].r,
                          bytes(b for _, b in out), codes, name)
        prev = ("iut", j)
    # the model may not send more than the IUT did before the observation ended
    if len(out) > len(iut):
        m, b = out[len(iut)]
        since = out[len(iut) - 1][0] if iut else 0.0
        if model_at and model_at[-1] > since:
            since = model_at[-1]
        if m + margin.late(max(0.0, m - since)) < end_model:
            at = wire.end - (end_model - m)
            return Replay(False, f"the model sends {b:02X} {_ms(m - since)} after the last event; the IUT sent "
                                 "nothing more", at, bytes(x for _, x in out), codes, name)
    return Replay(True, "", None, bytes(b for m, b in out if m <= end_model + 1e-9), codes, name)


def _log_order(wire: Wire) -> list[tuple[str, int]]:
    """The IUT's bytes and the tester's events in the order the harness saw them: a tester
    event after the ``seen`` IUT bytes read before it."""
    out: list[tuple[str, int]] = []
    j = 0
    for i, e in enumerate(wire.tester):
        while j < e.seen and j < len(wire.iut):
            out.append(("iut", j))
            j += 1
        out.append(("tester", i))
    out += [("iut", x) for x in range(j, len(wire.iut))]
    return out


def _ms(t: float) -> str:
    return f"{t * 1000:.1f} ms"
