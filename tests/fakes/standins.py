"""Stand-in IUTs that take a reading the manual allows but the reference model does not: each
is the reference station with one defensible difference, run in virtual time through the sim:
transport. A correct implementation may behave like any of them, so the suite must not fail
them (tests/core/test_grading.py). Unlike the broken variants (ptpcert.procedures.p3964.mutants) they are no
defects; they live with the tests and may use the station's internals."""

from __future__ import annotations

from ptpcert.model import events as ev
from ptpcert.model.app import Host
from ptpcert.model.codes import Code
from ptpcert.procedures.p3964.model import table as T
from ptpcert.procedures.p3964.model.codec import MAX_BLOCK
from ptpcert.procedures.p3964.model.params import Params3964
from ptpcert.procedures.p3964.model.station import Station3964
from ptpcert.procedures.p3964.mutants import Counting  # counts the data bytes and doubled DLEs of the block received
from ptpcert.transport import Factory
from ptpcert.transport.sim import SimTransport


def factory(station_class, *, app: str = "echo", host_class=Host, buffer_free: bool = True) -> Factory:
    """A sim: factory whose IUT is ``station_class`` with its application."""
    def make(vector, params: Params3964):
        def host_factory(p):
            st = station_class(p, name="iut")
            if vector is not None and vector.setup is not None and vector.setup[0] == "no_buffer":
                st.buffer_free = False
            return host_class(st, app)
        tester = params.with_(priority="high" if params.priority == "low" else "low")
        if vector is not None and vector.tester_params is not None:
            tester = vector.tester_params
        return SimTransport(params, host_factory, url=f"sim:{station_class.__name__}",
                            char_time=params.char_time, tester_char=tester.char_time)
    return Factory(make, SimTransport.capabilities, virtual=True)


class CountsAfterDoubling(Counting):
    """A17: the 1024-byte limit counts the bytes on the line, doubled DLEs twice: a block whose
    data take more than 1024 bytes after doubling is refused (16#0816)."""

    def _d_evaluate(self):
        if getattr(self, "count", 0) + getattr(self, "pairs", 0) > MAX_BLOCK:
            self._note(Code.FRAME_TOO_LONG)
        return super()._d_evaluate()


class AcceptsOverlong(Station3964):
    """A17: an agreed length above 1024: a 1025-byte block is accepted (non-strict)."""

    def _note(self, code):
        if code != Code.FRAME_TOO_LONG:
            super()._note(code)


class SmallBuffer(Counting):
    """A17 and Table 8-1 16#0816 ('longer than agreed'): an agreed length of 256 bytes, and a
    NAK as soon as a block is longer than that; the rest of the block then comes as stray
    characters."""

    LIMIT = 256

    def _store_run(self, run):
        room = self.LIMIT - getattr(self, "count", 0)
        if len(run) <= room or self.state is not T.RECEIVE:
            return super()._store_run(run)
        super()._store_run(run[:room + 1])
        self._note(Code.FRAME_TOO_LONG)
        self._input(T.T_CDT)              # refuse now, as when the block ends
        if len(run) > room + 1:
            self.receive(self.now, run[room + 1:])


class GuardTime(Station3964):
    """A8: the manual sets no guard time, so a station may pause before what it sends on its
    own: a retry STX after a refused attempt, its final NAK, the STX of a new job (the echo) or
    of a job deferred by a conflict. This one pauses 1.5 x ADT (a timeout's retry is not
    delayed: that is the edge of ADT itself)."""

    def _guard(self) -> float:
        return 1.5 * self.params.adt

    def _a_setup_timeout(self, v):
        super()._a_setup_timeout(v)
        self.timed_out = True

    def _a_release_timeout(self, v):
        super()._a_release_timeout(v)
        self.timed_out = True

    def _d_setup_check(self):
        out = super()._d_setup_check()
        self._hold()
        return out

    def _d_tx_check(self):
        out = super()._d_tx_check()
        self._hold()
        return out

    def _a_start_job(self, v):
        super()._a_start_job(v)
        self.after_pop = True             # an answer to the partner may go out first

    def _hold(self):
        if getattr(self, "timed_out", False):
            self.timed_out = False
        elif self.busy_until - self.now <= self.params.char_time + 1e-9:
            self.delay_output(self._guard())  # only what was just scheduled is waiting
        else:
            self.after_pop = True             # something goes out before it: delay after that

    def pop_output_runs(self, now=None):
        out = super().pop_output_runs(now)
        if getattr(self, "after_pop", False):
            self.after_pop = False
            if self.transmitting:
                self.delay_output(self._guard())
        return out


class AnswersAtEtxLate(Station3964):
    """A 3964 receiver that answers the end of a block after 0.6 x CDT: later than half the
    CDT, still before a BCC-waiting receiver would have timed out."""

    def _d_evaluate(self):
        out = super()._d_evaluate()
        self.delay_output(0.6 * self.params.cdt)
        return out


class NaksPartnersNak(Station3964):
    """A19: a receiver waiting for a repetition takes the partner's NAK for a stray character
    (NAK once the line is quiet, 16#0802)."""

    TABLE = {s: dict(rows) for s, rows in T.TABLE.items()}
    TABLE[T.WAIT_REPETITION][T.NAK] = T.Row("start_quiet_wait", T.IDLE_JUNK)


class DropsDeferredOnBreak(Station3964):
    """A21: a BREAK during a conflict reception ends the deferred job too (as the
    independent implementation of tests/independent reads it)."""

    def _a_abandon_reception(self, v):
        self.deferred = None
        super()._a_abandon_reception(v)


class SendsEmpty(Station3964):
    """Takes a job without data: the echo of an empty block is STX, DLE ETX [BCC]."""

    def request_send(self, now, payload):
        if payload:
            return super().request_send(now, payload)
        self._at(now, strict=True)
        self._jobs.append(b"")
        self._input(T.SEND_REQUEST)
        return True


class EchoesEmpty(Host):
    """The echo convention taken literally: an empty block is sent back too."""

    def drain(self, now=None):
        out = super().drain(now)
        for e in out:
            if isinstance(e, ev.Delivered) and not e.payload:
                self.station.request_send(self.station.now if now is None else now, b"")
        return out + self.station.pop_events()
