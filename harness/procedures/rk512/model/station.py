"""An RK 512 station: the RK 512 layer (:class:`~.core.Rk512Core`) over a 3964(R) station,
which stays the link (§2.2.1: RK 512 uses 3964(R) for all line traffic; every RK 512 frame
is the user data of one 3964(R) block, §2.2.3).

:class:`Rk512Station` presents the same driver interface as
:class:`~ptpcert.procedures.p3964.model.station.Station3964` (``power_on``, ``line_event``,
``next_deadline``, ``handle_timer``, ``pop_output[_runs]``, ``pop_events``,
``delay_output``, ``request_send``, ``idle``, ``pending_jobs``, ``state``, ``params`` with
``char_time``, ``late_timers_act_now``), so ``drive_station``, the ``sim:`` transport and
``model.link.Link`` carry it as they carry a 3964(R) station. It uses only the 3964(R)
station's public interface.

Events: the link's STATUS events pass through; its block events become RK 512 events
(:mod:`.events`): ``FrameReceived`` for a block delivered, ``FrameSent``/``FrameNotSent``
for a block of ours acknowledged or given up, plus ``RequestResult``, ``Served``, ``Ready``
and ``Wakeup``. ``request_send`` sends one raw frame (a tester's), outside both sides.
"""

from __future__ import annotations

from math import inf

from ptpcert.model.errors import ModelError
from ptpcert.model.events import Delivered, SendDone, SendFailed, Status
from ptpcert.procedures.p3964.model.codec import DLE
from ptpcert.procedures.p3964.model.readings import READINGS, Readings
from ptpcert.procedures.p3964.model.station import Station3964

from .core import Rk512Core
from .memory import Memory
from .params import Rk512Params
from .readings import RK512_READINGS, Rk512Readings
from .requests import Request

_EPS = 1e-9
_RECEIVE = "RECEIVE"


class Rk512Station(Rk512Core):
    """One RK 512 endpoint (both sides) over its own 3964(R) station, ``link``."""

    def __init__(self, params: Rk512Params | None = None, readings: Rk512Readings = RK512_READINGS,
                 *, link_readings: Readings = READINGS, memory: Memory | None = None,
                 name: str = "station", explain: bool = False, trace: bool = False):
        super().__init__(params, readings, memory=memory, name=name, explain=explain, trace=trace)
        self.link = Station3964(self.params.line, link_readings, name=name, explain=explain)
        self._late = False

    # -- the driver's switch for late wake-ups applies to both layers -----------------------
    @property
    def late_timers_act_now(self) -> bool:
        return self._late

    @late_timers_act_now.setter
    def late_timers_act_now(self, value: bool) -> None:
        self._late = bool(value)
        self.link.late_timers_act_now = bool(value)

    # ============================================================== driver interface
    def power_on(self, now: float) -> None:
        self._advance(now, strict=True)
        self.link.power_on(now)
        self._pump_link()
        super().power_on(now)

    def line_event(self, now: float, kind: str, value=0) -> None:
        """A character (``"byte"``), characters completed at one instant (``"bytes"``), a
        character with a parity/framing error (``"invalid"``) or a BREAK (``"break"``)."""
        self._advance(now, strict=True)
        link = self.link
        if kind == "byte":
            link.receive(now, value)
            self._pump_link()
        elif kind == "bytes":
            self._feed(now, bytes(value))
        elif kind == "invalid":
            link.receive_invalid(now, value)
            self._pump_link()
        elif kind == "break":
            link.line_break(now)
            self._pump_link()
        else:
            raise ModelError(f"{self.name}: unknown line event {kind!r}")
        self._at(now)

    def receive(self, now: float, data: bytes | bytearray | int) -> None:
        """Characters received intact, all completed at ``now``."""
        if isinstance(data, int):
            self.line_event(now, "byte", data)
        else:
            self.line_event(now, "bytes", data)

    def receive_invalid(self, now: float, value: int = 0) -> None:
        self.line_event(now, "invalid", value)

    def line_break(self, now: float) -> None:
        self.line_event(now, "break")

    def request_send(self, now: float, payload: bytes) -> bool:
        """Send one frame as it is (the tester's raw frame), outside both sides. False (the
        link refuses it with 16#1E41) for a length outside 1..1024."""
        self._advance(now, strict=True)
        self.send_raw(now, payload)
        self._pump_link()
        self._at(now)
        return 1 <= len(payload) <= 1024

    def request(self, now: float, req: Request | str) -> bool:
        self._advance(now, strict=True)
        ok = super().request(now, req)
        self._pump_link()
        return ok

    def restart(self, now: float) -> None:
        self._advance(now, strict=True)
        super().restart(now)
        self._pump_link()

    def next_deadline(self) -> float | None:
        d = self.link.next_deadline()
        t = self.own_deadline()
        if d is not None and d < t:
            t = d
        return None if t == inf else t

    def handle_timer(self, now: float) -> None:
        self._advance(now, strict=False)
        self._at(now)

    def pop_output(self, now: float | None = None) -> list[tuple[float, int]]:
        return self.link.pop_output(now)

    def pop_output_runs(self, now: float | None = None) -> list[tuple[float, bytes]]:
        return self.link.pop_output_runs(now)

    def delay_output(self, delta: float) -> None:
        self.link.delay_output(delta)

    @property
    def idle(self) -> bool:
        return self.link.idle and Rk512Core.idle.fget(self)

    @property
    def state(self) -> str:
        """The link's state (the 3964(R) flowcharts' names); the RK 512 sides' states are
        ``a_state`` and ``p_state``."""
        return self.link.state

    # ============================================================== internals
    def _lower_send(self, now: float, frame: bytes) -> None:
        self.link.request_send(now, frame)

    def _advance(self, now: float, strict: bool) -> None:
        """Handle the deadlines of both layers before ``now`` (``strict``) or up to and
        including it, in time order; a link deadline goes before an own timer of the same
        instant."""
        link = self.link
        late = self._late
        while True:
            t = self.own_deadline()
            if t == inf or (t >= now - _EPS if strict else t > now + _EPS):
                break
            at = now if late else t
            link.handle_timer(at if at > link.now else link.now)
            self._pump_link()
            if self.own_deadline() != t:
                continue  # the link's events moved our timers: look again
            self._fire(at)
        if not strict:
            link.handle_timer(now if now > link.now else link.now)
            self._pump_link()
            if self.own_deadline() <= now + _EPS:
                self._advance(now, strict)

    def _feed(self, now: float, data: bytes) -> None:
        """Characters of one instant, handed to the link so that the RK 512 layer sees each
        block event before the characters after it (a run inside a block in one piece)."""
        link = self.link
        i, n = 0, len(data)
        while i < n:
            if link.state == _RECEIVE:
                j = data.find(DLE, i)
                if j < 0:
                    j = n
                if j > i:
                    link.receive(now, data[i:j])
                    i = j
                    continue
            link.receive(now, data[i])
            i += 1
            self._pump_link()

    def _pump_link(self) -> None:
        """The link's events: STATUS passes through, blocks become frames."""
        link = self.link
        while True:
            events = link.pop_events()
            if not events:
                return
            for e in events:
                t = e.time if e.time > self.now else self.now
                cls = type(e)
                if cls is Status:
                    self._events.append(e)
                elif cls is Delivered:
                    self.frame_received(t, e.payload)
                elif cls is SendDone:
                    if self._inflight is not None:
                        self.frame_sent(t)
                elif cls is SendFailed:
                    if self._inflight is not None:
                        self.frame_failed(t, e.code)
