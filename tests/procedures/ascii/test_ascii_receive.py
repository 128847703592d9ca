"""The ASCII driver's receive side (§2.2.4; Figs. 2-21, 2-22, 2-23), in virtual time.

Set-up unless a test says otherwise: 9600 bit/s, 8 data bits, even parity, 1 stop bit
(11 bits, 1.146 ms a character), CDT 4 ms, no flow control, 250 buffered frames, prevent
overwrite. "idle" is 20 ms of quiet line, "g" a gap of 1 ms between two characters. The
expected frames are written from the manual's rules, never taken from the model."""

import pytest
from ascii_bench import GAP, Bench

from ptpcert.model.codes import Code
from ptpcert.model.hexbytes import parse_hex
from ptpcert.procedures.ascii.model import AsciiParams, AsciiReadings
from ptpcert.procedures.ascii.model import events as aev

H = parse_hex
CDT = AsciiParams(end_criterion="cdt")
EC = AsciiParams(end_criterion="end_chars", end_chars=(0x03,))
EC2 = AsciiParams(end_criterion="end_chars", end_chars=(0x0D, 0x0A))
FL5 = AsciiParams(end_criterion="fixed_length", fixed_length=5)

E806, E80C, E80D = Code.CDT_EXCEEDED, Code.CHARACTER_ERROR, Code.LINE_BREAK


def bench(params, app="none", **kw):
    return Bench(params, app, **kw)


def test_character_time_and_cdt_of_the_common_setup():
    # Table 2-8: 1 start + 8 data + parity + 1 stop = 11 bits; Table 2-7: CDT default 4 ms
    assert CDT.bits_per_char == 11
    assert CDT.char_time == pytest.approx(11 / 9600)
    assert CDT.cdt_ms == 4


# =========================================================== criterion "expiry of CDT"
class TestCdtCriterion:
    def test_a_pause_ends_the_frame(self):
        b = bench(CDT)
        b.send(H("48 65 6C 6C 6F")); b.idle()
        assert b.frames() == [H("48 65 6C 6C 6F")] and b.codes() == []

    def test_two_bursts_separated_by_idle_are_two_frames(self):
        b = bench(CDT)
        b.send(H("41 42")); b.idle(); b.send(H("43 44")); b.idle()
        assert b.frames() == [H("41 42"), H("43 44")]

    def test_a_short_gap_does_not_end_the_frame(self):
        b = bench(CDT)
        b.send(H("41 42")); b.send(H("43 44"), at=b.line_free + GAP); b.idle()
        assert b.frames() == [H("41 42 43 44")]

    def test_every_byte_value_is_data(self):
        # §2.2.4 code transparency: CDT criterion without XON/XOFF
        b = bench(CDT)
        b.send(H("02 03 0D 0A 00 FF 10 11 13")); b.idle()
        assert b.frames() == [H("02 03 0D 0A 00 FF 10 11 13")]

    def test_character_error_spoils_the_burst_and_is_reported_when_the_cdt_expires(self):
        # Fig. 2-21: wait for the CDT to expire, discard, enter the error in STATUS
        b = bench(CDT)
        b.send(H("41 42")); b.send_bad(0x43); last = b.send(H("44")); b.idle()
        b.send(H("51 52")); b.idle()
        assert b.frames() == [H("51 52")]
        (st,) = [e for e in b.of(aev.Status)]
        assert st.code == E80C and st.side == "receive"
        assert st.time == pytest.approx(last + CDT.cdt + CDT.char_time)
        assert b.discarded() == [(H("41 42 44"), aev.CHARACTER_ERROR, E80C)]

    def test_1024_bytes_are_one_frame(self):
        data = bytes(range(256)) * 4
        b = bench(CDT)
        b.send(data); b.idle()
        assert b.frames() == [data]

    @pytest.mark.parametrize("code", [Code.FRAME_TOO_LONG, Code.NO_RECEIVE_BUFFER])
    def test_1025_bytes_are_discarded(self, code):
        # Q13: not delivered; 16#0816 by default, 16#080A the other reading
        data = bytes(range(256)) * 4 + b"\x00"
        b = bench(CDT, readings=AsciiReadings(q13_overlong_frame_code=code))
        b.send(data); b.idle()
        assert b.frames() == [] and b.codes() == [code]
        b.send(H("41")); b.idle()
        assert b.frames() == [H("41")]

    @pytest.mark.parametrize("delta, merged", [(-0.0003, True), (0.0, True), (0.0003, False)])
    def test_both_edges_of_the_cdt(self, delta, merged):
        # a gap up to the CDT keeps the frame; a longer one ends it (Q4: exactly CDT keeps it)
        b = bench(CDT)
        b.send(H("41 42")); b.send(H("43 44"), at=b.line_free + CDT.cdt + delta); b.idle()
        assert b.frames() == ([H("41 42 43 44")] if merged else [H("41 42"), H("43 44")])

    @pytest.mark.parametrize("delta, merged", [(-0.0003, True), (0.0003, False)])
    def test_error_recovery_at_both_edges_of_the_cdt(self, delta, merged):
        # characters within the CDT after an error belong to the spoiled frame
        b = bench(CDT)
        b.send(H("41")); b.send_bad(0x42)
        b.send(H("43 44"), at=b.line_free + CDT.cdt + delta); b.idle()
        assert b.frames() == ([] if merged else [H("43 44")])
        assert b.codes() == [E80C]

    def test_frame_stored_at_cdt_expiry(self):
        b = bench(CDT, app="no_read")
        last = b.send(H("41 42")); b.idle()
        (e,) = b.of(aev.FrameStored)
        assert e.time == pytest.approx(last + CDT.cdt + CDT.char_time)


