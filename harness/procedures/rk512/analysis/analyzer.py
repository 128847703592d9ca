"""The RK 512 analyzer: 3964(R)'s line analysis with an RK 512 frame layer on each seat.

:class:`Rk512Analyzer` is the procedure's
:class:`~ptpcert.analysis.interface.ProcedureAnalyzer`, a subclass of 3964's
(:class:`~ptpcert.procedures.p3964.analysis.P3964Analyzer`): the link below RK 512 is judged
exactly as a stand-alone 3964(R) link is (blocks, acknowledgements, retries, timers). Each
model station it builds carries the seat's frame layer
(:class:`~ptpcert.procedures.rk512.analysis.frames.SeatFrames`), and that layer's deadlines as
its own (the line analysis drives every deadline through the station). The analyzer overrides
the hooks of 3964's read-ahead (``_seen``, ``_payload``, ``_request``) to hand the frame layer
each block a seat begins to send, and passes it the link's events: a block delivered, sent,
or given up on. A station is at rest only while its frame layer is: a command, its
continuation frames and their responses are one exchange, labelled e.g. "a SEND DB10 DW0 20
bytes, b REATEL 00". The alternatives of the frame layer come from
:class:`~ptpcert.procedures.rk512.analysis.replays.Replays`, mixed in.
"""

from __future__ import annotations

from dataclasses import dataclass
from math import inf
from typing import TYPE_CHECKING, Any

from ptpcert.analysis import OTHER, SEATS, Cause, clipped
from ptpcert.analysis.interface import EPS
from ptpcert.model.app import Host
from ptpcert.model.events import Delivered, SendDone, SendFailed
from ptpcert.procedures.p3964.analysis import HIGH_KEEPS, P3964Analyzer
from ptpcert.procedures.p3964.model import codec as L
from ptpcert.procedures.p3964.model.readings import READINGS
from ptpcert.procedures.p3964.model.station import Station3964
from ptpcert.procedures.rk512.analysis.frames import SeatFrames
from ptpcert.procedures.rk512.analysis.replays import Replays
from ptpcert.procedures.rk512.model import codec as K
from ptpcert.procedures.rk512.model.params import Rk512Params

if TYPE_CHECKING:
    from ptpcert.procedures.rk512.analysis.probe import Probe


@dataclass(frozen=True)
class FrameDue:
    """A deadline of the frame layer was reached (an event of the analysis, not of a station)."""

    time: float


class _LinkStation(Station3964):
    """The seat's 3964(R) station, carrying the frame layer's deadlines as its own (the line
    analysis drives every deadline through the station)."""

    frames: SeatFrames | None = None

    def __init__(self, *args, **kw):
        super().__init__(*args, **kw)
        self._due: list[FrameDue] = []

    def next_deadline(self):
        d = super().next_deadline()
        f = self.frames.deadline() if self.frames is not None else inf
        if f < inf and (d is None or f < d):
            return f
        return d

    def handle_timer(self, now: float) -> None:
        super().handle_timer(now)
        f = self.frames.deadline() if self.frames is not None else inf
        if f <= now + EPS:
            self._due.append(FrameDue(now))

    @property
    def has_events(self) -> bool:
        return bool(self._due) or super().has_events

    def pop_events(self):
        out = super().pop_events()
        if self._due:
            out = out + self._due
            self._due = []
        return out


class _Rk512LinkHost(Host):
    """The seat's link station with its RK 512 frame layer (``frames``)."""

    def __init__(self, station: _LinkStation, frames: SeatFrames):
        super().__init__(station, "none")
        self.frames = frames
        station.frames = frames


# ------------------------------------------------------------------ the analyzer


