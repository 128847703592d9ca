"""Data flow control of the ASCII driver (§2.2.4 "data flow control / handshaking"; Table 2-9)
and the automatic use of the V.24 signals (§2.2.4; Fig. 2-24), in virtual time."""

import pytest
from ascii_bench import Bench

from ptpcert.model.codes import Code
from ptpcert.model.events import SendDone
from ptpcert.model.hexbytes import parse_hex
from ptpcert.procedures.ascii.model import AsciiParams, AsciiReadings
from ptpcert.procedures.ascii.model import events as aev
from ptpcert.procedures.ascii.model.table import RxState, TxState

H = parse_hex
XON, XOFF = 0x11, 0x13
XX = AsciiParams(flow_control="xon_xoff", xon_wait_ms=2000)
XX_EC2 = XX.with_(end_criterion="end_chars", end_chars=(0x03,), buffer_frames=2)


def control_chars(b, start_after=-1.0):
    return [(t, x) for t, x in b.out if x in (XON, XOFF) and t > start_after]


# =========================================================== XON/XOFF: the receiving side
def test_xon_at_start_up():
    b = Bench(XX)
    assert b.out == [(0.0, XON)]


def test_xoff_when_the_frame_count_is_reached_and_xon_after_a_read():
    b = Bench(XX_EC2, app="no_read")
    b.send(H("41 03")); t2 = b.send(H("42 03")); b.idle()
    assert control_chars(b, 0.0) == [(pytest.approx(t2), XOFF)]
    b.idle(1.0)
    assert control_chars(b, 0.0) == [(pytest.approx(t2), XOFF)]     # sent once
    t_read = b.t
    assert b.read() == H("41 03")
    b.idle()
    assert control_chars(b, t2) == [(pytest.approx(t_read), XON)]


def test_frame_count_reading_n_minus_one():
    b = Bench(XX_EC2, app="no_read", readings=AsciiReadings(q14_xoff_frame_offset=-1))
    t1 = b.send(H("41 03")); b.idle()
    assert control_chars(b, 0.0) == [(pytest.approx(t1), XOFF)]


def test_xoff_when_50_bytes_are_left_during_the_tenth_frame():
    # 100-byte frames, CDT criterion, 250 frames: the fill reaches 1024 - 50 = 974 bytes
    # with the 74th byte of the 10th frame
    b = Bench(XX, app="no_read")
    arrivals = []
    for i in range(10):
        for k in range(100):
            arrivals.append(b.send(bytes([i])))
        b.idle()
    (t, x), = control_chars(b, 0.0)
    n = (1024 - 50) - 9 * 100
    assert x == XOFF and t == pytest.approx(arrivals[9 * 100 + n - 1])
    assert b.codes() == []
    # d_hold: while the partner is held, the pause after the 10th frame does not end it
    assert b.st.frames_stored == 9 and b.st.buffer_fill == 1000
    b.idle(1.0)
    assert b.st.frames_stored == 9
    t_read = b.t
    b.read()
    b.idle()
    # the read lifts the hold (XON); the CDT runs again from the end of the XON
    assert control_chars(b, t)[0] == (pytest.approx(t_read), XON)
    assert b.stored()[-1] == bytes([9]) * 100
    assert b.of(aev.FrameStored)[-1].time == pytest.approx(t_read + XX.char_time + XX.cdt + XX.char_time)


def test_without_the_hold_reading_the_pause_ends_the_frame():
    b = Bench(XX, app="no_read", readings=AsciiReadings(d_cdt_suspended_while_holding=False))
    for i in range(10):
        b.send(bytes([i]) * 100)
        b.idle()
    assert b.st.frames_stored == 10


@pytest.mark.parametrize("suspended", [True, False])
def test_a_frame_interrupted_by_xoff_survives_the_hold(suspended):
    # buffer_frames = 1: the first frame fills the buffer, XOFF; the partner stops in the
    # middle of its second frame and goes on only after the XON
    p = XX.with_(end_criterion="end_chars", end_chars=(0x03,), buffer_frames=1)
    b = Bench(p, app="no_read", readings=AsciiReadings(d_cdt_suspended_while_holding=suspended))
    b.send(H("41 03")); b.send(H("42 43"))
    b.idle(0.5)
    b.read(); b.idle(0.001)
    b.send(H("44 03")); b.idle()
    if suspended:
        assert b.stored() == [H("41 03"), H("42 43 44 03")] and b.codes() == []
    else:
        assert b.stored() == [H("41 03"), H("44 03")] and b.codes() == [Code.CDT_EXCEEDED]


