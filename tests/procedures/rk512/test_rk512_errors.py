"""Every RK 512 error event with its trigger, on the wire (§8.3 Table 8-1; §8.4 Table 8-3):
the requester's REATEL -> STATUS (class 09), its checks of the responses (class 0A) and of
its own requests (class 05), and the responder's checks of the commands (class 06) with the
REATEL it answers. The tester is a bare 3964R station that sends the frames a test crafts."""

import pytest
from rk512_helpers import (
    codes,
    delivered,
    of,
    pair,
    params,
    results,
    run_until,
    run_until_delivered,
    served,
    settle,
    wire,
    with_tester,
)
from rk512_rules import TABLE_8_3, UNKNOWN_REATEL, continuation, header, response

from ptpcert.model.codes import Code
from ptpcert.model.events import SendDone
from ptpcert.model.link import DELIVER, DROP, Link
from ptpcert.procedures.p3964.model.params import Params3964
from ptpcert.procedures.p3964.model.station import Station3964
from ptpcert.procedures.rk512.model import Rk512Readings, Rk512Station
from ptpcert.procedures.rk512.model.events import FrameSent

# == class 09: the REATEL of the partner's response (Table 8-3) ===================================
REATELS = sorted(TABLE_8_3) + [0x01, 0x0B, 0x42, 0xFE, 0xFF]


@pytest.mark.parametrize("reatel", REATELS)
def test_reatel_in_the_first_response(reatel):
    link, a, t = with_tester()
    a.request(link.now, "send DB10:DW0:LEN=300")
    run_until_delivered(link, t, 1)
    link.request(t, response(reatel))
    assert link.run_until_quiet(link.now + 60)
    want = TABLE_8_3.get(reatel, UNKNOWN_REATEL)
    [r] = results(link, a)
    assert not r.ok and r.code == want
    assert r.lines() == [f"RESULT send:DB10:DW0:LEN=300 STATUS 16#{want:04X}"]
    assert codes(link, a) == [want]
    assert len(delivered(link, t)) == 1          # R4.8: no continuation after an error


@pytest.mark.parametrize("reatel", REATELS)
def test_reatel_in_a_continuation_response(reatel):
    link, a, t = with_tester()
    a.request(link.now, "fetch DB10:DW0:LEN=400")
    run_until_delivered(link, t, 1)
    link.request(t, response(0, data=bytes(128)))
    run_until_delivered(link, t, 2)
    assert delivered(link, t)[1] == continuation("E", "D")
    link.request(t, response(reatel, first=False))
    assert link.run_until_quiet(link.now + 60)
    want = TABLE_8_3.get(reatel, UNKNOWN_REATEL)
    [r] = results(link, a)
    assert not r.ok and r.code == want and r.data is None
    assert len(delivered(link, t)) == 2


def test_reatel_from_a_model_partner():
    # the responder's own error reaches the requester as the mapped event: FETCH of a DB that
    # does not exist -> 16#0606 / REATEL 14h -> 16#0903
    link, a, b = pair()
    a.request(link.now, "fetch DB250:DW0:LEN=4")
    assert link.run_until_quiet(60)
    assert results(link, a)[0].code == Code.PARTNER_DB_ACCESS
    assert codes(link, b) == [Code.DB_NUMBER_NOT_ALLOWED]
    assert of(link, b, FrameSent)[0].frame == response(0x14)


# == class 06: the responder's checks of a partner's command ======================================
def serve(frames, readings=Rk512Readings(), setup=None, **kw):
    """The tester sends ``frames`` one after the other, each after the answer to the one
    before (if any); returns the link, the station and the frames the tester received."""
    link, a, t = with_tester(readings=readings, **kw)
    if setup:
        setup(a)
    for f in frames:
        send_and_wait(link, t, f)
    return link, a, delivered(link, t)


def send_and_wait(link, t, frame, quiet: float = 1.0):
    """The tester sends ``frame`` and waits for the answer, or ``quiet`` seconds without one
    (well inside the station's T_RES)."""
    n = len(delivered(link, t))
    link.request(t, frame)
    end = link.now + 60
    while len(delivered(link, t)) == n:
        nt = link.next_time()
        if nt > end or (t.idle and link.a.link.idle and nt > link.now + quiet):
            link.run_until(link.now + quiet)
            break
        link.run_until(nt)


