"""ptpcert.driver.drive_station on a virtual line that can stall the station's process: input
that was waiting when the process got the processor back goes before a timer that expired
while it was not running (issue 10, false alarm 5: the reference IUT under load)."""

import pytest

from ptpcert.driver import Endpoint, drive_station
from ptpcert.model.app import Host
from ptpcert.model.events import Delivered, Status
from ptpcert.procedures.p3964.model import codec
from ptpcert.procedures.p3964.model.params import Params3964
from ptpcert.procedures.p3964.model.station import Station3964

P = Params3964(procedure="3964R", cdt_ms=20, adt_ms=20)
STX, DLE, NAK = 0x02, 0x10, 0x15


class StallingLine(Endpoint):
    """A line in virtual time. ``inputs``: (time the byte is in the pipe, byte). While
    ``stall`` = (from, to) the station's process does not run: a poll that would wake up
    inside it returns at ``to`` with everything that has arrived by then."""

    def __init__(self, inputs, stall=None):
        self.t = 0.0
        self.inputs = sorted(inputs)
        self.stall = stall
        self.written: list[tuple[float, int]] = []

    def now(self):
        return self.t

    def poll(self, deadline):
        nxt = self.inputs[0][0] if self.inputs else float("inf")
        wake = min(deadline, nxt)
        if self.stall and self.stall[0] <= wake < self.stall[1]:
            wake = self.stall[1]
        self.t = max(self.t, wake)
        out = [(self.t, "byte", b) for at, b in self.inputs if at <= self.t]
        self.inputs = [x for x in self.inputs if x[0] > self.t]
        return out

    def write(self, data):
        self.written += [(self.t, b) for b in data]
        return self.t


def _run(stall):
    """The tester sends STX at 10 ms, and its block 2 ms after the station's DLE has
    reached it: well inside the station's CDT."""
    char = P.char_time
    stx_at = 0.010
    dle_done = stx_at + char          # the station answers at once; its DLE is complete here
    block = codec.body(b"ABC", "3964R")
    first = dle_done + 0.002
    inputs = [(stx_at, STX)] + [(first + (i + 1) * char, b) for i, b in enumerate(block)]
    st = Station3964(P, name="iut")
    line = StallingLine(inputs, stall)
    st.power_on(0.0)
    host = Host(st, "none")
    events = []
    drive_station(host, line, on_event=events.append, until=0.2)
    return line, events, first


def test_a_punctual_station_accepts_the_block():
    line, events, _ = _run(stall=None)
    assert [b for _, b in line.written][:3] == [NAK, DLE, DLE]   # start-up NAK, setup DLE, block DLE
    assert [e.payload for e in events if isinstance(e, Delivered)] == [b"ABC"]


def test_input_waiting_after_a_stall_goes_before_the_expired_timer():
    # the process is descheduled from just after its DLE until well after its CDT would
    # have run out; the whole block is in the pipe when it runs again
    _, _, first = _run(stall=None)
    stall = (first - 0.001, first + P.cdt + 0.030)
    line, events, _ = _run(stall=stall)
    sent = [b for _, b in line.written]
    assert sent[:3] == [NAK, DLE, DLE], [f"{b:02X}" for b in sent]
    assert NAK not in sent[1:]
    assert [e.payload for e in events if isinstance(e, Delivered)] == [b"ABC"]
    assert not [e for e in events if isinstance(e, Status)]


def test_a_timer_still_runs_out_when_nothing_came():
    # no block at all: the stall only delays the CDT timeout, it does not prevent it
    char = P.char_time
    st = Station3964(P, name="iut")
    line = StallingLine([(0.010, STX)], stall=(0.010 + char + 0.005, 0.010 + char + P.cdt + 0.030))
    st.power_on(0.0)
    drive_station(Host(st, "none"), line, until=0.3)
    sent = [b for _, b in line.written]
    assert sent == [NAK, DLE, NAK]
    assert line.written[-1][0] == pytest.approx(0.010 + char + P.cdt + 0.030 + char, abs=1e-6)


class LateLine(StallingLine):
    """Each write takes ``busy`` seconds before the byte is out (the process was busy or
    waited for a CPU); the endpoint records what the loop reports as late."""

    def __init__(self, inputs, busy):
        super().__init__(inputs)
        self.busy = busy
        self.lateness: list[float] = []

    def write(self, data):
        self.t += self.busy
        return super().write(data)

    def late(self, seconds):
        self.lateness.append(seconds)


@pytest.mark.parametrize("busy", [0.0, 0.004, 0.017])
def test_the_loop_reports_how_late_each_byte_went_out(busy):
    """A station's reply that goes out later than its plan is reported to the endpoint (the
    runner re-judges a failed attempt with it: its partner's DLE after an IUT's long block, 17 ms
    late under load, once passed as the IUT's fault)."""
    st = Station3964(P, name="iut")
    line = LateLine([(0.010, STX)], busy)
    st.power_on(0.0)
    drive_station(Host(st, "none"), line, until=0.05)
    assert [b for _, b in line.written][:2] == [NAK, DLE]
    assert len(line.lateness) == len(line.written)
    assert line.lateness[1] == pytest.approx(busy, abs=1e-9)
    assert all(x >= -1e-9 for x in line.lateness)