def test_xoff_with_the_first_byte_that_reaches_974():
    b = Bench(XX, app="no_read")
    b.send(bytes(973)); b.idle()
    assert control_chars(b, 0.0) == []
    t = b.send(b"\x01")
    assert control_chars(b, 0.0) == [(pytest.approx(t), XOFF)]


def test_break_aborts_the_send_job_in_the_other_reading():
    b = Bench(AsciiParams(), readings=AsciiReadings(d_break_aborts_send=True))
    data = bytes(range(0x20, 0x60))
    b.request(data)
    b.brk(at=0.01); b.idle(0.2)
    assert b.codes() == [Code.LINE_BREAK, Code.LINE_BREAK]
    assert b.failed() == [(data, Code.LINE_BREAK)] and len(b.wire()) < len(data)


def test_break_does_not_touch_a_send_job():
    b = Bench(AsciiParams())
    data = bytes(range(0x20, 0x60))
    b.request(data)
    b.brk(at=0.01); b.idle(0.2)
    assert b.codes() == [Code.LINE_BREAK] and b.wire() == data and b.done() == [data]


def test_partner_that_ignores_xoff_overflows_the_buffer():
    # 130-byte frames: seven fill 910 bytes; the 8th reaches 974 with its 64th byte (XOFF),
    # the partner goes on, and its 115th byte finds no room (910 + 114 = 1024): the frame is
    # discarded with 16#080A when the CDT ends it (Q17), the seven before stay intact, and
    # the discard frees the room again: XON (Q15). The 9th and 10th frames go the same way.
    b = Bench(XX, app="no_read")
    arrivals, ends = [], []
    for i in range(10):
        arrivals.append([b.send(bytes([i])) for _ in range(130)])
        ends.append(arrivals[-1][-1] + XX.cdt + XX.char_time)
        b.idle()
    assert b.st.stored_frames == tuple(bytes([i]) * 130 for i in range(7))
    assert b.discarded() == [(bytes([i]) * 130, aev.NO_ROOM, Code.NO_RECEIVE_BUFFER) for i in (7, 8, 9)]
    assert b.codes() == [Code.NO_RECEIVE_BUFFER] * 3
    expected = []
    for i in (7, 8, 9):
        expected += [(pytest.approx(arrivals[i][(974 - 910) - 1]), XOFF), (pytest.approx(ends[i]), XON)]
    assert control_chars(b, 0.0) == expected


@pytest.mark.parametrize("suspended", [True, False])
def test_100_byte_frames_from_a_partner_that_ignores_xoff(suspended):
    # 100-byte frames with idle between them, the CPU not reading. XOFF comes with the 74th
    # byte of the 10th frame. d_hold: the idle after the 10th frame does not end it while
    # the partner is held, so the 11th frame joins it and overflows the buffer at its 25th
    # byte (900 + 124 = 1024): the joined frame is discarded with 16#080A and frames 1..9
    # stay intact. Other reading: the 10th frame is stored, the 11th overflows.
    r = AsciiReadings(d_cdt_suspended_while_holding=suspended)
    b = Bench(XX, app="no_read", readings=r)
    for i in range(11):
        b.send(bytes([i]) * 100)
        b.idle()
    kept = 9 if suspended else 10
    assert b.st.stored_frames == tuple(bytes([i]) * 100 for i in range(kept))
    assert b.codes() == [Code.NO_RECEIVE_BUFFER]
    lost = bytes([9]) * 100 + bytes([10]) * 100 if suspended else bytes([10]) * 100
    assert b.discarded() == [(lost, aev.NO_ROOM, Code.NO_RECEIVE_BUFFER)]


def test_overflow_without_xon_after_discard_reading():
    b = Bench(XX, app="no_read", readings=AsciiReadings(q15_xon_after_discard=False))
    for i in range(8):
        b.send(bytes([i]) * 130)
        b.idle()
    assert [x for _, x in control_chars(b, 0.0)] == [XOFF]
    assert b.st.rx_state is RxState.WAIT_CHAR and b.codes() == [Code.NO_RECEIVE_BUFFER]
    t = b.t
    b.read(); b.idle()                     # the read lifts the hold
    assert control_chars(b, t - 1e-6) == [(pytest.approx(t), XON)]
    b.send(b"\x41"); b.idle()
    assert b.stored()[-1] == b"\x41"


def test_no_xon_after_a_read_without_xoff():
    b = Bench(XX_EC2, app="no_read")
    b.send(H("41 03")); b.idle(); b.read(); b.idle()
    assert control_chars(b, 0.0) == []