def req(link, st, spec):
    """A request of ``st`` issued from outside the link's run (its results recorded)."""
    link.run_until(link.now)
    st.request(link.now, spec)
    link.events.extend((st.name, e) for e in st.pop_events())


def C(b3="A", b4="D", b5=10, b6=0, length=2, data=4, b9=0xFF, b10=0x1F, b1=0):
    """A first command; ``data`` bytes of 5Ah follow."""
    return header(b3, b4, b5, b6, length, b9, b10, b1) + bytes([0x5A]) * data


CLASS_06 = [  # (case, frames, the event, the last frame the tester gets back)
    ("byte 1 01h", [C(b1=0x01)], 0x0601, response(0x10)),
    ("byte 1 FEh", [C(b1=0xFE)], 0x0601, response(0x10)),
    ("byte 3 'C'", [C(b3="C")], 0x0602, response(0x16)),
    ("byte 3 'a'", [C(b3="a")], 0x0602, response(0x16)),
    ("byte 4 'C' (43h) for counters", [C("E", "C", 0, 0, 1, 0)], 0x0604, response(0x10)),
    ("byte 4 lowercase 'd'", [C("E", "d", 10, 0, 1, 0)], 0x0604, response(0x10)),
    ("SEND with type X", [C("A", "X")], 0x0604, response(0x10)),
    ("SEND with type M", [C("A", "M")], 0x0604, response(0x10)),
    ("SEND DX with type X", [C("O", "X")], 0x0604, response(0x10)),
    ("FETCH type Q", [C("E", "Q", 0, 0, 1, 0)], 0x0604, response(0x10)),
    ("DB 0", [C(b5=0)], 0x0606, response(0x14)),
    ("DB beyond db_range", [C(b5=200)], 0x0606, response(0x14)),
    ("FETCH DX 0", [C("E", "X", 0, 0, 1, 0)], 0x0606, response(0x14)),
    ("start DW beyond the DB", [C(b6=255, data=2, length=1)], None, None),  # 510 < 512: fits
    ("FETCH M from byte 300", [C("E", "M", 1, 44, 1, 0)], 0x0607, response(0x0C)),
    ("FETCH T from cell 256", [C("E", "T", 1, 0, 1, 0)], 0x0607, response(0x0C)),
    ("length 0", [C(length=0, data=0)], 0x0608, response(0x34)),
    ("length over 512 words", [C("E", "D", 10, 0, 513, 0)], 0x0608, response(0x34)),
    ("beyond the end of the DB", [C("E", "D", 10, 250, 7, 0)], 0x0608, response(0x34)),
    ("flag bit 8", [C(b9=3, b10=0x18)], 0x0609, response(0x0C)),
    ("flag bit Eh", [C(b9=3, b10=0x1E)], 0x0609, response(0x0C)),
    ("CPU number 5", [C(b10=0x5F)], 0x060A, response(0x0C)),
    ("CPU number Eh", [C(b10=0xE3, b9=1)], 0x060A, response(0x0C)),
    ("SEND with fewer data", [C(length=5, data=8)], 0x060B, response(0x34)),
    ("SEND with more data", [C(length=5, data=12)], 0x060B, response(0x34)),
    ("first SEND frame of 127", [C(length=100, data=127)], 0x060B, response(0x34)),
    ("FETCH with data", [C("E", "D", 10, 0, 2, 2)], 0x060C, response(0x34)),
    ("continuation without request", [continuation("A", "D", bytes(4))], 0x060E, response(0x36, first=False)),
    ("command of 9 bytes", [C(data=0)[:9]], 0x0610, response(0x34)),
    ("command of 4 bytes", [C(data=0)[:4]], 0x0610, response(0x34)),
    ("command of 3 bytes", [C(data=0)[:3]], 0x0610, response(0x34)),
    ("continuation of 3 bytes", [continuation("A", "D")[:3]], 0x0610, response(0x34, first=False)),
    ("frame of 1 byte", [b"\x00"], 0x0610, response(0x34)),
]


@pytest.mark.parametrize("case,frames,event,reply", CLASS_06, ids=[c[0] for c in CLASS_06])
def test_class_06(case, frames, event, reply):
    link, a, got = serve(frames)
    if event is None:
        assert codes(link, a) == [] and got[-1] == response(0)
        return
    assert codes(link, a, "receive") == [event]
    assert got[-1] == reply
    assert served(link, a) == []             # no data written or read for a refused frame
    assert a.memory.db[10] == bytes((10 + i) & 0xFF for i in range(512))


