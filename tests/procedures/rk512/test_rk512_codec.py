"""The RK 512 codec, both ways: headers of every area and type, odd lengths, the CPU/flag
matrix, continuation and response frames, classification, segmentation, REATEL <-> STATUS
and the frame labels (§2.2.3, Tables 2-1/2-2, Figs. 2-13 to 2-16; §6.3.2; Table 8-3)."""

import pytest
from rk512_rules import TABLE_8_3, UNKNOWN_REATEL, body, continuation, header, hexb, response

from ptpcert.model.codes import Code
from ptpcert.procedures.p3964.model import codec as link_codec
from ptpcert.procedures.rk512.model import codec as C
from ptpcert.procedures.rk512.model.codec import Area, Header, Kind

# -- headers -------------------------------------------------------------------------------
# (op, area, number, address, LEN) -> the header the rules give (Table 2-1; §6.3.2, Tables
# 6-5/6-8): DB/DX by block and data word (offset / 2), words = ceil(LEN / 2); byte areas by
# a 16-bit byte address (AMB-14), LEN bytes; T/Z by cell number, words = ceil(LEN / 2).
CASES = [
    ("send", "DB", 10, 0, 100, header("A", "D", 10, 0, 50)),
    ("send", "DB", 10, 2, 100, header("A", "D", 10, 1, 50)),       # Fig. 2-13: DW 1, 50 words
    ("send", "DX", 5, 0, 2, header("O", "D", 5, 0, 1)),            # Table 2-1: 'O', byte 4 'D'
    ("fetch", "DB", 10, 200, 100, header("E", "D", 10, 100, 50)),  # Fig. 2-15: DW 100
    ("fetch", "DX", 7, 8, 4, header("E", "X", 7, 4, 2)),
    ("fetch", "E", 0, 3, 10, header("E", "E", 0, 3, 10)),
    ("fetch", "A", 0, 255, 1, header("E", "A", 0, 255, 1)),
    ("fetch", "M", 0, 20, 6, header("E", "M", 0, 20, 6)),
    ("fetch", "T", 0, 7, 8, header("E", "T", 0, 7, 4)),
    ("fetch", "Z", 0, 5, 20, header("E", "Z", 0, 5, 10)),          # R3.10: 10 counters = 20 bytes
]


