"""RK 512 over the 3964R link model, in virtual time: the worked examples byte by byte,
SEND and FETCH of every size class and data type, DLE doubling, quasi-full-duplex and the
response monitoring time on both sides (§2.2.3, Figs. 2-13 to 2-19; §6.3.2)."""

import pytest
from rk512_helpers import codes, delivered, of, pair, results, run_until, run_until_delivered, served, wire, with_tester
from rk512_rules import DLE, STX, body, continuation, exchange, header, hexb, response

from ptpcert.model.codes import Code
from ptpcert.procedures.rk512.model import Rk512Readings, describe
from ptpcert.procedures.rk512.model.codec import Area
from ptpcert.procedures.rk512.model.events import FrameReceived, FrameSent


# -- Examples 1 to 4 (3964R, A high priority, no flag, CPU 1) ------------------------------------
def test_example_1_send_10_bytes():
    link, a, b = pair()
    data = bytes([0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88, 0x99, 0xAA])
    a.request(link.now, "send DB10:DW0:LEN=10:DATA=" + data.hex())
    assert link.run_until_quiet(60)
    cmd = header("A", "D", 10, 0, 5) + data
    assert wire(link) == exchange(cmd, response(0))
    # the manual's numbers: the BCCs 42h and 13h
    assert body(cmd)[-1] == 0x42 and body(response(0))[-1] == 0x13
    assert bytes(b.memory.db[10][:10]) == data
    [r] = results(link, a)
    assert r.ok and r.code is None and r.data is None
    assert codes(link, a) == codes(link, b) == []


def test_example_1_without_cpu_and_flag():
    link, a, b = pair()
    data = bytes(range(0x11, 0xBB, 0x11))
    a.request(link.now, "send DB10:DW0:LEN=10:CPU=none:DATA=" + data.hex())
    assert link.run_until_quiet(60)
    cmd = header("A", "D", 10, 0, 5, b10=0xFF) + data
    assert body(cmd)[-1] == 0xA2
    assert wire(link) == exchange(cmd, response(0))


def test_example_2_send_200_bytes_with_one_continuation():
    link, a, b = pair()
    data = bytes(range(200))
    a.request(link.now, "send DB10:DW0:LEN=200:DATA=" + data.hex())
    assert link.run_until_quiet(60)
    first = header("A", "D", 10, 0, 100) + data[:128]
    cont = continuation("A", "D", data[128:])
    assert wire(link) == exchange(first, response(0)) + exchange(cont, response(0, first=False))
    assert body(first)[-1] == 0x88 and body(cont)[-1] == 0xE9 and body(response(0, first=False))[-1] == 0xEC
    assert bytes(b.memory.db[10][:200]) == data
    assert [r.ok for r in results(link, a)] == [True]


def test_example_3_fetch_6_bytes():
    link, a, b = pair()
    b.memory.db[10][:6] = bytes.fromhex("123456789ABC")
    a.request(link.now, "fetch DB10:DW0:LEN=6")
    assert link.run_until_quiet(60)
    cmd = header("E", "D", 10, 0, 3)
    resp = response(0, data=bytes.fromhex("123456789ABC"))
    assert wire(link) == exchange(cmd, resp)
    assert body(cmd)[-1] == 0xFB and body(resp)[-1] == 0x3D
    [r] = results(link, a)
    assert r.ok and r.data == bytes.fromhex("123456789ABC")
    assert r.lines() == ["FETCHED fetch:DB10:DW0:LEN=6 123456789ABC", "RESULT fetch:DB10:DW0:LEN=6 OK"]


def test_example_4_fetch_300_bytes_with_two_continuations():
    link, a, b = pair()
    src = bytes((0x80 + i) & 0xFF for i in range(300))
    b.memory.db[10][:300] = src
    a.request(link.now, "fetch DB10:DW0:LEN=300")
    assert link.run_until_quiet(60)
    cmd = header("E", "D", 10, 0, 150)
    c = continuation("E", "D")
    want = (exchange(cmd, response(0, data=src[:128]))
            + exchange(c, response(0, first=False, data=src[128:256]))
            + exchange(c, response(0, first=False, data=src[256:])))
    assert wire(link) == want
    assert [body(x)[-1] for x in (cmd, response(0, data=src[:128]), c,
                                  response(0, first=False, data=src[128:256]),
                                  response(0, first=False, data=src[256:]))] == [0x6E, 0x13, 0xED, 0xFC, 0xEC]
    assert results(link, a)[0].data == src