MULTI = [  # continuation errors: after a correct first frame of 300 bytes (150 words)
    ("continuation byte 3 changed", continuation("O", "D", bytes(128)), 0x0603, 0x16),
    ("continuation byte 3 changed to E", continuation("E", "D"), 0x0603, 0x16),
    ("continuation byte 4 changed", continuation("A", "X", bytes(128)), 0x0605, 0x10),
    ("continuation with fewer data", continuation("A", "D", bytes(127)), 0x0611, 0x34),
    ("continuation with more data", continuation("A", "D", bytes(129)), 0x0611, 0x34),
    ("first command instead of the continuation", C(), 0x060E, 0x36),
]


@pytest.mark.parametrize("case,frame,event,reatel", MULTI, ids=[m[0] for m in MULTI])
def test_class_06_in_continuations(case, frame, event, reatel):
    link, a, got = serve([C(length=150, data=128), frame])
    assert got[0] == response(0)
    assert codes(link, a) == [event]
    assert got[1] == response(reatel, first=frame[0] == 0)
    assert [s.final for s in served(link, a)] == [False]     # the first frame only
    # the request is over: a continuation now is out of sequence
    send_and_wait(link, link.b, continuation("A", "D", bytes(128)))
    assert delivered(link, link.b)[-1] == response(0x36, first=False)


def test_fetch_continuation_with_data():
    link, a, got = serve([C("E", "D", 10, 0, 150, 0), continuation("E", "D", b"\x00")])
    assert codes(link, a) == [Code.FETCH_WITH_DATA]
    assert got[1] == response(0x34, first=False)


def test_flag_beyond_the_flag_area():
    link, a, got = serve([C(b9=20, b10=0x13)], byte_area_bytes=16)
    assert codes(link, a) == [Code.FLAG_INVALID] and got == [response(0x0C)]


def test_start_address_beyond_a_small_db():
    link, a, got = serve([C(b6=200)], db_bytes=256)
    assert codes(link, a) == [Code.START_ADDRESS_TOO_HIGH] and got == [response(0x0C)]


def test_dx_without_dx_area():
    link, a, got = serve([C("O", "D", 5)], dx_range=[])
    assert codes(link, a) == [Code.DB_NUMBER_NOT_ALLOWED] and got == [response(0x14)]


def test_cpu_stop():
    def stop(a):
        a.memory.running = False
    link, a, got = serve([C(), C("E", "E", 0, 0, 4, 0)], setup=stop)
    assert codes(link, a) == [Code.CP_NOT_READY] * 2
    assert got == [response(0x2A)] * 2


def test_cpu_stop_during_a_request():
    link, a, t = with_tester()
    link.request(t, C(length=150, data=128))
    run_until_delivered(link, t, 1)
    a.memory.running = False
    link.request(t, continuation("A", "D", bytes(128)))
    assert link.run_until_quiet(link.now + 60)
    assert delivered(link, t)[1] == response(0x2A, first=False)
    assert codes(link, a) == [Code.CP_NOT_READY]


def test_flag_locked_then_free():
    # AMB-07: a flag of 1 locks (32h); 0 lets the transfer through, which sets it (AMB-08)
    def lock(a):
        a.memory.set_flag(3, 5)
    link, a, got = serve([C(b9=3, b10=0x15)], setup=lock)
    assert codes(link, a) == [Code.DB_LOCKED] and got == [response(0x32)]
    a.memory.set_flag(3, 5, 0)
    send_and_wait(link, link.b, C(b9=3, b10=0x15))
    assert delivered(link, link.b)[-1] == response(0)
    assert a.memory.flag(3, 5) == 1
    [s] = served(link, a)
    assert s.final and s.flag == (3, 5)
    send_and_wait(link, link.b, C(b9=3, b10=0x15))
    assert delivered(link, link.b)[-1] == response(0x32)


def test_pipelined_command_before_the_response():
    # 16#060E: a second command while the response to the first has not been sent: answered
    # 36h; with n7 the open request ends after its own response
    link, a, t = with_tester(tester_prio="high")
    link.request(t, C(length=150, data=128))
    # the tester's next block crosses a's response: the tester is high priority, a defers
    run_until(link, lambda: a.link.state == "WAIT_SETUP_ACK")
    link.request(t, continuation("A", "D", bytes(128)))
    assert link.run_until_quiet(link.now + 60)
    got = delivered(link, t)
    # the open request's response was with the link already; the refusal follows it
    assert got == [response(0), response(0x36, first=False)]
    assert codes(link, a) == [Code.PARTNER_SEQUENCE_ERROR]
    assert a.p_state == "P_IDLE"


