"""The application above an RK 512 station (request scripts, coordination-flag resets, CPU
STOP), the IUT interface lines, the ideal frame link, and the driver interface: an
Rk512Station runs under drive_station, the sim: transport and model.link.Link as a 3964(R)
station does."""

from collections import deque
from math import inf

import pytest
from rk512_helpers import codes, of, params, results
from rk512_rules import DLE, STX, body, header, response

from ptpcert.driver import Endpoint, drive_station
from ptpcert.model.codes import Code
from ptpcert.model.events import Status
from ptpcert.model.link import Link
from ptpcert.procedures.p3964.model.params import Params3964
from ptpcert.procedures.rk512.model import (
    FrameLink,
    RequestResult,
    Rk512Core,
    Rk512Host,
    Rk512Params,
    Rk512Station,
    interface_lines,
    parse_cf_set,
)
from ptpcert.procedures.rk512.model.events import FrameReceived, FrameSent, Ready
from ptpcert.transport.sim import SimTransport

SCRIPT = """
send DB10:DW0:LEN=200
fetch E:0:LEN=10          # inputs
wait 500
send DX7:OFF=6:LEN=5:CF=12.3:CPU=2:DATA=0102031004
fetch DB250:DW0:LEN=2     # no such DB at the partner
send DB0:DW0:LEN=2        # refused before the wire
"""


def hosts_pair(script, b_host=None, baud=9600, **kw):
    a = Rk512Station(params("high", baud, **kw), name="a")
    b = Rk512Station(params("low", baud, **kw), name="b")
    ha = Rk512Host(a, script)
    hb = b_host(b) if b_host else Rk512Host(b)
    # the partner is up first: a script that starts at power-on while the partner's start-up
    # NAK is on the line has its first STX refused (3964R retries, 16#0702 / 16#0701)
    link = Link(b, a, hosts={"a": ha, "b": hb})
    link.power_on(0.0, b_at=0.1)
    return link, a, b, ha, hb


def test_script_runs_in_order():
    link, a, b, ha, hb = hosts_pair(SCRIPT)
    assert link.run_until_quiet(120)
    assert ha.done
    got = [(r.label, r.ok, r.code) for r in ha.results]
    assert got == [
        ("send:DB10:DW0:LEN=200", True, None),
        ("fetch:E:0:LEN=10", True, None),
        ("send:DX7:OFF=6:LEN=5:CF=12.3:CPU=2:DATA=0102031004", True, None),
        ("fetch:DB250:DW0:LEN=2", False, Code.PARTNER_DB_ACCESS),
        ("send:DB0:DW0:LEN=2", False, Code.ADDRESS_OUT_OF_RANGE),
    ]
    assert ha.results[1].data == bytes(0x40 + i for i in range(10))
    # wait 500: the next request starts 500 ms after the previous one ended
    sent = [e.time for e in of(link, a, FrameSent) if e.frame[2] != 0]
    third_cmd_handed = [e for e in of(link, a, FrameSent) if e.frame[:4] == b"\x00\x00\x4f\x44"][0]
    assert third_cmd_handed.time >= ha.results[1].time + 0.5
    assert len(sent) == 5                                         # 2 + 1 + 1 + 1; DB0 never sent
    assert bytes(b.memory.dx[7][6:12]) == bytes.fromhex("010203100400")
    assert b.memory.flag(12, 3) == 0                              # set by the transfer, cleared at once


def test_interface_lines():
    link, a, b, ha, hb = hosts_pair(SCRIPT)
    assert link.run_until_quiet(120)
    lines = [line for n, e in link.events if n == "a" for line in interface_lines(e)]
    assert lines == [
        "RESULT send:DB10:DW0:LEN=200 OK",
        "FETCHED fetch:E:0:LEN=10 40414243444546474849",
        "RESULT fetch:E:0:LEN=10 OK",
        "RESULT send:DX7:OFF=6:LEN=5:CF=12.3:CPU=2:DATA=0102031004 OK",
        "STATUS 16#0903",
        "RESULT fetch:DB250:DW0:LEN=2 STATUS 16#0903",
        "STATUS 16#0514",
        "RESULT send:DB0:DW0:LEN=2 STATUS 16#0514",
    ]
    assert [line for n, e in link.events if n == "b" for line in interface_lines(e)] == ["STATUS 16#0606"]


