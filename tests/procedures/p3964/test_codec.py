"""Codec: DLE doubling, BCC, framing and parsing, checked against the manual's examples
(Fig. 2-4 and blocks with data DLEs, §2.2.2 Block check character) and both ways with hypothesis."""

import pytest
from hypothesis import given
from hypothesis import strategies as st

from ptpcert.model.hexbytes import hexstr, parse_hex
from ptpcert.procedures.p3964.model import codec
from ptpcert.procedures.p3964.model.codec import DLE, FrameError, bcc, body, frame, parse, parse_body, stuff, unstuff

P1 = parse_hex("31 10 32 15 03")

# Payloads biased toward the control characters.
payloads = st.lists(st.sampled_from([0x02, 0x03, 0x10, 0x15, 0x00]) | st.integers(0, 255),
                    min_size=0, max_size=300).map(bytes)


def test_fig_2_4_example():
    # Fig. 2-4: user data 30 31 32 -> line 02 30 31 32 10 03 20
    assert frame(parse_hex("30 31 32"), "3964R") == parse_hex("02 30 31 32 10 03 20")


def test_p1_worked_example():
    # §4.3: stuffed data 31 10 10 32 15 03, BCC 06
    assert stuff(P1) == parse_hex("31 10 10 32 15 03")
    assert frame(P1, "3964R") == parse_hex("02 31 10 10 32 15 03 10 03 06")
    assert frame(P1, "3964") == parse_hex("02 31 10 10 32 15 03 10 03")


@pytest.mark.parametrize("payload,line", [
    ("31 10 32 03", "02 31 10 10 32 03 10 03 13"),
    ("41 42 10", "02 41 42 10 10 10 03 10"),
    ("10", "02 10 10 10 03 13"),
    ("10 10", "02 10 10 10 10 10 03 13"),
    ("00", "02 00 10 03 13"),
    ("31 00 33", "02 31 00 33 10 03 11"),
])
def test_reference_blocks(payload, line):
    assert frame(parse_hex(payload), "3964R") == parse_hex(line)
    assert frame(parse_hex(payload), "3964") == parse_hex(line)[:-1]
    assert parse(parse_hex(line), "3964R") == parse_hex(payload)


def test_bcc_equal_to_dle_is_not_doubled():
    # §3 item 5: the BCC after DLE ETX is taken as it is, even when it equals DLE
    line = frame(parse_hex("41 42 10"), "3964R")
    assert line.endswith(parse_hex("10 10 10 03 10"))
    assert parse_body(line[1:], "3964R") == parse_hex("41 42 10")
    with pytest.raises(FrameError) as e:  # a doubled BCC leaves a byte over
        parse_body(line[1:] + bytes([DLE]), "3964R")
    assert e.value.kind == "trailing-bytes"


@pytest.mark.parametrize("wrong,why", [(0x16, "doubled DLE counted once"),
                                       (0x04, "STX included"),
                                       (0x15, "DLE ETX not included")])
def test_negative_bcc_vectors_are_rejected(wrong, why):
    # §4.3 table of mistakes: a conforming receiver refuses each with 16#0808
    data = stuff(P1) + parse_hex("10 03") + bytes([wrong])
    with pytest.raises(FrameError) as e:
        parse_body(data, "3964R")
    assert e.value.kind == "bcc-mismatch"
    assert codec.FRAME_ERROR_STATUS[e.value.kind] == 0x0808


def test_closed_form_of_bcc():
    # §4.1: BCC = XOR(all user bytes != 10) ^ 13
    x = 0
    for b in P1:
        if b != DLE:
            x ^= b
    assert bcc(stuff(P1)) == x ^ 0x13 == 0x06


@given(payloads)
def test_stuff_roundtrip(p):
    s = stuff(p)
    assert unstuff(s) == p
    assert len(s) == len(p) + p.count(DLE)


@given(payloads, st.sampled_from(["3964", "3964R"]))
def test_frame_parse_roundtrip(p, proc):
    if len(p) > codec.MAX_BLOCK:
        return
    assert parse(frame(p, proc), proc) == p
    assert len(frame(p, proc)) == 1 + len(p) + p.count(DLE) + 2 + (proc == "3964R")


@given(payloads.filter(lambda p: 1 <= len(p)), st.integers(0, 254))
def test_any_single_bcc_change_is_detected(p, delta):
    f = bytearray(frame(p, "3964R"))
    f[-1] ^= delta + 1
    with pytest.raises(FrameError):
        parse(bytes(f), "3964R")


@pytest.mark.parametrize("data,kind,offset", [
    ("31 10 41 10 03 41", "dle-other", 2),
    ("31 32", "no-end", 2),
    ("31 10", "no-end", 1),
    ("31 10 03", "missing-bcc", 3),
    ("31 10 03 22 00", "trailing-bytes", 4),
])
def test_parse_errors_are_precise(data, kind, offset):
    with pytest.raises(FrameError) as e:
        parse_body(parse_hex(data), "3964R")
    assert (e.value.kind, e.value.offset) == (kind, offset)


def test_too_long_block():
    with pytest.raises(FrameError) as e:
        parse_body(body(bytes(1025), "3964R"), "3964R")
    assert e.value.kind == "too-long"
    assert parse_body(body(bytes(1024), "3964R"), "3964R") == bytes(1024)


def test_missing_stx_and_lone_dle():
    with pytest.raises(FrameError) as e:
        parse(parse_hex("31 10 03 22"), "3964R")
    assert e.value.kind == "missing-stx"
    with pytest.raises(FrameError) as e:
        unstuff(parse_hex("31 10 32"))
    assert e.value.kind == "lone-dle" and e.value.offset == 1


def test_hex_helpers():
    assert hexstr(parse_hex("0210 1003")) == "02 10 10 03"
    with pytest.raises(ValueError, match="odd"):
        parse_hex("021")
    with pytest.raises(ValueError, match="not a hex digit"):
        parse_hex("0G")
    with pytest.raises(ValueError, match="3964"):
        frame(b"1", "3965")