def test_response_not_sent():
    # 16#0612: the tester never acknowledges the response block (3964R gives up first)
    drop = {"on": False}
    a = Rk512Station(params("high"), name="a")
    t = Station3964(Params3964(priority="low"), name="t")
    link = settle(Link(a, t, hook=lambda w: DROP if drop["on"] and w.src == "t" else DELIVER))
    link.request(t, C())
    run_until(link, lambda: of(link, t, SendDone))
    drop["on"] = True
    assert link.run_until_quiet(link.now + 120)
    cs = codes(link, a, "receive")
    assert cs[-1] == Code.RESPONSE_NOT_SENT
    assert Code.SETUP_ATTEMPTS_EXCEEDED in codes(link, a, "send")
    assert cs.index(Code.RESPONSE_NOT_SENT) == len(cs) - 1
    assert a.p_state == "P_IDLE"


def test_unsolicited_response_gets_no_frame():
    # R5.11 / P-15: a response to nobody is not answered (3964R DLE only); 16#0A01
    link, a, got = serve([response(0)])
    assert got == [] and codes(link, a) == [Code.RESPONSE_OUT_OF_SEQUENCE]
    assert results(link, a) == []


# == class 0A: the requester's checks of the responses ============================================
def ask(spec, tester_prio="low", **kw):
    link, a, t = with_tester(tester_prio=tester_prio, **kw)
    a.request(link.now, spec)
    run_until_delivered(link, t, 1)
    return link, a, t


def answer(link, t, frame):
    n = len(delivered(link, t))
    link.request(t, frame)
    run_until(link, lambda: results(link, link.a) or len(delivered(link, t)) > n)


CLASS_0A = [
    ("send DB10:DW0:LEN=4", b"\x01\x00\x00\x00", 0x0A02),
    ("send DB10:DW0:LEN=4", b"\x7f\x00\x00\x34", 0x0A02),
    ("send DB10:DW0:LEN=4", response(0, data=b"\x00"), 0x0A04),
    ("send DB10:DW0:LEN=4", response(0x34, data=b"\x00"), 0x0A04),     # AMB-33
    ("fetch DB10:DW0:LEN=6", response(0, data=bytes(5)), 0x0A03),
    ("fetch DB10:DW0:LEN=6", response(0, data=bytes(7)), 0x0A03),
    ("fetch DB10:DW0:LEN=6", response(0x14, data=bytes(6)), 0x0A03),   # AMB-33
    ("fetch DB10:DW0:LEN=6", response(0), 0x0A03),
    ("send DB10:DW0:LEN=4", response(0, first=False), 0x0A01),
    ("send DB10:DW0:LEN=4", b"\x00\x00\x00", 0x0610),                  # AMB-10/19
    ("send DB10:DW0:LEN=4", b"\x00", 0x0610),
]


@pytest.mark.parametrize("spec,frame,code", CLASS_0A)
def test_class_0a(spec, frame, code):
    link, a, t = ask(spec)
    answer(link, t, frame)
    assert link.run_until_quiet(link.now + 60)
    [r] = results(link, a)
    assert not r.ok and r.code == code and r.data is None
    assert codes(link, a, "send") == [code]


def test_first_response_after_a_continuation():
    link, a, t = ask("send DB10:DW0:LEN=200")
    answer(link, t, response(0))
    run_until_delivered(link, t, 2)
    answer(link, t, response(0))
    assert link.run_until_quiet(link.now + 60)
    assert results(link, a)[0].code == Code.RESPONSE_OUT_OF_SEQUENCE


def test_fetch_continuation_response_of_wrong_length():
    link, a, t = ask("fetch DB10:DW0:LEN=200")
    answer(link, t, response(0, data=bytes(128)))
    run_until_delivered(link, t, 2)
    answer(link, t, response(0, first=False, data=bytes(73)))
    assert link.run_until_quiet(link.now + 60)
    assert results(link, a)[0].code == Code.RESPONSE_DATA_LENGTH