def test_examples_over_3964_without_bcc():
    # AMB-27: RK 512 over plain 3964: the same frames, no BCC
    link, a, b = pair(proc="3964")
    a.request(link.now, "send DB10:DW0:LEN=4:DATA=11223344")
    assert link.run_until_quiet(60)
    assert wire(link) == exchange(header("A", "D", 10, 0, 2) + bytes.fromhex("11223344"), response(0), bcc=False)


def test_example_1_at_every_baud_rate_takes_the_line_time():
    # the station paces its bytes: the exchange cannot end before its characters are through
    for baud in (300, 9600, 76800):
        link, a, b = pair(baud=baud)
        t0 = link.now
        a.request(t0, "send DB10:DW0:LEN=10")
        assert link.run_until_quiet(60)
        r = results(link, a)[0]
        n_chars = len(wire(link))
        assert r.ok and r.time - t0 >= (n_chars - 1) * a.params.char_time - 1e-9


# -- every size class and data type --------------------------------------------------------------
BIG = dict(db_bytes=2048, byte_area_bytes=2048, cell_area_cells=1024)
PATTERN_BASE = {Area.E: 0x40, Area.A: 0xC0, Area.T: 0x20, Area.Z: 0x60, Area.M: None}


def _pattern(area, number, start, n):
    if area is Area.DB:
        return bytes((number + start + i) & 0xFF for i in range(n))
    if area is Area.DX:
        return bytes((number + start + i + 0x80) & 0xFF for i in range(n))
    base = PATTERN_BASE[area]
    return bytes(n) if base is None else bytes((base + start + i) & 0xFF for i in range(n))