# =========================================================== criterion "end character" 03
class TestOneEndCharacter:
    def test_the_end_character_is_part_of_the_frame(self):
        b = bench(EC)
        b.send(H("41 42 43 03")); b.idle()
        assert b.frames() == [H("41 42 43 03")] and b.codes() == []

    def test_the_end_character_completes_the_frame_at_once(self):
        b = bench(EC, app="no_read")
        b.send(H("41 03")); t2 = b.send(H("42 03")); b.idle()
        assert b.stored() == [H("41 03"), H("42 03")]
        assert b.of(aev.FrameStored)[1].time == pytest.approx(t2)

    def test_characters_after_the_end_character_are_discarded_when_the_cdt_expires(self):
        b = bench(EC)
        b.send(H("41 42 03 58 59")); b.idle()
        assert b.frames() == [H("41 42 03")]
        assert b.discarded() == [(H("58 59"), aev.CDT_EXPIRED, E806)]
        assert b.codes() == [E806]

    def test_trailing_characters_discarded_silently_in_the_other_reading(self):
        b = bench(EC, readings=AsciiReadings(q10_trailing_discard_code=None))
        b.send(H("41 42 03 58 59")); b.idle()
        assert b.frames() == [H("41 42 03")] and b.codes() == []

    def test_trailing_characters_merge_with_the_next_frame(self):
        b = bench(EC)
        b.send(H("41 42 03 58 59")); b.send(H("43 44 03"), at=b.line_free + GAP); b.idle()
        assert b.frames() == [H("41 42 03"), H("58 59 43 44 03")] and b.codes() == []

    def test_a_frame_without_end_character_is_discarded_with_0806(self):
        b = bench(EC)
        last = b.send(H("41 42 43")); b.idle()
        assert b.frames() == []
        (st,) = b.of(aev.Status)
        assert st.code == E806 and st.time == pytest.approx(last + EC.cdt + EC.char_time)

    def test_a_frame_without_end_character_merges_with_the_next(self):
        b = bench(EC)
        b.send(H("41 42 43")); b.send(H("44 45 03"), at=b.line_free + GAP); b.idle()
        assert b.frames() == [H("41 42 43 44 45 03")]

    def test_a_fragment_cut_by_idle_is_discarded_and_the_next_frame_stands(self):
        b = bench(EC)
        b.send(H("41 42")); b.idle(); b.send(H("43 03")); b.idle()
        assert b.frames() == [H("43 03")] and b.codes() == [E806]

    def test_end_character_inside_the_data_splits_the_user_payload(self):
        # not code transparent (§2.2.4): the user meant 41 03 42; the receiver sees two frames
        b = bench(EC)
        b.send(H("41 03 42 03")); b.idle()
        assert b.frames() == [H("41 03"), H("42 03")]

    def test_character_error_reported_when_a_valid_end_character_arrives(self):
        # Fig. 2-22: after an error, wait for a valid end character
        b = bench(EC)
        b.send(H("41")); b.send_bad(0x42); end = b.send(H("43 03")); b.idle()
        b.send(H("44 03")); b.idle()
        assert b.frames() == [H("44 03")]
        (st,) = b.of(aev.Status)
        assert st.code == E80C and st.time == pytest.approx(end)

    def test_end_character_alone_is_a_frame(self):
        b = bench(EC)
        b.send(H("03")); b.idle()
        assert b.frames() == [H("03")]

    @pytest.mark.parametrize("delta, merged", [(-0.0003, True), (0.0, True), (0.0003, False)])
    def test_fragment_at_both_edges_of_the_cdt(self, delta, merged):
        b = bench(EC)
        b.send(H("41 42")); b.send(H("43 03"), at=b.line_free + EC.cdt + delta); b.idle()
        if merged:
            assert b.frames() == [H("41 42 43 03")] and b.codes() == []
        else:
            assert b.frames() == [H("43 03")] and b.codes() == [E806]

    @pytest.mark.parametrize("delta, merged", [(-0.0003, True), (0.0003, False)])
    def test_trailing_characters_at_both_edges_of_the_cdt(self, delta, merged):
        b = bench(EC)
        b.send(H("41 03 58")); b.send(H("59 03"), at=b.line_free + EC.cdt + delta); b.idle()
        if merged:
            assert b.frames() == [H("41 03"), H("58 59 03")] and b.codes() == []
        else:
            assert b.frames() == [H("41 03"), H("59 03")] and b.codes() == [E806]

    @pytest.mark.parametrize("delta, merged", [(-0.0003, True), (0.0003, False)])
    def test_error_recovery_at_both_edges_of_the_cdt(self, delta, merged):
        # within the CDT the end character ends the spoiled frame; after it the CDT did
        b = bench(EC)
        b.send(H("41")); b.send_bad(0x42)
        b.send(H("43 03"), at=b.line_free + EC.cdt + delta); b.idle()
        assert b.codes() == [E80C]
        assert b.frames() == ([] if merged else [H("43 03")])

    def test_cdt_ending_a_spoiled_frame_can_also_report_0806(self):
        # Q12, other reading
        b = bench(EC, readings=AsciiReadings(q12_cdt_also_reports_0806=True))
        b.send(H("41")); b.send_bad(0x42); b.idle()
        assert b.codes() == [E80C, E806]