class Rk512Analyzer(Replays, P3964Analyzer):
    """Line analysis of an RK 512 link: the 3964(R) link and the RK 512 frames (module docstring).
    ``rk_params`` maps each seat to its
    :class:`~ptpcert.procedures.rk512.model.params.Rk512Params`."""

    reference = "§2.2.3; Figs. 2-13 to 2-19; Tables 2-1, 2-2, 8-3"

    def __init__(self, link_procedure: Any, rk_params: dict[str, Rk512Params], late_ms: float = 50.0):
        super().__init__(link_procedure, {s: rk_params[s].line for s in SEATS}, {"a": "none", "b": "none"}, late_ms)
        self.rk = dict(rk_params)
        self._checker: dict[str, Probe] = {}
        self._alts: list | None = None
        self._cut: bytes | None = None
        #: per seat, the latest block whose end the line does not show
        self._partial: dict[str, bytes] = {}

    def quiet(self) -> float:
        """How long a quiet line must be before no RK 512 request can be open."""
        return 1.25 * max(p.t_res for p in self.rk.values()) + self.late_abs

    # -- stations -------------------------------------------------------------------------
    def _station(self, seat: str, readings: Any = None) -> Station3964:
        return _LinkStation(self.params[seat], readings or READINGS, name=seat, explain=True)

    def fresh(self, seat: str, t: float, readings: Any = None) -> Host:
        host = super().fresh(seat, t, readings)
        return _Rk512LinkHost(host.station, SeatFrames(self, seat))

    def powered(self, seat: str, t: float) -> Host:
        host = super().powered(seat, t)
        return _Rk512LinkHost(host.station, SeatFrames(self, seat, anchored=True))

    def at_rest(self, host: Host) -> bool:
        return host.station.idle and host.frames.resting

    def begins_in(self, host: Host, byte: int) -> bool:
        """An STX begins an exchange only while no RK 512 request is open on the seat: a
        response, a continuation command belong to the exchange of their request."""
        return self.begins(byte) and host.frames.resting

    def wrong(self, run, item, byte: int, cause: Cause) -> Cause:
        """A high-priority station that answers the partner's crossing STX with DLE, where
        the model sends its block after the partner's DLE, breaks the initialization
        conflict's rule (Fig. 2-8), not the block's."""
        inputs, k = run.judge.inputs, run.i_in
        if (item.kind == "byte" and item.value == L.DLE and run.st.params.priority == "high" and k >= 2
                and [(x.kind, x.value) for x in inputs[k - 2:k]] == [("byte", L.STX), ("byte", L.DLE)]):
            return Cause("reply", *HIGH_KEEPS, 0.0, 0.0, rules=("3964.CONFLICT.HIGH-WAITS",))
        return super().wrong(run, item, byte, cause)

    # -- the frame layer's inputs ---------------------------------------------------------
    def _seen(self, best: bytes, data: bytearray) -> bytes | None:
        out = super()._seen(best, data)
        self._cut = out         # the line shows no end of this block
        return out

    def _payload(self, run, index: int) -> Any:
        self._cut = None
        out = super()._payload(run, index)
        if isinstance(out, bytes) and out == self._cut:
            self._partial[run.judge.seat] = out
        return out

    def _request(self, run, t: float, payload: bytes) -> None:
        frames = getattr(run.host, "frames", None)
        if frames is not None:
            seat = run.judge.seat
            frames.handed_over(run, t, payload, self._partial.get(seat) == payload)
        super()._request(run, t, payload)

    def event(self, run, e) -> None:
        super().event(run, e)
        frames = getattr(run.host, "frames", None)
        if frames is None:
            return
        cls = type(e)
        if cls is Delivered:
            frames.received(run, e.time, e.payload)
        elif cls is SendDone:
            frames.sent(run, e.time, e.payload)
        elif cls is SendFailed:
            frames.failed(run, e.time, e.payload)
        elif cls is FrameDue:
            frames.due(run, e.time)

    # -- reports --------------------------------------------------------------------------
    def label(self, items) -> str:
        """The RK 512 frames of an exchange, e.g. "a SEND DB10 DW0 20 bytes, b REATEL 00"."""
        frames = _frames_of(items, {s: self.params[s].has_bcc for s in SEATS})
        if not frames:
            return super().label(items)
        words = []
        for seat, f in frames:
            kind = K.classify(f)
            if kind in (K.Kind.RESPONSE, K.Kind.CONTINUATION_RESPONSE) and len(f) >= 4:
                text = ("REATEL 00" if f[3] == 0 else f"REATEL {f[3]:02X}h") + (
                    f" + {len(f) - 4} bytes" if len(f) > 4 else "")
                if kind is K.Kind.CONTINUATION_RESPONSE:
                    text = "continuation " + text
            else:
                text = K.describe(f)
            words.append(f"{seat} {text}")
        return clipped(", ".join(words), 240)


def _frames_of(items, bcc: dict[str, bool]) -> list[tuple[str, bytes]]:
    """The blocks of an exchange's items as (seat, user data), in the order they ended: a
    block begins after the other seat's DLE answers an STX and ends with DLE ETX (the BCC
    after it skipped)."""
    out = []
    state = {s: None for s in SEATS}       # None, "stx", or a bytearray being received
    esc = {s: False for s in SEATS}
    skip = {s: 0 for s in SEATS}
    for seat, it in items:
        other = OTHER[seat]
        if it.kind != "byte":
            state[seat] = None
            continue
        b = it.value
        if skip[seat]:
            skip[seat] -= 1
            continue
        blk = state[seat]
        if isinstance(blk, bytearray):
            if esc[seat]:
                esc[seat] = False
                if b == 0x10:
                    blk.append(b)
                elif b == 0x03:
                    out.append((seat, bytes(blk)))
                    state[seat] = None
                    skip[seat] = 1 if bcc[seat] else 0
                else:
                    blk += bytes((0x10, b))
            elif b == 0x10:
                esc[seat] = True
            else:
                blk.append(b)
            continue
        if b == 0x02:
            state[seat] = "stx"
        elif b == 0x10 and state[other] == "stx":
            state[other], esc[other] = bytearray(), False
    return out