def test_xon_after_every_read_in_the_other_reading():
    b = Bench(XX_EC2, app="no_read", readings=AsciiReadings(q15_xon_only_after_xoff=False))
    b.send(H("41 03")); b.idle(); t = b.t; b.read(); b.idle()
    assert control_chars(b, 0.0) == [(pytest.approx(t), XON)]


def test_received_xon_xoff_are_not_data():
    b = Bench(XX.with_(end_criterion="end_chars", end_chars=(0x03,)))
    b.send(H("41 11 42 13 43 11 03")); b.idle()
    assert b.frames() == [H("41 42 43 03")]


@pytest.mark.parametrize("restarts", [False, True])
def test_received_xon_does_not_restart_the_cdt(restarts):
    # Q16: 41, then XON 3 ms later, then 42 3 ms after that: 6 ms > CDT since 41
    p = XX
    b = Bench(p, readings=AsciiReadings(q16_flow_char_restarts_cdt=restarts))
    b.send(H("41")); b.send(H("11"), at=b.line_free + 0.003); b.send(H("42"), at=b.line_free + 0.003)
    b.idle()
    assert b.frames() == ([H("41 42")] if restarts else [H("41"), H("42")])


def test_xoff_goes_out_between_the_characters_of_a_frame_being_sent():
    # full duplex: the station sends a long frame while its buffer reaches the frame count
    p = XX.with_(end_criterion="end_chars", end_chars=(0x03,), buffer_frames=1)
    b = Bench(p, app="no_read")
    b.clear()
    data = bytes(range(0x20, 0x50)) + b"\x03"
    b.request(data)
    t = b.send(H("41 03"), at=0.005)
    b.idle(0.2)
    xoffs = [s for s, x in b.out if x == XOFF]
    assert len(xoffs) == 1 and xoffs[0] >= t
    assert xoffs[0] - t < p.char_time + 1e-9       # at the next character boundary
    assert bytes(x for _, x in b.out if x != XOFF) == data
    starts = [s for s, _ in b.out]
    assert all(b2 - a2 == pytest.approx(p.char_time) for a2, b2 in zip(starts, starts[1:]))


# =========================================================== XON/XOFF: the sending side
def sending_bench(n=500, **kw):
    b = Bench(XX.with_(**kw) if kw else XX)
    b.clear()
    data = bytes((i % 0x60) + 0x20 for i in range(n))
    b.request(data)
    return b, data


def test_xoff_stops_the_sender_and_xon_resumes_it():
    b, data = sending_bench()
    char = XX.char_time
    t_off = b.send(H("13"), at=50 * char)       # complete after about 51 characters out
    t_on = b.send(H("11"), at=t_off + 1.0)
    b.idle(1.0)
    assert b.wire() == data                    # no loss, no duplicate
    assert not [s for s, _ in b.out if t_off + 1e-9 < s < t_on - 1e-9]
    assert b.done() == [data] and b.codes() == []


@pytest.mark.parametrize("k", list(range(0, 9)))
def test_xoff_at_every_point_of_a_frame(k):
    # the XOFF completes half a character after character k-1 started (k = 0: before the
    # job): the k characters that have started are on the line, the rest follows the XON
    b = Bench(XX)
    b.clear()
    data = H("30 31 32 33 34 35 36 37")
    char = XX.char_time
    t0 = 0.01
    arrive = t0 + (k - 0.5) * char
    if k == 0:
        b.send(H("13"), at=arrive - char)
        b.request(data, at=t0)
    else:
        b.request(data, at=t0)
        b.send(H("13"), at=arrive - char)
    b.idle(0.1)
    assert b.wire() == data[:k]
    assert b.done() == ([data] if k == len(data) else [])
    t_on = b.send(H("11"))
    b.idle(0.1)
    assert b.wire() == data and b.done() == [data] and b.codes() == []
    if k < len(data):
        assert b.out[k][0] == pytest.approx(t_on)    # the rest starts with the XON


def test_xoff_in_the_middle_of_a_character_lets_it_finish():
    b = Bench(XX)
    data = H("30 31 32 33 34 35 36 37")
    char = XX.char_time
    b.request(data, at=0.01)
    # XOFF completes in the middle of character 3 (index 2)
    b.send(H("13"), at=0.01 + 2.5 * char - char)
    b.idle(0.1)
    assert b.wire()[1:] == data[:3]
    b.send(H("11")); b.idle(0.1)
    assert b.wire()[1:] == data


def test_chars_after_xoff_reading():
    b = Bench(XX, readings=AsciiReadings(q15_chars_after_xoff=2))
    data = H("30 31 32 33 34 35 36 37")
    char = XX.char_time
    b.request(data, at=0.01)
    b.send(H("13"), at=0.01 + 2.5 * char - char)
    b.idle(0.1)
    assert b.wire()[1:] == data[:5]