# =========================================================== two end characters 0D 0A
class TestTwoEndCharacters:
    def test_the_pair_ends_the_frame(self):
        b = bench(EC2)
        b.send(H("41 42 0D 0A")); b.idle()
        assert b.frames() == [H("41 42 0D 0A")]

    def test_a_lone_first_end_character_is_data(self):
        b = bench(EC2)
        b.send(H("41 0D 42 0D 0A")); b.idle()
        assert b.frames() == [H("41 0D 42 0D 0A")]

    @pytest.mark.parametrize("data", [H("41 42 0D"), H("41 0A 0D")])
    def test_no_complete_pair_is_a_fragment(self, data):
        b = bench(EC2)
        b.send(data); b.idle()
        assert b.frames() == [] and b.codes() == [E806]

    def test_overlapping_first_end_characters(self):
        b = bench(EC2)
        b.send(H("41 0D 0D 0A")); b.idle()
        assert b.frames() == [H("41 0D 0D 0A")]

    def test_trailing_characters_merge(self):
        b = bench(EC2)
        b.send(H("41 0D 0A 42")); b.send(H("43 0D 0A"), at=b.line_free + GAP); b.idle()
        assert b.frames() == [H("41 0D 0A"), H("42 43 0D 0A")]

    @pytest.mark.parametrize("delta, merged", [(-0.0003, True), (0.0003, False)])
    def test_pair_split_by_a_pause_at_both_edges_of_the_cdt(self, delta, merged):
        b = bench(EC2)
        b.send(H("41 0D")); b.send(H("0A"), at=b.line_free + EC2.cdt + delta); b.idle()
        if merged:
            assert b.frames() == [H("41 0D 0A")] and b.codes() == []
        else:
            # 41 0D is a fragment; the lone 0A after the pause is one too
            assert b.frames() == [] and b.codes() == [E806, E806]

    def test_an_error_between_the_end_characters_breaks_the_pair(self):
        b = bench(EC2)
        b.send(H("41 0D")); b.send_bad(0x0D); b.send(H("0A 42")); end = b.send(H("0D 0A")); b.idle()
        (st,) = b.of(aev.Status)
        assert st.code == E80C and st.time == pytest.approx(end)
        assert b.frames() == []

    def test_equal_end_characters(self):
        p = AsciiParams(end_criterion="end_chars", end_chars=(0x0D, 0x0D))
        b = bench(p)
        b.send(H("41 0D 0D 0D 42 0D 0D")); b.idle()
        assert b.frames() == [H("41 0D 0D"), H("0D 42 0D 0D")]

    def test_nul_can_be_the_second_end_character(self):
        # Q7: two end characters are configured by giving two; 00 is then a real one
        p = AsciiParams(end_criterion="end_chars", end_chars=(0x03, 0x00))
        b = bench(p)
        b.send(H("41 03 00")); b.idle()
        assert b.frames() == [H("41 03 00")]


