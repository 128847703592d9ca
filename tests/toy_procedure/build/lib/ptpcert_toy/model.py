"""The toy procedure's model, sans-IO and in explicit time: a station that answers every ENQ
it receives with one ACK, its reply delay (RDT) after the ENQ arrived, and ignores every other
character and line condition. Standard library and ptpcert's neutral model only."""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass

from ptpcert.model.errors import ParameterError
from ptpcert.model.line import BAUD_RATES, LineSettings

ENQ, ACK = 0x05, 0x06
_EPS = 1e-9


@dataclass(frozen=True)
class ToyParams:
    reply_delay_ms: int = 20
    baud_rate: int = 9600

    def __post_init__(self) -> None:
        if isinstance(self.reply_delay_ms, bool) or not isinstance(self.reply_delay_ms, int) \
                or not 10 <= self.reply_delay_ms <= 1000:
            raise ParameterError("reply_delay_ms", self.reply_delay_ms, "10 to 1000 (ms)")
        if self.baud_rate not in BAUD_RATES:
            raise ParameterError("baud_rate", self.baud_rate, ", ".join(map(str, BAUD_RATES)))

    @property
    def line(self) -> LineSettings:
        return LineSettings(self.baud_rate, 8, "none", 1)

    @property
    def char_time(self) -> float:
        return self.line.char_time

    @property
    def reply(self) -> float:
        return self.reply_delay_ms / 1000.0


class ToyStation:
    """The station, with the driver interface ptpcert's transports and driver use."""

    def __init__(self, params: ToyParams, name: str = "iut"):
        self.params, self.name = params, name
        self.now = 0.0
        self.late_timers_act_now = False
        self._replies: deque[float] = deque()        # when each ACK is due
        self._tx: deque[tuple[float, int]] = deque()  # (start on the line, byte)
        self._busy = 0.0                              # the line is ours until then

    @property
    def idle(self) -> bool:
        return not self._replies and not self._tx

    def power_on(self, now: float) -> None:
        self.now = now

    def line_event(self, now: float, kind: str, value: int = 0) -> None:
        self.now = max(self.now, now)
        if kind == "byte" and value == ENQ:
            self._replies.append(now + self.params.reply)

    def next_deadline(self) -> float | None:
        return self._replies[0] if self._replies else None

    def handle_timer(self, now: float) -> None:
        self.now = max(self.now, now)
        while self._replies and self._replies[0] <= now + _EPS:
            self._replies.popleft()
            start = max(now, self._busy)
            self._tx.append((start, ACK))
            self._busy = start + self.params.char_time

    def pop_output(self, now: float | None = None) -> list[tuple[float, int]]:
        out = []
        while self._tx and (now is None or self._tx[0][0] <= now + _EPS):
            out.append(self._tx.popleft())
        return out

    def delay_output(self, late: float) -> None:
        self._tx = deque((t + late, b) for t, b in self._tx)
        self._busy += late

    def pop_events(self) -> list:
        return []

    def request_send(self, now: float, payload: bytes) -> bool:
        return False    # a toy station has no send jobs