def test_flag_set_at_start_and_reset_later():
    # the flag_set setup: 12.3 set at start, cleared by the application 2 s later; every
    # transfer naming it sets it again and it is cleared 2 s after that (AMB-07/08)
    script = "\n".join(["send DB1:DW0:LEN=2:CF=12.3", "wait 2500", "send DB1:DW0:LEN=2:CF=12.3",
                        "send DB1:DW0:LEN=2:CF=12.3", "wait 2500", "fetch M:12:LEN=1:CF=12.3"])
    link, a, b, ha, hb = hosts_pair(script, b_host=lambda st: Rk512Host(st, cf_set=[(12, 3, 2000)]))
    assert b.memory.flag(12, 3) == 1
    assert link.run_until_quiet(120)
    assert [(r.ok, r.code) for r in ha.results] == [
        (False, Code.PARTNER_DB_LOCKED), (True, None), (False, Code.PARTNER_DB_LOCKED), (True, None)]
    assert ha.results[3].data == b"\x00"        # the flag byte as served, before it is set again
    assert b.memory.flag(12, 3) == 0            # the last set was cleared 2 s later too
    assert codes(link, b) == [Code.DB_LOCKED, Code.DB_LOCKED]


def test_cpu_stop():
    link, a, b, ha, hb = hosts_pair("send DB1:DW0:LEN=2\nfetch E:0:LEN=2",
                                    b_host=lambda st: Rk512Host(st, cpu_stop=True))
    assert link.run_until_quiet(60)
    assert [r.code for r in ha.results] == [Code.PARTNER_NO_RESTART] * 2


def test_parse_cf_set():
    assert parse_cf_set("12.3@500") == (12, 3, 500)
    for bad in ("12.8@5", "12@5", "x"):
        with pytest.raises(ValueError):
            parse_cf_set(bad)
    st = Rk512Station(Rk512Params(byte_area_bytes=8))
    with pytest.raises(ValueError):
        Rk512Host(st, cf_set=[(9, 0, 10)])


def test_empty_script_is_done():
    link, a, b, ha, hb = hosts_pair("")
    assert link.run_until_quiet(10) and ha.done and ha.results == []
    assert [type(e) for n, e in link.events if n == "a"] == [Ready]


# -- the ideal frame link ------------------------------------------------------------------------
def test_frame_link_gives_the_same_results():
    link, a, b, ha, hb = hosts_pair(SCRIPT, baud=None)
    assert link.run_until_quiet(120)
    ca, cb = Rk512Core(Rk512Params(), name="a"), Rk512Core(Rk512Params(), name="b")
    fa = Rk512Host(ca, SCRIPT)
    fl = FrameLink(ca, cb, hosts={"a": fa, "b": Rk512Host(cb)})
    fl.power_on(0.1)
    assert fl.run_until_quiet(120)
    assert [(r.label, r.ok, r.code, r.data) for r in fa.results] == \
        [(r.label, r.ok, r.code, r.data) for r in ha.results]
    assert cb.memory.snapshot() == b.memory.snapshot()
    # the frames: as the stations acknowledged them over 3964R
    full = [(n, e.frame) for n, e in link.events if isinstance(e, FrameSent)]
    assert [(n, f) for _, n, f in fl.frames] == full
    assert not any(isinstance(e, (FrameSent, FrameReceived)) for n, e in fl.events)


def test_frame_link_with_frame_events_and_delay():
    ca, cb = Rk512Core(Rk512Params(response_time_ms=1000), name="a"), Rk512Core(Rk512Params(), name="b")
    fl = FrameLink(ca, cb, delay=0.6, frame_events=True)
    fl.power_on(0.0)
    fl.request(ca, "fetch DB1:DW0:LEN=2")
    assert fl.run_until_quiet(60)
    r = [e for n, e in fl.events if isinstance(e, RequestResult)][0]
    assert r.ok and r.time == pytest.approx(1.2)                   # two frames, 0.6 s each
    assert len([e for n, e in fl.events if isinstance(e, FrameReceived)]) == 2
    # a delay beyond T_RES: the response comes too late
    ca, cb = Rk512Core(Rk512Params(response_time_ms=1000), name="a"), Rk512Core(Rk512Params(), name="b")
    fl = FrameLink(ca, cb, delay=1.5)
    fl.power_on(0.0)
    fl.request(ca, "fetch DB1:DW0:LEN=2")
    assert fl.run_until_quiet(60)
    codes_a = [e.code for n, e in fl.events if n == "a" and isinstance(e, Status)]
    assert codes_a == [Code.RESPONSE_TIMEOUT, Code.RESPONSE_OUT_OF_SEQUENCE]