# =========================================================== criterion "fixed length" N = 5
class TestFixedLength:
    def test_n_characters_are_a_frame(self):
        b = bench(FL5)
        b.send(H("31 32 33 34 35")); b.idle()
        assert b.frames() == [H("31 32 33 34 35")] and b.codes() == []

    def test_the_nth_character_completes_the_frame_at_once(self):
        b = bench(FL5, app="no_read")
        b.send(H("31 32 33 34")); t5 = b.send(H("35"))
        (e,) = b.of(aev.FrameStored)
        assert e.time == pytest.approx(t5)

    def test_ten_characters_are_two_frames(self):
        b = bench(FL5)
        b.send(H("31 32 33 34 35 36 37 38 39 3A")); b.idle()
        assert b.frames() == [H("31 32 33 34 35"), H("36 37 38 39 3A")]

    def test_surplus_characters_discarded_when_the_cdt_expires(self):
        b = bench(FL5)
        b.send(H("31 32 33 34 35 36 37")); b.idle()
        assert b.frames() == [H("31 32 33 34 35")]
        assert b.discarded() == [(H("36 37"), aev.CDT_EXPIRED, E806)]

    def test_surplus_characters_merge_with_the_next_frame(self):
        b = bench(FL5)
        b.send(H("31 32 33 34 35 36 37")); b.send(H("41 42 43 44 45"), at=b.line_free + GAP); b.idle()
        assert b.frames() == [H("31 32 33 34 35"), H("36 37 41 42 43")]
        assert b.discarded() == [(H("44 45"), aev.CDT_EXPIRED, E806)]

    def test_a_short_frame_is_discarded(self):
        b = bench(FL5)
        b.send(H("31 32 33")); b.idle()
        assert b.frames() == [] and b.codes() == [E806]

    def test_a_short_frame_merges_with_the_next(self):
        b = bench(FL5)
        b.send(H("31 32 33")); b.send(H("41 42 43 44 45"), at=b.line_free + GAP); b.idle()
        assert b.frames() == [H("31 32 33 41 42")]
        assert b.discarded() == [(H("43 44 45"), aev.CDT_EXPIRED, E806)]

    def test_code_transparent(self):
        b = bench(FL5)
        b.send(H("03 0D 0A 11 13")); b.idle()
        assert b.frames() == [H("03 0D 0A 11 13")]

    def test_character_error_reported_when_n_characters_have_arrived(self):
        # Fig. 2-23: wait for the configured number of characters
        b = bench(FL5)
        b.send(H("31")); b.send_bad(0x32); fifth = b.send(H("33 34 35")); b.idle()
        b.send(H("41 42 43 44 45")); b.idle()
        assert b.frames() == [H("41 42 43 44 45")]
        (st,) = b.of(aev.Status)
        assert st.code == E80C and st.time == pytest.approx(fifth)

    def test_error_in_the_last_character(self):
        b = bench(FL5)
        b.send(H("31 32 33 34")); t = b.send_bad(0x35); b.send(H("41 42 43 44 45")); b.idle()
        assert b.frames() == [H("41 42 43 44 45")]
        assert [(e.code, e.time) for e in b.of(aev.Status)] == [(E80C, pytest.approx(t))]

    def test_length_one(self):
        b = bench(AsciiParams(end_criterion="fixed_length", fixed_length=1))
        b.send(H("41 42 43")); b.idle()
        assert b.frames() == [H("41"), H("42"), H("43")]

    def test_length_one_with_an_error(self):
        b = bench(AsciiParams(end_criterion="fixed_length", fixed_length=1))
        b.send(H("41")); b.send_bad(0x42); b.send(H("43")); b.idle()
        assert b.frames() == [H("41"), H("43")] and b.codes() == [E80C]

    @pytest.mark.parametrize("delta, merged", [(-0.0003, True), (0.0, True), (0.0003, False)])
    def test_short_frame_at_both_edges_of_the_cdt(self, delta, merged):
        b = bench(FL5)
        b.send(H("31 32 33")); b.send(H("34 35"), at=b.line_free + FL5.cdt + delta); b.idle()
        if merged:
            assert b.frames() == [H("31 32 33 34 35")] and b.codes() == []
        else:
            assert b.frames() == [] and b.codes() == [E806, E806]

    @pytest.mark.parametrize("delta, merged", [(-0.0003, True), (0.0003, False)])
    def test_surplus_at_both_edges_of_the_cdt(self, delta, merged):
        b = bench(FL5)
        b.send(H("31 32 33 34 35 36")); b.send(H("37 38 39 3A"), at=b.line_free + FL5.cdt + delta); b.idle()
        if merged:
            assert b.frames() == [H("31 32 33 34 35"), H("36 37 38 39 3A")] and b.codes() == []
        else:
            assert b.frames() == [H("31 32 33 34 35")] and b.codes() == [E806, E806]

    @pytest.mark.parametrize("delta, merged", [(-0.0003, True), (0.0003, False)])
    def test_error_recovery_at_both_edges_of_the_cdt(self, delta, merged):
        b = bench(FL5)
        b.send(H("31")); b.send_bad(0x32)
        b.send(H("41 42 43 44 45"), at=b.line_free + FL5.cdt + delta); b.idle()
        if merged:
            # 31 <32> 41 42 43 is the spoiled frame; 44 45 a short one
            assert b.frames() == [] and b.codes() == [E80C, E806]
        else:
            assert b.frames() == [H("41 42 43 44 45")] and b.codes() == [E80C]