def test_xon_wait_expires_with_0708():
    b, data = sending_bench()
    t_off = b.send(H("13"), at=0.05)
    b.idle(5.0)
    sent = b.wire()
    assert len(sent) < len(data) and data.startswith(sent)
    assert not [s for s, _ in b.out if s > t_off + 1e-9]
    (st,) = b.of(aev.Status)
    assert st.code == Code.XON_CTS_WAIT_EXPIRED and st.side == "send" and st.final
    assert st.time == pytest.approx(t_off + 2.0)
    assert b.failed() == [(data, Code.XON_CTS_WAIT_EXPIRED)]


def test_xon_just_before_the_wait_expires_resumes():
    b, data = sending_bench()
    t_off = b.send(H("13"), at=0.05)
    b.send(H("11"), at=t_off + 2.0 - 0.001 - XX.char_time)
    b.idle(2.0)
    assert b.wire() == data and b.codes() == []


def test_xoff_while_idle_holds_the_next_frame():
    b = Bench(XX)
    b.clear()
    b.send(H("13")); b.request(H("41 42")); b.idle(0.5)
    assert b.wire() == b""
    t_on = b.send(H("11")); b.idle()
    assert b.wire() == H("41 42") and b.out[0][0] == pytest.approx(t_on)


def test_xoff_while_idle_ignored_in_the_other_reading():
    b = Bench(XX, readings=AsciiReadings(q16_xoff_while_idle_holds=False))
    b.clear()
    b.send(H("13")); b.request(H("41 42")); b.idle()
    assert b.wire() == H("41 42")


def test_a_job_held_by_xoff_fails_after_the_wait_time():
    b = Bench(XX)
    b.send(H("13"))
    t = b.t
    b.request(H("41 42")); b.idle(3.0)
    (st,) = b.of(aev.Status)
    assert st.code == Code.XON_CTS_WAIT_EXPIRED and st.time == pytest.approx(t + 2.0)


def test_repeated_xoff_does_not_restart_the_wait():
    b, data = sending_bench()
    t_off = b.send(H("13"), at=0.05)
    b.send(H("13"), at=t_off + 1.0)
    b.idle(3.0)
    (st,) = b.of(aev.Status)
    assert st.time == pytest.approx(t_off + 2.0)


# =========================================================== RTS/CTS
RC = AsciiParams(flow_control="rts_cts", xon_wait_ms=2000)


def test_rts_on_at_start_up():
    b = Bench(RC)
    assert b.signals == [(0.0, "rts", 1)] and b.out == []


def test_rts_off_at_the_frame_count_and_on_after_a_read():
    b = Bench(RC.with_(buffer_frames=1), app="no_read")
    t = b.send(H("41 42")); b.idle()
    off = t + RC.cdt + RC.char_time             # the frame is complete when the CDT expires
    assert b.signals[1:] == [(pytest.approx(off), "rts", 0)]
    tr = b.t
    b.read(); b.idle()
    assert b.signals[2:] == [(pytest.approx(tr), "rts", 1)]


def test_cts_off_stops_the_sender_and_0708_after_the_wait_time():
    b = Bench(RC)
    data = bytes(range(0x20, 0x80))
    b.request(data)
    b.modem("cts", 0, at=0.02)
    b.idle(5.0)
    assert not [s for s, _ in b.out if s > 0.02 + 1e-9]
    (st,) = b.of(aev.Status)
    assert st.code == Code.XON_CTS_WAIT_EXPIRED and st.time == pytest.approx(2.02)


def test_cts_back_on_resumes():
    b = Bench(RC)
    data = bytes(range(0x20, 0x80))
    b.request(data)
    b.modem("cts", 0, at=0.02)
    b.modem("cts", 1, at=1.02)
    b.idle(1.0)
    assert b.wire() == data and b.done() == [data]
    assert not [s for s, _ in b.out if 0.02 + 1e-9 < s < 1.02 - 1e-9]


def test_cts_off_before_the_job_holds_it():
    b = Bench(RC, cts=False)
    b.request(H("41"))
    assert b.st.tx_state is TxState.STOPPED and b.wire() == b""
    b.modem("cts", 1, at=0.5); b.idle()
    assert b.wire() == H("41")


# =========================================================== automatic use of V.24 signals
AV = AsciiParams(flow_control="auto_v24")


def test_dtr_on_rts_off_at_start_up():
    b = Bench(AV)
    assert b.signals == [(0.0, "dtr", 1)] and b.st.rts == 0


def test_no_dtr_with_other_flow_control():
    assert Bench(AsciiParams()).signals == []


