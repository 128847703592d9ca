"""The application above an RK 512 station: the CPU program that issues the requests of a
request script on the active side (P_SND_RK) and looks after the coordination flags of the
passive side (P_RCV_RK and the user program, §6.3.2). The passive side serves partners
always; it needs nothing from the application.

Set-ups of the reference IUT (the ``[iut.setups]`` of a profile): ``cpu_stop`` (the CPU is
in STOP: every partner command gets REATEL 2Ah) and ``cf_set`` (flag B.b is set at start
and cleared by the application ``reset_ms`` after it was set, again after every transfer
that sets it). A flag that a transfer sets and ``cf_set`` does not name is cleared after
``flag_reset_ms`` (default 0: at once, the program processes the data at once).
"""

from __future__ import annotations

import re

from ptpcert.model.events import Event

from .events import Ready, RequestResult, Served, Wakeup
from .requests import Request, Wait, parse_script

_SCRIPT = "script"


def parse_cf_set(text: str) -> tuple[int, int, int]:
    """``"12.3@500"`` -> (12, 3, 500): flag byte, bit, reset time in ms."""
    m = re.fullmatch(r"\s*(\d+)\.(\d+)@(\d+)\s*", text)
    if not m:
        raise ValueError(f"{text!r}: a coordination flag and its reset time, B.b@ms (e.g. 12.3@500)")
    byte, bit, ms = (int(x) for x in m.groups())
    if bit > 7:
        raise ValueError(f"{text!r}: the bit number is 0..7")
    return byte, bit, ms


class Rk512Host:
    """A station plus its application. :meth:`drain` runs the application on the station's
    events and returns them all; ``results`` collects the request results in order."""

    def __init__(self, station, script: str | list = (), *, cpu_stop: bool = False,
                 cf_set: list[tuple[int, int, int]] | tuple = (), flag_reset_ms: int = 0):
        self.station = station
        self.script: list[Request | Wait] = parse_script(script) if isinstance(script, str) else list(script)
        self._i = 0
        self._running: Request | None = None
        self._waiting = False
        self._started = False
        self.results: list[RequestResult] = []
        self.flag_reset_ms = flag_reset_ms
        mem = station.memory
        self._locked = station.readings.amb07_locked_value
        self._reset = {}
        for byte, bit, ms in cf_set:
            if not mem.flag_exists(byte, bit):
                raise ValueError(f"flag {byte}.{bit} is outside the flag area of {len(mem.areas['M'])} bytes")
            mem.set_flag(byte, bit, self._locked)
            self._reset[(byte, bit)] = ms
        mem.running = not cpu_stop

    @property
    def done(self) -> bool:
        """Every item of the script has run."""
        return self._i >= len(self.script) and self._running is None and not self._waiting

    def drain(self, now: float | None = None) -> list[Event]:
        out: list = []
        st = self.station
        while True:
            events = st.pop_events()
            if not events:
                return out
            out.extend(events)
            at = st.now if now is None else now
            for e in events:
                cls = type(e)
                if cls is RequestResult:
                    self.results.append(e)
                    if self._running is not None and e.label == self._running.label:
                        self._running = None
                        self._next(at)
                elif cls is Served:
                    if e.flag is not None:
                        ms = self._reset.get(e.flag, self.flag_reset_ms)
                        self._clear_later(at, e.flag, ms)
                elif cls is Wakeup:
                    if e.tag == _SCRIPT:
                        self._waiting = False
                        self._next(at)
                    elif isinstance(e.tag, tuple) and e.tag[0] == "flag":
                        st.memory.set_flag(e.tag[1], e.tag[2], 1 - self._locked)
                elif cls is Ready and not self._started:
                    self._started = True
                    for (byte, bit), ms in self._reset.items():
                        self._clear_later(e.time, (byte, bit), ms)
                    self._next(at)

    def _clear_later(self, at: float, flag: tuple[int, int], ms: int) -> None:
        if ms <= 0:
            self.station.memory.set_flag(flag[0], flag[1], 1 - self._locked)
        else:
            self.station.wake_at(at + ms / 1000.0, ("flag", flag[0], flag[1]))

    def _next(self, at: float) -> None:
        """Run the script on: the next request, or the next wait."""
        st = self.station
        while self._running is None and not self._waiting and self._i < len(self.script):
            item = self.script[self._i]
            self._i += 1
            if isinstance(item, Wait):
                self._waiting = True
                st.wake_at(at + item.ms / 1000.0, _SCRIPT)
            else:
                self._running = item
                st.request(at, item)