# =========================================================== line conditions, all criteria
@pytest.mark.parametrize("params", [CDT, EC, FL5], ids=["cdt", "end_chars", "fixed_length"])
class TestLineConditions:
    def test_break_inside_a_frame_discards_it_and_reports_080d_at_once(self, params):
        b = bench(params)
        b.send(H("41 42")); b.brk()
        t = b.t
        b.idle()
        assert [(e.code, e.time) for e in b.of(aev.Status)] == [(E80D, t)]
        assert b.discarded() == [(H("41 42"), aev.LINE_BREAK, E80D)]
        b.send(H("31 32 33 34 03") if params is not FL5 else H("31 32 33 34 35")); b.idle()
        assert b.frames() == [H("31 32 33 34 03") if params is not FL5 else H("31 32 33 34 35")]

    def test_break_while_idle_reports_080d(self, params):
        b = bench(params)
        b.brk(); b.idle()
        assert b.codes() == [E80D] and b.discarded() == []

    def test_error_first_character(self, params):
        b = bench(params)
        b.send_bad(0x41); b.send(H("42 43 44 03") if params is not FL5 else H("42 43 44 45")); b.idle()
        assert b.frames() == [] and b.codes() == [E80C]
        b.send(H("51 52 53 54 03") if params is not FL5 else H("51 52 53 54 55")); b.idle()
        assert b.frames() == [H("51 52 53 54 03") if params is not FL5 else H("51 52 53 54 55")]

    def test_nothing_is_received_before_start_up(self, params):
        b = Bench(params, "none", power_on=False)
        b.send(H("41 42 03 04 05")); b.idle()
        b.st.power_on(b.t)
        b.idle()
        assert b.frames() == [] and b.codes() == []