def test_response_before_the_continuation_was_sent():
    # the tester (high priority) sends a second response while a's continuation waits: a
    # defers its STX and receives it in A_SEND_CONTINUATION: 16#0A01 (AMB-32: an extra
    # response, reported); the continuation goes out and its own answer completes the request
    link, a, t = ask("send DB10:DW0:LEN=200", tester_prio="high")
    link.request(t, response(0))
    link.request(t, response(0))
    run_until_delivered(link, t, 2)
    assert delivered(link, t)[1][:4] == continuation("A", "D")
    assert codes(link, a) == [Code.RESPONSE_OUT_OF_SEQUENCE] and results(link, a) == []
    link.request(t, response(0, first=False))
    assert link.run_until_quiet(link.now + 60)
    assert [r.ok for r in results(link, a)] == [True]


def test_response_before_the_continuation_ends_the_request_under_the_other_reading():
    link, a, t = ask("send DB10:DW0:LEN=200", tester_prio="high",
                     readings=Rk512Readings(amb32_early_response_ends_request=True))
    link.request(t, response(0))
    link.request(t, response(0))
    assert link.run_until_quiet(link.now + 60)
    [r] = results(link, a)
    assert r.code == Code.RESPONSE_OUT_OF_SEQUENCE
    # the continuation was already with the link: it still goes out (it cannot be recalled)
    assert delivered(link, t)[1][:4] == continuation("A", "D")


def test_unsolicited_response_while_idle_is_not_final():
    link, a, t = with_tester()
    link.request(t, response(0x34))
    assert link.run_until_quiet(60)
    assert codes(link, a) == [Code.RESPONSE_OUT_OF_SEQUENCE]
    assert results(link, a) == [] and not of(link, a, FrameSent)


# == class 05: the requester's own checks and failures ============================================
@pytest.mark.parametrize("spec,code", [
    ("send DB10:DW0:LEN=0", Code.LEN_ILLEGAL),
    ("send DB10:DW0:LEN=1025", Code.LENGTH_INVALID_FOR_CP),
    ("send DB0:DW0:LEN=2", Code.ADDRESS_OUT_OF_RANGE),
    ("fetch M:256:LEN=2", Code.ADDRESS_OUT_OF_RANGE),
    ("send DB1:DW0:LEN=2:CF=1.8", Code.INVALID_FLAG_BIT),
    ("send DB1:DW0:LEN=2:CPU=5", Code.CPU_NUMBER_TOO_HIGH),
    ("send E:0:LEN=2", Code.INVALID_FB_PARAMETERS),
])
def test_local_refusals_never_reach_the_wire(spec, code):
    link, a, t = with_tester()
    req(link, a, spec)
    assert link.run_until_quiet(60)
    assert wire(link) == []
    [r] = results(link, a)
    assert r.code == code and codes(link, a) == [code]


def test_request_before_power_on():
    a = Rk512Station(params("high"), name="a")
    assert a.request(0.0, "send DB10:DW0:LEN=2") is False
    [s, r] = a.pop_events()
    assert s.code == r.code == Code.NOT_ALLOWED_IN_MODE and s.final


def test_command_not_sent():
    # 16#051A after the 3964R procedure error: the tester never answers the STX
    a = Rk512Station(params("high"), name="a")
    t = Station3964(Params3964(priority="low"), name="t")
    link = settle(Link(a, t, hook=lambda w: DROP if w.src == "t" else DELIVER))
    a.request(link.now, "send DB10:DW0:LEN=2")
    assert link.run_until_quiet(link.now + 120)
    cs = codes(link, a, "send")
    assert cs[-2:] == [Code.SETUP_ATTEMPTS_EXCEEDED, Code.COMMAND_NOT_SENT]
    assert results(link, a)[0].code == Code.COMMAND_NOT_SENT


def test_restart_aborts_the_request():
    link, a, t = with_tester()
    req(link, a, "send DB10:DW0:LEN=200")
    req(link, a, "fetch E:0:LEN=2")
    run_until_delivered(link, t, 1)
    a.restart(link.now)
    link.events.extend((a.name, e) for e in a.pop_events())
    assert [(r.label, r.code) for r in results(link, a)] == [
        ("send:DB10:DW0:LEN=200", Code.ABORTED_BY_CP_RESTART), ("fetch:E:0:LEN=2", Code.ABORTED_BY_CP_RESTART)]
    assert a.a_state == "A_IDLE" and a.job is None
    # the response to the aborted command is then a response without request
    link.request(t, response(0))
    assert link.run_until_quiet(link.now + 60)
    assert codes(link, a)[-1] == Code.RESPONSE_OUT_OF_SEQUENCE
