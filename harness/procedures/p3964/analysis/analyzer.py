"""The 3964/3964R analyzer: what the procedure brings to line analysis (``ptpcert analyze``,
``ptpcert monitor``).

:class:`P3964Analyzer` is the procedure's
:class:`~ptpcert.analysis.interface.ProcedureAnalyzer`. It holds the timing (how long a quiet
line must be before both stations rest, how late a byte may come), builds the model stations
of each seat (at rest, their receive buffer taken as busy until the seat's DLE shows it free,
or just switched on), names the alternatives to try before a difference stands (a busy
receive buffer, the other readings of the manual's open points, the other seat's bytes moved
within the timing resolution) and labels an exchange ("a STX, b DLE, a block 31 32 (2 bytes,
BCC), b DLE"). What the seat's bytes reveal comes from
:class:`~ptpcert.procedures.p3964.analysis.events.LocalEvents`, why the model sends each byte
and what a byte breaks from :class:`~ptpcert.procedures.p3964.analysis.causes.Causes`. RK
512's analyzer is a subclass (its link is 3964(R)).
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

from ptpcert.analysis.interface import OTHER, SEATS, ProcedureAnalyzer, Variant, resolution_variants
from ptpcert.model.app import Host
from ptpcert.procedures.p3964.analysis.causes import Causes, timer_duration
from ptpcert.procedures.p3964.analysis.events import LocalEvents
from ptpcert.procedures.p3964.model.codec import DLE, ETX
from ptpcert.procedures.p3964.model.params import T_NAKTIM
from ptpcert.procedures.p3964.model.readings import READINGS
from ptpcert.procedures.p3964.model.station import Station3964

_BUFFER_WORDS = ("with its receive buffer not free when the partner's STX came (the application's buffer is "
                 "not on the line: Fig. 2-11 'buffer not free', DLE once one is free or NAK after T_NAKTIM)")

#: the readings of the open points the alternatives take, in words
_READING_WORDS = {
    "A4": "the setup counter is not reset for a new transmission attempt",
    "A6": "a second NAK ends the last transmission attempt",
    "A7": "a quiet wait is not restarted by further characters",
    "A10": "a DLE during the end sequence counts as a character during the block",
    "A11": "DLE followed by another character is answered by NAK at once",
    "A12": "T_ADT at release runs from DLE ETX",
    "A13": "a character error in idle is not answered by NAK",
    "A17": "a zero-length block is refused",
    "A19": "a NAK while waiting for a repetition ends the wait with another code",
    "A21": "the collided STX of an initialization conflict is not counted",
    "A23": "a high-priority station restarts T_ADT at the partner's STX",
}


class P3964Analyzer(LocalEvents, Causes, ProcedureAnalyzer):
    """Line analysis of a 3964/3964R link (see the module docstring). ``late_ms`` is the
    tolerance of the timing windows (see :mod:`~ptpcert.procedures.p3964.analysis.causes`)."""

    reference = "§2.2.2; Figs. 2-5 to 2-12"

    def __init__(self, procedure: Any, params: dict[str, Any], apps: dict[str, str] | None = None,
                 late_ms: float = 50.0):
        super().__init__(procedure, params, apps)
        self.late_abs = late_ms / 1000.0
        self._longest = max(max(p.cdt, p.adt) for p in self.params.values())
        self._rest = (1.25 * max(self._longest, T_NAKTIM) + self.late_abs
                      + 4 * max(self.char(s) for s in SEATS))
        #: the send jobs the line revealed that a CP 341 refuses (no data, or more than it takes):
        #: (seat, index of the STX in the seat's items) -> their data
        self.unsendable: dict[tuple[str, int], bytes] = {}
        self._variants: list[Variant] | None = None

    # -- timing ---------------------------------------------------------------------------
    def rest_gap(self) -> float:
        return self._rest

    def early_wait(self, host: Host) -> float:
        st = host.station
        running = st.timer
        c = st.params.char_time
        if running is None:
            return c + 3e-6
        return c + 0.05 * timer_duration(st.params, running[0]) + 3e-6

    def late_max(self, seat: str) -> float:
        p, q = self.params[seat], self.params[OTHER[seat]]
        return max(q.adt, q.cdt, self.late_abs + 0.25 * max(p.cdt, p.adt, T_NAKTIM), self._rest)

    # -- stations -------------------------------------------------------------------------
    def _station(self, seat: str, readings: Any = None) -> Station3964:
        return Station3964(self.params[seat], readings or READINGS, name=seat, explain=True)

    def fresh(self, seat: str, t: float, readings: Any = None) -> Host:
        st = self._station(seat, readings)
        c = self.char(seat)
        on = t - 2 * c - 1e-6
        st.set_buffer_free(on, False)   # busy until the station's DLE shows it free (see .events)
        st.power_on(on)
        st.pop_output()
        st.pop_events()
        st.tx_log.clear()
        return Host(st, "none" if self.apps[seat] == "none" else "echo")

    def powered(self, seat: str, t: float) -> Host:
        st = self._station(seat)
        st.set_buffer_free(t, False)
        st.power_on(t)
        return Host(st, "none" if self.apps[seat] == "none" else "echo")

    def at_rest(self, host: Host) -> bool:
        return host.station.idle

    # -- alternatives ---------------------------------------------------------------------
    def variants(self, seat: str, resolution: float) -> list[Variant]:
        out = resolution_variants(resolution, "send jobs and free buffers")
        if self._variants is None:
            kit = self.procedure.fuzz_kit()
            # every alternative starts with its receive buffer busy (see fresh): this one with
            # nothing else changed says that a busy buffer explains the seat (Fig. 2-11)
            self._variants = [Variant("buffer", _BUFFER_WORDS, kind="buffer")] + [
                Variant(name, f"with the other reading of the manual's open point {name} "
                              f"({_READING_WORDS.get(name, 'see ptpcert.procedures.p3964.model.readings')})",
                        readings=replace(READINGS, **change))
                for name, change in (kit.alternatives if kit is not None else ())]
        return out + self._variants

    # -- reports --------------------------------------------------------------------------
    def describe(self, seat: str, its: list) -> str:
        """E.g. "STX", "block 31 10 32 (3 bytes, BCC)" or "DLE BREAK" (see :meth:`label`)."""
        parts = []
        data = bytearray()

        def flush() -> None:
            if data:
                parts.append(self._run_text(bytes(data)))
                data.clear()

        for it in its:
            if it.kind == "break":
                flush()
                parts.append("BREAK")
            elif it.kind == "invalid":
                flush()
                parts.append(f"{it.value:02X}(error)")
            else:
                data.append(it.value)
        flush()
        return " ".join(parts)

    def _run_text(self, data: bytes) -> str:
        if len(data) == 1:
            return self.name(data[0])
        end = data.find(bytes((DLE, ETX)))
        while end > 0:
            # an even number of DLEs before it: a real DLE ETX
            n = 0
            while end - 1 - n >= 0 and data[end - 1 - n] == DLE:
                n += 1
            if n % 2 == 0:
                break
            end = data.find(bytes((DLE, ETX)), end + 1)
        if end >= 0:
            payload = bytes(data[:end]).replace(bytes((DLE, DLE)), bytes((DLE,)))
            shown = payload[:8].hex(" ").upper() + (" ..." if len(payload) > 8 else "")
            tail = len(data) - end - 2
            return f"block {shown} ({len(payload)} bytes{', BCC' if tail == 1 else ''})".replace("block  (", "block (")
        if len(data) <= 6:
            return " ".join(self.name(x) for x in data)
        return data[:6].hex(" ").upper() + f" ... ({len(data)} bytes)"