def _check_frames(link, a, n, fetch):
    """The frames on the wire: ceil(n/128) commands, 128 data bytes in every frame but the
    last, continuation headers FF 00 b3 b4, one response per command (R4.2-R4.6)."""
    sent = [e.frame for e in of(link, a, FrameSent)]
    got = [e.frame for e in of(link, a, FrameReceived)]
    k = -(-n // 128)
    assert len(sent) == len(got) == k
    for i, (cmd, resp) in enumerate(zip(sent, got)):
        chunk = min(128, n - 128 * i)
        if i == 0:
            assert len(cmd) == 10 + (0 if fetch else chunk)
            assert resp[:4] == response(0)
        else:
            assert cmd[:4] == bytes([0xFF, 0x00]) + sent[0][2:4]
            assert len(cmd) == 4 + (0 if fetch else chunk)
            assert resp[:4] == response(0, first=False)
        assert len(resp) == 4 + (chunk if fetch else 0)


@pytest.mark.parametrize("n", [1, 10, 128, 129, 200, 1024])
@pytest.mark.parametrize("area", ["DB", "DX"])
def test_send_sizes(n, area):
    link, a, b = pair(baud=None, **BIG)
    a.request(link.now, f"send {area}7:DW3:LEN={n}")
    assert link.run_until_quiet(120)
    [r] = results(link, a)
    assert r.ok, r
    wire_n = n + (n & 1)                                # padded to whole words
    _check_frames(link, a, wire_n, fetch=False)
    data = bytes((0x10 + 7 * i) & 0xFF for i in range(n)) + bytes(n & 1)
    mem = b.memory.db[7] if area == "DB" else b.memory.dx[7]
    assert bytes(mem[6:6 + wire_n]) == data
    assert bytes(mem[:6]) == _pattern(Area[area], 7, 0, 6)          # nothing before it touched
    assert bytes(mem[6 + wire_n:6 + wire_n + 2]) == _pattern(Area[area], 7, 6 + wire_n, 2)
    ws = [s for s in served(link, b)]
    assert b"".join(s.data for s in ws) == data and [s.final for s in ws] == [False] * (len(ws) - 1) + [True]


@pytest.mark.parametrize("n", [6, 128, 300, 1024])
@pytest.mark.parametrize("area", ["DB", "DX", "E", "A", "M", "T", "Z"])
@pytest.mark.parametrize("big", [True, False], ids=["big", "profile"])
def test_fetch_sizes(n, area, big):
    kw = BIG if big else {}
    link, a, b = pair(baud=None, **kw)
    ar = Area[area]
    spec = f"{area}9:DW2:LEN={n}" if ar.block else f"{area}:2:LEN={n}"
    a.request(link.now, "fetch " + spec)
    assert link.run_until_quiet(120)
    [r] = results(link, a)
    start = 4 if ar.block or ar.words else 2                     # DW 2 = byte 4; cell 2 = byte 4
    size = b.params.db_bytes if ar.block else (2 * b.params.cell_area_cells if ar.words else b.params.byte_area_bytes)
    if start + n <= size:
        assert r.ok and r.data == _pattern(ar, 9, start, n)
        _check_frames(link, a, n, fetch=True)
    else:
        # beyond the end of the area: the length is refused (AMB-25 reading), REATEL 34h
        assert not r.ok and r.code == Code.PARTNER_FRAME_LENGTH
        assert codes(link, b) == [Code.LENGTH_NOT_ALLOWED]
        assert of(link, b, FrameSent)[0].frame == response(0x34)


def test_fetch_odd_length_stores_len_bytes():
    # §6.3.2 "Notes on DB/DX": 3 words are asked for, 5 bytes stored
    link, a, b = pair()
    a.request(link.now, "fetch DB10:OFF=6:LEN=5")
    assert link.run_until_quiet(60)
    assert of(link, a, FrameSent)[0].frame == header("E", "D", 10, 3, 3)
    assert len(of(link, a, FrameReceived)[0].frame) == 4 + 6
    assert results(link, a)[0].data == _pattern(Area.DB, 10, 6, 5)


def test_fetch_odd_length_of_a_byte_area():
    link, a, b = pair()
    a.request(link.now, "fetch E:3:LEN=5")
    assert link.run_until_quiet(60)
    assert of(link, a, FrameSent)[0].frame == header("E", "E", 0, 3, 5)
    assert results(link, a)[0].data == _pattern(Area.E, 0, 3, 5)


def test_fetch_counters_sends_z():
    link, a, b = pair()
    a.request(link.now, "fetch Z:5:LEN=20")
    assert link.run_until_quiet(60)
    assert of(link, a, FrameSent)[0].frame == header("E", "Z", 0, 5, 10)
    assert results(link, a)[0].data == _pattern(Area.Z, 0, 10, 20)


# -- DLE doubling (3964R §2.2.2 note) in the header, the data, the REATEL, and a BCC of 10h --------
def test_dle_doubling_in_header_and_data():
    link, a, b = pair()
    a.request(link.now, "send DB16:DW16:LEN=4:DATA=10203010")
    assert link.run_until_quiet(60)
    cmd = hexb("00 00 41 44 10 10 00 02 FF 1F 10 20 30 10")
    assert wire(link) == exchange(cmd, response(0))
    assert bytes(b.memory.db[16][32:36]) == hexb("10 20 30 10")


def test_dle_doubling_in_the_length_field():
    link, a, b = pair(**BIG)
    a.request(link.now, "fetch DB16:DW0:LEN=32")               # 16 words: length 00 10
    assert link.run_until_quiet(60)
    cmd = header("E", "D", 16, 0, 16)
    assert cmd[6:8] == b"\x00\x10"
    assert wire(link)[2:2 + len(body(cmd))] == [("a", x) for x in body(cmd)]
    assert results(link, a)[0].ok


def test_dle_doubling_in_the_reatel():
    # a command with byte 1 = 01h is refused with REATEL 10h, a DLE, doubled on the wire
    link, a, t = with_tester()
    link.request(t, header("A", "D", 10, 0, 1, b1=0x01) + b"\x00\x00")
    assert link.run_until_quiet(60)
    reply = [x for s, x in wire(link) if s == "a"]
    assert reply[-8:] == list(body(response(0x10)))
    assert body(response(0x10)) == hexb("00 00 00 10 10 10 03 13")
    assert delivered(link, t) == [response(0x10)]
    assert codes(link, a) == [Code.CMD_BYTE1_INVALID]


def test_a_bcc_of_10h_is_not_doubled():
    # data chosen so that the BCC is 10h: XOR of the payload = 10h ^ 10h ^ 03h = 03h
    head = header("A", "D", 10, 0, 1)
    x = 0
    for v in head + b"\x00":
        x ^= v
    data = bytes([0x00, x ^ 0x03])   # the payload XORs to 03h (10h ^ 13h)
    cmd = head + data
    blk = body(cmd)
    assert blk[-1] == DLE and blk[-3:-1] == b"\x10\x03"
    link, a, b = pair()
    a.request(link.now, "send DB10:DW0:LEN=2:DATA=" + data.hex())
    assert link.run_until_quiet(60)
    assert wire(link) == exchange(cmd, response(0))
    assert results(link, a)[0].ok


# -- quasi-full-duplex (§2.2.3, Fig. 2-17) --------------------------------------------------------
@pytest.mark.parametrize("baud", [None, 9600])
@pytest.mark.parametrize("gap", [0.0, 0.05, 0.2])
def test_crossing_requests(baud, gap):
    # both stations request at (nearly) the same time: both complete, every command is answered
    # exactly once, and neither sends a further command of its request before the answer
    link, a, b = pair(baud=baud, **BIG)
    t0 = link.now
    a.request(t0, "send DB20:DW0:LEN=400")
    link.run_until(t0 + gap)
    b.request(link.now, "fetch DB30:DW0:LEN=300")
    assert link.run_until_quiet(t0 + 120)
    assert [r.ok for r in results(link, a)] == [True]
    [rb] = results(link, b)
    assert rb.ok and rb.data == _pattern(Area.DB, 30, 0, 300)
    assert bytes(b.memory.db[20][:400]) == bytes((0x10 + 7 * i) & 0xFF for i in range(400))
    for me, peer in ((a, b), (b, a)):
        # the frames each side received, in order: commands of the peer and responses to ours
        seq = []
        for n, e in link.events:
            if n == me.name and isinstance(e, FrameReceived):
                seq.append(("rx", e.frame))
            elif n == me.name and isinstance(e, FrameSent):
                seq.append(("tx", e.frame))
        outstanding = 0
        for d, f in seq:
            is_cmd = f[2] != 0
            if d == "tx" and is_cmd:
                assert outstanding == 0, "depth 1: a second command before the answer"
                outstanding = 1
            elif d == "rx" and not is_cmd:
                assert outstanding == 1
                outstanding = 0
        assert outstanding == 0
        cmds = [f for d, f in seq if d == "rx" and f[2] != 0]
        answers = [f for d, f in seq if d == "tx" and f[2] == 0]
        assert len(cmds) == len(answers)
    assert codes(link, a) == codes(link, b) == []


def test_fig_2_17_interleaving():
    # Fig. 2-17: the partner's own SEND, already in its output buffer, goes out before the
    # continuation response it owes (R8.4 b); each side holds one request of its own and
    # serves one of the partner's (R8.3)
    link, a, b = pair(baud=9600, **BIG)
    t0 = link.now
    a.request(t0, "send DB1:DW0:LEN=300")
    # b's request when its first response has been acknowledged: a's continuation is coming
    while not of(link, b, FrameSent):
        link.run_until(link.next_time())
    b.request(link.now, "send DB2:DW0:LEN=10")
    assert link.run_until_quiet(t0 + 60)
    sent_b = [describe(e.frame) for e in of(link, b, FrameSent)]
    assert sent_b == ["response REATEL 00", "SEND DB2 DW0 10 bytes",
                      "continuation response REATEL 00", "continuation response REATEL 00"]
    sent_a = [describe(e.frame) for e in of(link, a, FrameSent)]
    assert sorted(sent_a) == sorted(["SEND DB1 DW0 300 bytes (128 in this frame)", "continuation SEND 128 bytes",
                                     "continuation SEND 44 bytes", "response REATEL 00"])
    assert sent_a[:2] == ["SEND DB1 DW0 300 bytes (128 in this frame)", "continuation SEND 128 bytes"]
    assert [r.ok for r in results(link, a) + results(link, b)] == [True, True]
    assert codes(link, a, "send") == [] and codes(link, b, "send") == []


# -- T_RES (§2.2.3, Figs. 2-18/2-19) --------------------------------------------------------------
def test_t_res_at_the_requester():
    # the partner accepts the block but never answers: 16#0A05 after T_RES from its DLE (AMB-17)
    link, a, t = with_tester(response_time_ms=5000)
    a.request(link.now, "send DB10:DW0:LEN=4")
    run_until(link, lambda: of(link, a, FrameSent))
    acked = of(link, a, FrameSent)[0].time
    assert link.run_until_quiet(acked + 60)
    [r] = results(link, a)
    assert not r.ok and r.code == Code.RESPONSE_TIMEOUT
    assert r.time == pytest.approx(acked + 5.0)
    assert r.lines() == ["RESULT send:DB10:DW0:LEN=4 STATUS 16#0A05"]
    # a late response is then a response without request (16#0A01), not a success
    link.request(t, response(0))
    assert link.run_until_quiet(link.now + 60)
    assert codes(link, a)[-1] == Code.RESPONSE_OUT_OF_SEQUENCE and len(results(link, a)) == 1


def test_t_res_starts_at_hand_over_under_the_other_reading():
    link, a, t = with_tester(readings=Rk512Readings(amb17_tres_start="handed_over"), response_time_ms=5000)
    t0 = link.now
    a.request(t0, "send DB10:DW0:LEN=4")
    assert link.run_until_quiet(t0 + 60)
    assert results(link, a)[0].time == pytest.approx(t0 + 5.0)


def test_response_just_inside_t_res_is_taken():
    link, a, t = with_tester(response_time_ms=5000)
    a.request(link.now, "send DB10:DW0:LEN=4")
    run_until(link, lambda: of(link, a, FrameSent))
    acked = of(link, a, FrameSent)[0].time
    link.run_until(acked + 4.9)
    link.request(t, response(0))
    assert link.run_until_quiet(link.now + 60)
    assert results(link, a)[0].ok


def test_t_res_at_the_responder():
    # after a non-final response the responder waits T_RES for the continuation (R7.7), then
    # aborts (AMB-18: 16#0A05) and a late continuation is a sequence error (36h)
    link, a, t = with_tester(response_time_ms=5000)
    link.request(t, header("A", "D", 10, 0, 100) + bytes(128))
    run_until(link, lambda: of(link, a, FrameSent))
    assert delivered(link, t) == [response(0)]
    sent = of(link, a, FrameSent)[0].time
    assert a.p_state == "P_WAIT_CONTINUATION"
    link.run_until(sent + 5.0 + 0.01)
    assert a.p_state == "P_IDLE"
    assert codes(link, a) == [Code.RESPONSE_TIMEOUT]
    link.request(t, continuation("A", "D", bytes(72)))
    run_until_delivered(link, t, 2)
    assert delivered(link, t)[1] == response(0x36, first=False)
    assert codes(link, a)[-1] == Code.PARTNER_SEQUENCE_ERROR
    assert [s.final for s in served(link, a)] == [False]      # only the first frame was stored


def test_continuation_just_inside_t_res_is_taken():
    link, a, t = with_tester(response_time_ms=5000)
    link.request(t, header("A", "D", 10, 0, 100) + bytes(128))
    run_until(link, lambda: of(link, a, FrameSent))
    sent = of(link, a, FrameSent)[0].time
    link.run_until(sent + 4.8)
    link.request(t, continuation("A", "D", bytes(range(72))))
    run_until_delivered(link, t, 2)
    assert delivered(link, t)[1] == response(0, first=False)
    assert bytes(a.memory.db[10][128:200]) == bytes(range(72))
    assert codes(link, a) == []


# -- Examples 5 and 6 as the model stations put them on the wire -----------------------------------
def _blocks(link, name):
    """The blocks ``name`` sent, each as the bytes between its STX (after the partner's DLE)
    and the end of its BCC."""
    out, cur, seq = [], None, wire(link)
    for i, (src, x) in enumerate(seq):
        if src != name:
            continue
        if cur is None:
            if x == STX:
                cur = bytearray()
            continue
        cur.append(x)
        if len(cur) >= 3 and cur[-3] == DLE and cur[-2] == 0x03 and (len(cur) < 4 or cur[-4] != DLE or _even_dles(cur[:-2])):
            out.append(bytes(cur))
            cur = None
    return out


def _even_dles(b):
    n = 0
    for x in reversed(b):
        if x != DLE:
            break
        n += 1
    return n % 2 == 1


EXAMPLE_5_WIRE = {  # REATEL -> (a command that earns it, the first response block of our notes)
    0x0C: (header("E", "M", 1, 44, 1), "00 00 00 0C 10 03 1F"),
    0x10: (header("A", "D", 10, 0, 1, b1=0x01) + b"\x00\x00", "00 00 00 10 10 10 03 13"),
    0x14: (header("E", "D", 250, 0, 2), "00 00 00 14 10 03 07"),
    0x16: (header("C", "D", 10, 0, 1) + b"\x00\x00", "00 00 00 16 10 03 05"),
    0x34: (header("E", "D", 10, 0, 2) + b"\x00", "00 00 00 34 10 03 27"),
    0x36: (continuation("E", "D"), "FF 00 00 36 10 03 DA"),
}


@pytest.mark.parametrize("reatel", sorted(EXAMPLE_5_WIRE))
def test_example_5_error_responses_on_the_wire(reatel):
    # the blocks the model's responder sends for its errors are the worked blocks; 0Ah and 12h
    # have no responder event (AMB-10) and come only from S5 partners
    cmd, block = EXAMPLE_5_WIRE[reatel]
    link, a, t = with_tester()
    link.request(t, cmd)
    assert link.run_until_quiet(60)
    assert _blocks(link, "a") == [hexb(block)]


def test_example_5_locked_and_not_ready_on_the_wire():
    link, a, t = with_tester()
    a.memory.set_flag(3, 5)
    link.request(t, header("A", "D", 10, 0, 1, b9=3, b10=0x15) + b"\x00\x00")
    assert link.run_until_quiet(60)
    a.memory.running = False
    link.request(t, header("A", "D", 10, 0, 1) + b"\x00\x00")
    assert link.run_until_quiet(link.now + 60)
    assert _blocks(link, "a") == [hexb("00 00 00 32 10 03 21"), hexb("00 00 00 2A 10 03 39")]


EXAMPLE_6_WIRE = [
    ("send DB16:OFF=32:LEN=4:DATA=10203010", "00 00 41 44 10 10 10 10 00 02 FF 1F 10 10 20 30 10 10 10 03 E4"),
    ("send DX5:DW0:LEN=2:DATA=ABCD", "00 00 4F 44 05 00 00 01 FF 1F AB CD 10 03 9A"),
    ("send DB10:DW0:LEN=2:CF=3.5:CPU=2:DATA=DEAD", "00 00 41 44 0A 00 00 01 03 25 DE AD 10 03 48"),
    ("send DB10:OFF=7:LEN=11:DATA=0102030405060708090A0B",
     "00 00 41 44 0A 03 00 06 FF 1F 01 02 03 04 05 06 07 08 09 0A 0B 00 10 03 F9"),
    ("fetch DB10:OFF=6:LEN=5", "00 00 45 44 0A 03 00 03 FF 1F 10 03 F8"),
    ("fetch DX7:DW4:LEN=4", "00 00 45 58 07 04 00 02 FF 1F 10 03 EF"),
    ("fetch M:20:LEN=6", "00 00 45 4D 00 14 00 06 FF 1F 10 03 E9"),
    ("fetch Z:5:LEN=20", "00 00 45 5A 00 05 00 0A FF 1F 10 03 E3"),
]


@pytest.mark.parametrize("spec,block", EXAMPLE_6_WIRE)
def test_example_6_on_the_wire(spec, block):
    link, a, b = pair()
    a.request(link.now, spec)
    assert link.run_until_quiet(60)
    assert _blocks(link, "a")[0] == hexb(block)
    assert results(link, a)[0].ok


# -- why the station sent what it sent (explain) -------------------------------------------------
def test_explain_log():
    from rk512_helpers import params, settle

    from ptpcert.model.link import Link
    from ptpcert.procedures.rk512.model import Rk512Station
    a = Rk512Station(params("high"), name="a", explain=True)
    b = Rk512Station(params("low"), name="b", explain=True)
    link = settle(Link(a, b))
    a.request(link.now, "send DB10:DW0:LEN=200")
    a.request(link.now, "fetch DB0:DW0:LEN=2")      # refused locally: no frame, no entry
    assert link.run_until_quiet(60)
    b.request(link.now, "fetch DB250:DW0:LEN=2")
    assert link.run_until_quiet(link.now + 60)
    why_a = [(describe(f), side, str(inp), code) for _, f, side, inp, ref, code, detail in a.frame_log]
    assert why_a == [
        ("SEND DB10 DW0 200 bytes (128 in this frame)", "A", "CPU_REQUEST", None),
        ("continuation SEND 72 bytes", "A", "RESPONSE", None),
        ("response REATEL 14h -> 16#0903", "P", "COMMAND", None),
    ]
    refs = [ref for *_, ref, code, detail in a.frame_log]
    assert refs[0].startswith("Fig. 2-18") and refs[2].startswith("Fig. 2-19")
    assert a.frame_log[2][6] == "REATEL 14h for 16#0606"
    # FrameSent carries the row's reference; the link explains its own bytes
    assert [e.reason for e in of(link, a, FrameSent)][0] == refs[0]
    assert a.link.tx_log
