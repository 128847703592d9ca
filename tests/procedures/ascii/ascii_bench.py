"""A tester in virtual time for one ASCII model station: it plays the partner on the line
(sends characters back to back or with gaps, characters with errors, BREAK, modem-line
changes) and records what the station sends, its signals and its events. Used by the
tests of the ASCII model (tests/test_ascii_*.py)."""

from __future__ import annotations

from ptpcert.model.events import Delivered, SendDone, SendFailed, Status
from ptpcert.procedures.ascii.model import AsciiHost, AsciiParams, AsciiStation
from ptpcert.procedures.ascii.model.events import FrameDiscarded, FrameStored
from ptpcert.procedures.ascii.model.readings import READINGS

EPS = 1e-9
IDLE = 0.020   # a line idle for 20 ms: longer than the CDT of every test that uses it
GAP = 0.001    # a 1 ms gap between two characters: shorter than the CDT (4 ms at least)


class Bench:
    def __init__(self, params: AsciiParams | None = None, app: str = "none", *,
                 readings=READINGS, read_delay: float = 0.0, power_on: bool = True, **kw):
        self.p = params or AsciiParams()
        self.st = AsciiStation(self.p, readings, name="iut", explain=True, **kw)
        self.host = AsciiHost(self.st, app, read_delay=read_delay)
        self.char = self.p.char_time
        self.t = 0.0
        self.line_free = 0.0        # the tester's own transmitter
        self.out: list[tuple[float, int]] = []          # the station's characters (start, byte)
        self.signals: list[tuple[float, str, int]] = []
        self.events: list = []
        if power_on:
            self.st.power_on(0.0)
            self._collect(0.0)

    # -- time ---------------------------------------------------------------------------
    def _collect(self, t: float) -> None:
        self.out += self.st.pop_output(t)
        self.signals += self.st.pop_signals(t)
        self.events += self.host.drain(t)

    def _advance(self, until: float, inclusive: bool = True) -> None:
        while True:
            d = self.st.next_deadline()
            if d is None or d > until + EPS or (not inclusive and d >= until - EPS):
                break
            d = max(d, self.st.now)
            self.st.handle_timer(d)
            self._collect(d)

    def run(self, until: float) -> None:
        """Let the station run, with no input, up to ``until``."""
        self._advance(until)
        self.t = max(self.t, until)
        self._collect(self.t)

    def idle(self, d: float = IDLE) -> None:
        """The tester keeps the line idle for ``d`` after its last character."""
        self.run(max(self.t, self.line_free) + d)

    def _arrive(self, at: float, kind: str, value=0) -> None:
        self._advance(at, inclusive=False)
        self.st.line_event(at, kind, value)
        self._collect(at)
        self.t = max(self.t, at)

    # -- the tester's actions -----------------------------------------------------------
    def send(self, data: bytes, gap: float = 0.0, at: float | None = None) -> float:
        """Send characters back to back (or ``gap`` apart), starting at ``at`` (default:
        now, or when the tester's line is free). Returns when the last one is complete."""
        start = max(self.t if at is None else at, self.line_free)
        for i, b in enumerate(data):
            s = start + i * (self.char + gap)
            self._arrive(s + self.char, "byte", b)
            self.line_free = s + self.char
        return self.line_free

    def send_bad(self, byte: int = 0x00, at: float | None = None) -> float:
        """One character with a parity error."""
        start = max(self.t if at is None else at, self.line_free)
        self._arrive(start + self.char, "invalid", byte)
        self.line_free = start + self.char
        return self.line_free

    def brk(self, at: float | None = None) -> None:
        t = max(self.t if at is None else at, self.line_free)
        self._arrive(t, "break")

    def modem(self, name: str, value: int, at: float | None = None) -> None:
        self._arrive(self.t if at is None else at, name, value)

    def request(self, payload: bytes, at: float | None = None) -> bool:
        t = self.t if at is None else at
        self._advance(t, inclusive=False)
        self.t = max(self.t, t)
        ok = self.st.request_send(self.t, payload)
        self._collect(self.t)
        return ok

    def read(self, at: float | None = None) -> bytes | None:
        t = self.t if at is None else at
        self._advance(t, inclusive=False)
        self.t = max(self.t, t)
        frame = self.st.read_frame(self.t)
        self._collect(self.t)
        return frame

    # -- what happened ------------------------------------------------------------------
    def of(self, kind) -> list:
        return [e for e in self.events if isinstance(e, kind)]

    def frames(self) -> list[bytes]:
        """What the application read (NDR, in order)."""
        return [e.payload for e in self.of(Delivered)]

    def stored(self) -> list[bytes]:
        return [e.payload for e in self.of(FrameStored)]

    def discarded(self) -> list[tuple[bytes, str, int | None]]:
        return [(e.data, e.reason, e.code) for e in self.of(FrameDiscarded)]

    def codes(self, side: str | None = None) -> list[int]:
        return [e.code for e in self.of(Status) if side is None or e.side == side]

    def done(self) -> list[bytes]:
        return [e.payload for e in self.of(SendDone)]

    def failed(self) -> list[tuple[bytes, int]]:
        return [(e.payload, e.code) for e in self.of(SendFailed)]

    def wire(self) -> bytes:
        return bytes(b for _, b in self.out)

    def clear(self) -> None:
        self.out.clear()
        self.signals.clear()
        self.events.clear()
