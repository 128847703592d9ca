"""3964(R) variants that break a timer: the CDT, the ADT and T_NAKTIM (Table 2-4, Fig. 2-11).

Part of :mod:`ptpcert.procedures.p3964.mutants`. Each runs one of the station's timers
for the wrong time (half of it), or not at all where the manual starts it. The repetition
wait T_BLOCK is broken only together with what follows it (:mod:`.receiving`). A
``# SUITE...`` comment above a variant names the case of the rules catalogue it was made for.
"""

from __future__ import annotations

from ptpcert.procedures.p3964.model import table as T
from ptpcert.procedures.p3964.model.params import T_NAKTIM
from ptpcert.procedures.p3964.model.station import Station3964

from .registry import mutant


@mutant("adt-half", "Table 2-4: the sender waits only half the ADT for DLE")
class _(Station3964):
    def _durations(self):
        cdt, adt = super()._durations()
        return cdt, adt / 2


@mutant("cdt-half", "Table 2-4: the receiver times out after half the CDT")
class _(Station3964):
    def _durations(self):
        cdt, adt = super()._durations()
        return cdt / 2, adt


@mutant("no-cdt-after-dle", "Table 8-1 16#0806: no timeout for the first character after the receiver's DLE")
class _(Station3964):
    def _d_receive_entry(self):
        out = super()._d_receive_entry()
        if out == T.RECEIVE:
            self._stop_timer()
        return out


# SUITE.TIMING.GAP-AT-80-CDT-IN-DLE-PAIR
@mutant("cdt-half-after-data-dle", "Fig. 2-12 'wait for ETX', 'start T_CDT': after a DLE in the data the receiver waits only half the CDT")
class _(Station3964):
    def _a_dle_received(self, v):
        super()._a_dle_received(v)
        self._start_timer(T.T_CDT, self._durations()[0] / 2)


# SUITE.RECEIVE.NO-FREE-BUFFER
@mutant("buffer-wait-too-short", "Fig. 2-11 'T_NAKTIM = 400 ms': with no free buffer the STX is answered with NAK after 200 ms")
class _(Station3964):
    def _d_receive_entry(self):
        out = super()._d_receive_entry()
        if out is T.WAIT_BUFFER:
            self._start_timer(T.T_NAKTIM, T_NAKTIM / 2)
        return out