@pytest.mark.parametrize("op,area,number,address,length,want", CASES)
def test_header_of_every_area_both_ways(op, area, number, address, length, want):
    h = C.command_header(op, Area[area], number, address, length)
    assert h.encode() == want
    back = C.decode_header(want)
    assert back == h and back.encode() == want
    assert back.nbytes == (2 * ((length + 1) // 2) if Area[area].words else length)


def test_counter_letter_is_z_not_c():
    # Table 2-1 "'C' (5AH)": 5Ah is 'Z' (AMB-01)
    h = C.command_header("fetch", Area.Z, 0, 0, 2)
    assert h.dtype == 0x5A == ord("Z")


@pytest.mark.parametrize("length,words,pad", [(1, 1, 1), (11, 6, 1), (12, 6, 0), (1023, 512, 1), (1024, 512, 0)])
def test_odd_send_length_to_a_db_is_padded(length, words, pad):
    # §6.3.2 "Important notes": an odd LEN is rounded up to whole words, one 00h appended
    from ptpcert.procedures.rk512.model.requests import Request, request_header, send_payload
    req = Request("send", Area.DB, 10, 0, length, data=bytes([0xEE]) * length)
    h = request_header(req)
    assert h.length == words
    assert send_payload(req, h) == bytes([0xEE]) * length + bytes(pad)


@pytest.mark.parametrize("area,length,wire", [("DB", 5, 3), ("DX", 5, 3), ("T", 5, 3), ("Z", 3, 2),
                                               ("M", 5, 5), ("E", 7, 7), ("A", 1, 1)])
def test_odd_fetch_length(area, length, wire):
    # §6.3.2 "Notes on DB/DX": one more byte is asked for in word areas; AMB-34: byte areas as is
    h = C.command_header("fetch", Area[area], 1, 0, length)
    assert h.length == wire


def test_odd_fetch_of_byte_area_padded_under_the_other_reading():
    h = C.command_header("fetch", Area.M, 0, 0, 5, pad_byte_areas=True)
    assert h.length == 6


def test_odd_offset_rounds_down():
    # §6.3.2: R_OFFSET 7 -> 6, DW 3
    assert C.command_header("send", Area.DB, 10, 7, 2).address == 3


def test_byte_area_address_is_16_bit():
    h = C.command_header("fetch", Area.M, 0, 300, 1)
    assert (h.number, h.address) == (0x01, 0x2C)


# Table 2-1 / Fig. 2-13: bytes 9 and 10 for every combination of CPU number and flag
MATRIX = [
    (1, None, 0xFF, 0x1F), (2, None, 0xFF, 0x2F), (3, None, 0xFF, 0x3F), (4, None, 0xFF, 0x4F),
    (1, (3, 5), 3, 0x15), (2, (3, 5), 3, 0x25), (4, (254, 7), 254, 0x47), (3, (0, 0), 0, 0x30),
    (None, (12, 3), 12, 0x03), (None, (0, 7), 0, 0x07),
    (None, None, 0xFF, 0xFF),
    (0, None, 0xFF, 0x0F),          # AMB-22 reading: CPU 0 sent as nibble 0
    (0, (1, 1), 1, 0x01),
]


@pytest.mark.parametrize("cpu,cf,b9,b10", MATRIX)
def test_cpu_flag_matrix(cpu, cf, b9, b10):
    assert C.flag_cpu_bytes(cf, cpu) == (b9, b10)
    h = C.command_header("send", Area.DB, 1, 0, 2, cf=cf, cpu=cpu)
    raw = h.encode()
    assert (raw[8], raw[9]) == (b9, b10)
    back = C.decode_header(raw)
    assert back.flag == cf
    if cf is not None:
        assert back.cf_bit == cf[1]


def test_cpu0_without_flag_other_reading():
    assert C.flag_cpu_bytes(None, 0, cpu0_nibble=0xF) == (0xFF, 0xFF)


@pytest.mark.parametrize("SF,R_TYP,b3,b4", [
    ("S", "D", "A", "D"), ("S", "X", "O", "D"), ("F", "D", "E", "D"), ("F", "X", "E", "X"),
    ("F", "M", "E", "M"), ("F", "F", "E", "M"), ("F", "I", "E", "E"), ("F", "E", "E", "E"),
    ("F", "Q", "E", "A"), ("F", "O", "E", "A"), ("F", "A", "E", "A"), ("F", "C", "E", "Z"),
    ("F", "Z", "E", "Z"), ("F", "T", "E", "T"),
])
def test_p_snd_rk_mapping(SF, R_TYP, b3, b4):
    # §6.3.2, Tables 6-4 to 6-8: FB mnemonics -> wire letters
    h = C.psnd_header(SF, R_TYP, 9, 4, 8)
    raw = h.encode()
    assert raw[2:4] == (b3 + b4).encode()
    assert raw[8:10] == b"\xff\x1f"  # defaults: no flag (255), CPU 1


def test_p_snd_rk_flag_parameters():
    raw = C.psnd_header("S", "D", 10, 0, 2, R_CF_BYT=3, R_CF_BIT=5, R_CPU_NO=2).encode()
    assert raw[8:10] == bytes([3, 0x25])
    with pytest.raises(ValueError):
        C.psnd_header("X", "D", 10, 0, 2)
    with pytest.raises(ValueError):
        C.psnd_header("F", "K", 10, 0, 2)


def test_encode_checks_ranges():
    with pytest.raises(ValueError):
        Header(0x41, 0x44, 256, 0, 1).encode()
    with pytest.raises(ValueError):
        Header(0x41, 0x44, 1, 0, 70000).encode()
    with pytest.raises(C.FrameError):
        C.decode_header(bytes(9))


# -- segmentation (§2.2.3, Figs. 2-14/2-16) ---------------------------------------------------
@pytest.mark.parametrize("n,sizes", [(1, [1]), (127, [127]), (128, [128]), (129, [128, 1]),
                                     (200, [128, 72]), (300, [128, 128, 44]), (1024, [128] * 8)])
def test_chunks(n, sizes):
    assert C.chunk_sizes(n) == sizes


@pytest.mark.parametrize("n", [2, 128, 130, 200, 1024])
def test_send_frames(n):
    data = bytes((7 * i) & 0xFF for i in range(n))
    h = C.command_header("send", Area.DB, 10, 0, n)
    frames = C.send_frames(h, data)
    assert len(frames) == -(-n // 128)
    assert frames[0][:10] == header("A", "D", 10, 0, n // 2)
    assert frames[0][10:] == data[:128]
    for k, f in enumerate(frames[1:], 1):
        assert f[:4] == continuation("A", "D")     # byte 3/4 as in the first frame
        assert f[4:] == data[128 * k:128 * (k + 1)]
        assert len(f) - 4 == (128 if k < len(frames) - 1 else n - 128 * k)


def test_fetch_frames():
    h = C.command_header("fetch", Area.T, 0, 0, 300)
    frames = C.fetch_frames(h)
    assert frames == [header("E", "T", 0, 0, 150)] + [continuation("E", "T")] * 2


# -- responses and classification -------------------------------------------------------------
def test_responses():
    assert C.response(True, 0) == response(0) == b"\x00\x00\x00\x00"
    assert C.response(False, 0x34) == response(0x34, first=False)
    assert C.response(True, 0, b"\x12\x34") == response(0, data=b"\x12\x34")
    r = C.decode_response(b"\xff\x00\x00\x00\xab")
    assert (r.first, r.reatel, r.data) == (False, 0, b"\xab")
    with pytest.raises(C.FrameError):
        C.decode_response(b"\x00\x00\x00")


@pytest.mark.parametrize("frame,kind", [
    (header("A", "D", 1, 0, 1) + b"\x00\x00", Kind.COMMAND),
    (continuation("E", "D"), Kind.CONTINUATION),
    (response(0), Kind.RESPONSE),
    (response(0x36, first=False), Kind.CONTINUATION_RESPONSE),
    (header("A", "D", 1, 0, 1, b1=0x01), Kind.BAD_COMMAND),
    (b"\x7f\x00\x00\x00", Kind.BAD_RESPONSE),
    (b"\x00\x00", Kind.SHORT),
    (b"", Kind.SHORT),
    (b"\x00\x00\x43", Kind.COMMAND),   # byte 3 is all that tells a command from a response
])
def test_classify(frame, kind):
    assert C.classify(frame) is kind


# -- REATEL <-> STATUS (Table 8-3) -------------------------------------------------------------
def test_every_reatel_of_table_8_3():
    for reatel in range(256):
        want = None if reatel == 0 else TABLE_8_3.get(reatel, UNKNOWN_REATEL)
        assert C.status_for_reatel(reatel) == want, hex(reatel)


def test_class_06_events_and_their_reatel():
    # Table 8-3, the passive-side events listed per REATEL
    want = {0x0601: 0x10, 0x0602: 0x16, 0x0603: 0x16, 0x0604: 0x10, 0x0605: 0x10, 0x0606: 0x14,
            0x0607: 0x0C, 0x0608: 0x34, 0x0609: 0x0C, 0x060A: 0x0C, 0x060B: 0x34, 0x060C: 0x34,
            0x060D: 0x2A, 0x060E: 0x36, 0x060F: 0x32, 0x0611: 0x34}
    got = {int(c): r for c, r in C.STATUS_REATEL.items() if c >> 8 == 6}
    assert got == want
    assert Code.FRAME_TOO_SHORT not in C.STATUS_REATEL and Code.RESPONSE_NOT_SENT not in C.STATUS_REATEL
    assert C.reatels_for_status(0x090C) == [0x34]


# -- the manual's worked blocks (Examples 5 and 6 of our notes, derived from the rules) --------
EXAMPLE_5 = {  # REATEL: (first response block, continuation response block) after STX/DLE
    0x00: ("00 00 00 00 10 03 13", "FF 00 00 00 10 03 EC"),
    0x0A: ("00 00 00 0A 10 03 19", "FF 00 00 0A 10 03 E6"),
    0x0C: ("00 00 00 0C 10 03 1F", "FF 00 00 0C 10 03 E0"),
    0x10: ("00 00 00 10 10 10 03 13", "FF 00 00 10 10 10 03 EC"),
    0x12: ("00 00 00 12 10 03 01", "FF 00 00 12 10 03 FE"),
    0x14: ("00 00 00 14 10 03 07", "FF 00 00 14 10 03 F8"),
    0x16: ("00 00 00 16 10 03 05", "FF 00 00 16 10 03 FA"),
    0x2A: ("00 00 00 2A 10 03 39", "FF 00 00 2A 10 03 C6"),
    0x32: ("00 00 00 32 10 03 21", "FF 00 00 32 10 03 DE"),
    0x34: ("00 00 00 34 10 03 27", "FF 00 00 34 10 03 D8"),
    0x36: ("00 00 00 36 10 03 25", "FF 00 00 36 10 03 DA"),
}


@pytest.mark.parametrize("reatel", sorted(EXAMPLE_5))
def test_example_5_response_blocks(reatel):
    first, cont = EXAMPLE_5[reatel]
    for is_first, text in ((True, first), (False, cont)):
        frame = C.response(is_first, reatel)
        assert body(response(reatel, is_first)) == hexb(text)
        assert link_codec.body(frame, "3964R") == hexb(text)


EXAMPLE_6 = [  # (the request's terms, data, the block after STX/DLE)
    (("send", Area.DB, 16, 32, 4), "10 20 30 10",
     "00 00 41 44 10 10 10 10 00 02 FF 1F 10 10 20 30 10 10 | 10 03 E4"),
    (("send", Area.DX, 5, 0, 2), "AB CD", "00 00 4F 44 05 00 00 01 FF 1F AB CD | 10 03 9A"),
    (("send", Area.DB, 10, 0, 2, (3, 5), 2), "DE AD", "00 00 41 44 0A 00 00 01 03 25 DE AD | 10 03 48"),
    (("send", Area.DB, 10, 7, 11), "01 02 03 04 05 06 07 08 09 0A 0B 00",
     "00 00 41 44 0A 03 00 06 FF 1F 01 02 03 04 05 06 07 08 09 0A 0B 00 | 10 03 F9"),
    (("fetch", Area.DB, 10, 6, 5), "", "00 00 45 44 0A 03 00 03 FF 1F | 10 03 F8"),
    (("fetch", Area.DX, 7, 8, 4), "", "00 00 45 58 07 04 00 02 FF 1F | 10 03 EF"),
    (("fetch", Area.M, 0, 20, 6), "", "00 00 45 4D 00 14 00 06 FF 1F | 10 03 E9"),
    (("fetch", Area.Z, 0, 5, 20), "", "00 00 45 5A 00 05 00 0A FF 1F | 10 03 E3"),
]


@pytest.mark.parametrize("terms,data,block", EXAMPLE_6)
def test_example_6_headers(terms, data, block):
    op, area, number, address, length, *rest = terms
    cf = rest[0] if rest else None
    cpu = rest[1] if len(rest) > 1 else 1
    h = C.command_header(op, area, number, address, length, cf=cf, cpu=cpu)
    frame = h.encode() + hexb(data)
    assert link_codec.body(frame, "3964R") == hexb(block)
    assert body(frame) == hexb(block)


def test_fig_2_13_header():
    h = C.command_header("send", Area.DB, 10, 2, 100)
    assert h.encode() == hexb("00 00 41 44 0A 01 00 32 FF 1F")


# -- labels ------------------------------------------------------------------------------------
@pytest.mark.parametrize("frame,label", [
    (header("A", "D", 10, 0, 50) + bytes(100), "SEND DB10 DW0 100 bytes"),
    (header("A", "D", 10, 0, 100) + bytes(128), "SEND DB10 DW0 200 bytes (128 in this frame)"),
    (header("O", "D", 7, 3, 3) + bytes(6), "SEND DX7 DW3 6 bytes"),
    (header("E", "E", 0, 0, 10), "FETCH E 0 10 bytes"),
    (header("E", "Z", 0, 5, 10), "FETCH Z 5 20 bytes"),
    (header("A", "D", 10, 0, 1, b9=12, b10=0x23) + bytes(2), "SEND DB10 DW0 2 bytes CF 12.3 CPU 2"),
    (header("E", "D", 10, 0, 1, b10=0xFF), "FETCH DB10 DW0 2 bytes no CPU"),
    (continuation("A", "D", bytes(72)), "continuation SEND 72 bytes"),
    (continuation("E", "D"), "continuation FETCH"),
    (response(0), "response REATEL 00"),
    (response(0x34), "response REATEL 34h -> 16#090C"),
    (response(0x42, first=False), "continuation response REATEL 42h -> 16#090E"),
    (response(0, data=bytes(6)), "response REATEL 00 + 6 data bytes"),
    (b"\x00\x00", "short frame (2 bytes: 00 00)"),
    (header("A", "D", 1, 0, 1)[:6], "SEND, too short (6 bytes)"),
])
def test_describe(frame, label):
    assert C.describe(frame) == label


def test_describe_never_raises():
    import random
    rnd = random.Random(5)
    for _ in range(2000):
        frame = bytes(rnd.randrange(256) for _ in range(rnd.randrange(0, 20)))
        assert isinstance(C.describe(frame), str)