# -- the driver interface -------------------------------------------------------------------------
class PeerEndpoint(Endpoint):
    """The line to a model peer in virtual time, for drive_station: what the driver writes
    reaches the peer at once (it writes a byte when it is complete), the peer's bytes come
    back one character time after they start."""

    def __init__(self, peer, char):
        self.peer, self.char, self.t = peer, char, 0.0
        self.inbox: list[int] = []
        self.pending: deque = deque()
        self.wire: list[tuple[str, int]] = []

    def now(self):
        return self.t

    def write(self, data):
        for b in data:
            self.wire.append(("iut", b))
            self.peer.line_event(max(self.t, self.peer.now), "byte", b)
        return self.t

    def poll(self, deadline):
        peer = self.peer
        while True:
            for start, b in peer.pop_output(self.t):
                self.pending.append((start + self.char, b))
            ready = []
            while self.pending and self.pending[0][0] <= self.t + 1e-12:
                t, b = self.pending.popleft()
                self.wire.append(("peer", b))
                ready.append((t, "byte", b))
            if ready:
                return ready
            d = peer.next_deadline()
            nxt = min([deadline] + ([d] if d is not None else []) + ([self.pending[0][0]] if self.pending else []))
            if nxt == inf:
                raise EOFError
            if nxt >= deadline:
                self.t = max(self.t, deadline)
                return []
            self.t = max(self.t, nxt)
            if d is not None and d <= self.t:
                peer.handle_timer(self.t)


def test_drive_station_runs_an_rk512_iut():
    iut = Rk512Station(params("low"), name="iut")
    host = Rk512Host(iut, "send DB10:DW0:LEN=300\nfetch A:4:LEN=3")
    peer = Rk512Station(params("high"), name="peer")
    peer.power_on(0.0)
    ep = PeerEndpoint(peer, iut.params.char_time)
    iut.power_on(0.0)
    seen = []
    drive_station(host, ep, stop=lambda: host.done and peer.idle, on_event=seen.append, until=60.0)
    assert iut.late_timers_act_now and iut.link.late_timers_act_now
    assert [(r.label, r.ok) for r in host.results] == [("send:DB10:DW0:LEN=300", True), ("fetch:A:4:LEN=3", True)]
    assert host.results[1].data == bytes([0xC4, 0xC5, 0xC6])
    assert bytes(peer.memory.db[10][:300]) == bytes((0x10 + 7 * i) & 0xFF for i in range(300))
    assert any(isinstance(e, FrameSent) for e in seen)


def test_sim_transport_carries_an_rk512_station():
    p = Params3964(priority="low")
    char = p.char_time
    tr = SimTransport(p, lambda lp: Rk512Host(Rk512Station(Rk512Params(line=lp), name="iut")),
                      char_time=char)
    tr.open()
    tr.read(0.01)                                           # the start-up NAK

    def send(data):
        # the tester's bytes go out at line speed: each is handed over when it is complete
        for b in data:
            tr.read(tr.now() + char)
            tr.write(bytes([b]))

    def receive(n):
        got = []
        while len(got) < n:
            got += [b for _, b in tr.read(tr.now() + 1.0)]
        return bytes(got)

    send([STX])
    assert receive(1) == bytes([DLE])
    send(body(header("E", "D", 10, 0, 2)))
    assert receive(2) == bytes([DLE, STX])                  # block accepted; the response follows
    send([DLE])
    assert receive(11) == body(response(0, data=bytes([10, 11, 12, 13])))
    send([DLE])
    tr.read(tr.now() + 0.1)
    assert [type(e).__name__ for e in tr.events if not isinstance(e, Ready)] == [
        "FrameReceived", "Served", "FrameSent"]
    assert tr.status_reports() == []


def test_raw_frames_of_a_tester_station():
    # request_send (Link.request) sends one frame as it is: the tester's seat; neither side
    # of the sender takes note of it, the partner answers it as any command
    link, a, b, ha, hb = hosts_pair("")
    link.request(a, header("E", "E", 0, 0, 2))
    assert link.run_until_quiet(link.now + 60)
    assert [e.frame for e in of(link, a, FrameReceived)] == [response(0, data=b"\x40\x41")]
    assert codes(link, a) == [Code.RESPONSE_OUT_OF_SEQUENCE]    # the answer is one to nobody
    assert a.a_state == "A_IDLE" and results(link, a) == []