def test_seven_data_bits_mask_the_eighth_bit():
    # a 7-bit character frame carries 00..7F (§2.2.4)
    b = bench(AsciiParams(data_bits=7, end_criterion="end_chars", end_chars=(0x03,)))
    b.send(bytes([0xC1, 0x83])); b.idle()
    assert b.frames() == [H("41 03")]


# =========================================================== receive buffer (Table 2-10)
class TestReceiveBuffer:
    def test_frames_are_read_oldest_first(self):
        b = bench(EC, app="no_read")
        for x in (H("31 03"), H("32 03"), H("33 03")):
            b.send(x)
        b.idle()
        assert [b.read(), b.read(), b.read(), b.read()] == [H("31 03"), H("32 03"), H("33 03"), None]

    def test_full_buffer_with_overwrite_protection_discards_the_new_frame(self):
        p = EC.with_(buffer_frames=2)
        b = bench(p, app="no_read")
        b.send(H("31 03")); b.send(H("32 03")); t = b.send(H("33 03")); b.idle()
        assert b.st.stored_frames == (H("31 03"), H("32 03"))
        assert [(e.code, e.time) for e in b.of(aev.Status)] == [(Code.NO_RECEIVE_BUFFER, pytest.approx(t))]
        assert b.discarded() == [(H("33 03"), aev.BUFFER_FULL, Code.NO_RECEIVE_BUFFER)]
        assert b.read() == H("31 03")
        b.send(H("34 03")); b.idle()
        assert b.st.stored_frames == (H("32 03"), H("34 03"))

    def test_without_overwrite_protection_the_newest_frame_replaces_the_unread_one(self):
        p = EC.with_(buffer_frames=1, prevent_overwrite=False)
        b = bench(p, app="no_read")
        b.send(H("31 03")); b.send(H("32 03")); b.send(H("33 03")); b.idle()
        assert b.st.stored_frames == (H("33 03"),) and b.codes() == []
        assert [d for d, r, _ in b.discarded()] == [H("31 03"), H("32 03")]
        assert {r for _, r, _ in b.discarded()} == {aev.OVERWRITTEN}
        assert b.read() == H("33 03")

    def test_1024_bytes_fill_the_buffer(self):
        # four frames of 256 bytes fill it; a fifth finds no room and is discarded (16#080A)
        p = AsciiParams()
        b = bench(p, app="no_read")
        for i in range(5):
            b.send(bytes([i]) * 256); b.idle()
        assert b.st.frames_stored == 4 and b.st.buffer_fill == 1024
        assert b.codes() == [Code.NO_RECEIVE_BUFFER]
        assert b.discarded() == [(bytes([4]) * 256, aev.NO_ROOM, Code.NO_RECEIVE_BUFFER)]
        b.read()
        b.send(bytes([5]) * 256); b.idle()
        assert b.st.frames_stored == 4

    def test_a_frame_that_overflows_the_buffer_is_discarded_the_earlier_ones_stay(self):
        p = AsciiParams()
        b = bench(p, app="no_read")
        b.send(bytes(1000)); b.idle()
        b.send(bytes([1]) * 30); b.idle()
        assert b.st.stored_frames == (bytes(1000),)
        assert b.codes() == [Code.NO_RECEIVE_BUFFER]

    def test_overwrite_frame_may_use_the_space_of_the_unread_one(self):
        p = AsciiParams(buffer_frames=1, prevent_overwrite=False)
        b = bench(p, app="no_read")
        b.send(bytes(1000)); b.idle()
        b.send(bytes([1]) * 1000); b.idle()
        assert b.st.stored_frames == (bytes([1]) * 1000,) and b.codes() == []

    def test_the_application_reads_each_frame_once(self):
        b = bench(EC, app="none")
        b.send(H("31 03 32 03")); b.idle()
        assert b.frames() == [H("31 03"), H("32 03")] and b.st.frames_stored == 0
