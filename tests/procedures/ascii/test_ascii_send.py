"""The ASCII driver's send side (§2.2.4; Fig. 2-20; Table 6-2), and the echo application,
in virtual time. The expected line is written from the manual's rules."""

import pytest
from ascii_bench import Bench

from ptpcert.model.codes import Code
from ptpcert.model.events import Delivered, SendDone
from ptpcert.model.hexbytes import parse_hex
from ptpcert.procedures.ascii.model import AsciiParams, AsciiReadings, send_bytes

H = parse_hex
EC = AsciiParams(end_criterion="end_chars", end_chars=(0x03,))
EC2 = AsciiParams(end_criterion="end_chars", end_chars=(0x0D, 0x0A))


def frames_on_line(out, char):
    """Split the station's characters into bursts sent back to back: [(first start,
    last stop, bytes)]."""
    bursts = []
    for start, b in out:
        if bursts and abs(start - bursts[-1][1]) < 1e-9:
            s, _, data = bursts[-1]
            bursts[-1] = (s, start + char, data + bytes([b]))
        else:
            bursts.append((start, start + char, bytes([b])))
    return bursts


# =========================================================== the pause between frames (§2.2.4)
@pytest.mark.parametrize("cdt_ms", [4, 100])
def test_cdt_criterion_holds_more_than_the_cdt_between_frames(cdt_ms):
    p = AsciiParams(cdt_ms=cdt_ms)
    b = Bench(p)
    b.request(H("41 42")); b.request(H("43 44")); b.idle(1.0)
    (s1, e1, d1), (s2, e2, d2) = frames_on_line(b.out, p.char_time)
    assert (d1, d2) == (H("41 42"), H("43 44"))
    assert s2 - e1 > p.cdt
    # Q5: the pause is the CDT and one character time
    assert s2 - e1 == pytest.approx(p.cdt + p.char_time)
    assert b.done() == [H("41 42"), H("43 44")]


def test_pause_of_the_other_reading():
    p = AsciiParams()
    b = Bench(p, readings=AsciiReadings(q5_send_pause_extra_chars=0.5))
    b.request(H("41")); b.request(H("42")); b.idle(1.0)
    (_, e1, _), (s2, _, _) = frames_on_line(b.out, p.char_time)
    assert s2 - e1 == pytest.approx(p.cdt + 0.5 * p.char_time)


def test_no_wait_when_the_last_frame_is_long_gone():
    p = AsciiParams(cdt_ms=100)
    b = Bench(p)
    b.request(H("41")); b.idle(1.0)
    t = b.t
    b.request(H("42")); b.idle()
    assert b.out[-1] == (pytest.approx(t), 0x42)


def test_a_frame_goes_out_back_to_back_and_done_follows_its_last_stop_bit():
    p = AsciiParams()
    b = Bench(p)
    b.request(bytes(range(20)), at=0.01); b.idle(0.1)
    starts = [s for s, _ in b.out]
    assert b.wire() == bytes(range(20))
    assert starts == pytest.approx([0.01 + i * p.char_time for i in range(20)])
    (done,) = b.of(SendDone)
    assert done.time == pytest.approx(0.01 + 20 * p.char_time)


@pytest.mark.parametrize("pause", [True, False])
def test_fixed_length_pause_can_be_switched_off(pause):
    p = AsciiParams(end_criterion="fixed_length", fixed_length=5, send_pause=pause)
    b = Bench(p)
    b.request(H("31 32 33 34 35")); b.request(H("36 37 38 39 3A")); b.idle()
    bursts = frames_on_line(b.out, p.char_time)
    assert b.wire() == H("31 32 33 34 35 36 37 38 39 3A")
    if pause:
        (_, e1, _), (s2, _, _) = bursts
        assert s2 - e1 >= p.cdt
    else:
        assert len(bursts) == 1   # no minimum gap required; the model sends at once


def test_end_character_criterion_has_no_pause():
    b = Bench(EC)
    b.request(H("41 03")); b.request(H("42 03")); b.idle()
    assert len(frames_on_line(b.out, EC.char_time)) == 1
    assert b.wire() == H("41 03 42 03")


def test_a_second_job_waits_for_the_first():
    b = Bench(EC)
    b.request(bytes(10) + b"\x03")
    b.request(H("42 03"), at=b.t + 3 * EC.char_time)
    b.idle()
    assert b.wire() == bytes(10) + H("03 42 03")


# =========================================================== the send variants (§2.2.4)
def test_up_to_and_including_the_end_character():
    b = Bench(EC.with_(send_variant="up_to_end"))
    b.request(H("41 42 03 44 45")); b.idle()
    assert b.wire() == H("41 42 03") and b.done() == [H("41 42 03 44 45")]


def test_up_to_and_including_the_end_sequence():
    b = Bench(EC2.with_(send_variant="up_to_end"))
    b.request(H("41 0D 0A 42")); b.idle()
    assert b.wire() == H("41 0D 0A")


def test_up_to_end_with_the_first_end_character_alone():
    r = AsciiReadings(q6_up_to_end_finds_sequence=False)
    b = Bench(EC2.with_(send_variant="up_to_end"), readings=r)
    b.request(H("41 0D 42 0D 0A")); b.idle()
    assert b.wire() == H("41 0D")


