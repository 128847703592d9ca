"""Pure helpers of the ASCII model: the send variants (§2.2.4), names of control characters,
the frame decoder for transcripts, and the station's explanation of what it sent."""

import pytest
from ascii_bench import Bench

from ptpcert.model.hexbytes import parse_hex
from ptpcert.procedures.ascii.model import AsciiParams, AsciiReadings, char_name, describe, send_bytes, split_frames
from ptpcert.procedures.ascii.model.codec import find_end

H = parse_hex
EC = AsciiParams(end_criterion="end_chars", end_chars=(0x03,))
EC2 = AsciiParams(end_criterion="end_chars", end_chars=(0x0D, 0x0A))


@pytest.mark.parametrize("b, name", [(0x03, "ETX"), (0x0D, "CR"), (0x0A, "LF"), (0x11, "DC1"),
                                     (0x13, "DC3"), (0x00, "NUL"), (0x7F, "DEL"), (0x41, "41"), (0xFF, "FF")])
def test_char_name(b, name):
    assert char_name(b) == name


def test_find_end():
    assert find_end(H("41 0D 42 0D 0A 43"), H("0D 0A")) == 5
    assert find_end(H("41 0A 0D"), H("0D 0A")) == -1
    assert find_end(H("03 41 03"), H("03"), 1) == 3


@pytest.mark.parametrize("variant, data, wire", [
    ("up_to_end", H("41 42 03 44 45"), H("41 42 03")),
    ("up_to_end", H("03"), H("03")),
    ("len_with_end", H("41 42 03 44"), H("41 42 03 44")),
    ("len_append_end", H("41 42"), H("41 42 03")),
    ("len_append_end", H("41 03"), H("41 03 03")),
])
def test_send_variants_one_end_character(variant, data, wire):
    assert send_bytes(data, EC.with_(send_variant=variant)) == wire


def test_send_variants_two_end_characters():
    assert send_bytes(H("41 0D 42 0D 0A 43"), EC2) == H("41 0D 42 0D 0A")
    assert send_bytes(H("41 0D 42 0D 0A 43"), EC2, AsciiReadings(q6_up_to_end_finds_sequence=False)) == H("41 0D")
    assert send_bytes(H("41"), EC2.with_(send_variant="len_append_end")) == H("41 0D 0A")


def test_split_by_end_characters_names_them():
    pieces = split_frames(H("41 42 03 43 03 44"), EC)
    assert [(p.kind, p.data) for p in pieces] == [("frame", H("41 42 03")), ("frame", H("43 03")),
                                                  ("fragment", H("44"))]
    assert describe(H("41 42 03 43 03 44"), EC) == "[41 42 <ETX>] [43 <ETX>] [44]?"
    assert describe(H("41 0D 0A"), EC2) == "[41 <CR> <LF>]"


def test_split_by_fixed_length():
    p = AsciiParams(end_criterion="fixed_length", fixed_length=2)
    assert describe(H("31 32 33 34 35"), p) == "[31 32] [33 34] [35]?"


def test_split_by_pauses_when_timed():
    p = AsciiParams()
    c = p.char_time
    timed = [(0.0, 0x41), (c, 0x42), (2 * c + p.cdt + 0.001, 0x43)]
    pieces = split_frames(timed, p)
    assert [(x.kind, x.data) for x in pieces] == [("frame", H("41 42")), ("frame", H("43"))]
    assert pieces[0].start == 0.0 and pieces[0].end == pytest.approx(2 * c)
    # a gap of exactly the CDT does not split (Q4)
    timed = [(0.0, 0x41), (c + p.cdt, 0x42)]
    assert describe(timed, p) == "[41 42]"


def test_a_pause_cuts_a_fragment_under_end_characters():
    c = EC.char_time
    timed = [(0.0, 0x41), (c + 0.02, 0x42), (2 * c + 0.02, 0x03)]
    assert describe(timed, EC) == "[41]? [42 <ETX>]"


def test_xon_xoff_are_named():
    # a frame is listed when it is complete, after the flow-control characters inside it
    p = EC.with_(flow_control="xon_xoff")
    assert describe(H("41 13 42 11 03"), p) == "XOFF(13) XON(11) [41 42 <ETX>]"
    assert describe(H("41 13 42 11 03"), EC) == "[41 13 42 11 <ETX>]"


def test_the_station_explains_what_it_sent():
    b = Bench(AsciiParams(flow_control="xon_xoff", end_criterion="end_chars", buffer_frames=1), app="echo",
              read_delay=0.1)
    b.send(H("41 03")); b.idle(0.5)
    log = b.st.tx_log
    assert [r.data for r in log] == [H("11"), H("13"), H("11"), H("41 03")]
    startup, xoff, xon, echo = log
    assert startup.kind == "control" and startup.why.input == "START"
    assert xoff.why.machine == "fc" and xoff.why.action == "hold_partner"
    assert xon.why.action == "let_partner_send" and "§2.2.4" in str(xon.why)
    assert echo.kind == "data" and echo.why.machine == "tx" and echo.why.decisions == ["START"]
    assert b.st.explain(echo.start + b.char).data == H("41 03")