def test_rts_on_then_data_after_the_output_waiting_time_then_rts_off():
    b = Bench(AV)
    b.request(H("41 42 43"), at=0.1)
    b.idle(0.2)
    char = AV.char_time
    (s_on, _, _), (s_off, _, _) = [x for x in b.signals if x[1] == "rts"]
    assert s_on == pytest.approx(0.1)
    assert b.out[0][0] == pytest.approx(0.1 + 0.010)         # first start bit at RTS ON + 10 ms
    last_stop = b.out[-1][0] + char
    assert s_off == pytest.approx(last_stop + 0.010)           # RTS OFF 10 ms after the last stop bit
    assert b.wire() == H("41 42 43")
    (done,) = b.of(SendDone)
    assert done.time == pytest.approx(s_off)                   # Q19: DONE with RTS OFF


def test_done_at_the_last_stop_bit_in_the_other_reading():
    b = Bench(AV, readings=AsciiReadings(q19_done_at_rts_off=False))
    b.request(H("41"), at=0.1); b.idle(0.2)
    (done,) = b.of(SendDone)
    assert done.time == pytest.approx(0.11 + AV.char_time)


def test_cts_off_at_the_end_of_the_waiting_time_aborts_with_0818():
    b = Bench(AV, cts=False)
    b.request(H("41 42 43"), at=0.1); b.idle(0.2)
    assert b.wire() == b""
    (st,) = b.of(aev.Status)
    assert (st.code, st.side, st.time) == (Code.DSR_CTS_DROPPED, "send", pytest.approx(0.11))
    assert [x for x in b.signals if x[1] == "rts"] == [(0.1, "rts", 1), (pytest.approx(0.11), "rts", 0)]


def test_cts_on_during_the_waiting_time_is_enough():
    b = Bench(AV, cts=False)
    b.request(H("41"), at=0.1)
    b.modem("cts", 1, at=0.105)
    b.idle(0.2)
    assert b.wire() == H("41") and b.out[0][0] == pytest.approx(0.11)


def test_cts_dropping_while_sending_aborts_with_0818():
    b = Bench(AV)
    data = bytes(range(0x20, 0x40))
    b.request(data, at=0.1)
    b.modem("cts", 0, at=0.115)
    b.idle(0.2)
    assert data.startswith(b.wire()) and len(b.wire()) < len(data)
    assert not [s for s, _ in b.out if s > 0.115 + 1e-9]
    assert b.codes() == [Code.DSR_CTS_DROPPED] and b.failed() == [(data, Code.DSR_CTS_DROPPED)]


def test_cts_on_after_rts_off_has_no_effect():
    b = Bench(AV)
    b.request(H("41"), at=0.1); b.idle(0.2)
    b.modem("cts", 0); b.modem("cts", 1); b.idle()
    assert b.codes() == [] and b.done() == [H("41")]


def test_nothing_is_received_while_dsr_is_off():
    b = Bench(AV, dsr=False)
    b.send(H("41 42")); b.idle()
    assert b.frames() == [] and b.codes() == []
    b.modem("dsr", 1); b.send(H("43")); b.idle()
    assert b.frames() == [H("43")]


def test_dsr_off_during_reception_aborts_it():
    b = Bench(AV)
    b.send(H("41 42")); b.modem("dsr", 0); b.idle()
    assert b.frames() == [] and b.codes() == [Code.DSR_CTS_DROPPED]
    assert b.discarded() == [(H("41 42"), aev.DSR_OFF, Code.DSR_CTS_DROPPED)]


def test_dsr_off_during_sending_aborts_the_job():
    b = Bench(AV)
    b.request(bytes(range(0x20, 0x40)), at=0.1)
    b.modem("dsr", 0, at=0.112)
    b.idle(0.2)
    assert b.codes("send") == [Code.DSR_CTS_DROPPED]
    assert b.st.rts == 0


def test_send_does_not_need_dsr():
    b = Bench(AV, dsr=False)
    b.request(H("41"), at=0.1); b.idle(0.2)
    assert b.wire() == H("41")
    b = Bench(AV, dsr=False, readings=AsciiReadings(q19_send_needs_dsr=True))
    b.request(H("41"), at=0.1); b.idle(0.2)
    assert b.wire() == b"" and b.codes() == [Code.DSR_CTS_DROPPED]


def test_no_flow_control_ignores_cts_and_sends_xon_xoff_as_data():
    b = Bench(AsciiParams(), cts=False)
    b.request(H("41")); b.send(H("11 13")); b.idle()
    assert b.wire() == H("41") and b.frames() == [H("11 13")]