def test_up_to_end_without_end_character():
    # Q6: the LEN bytes go out; the other reading refuses the job
    b = Bench(EC.with_(send_variant="up_to_end"))
    b.request(H("41 42")); b.idle()
    assert b.wire() == H("41 42")
    b = Bench(EC.with_(send_variant="up_to_end"),
              readings=AsciiReadings(q6_up_to_end_without_end_sends_all=False))
    assert not b.request(H("41 42"))
    b.idle()
    assert b.wire() == b"" and b.failed() == [(H("41 42"), Code.LEN_ILLEGAL)]


def test_exactly_len_bytes():
    b = Bench(EC.with_(send_variant="len_with_end"))
    b.request(H("41 42 43 03")); b.idle()
    assert b.wire() == H("41 42 43 03")


def test_exactly_len_bytes_even_if_the_last_is_no_end_character():
    b = Bench(EC.with_(send_variant="len_with_end"))
    b.request(H("41 03 43")); b.idle()
    assert b.wire() == H("41 03 43")


@pytest.mark.parametrize("params, end", [(EC, H("03")), (EC2, H("0D 0A"))])
def test_len_bytes_plus_end_characters(params, end):
    b = Bench(params.with_(send_variant="len_append_end"))
    b.request(H("41 42 43")); b.idle()
    assert b.wire() == H("41 42 43") + end


def test_append_variant_may_exceed_1024_on_the_line():
    b = Bench(EC2.with_(send_variant="len_append_end"))
    assert b.request(bytes(1024))
    b.idle(2.0)
    assert b.wire() == bytes(1024) + H("0D 0A")


@pytest.mark.parametrize("params", [AsciiParams(), AsciiParams(end_criterion="fixed_length", fixed_length=7)])
def test_cdt_and_fixed_length_send_the_data_as_given(params):
    data = H("03 0D 0A 11 13 00 FF")
    assert send_bytes(data, params) == data
    b = Bench(params)
    b.request(data); b.idle()
    assert b.wire() == data


# =========================================================== length rules (Table 6-2, Table 8-2)
@pytest.mark.parametrize("n", [0, 1025])
def test_illegal_len_is_refused_and_nothing_goes_out(n):
    b = Bench(AsciiParams())
    assert not b.request(bytes(n))
    b.idle()
    assert b.wire() == b"" and b.codes() == [Code.LEN_ILLEGAL]
    assert b.failed() == [(bytes(n), Code.LEN_ILLEGAL)]


@pytest.mark.parametrize("n", [1, 1024])
def test_len_limits_are_allowed(n):
    b = Bench(AsciiParams())
    assert b.request(bytes(n))
    b.idle(2.0)
    assert b.wire() == bytes(n) and b.done() == [bytes(n)]


def test_seven_bit_frame_cannot_carry_8_bit_data():
    b = Bench(AsciiParams(data_bits=7))
    with pytest.raises(ValueError):
        b.request(H("41 C1"))


def test_xon_xoff_codes_in_send_data_are_sent_as_given():
    # §2.2.4: they must not occur in user data; what the driver does with them is open (sent)
    b = Bench(AsciiParams(flow_control="xon_xoff"))
    b.clear()
    b.request(H("41 11 13 42")); b.idle()
    assert b.wire() == H("41 11 13 42")


# =========================================================== echo application
def test_echo_sends_each_frame_back_with_its_end_character():
    b = Bench(EC, app="echo")
    b.send(H("41 42 03")); b.idle()
    assert b.frames() == [H("41 42 03")] and b.wire() == H("41 42 03")


def test_echo_with_appended_end_character():
    b = Bench(EC.with_(send_variant="len_append_end"), app="echo")
    b.send(H("41 03")); b.idle()
    assert b.wire() == H("41 03 03")


def test_echo_reads_the_next_frame_only_when_its_job_is_done():
    b = Bench(EC, app="echo")
    t = b.send(H("31 32 33 03 41 03"))
    assert b.st.frames_stored == 1          # 41 03 waits: 31 32 33 03 is being sent
    b.idle()
    assert b.wire() == H("31 32 33 03 41 03")
    second = [e for e in b.frames()]
    assert second == [H("31 32 33 03"), H("41 03")]
    # the first frame was complete two characters before t, its echo (four characters)
    # was done two characters after t: then the second frame was read
    assert b.of(Delivered)[1].time == pytest.approx(t - 2 * EC.char_time + 4 * EC.char_time)


def test_slow_reader_reads_a_frame_only_after_its_delay():
    b = Bench(EC, app="echo", read_delay=0.5)
    t = b.send(H("41 03")); b.idle(1.0)
    (d,) = b.of(Delivered)
    assert d.time == pytest.approx(t + 0.5)
    assert b.out[0][0] == pytest.approx(t + 0.5)


def test_no_read_application_leaves_the_frames_in_the_buffer():
    b = Bench(EC, app="no_read")
    b.send(H("41 03 42 03")); b.idle()
    assert b.frames() == [] and b.st.stored_frames == (H("41 03"), H("42 03")) and b.wire() == b""


def test_none_application_reads_and_never_sends():
    b = Bench(EC, app="none")
    b.send(H("41 03 42 03")); b.idle()
    assert b.frames() == [H("41 03"), H("42 03")] and b.wire() == b""


def test_full_duplex_receives_while_sending():
    b = Bench(EC, app="none")
    b.request(bytes(range(4, 40)) + b"\x03")
    b.send(H("41 42 03"), at=0.002); b.idle(0.1)
    assert b.frames() == [H("41 42 03")] and b.wire() == bytes(range(4, 40)) + b"\x03"
