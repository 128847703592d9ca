"""Every reading of an open point (Rk512Readings) is honoured: the default and the
alternative each give the behaviour their comment describes. A meta test keeps this file in
step with the fields."""

import dataclasses

import pytest
from rk512_rules import continuation, header, response

from ptpcert.model.codes import Code
from ptpcert.procedures.rk512.model import Rk512Core, Rk512Params, Rk512Readings
from ptpcert.procedures.rk512.model.readings import RK512_READINGS
from ptpcert.procedures.rk512.model.requests import parse_line, request_header


class Core(Rk512Core):
    """A core with a recording lower edge: frames handed over land in ``out``."""

    def __init__(self, readings=RK512_READINGS, **kw):
        super().__init__(Rk512Params(**kw), readings, name="c")
        self.out: list[bytes] = []
        self.t = 0.0
        self.power_on(0.0)

    def _lower_send(self, now, frame):
        self.out.append(frame)

    def step(self, dt=0.01):
        self.t += dt
        return self.t

    def cmd(self, frame):
        """The partner's frame arrives; our answer (if any) is acknowledged at once."""
        n = len(self.out)
        self.frame_received(self.step(), frame)
        if self._inflight is not None and len(self.out) > n:
            self.frame_sent(self.step())
        return self.out[n:]

    def events(self):
        return self.pop_events()

    def codes(self, evs):
        return [e.code for e in evs if type(e).__name__ == "Status"]


def C(b3="A", b4="D", b5=10, b6=0, length=2, data=4, b9=0xFF, b10=0x1F, b1=0, b2=0):
    f = header(b3, b4, b5, b6, length, b9, b10, b1) + bytes([0x5A]) * data
    return f[:1] + bytes([b2]) + f[2:]


def R(**changes):
    return dataclasses.replace(RK512_READINGS, **changes)


TESTED: set[str] = set()


def reading(name):
    def mark(fn):
        TESTED.add(name)
        return fn
    return mark


@reading("amb01_counter_letter")
def test_amb01_counter_letter():
    assert request_header(parse_line("fetch Z:0:LEN=2")).dtype == 0x5A
    assert request_header(parse_line("fetch Z:0:LEN=2"), R(amb01_counter_letter=0x43)).dtype == 0x43


@reading("amb01_accept_c_for_counters")
def test_amb01_accept_c():
    assert Core().cmd(C("E", "C", 0, 0, 1, 0)) == [response(0x10)]
    assert Core(R(amb01_accept_c_for_counters=True)).cmd(C("E", "C", 0, 0, 1, 0)) == [response(0, data=b"\x60\x61")]


@reading("amb03_send_dx_letter")
def test_amb03_send_dx_letter():
    assert request_header(parse_line("send DX5:DW0:LEN=2")).command == ord("O")
    assert request_header(parse_line("send DX5:DW0:LEN=2"), R(amb03_send_dx_letter=0x41)).command == ord("A")


@reading("amb03_accept_send_type_x")
def test_amb03_accept_type_x():
    assert Core().cmd(C("A", "X", 5)) == [response(0x10)]
    c = Core(R(amb03_accept_send_type_x=True))
    assert c.cmd(C("A", "X", 5)) == [response(0)]
    assert bytes(c.memory.dx[5][:4]) == bytes([0x5A] * 4)


@reading("amb07_locked_value")
def test_amb07_polarity():
    c = Core()
    c.memory.set_flag(2, 1)
    assert c.cmd(C(b9=2, b10=0x11)) == [response(0x32)]
    c = Core(R(amb07_locked_value=0))
    assert c.cmd(C(b9=2, b10=0x11)) == [response(0x32)]        # a flag of 0 locks now
    c.memory.set_flag(2, 1)
    assert c.cmd(C(b9=2, b10=0x11)) == [response(0)]
    assert c.memory.flag(2, 1) == 0                             # ...and the transfer "sets" it to 0


@reading("amb08_set_flag_after_transfer")
def test_amb08_flag_after_transfer():
    c = Core()
    c.cmd(C(b9=2, b10=0x11))
    assert c.memory.flag(2, 1) == 1
    c = Core(R(amb08_set_flag_after_transfer=False))
    c.cmd(C(b9=2, b10=0x11))
    assert c.memory.flag(2, 1) == 0


@reading("amb10_short_command_reatel")
def test_amb10_short_command():
    assert Core().cmd(C()[:6]) == [response(0x34)]
    c = Core(R(amb10_short_command_reatel=None))
    assert c.cmd(C()[:6]) == [] and c.codes(c.events()) == [Code.FRAME_TOO_SHORT]
    assert c.p_state == "P_IDLE"
    assert c.cmd(b"\x00") == []


@reading("amb10_short_response_ends_request")
def test_amb10_short_response():
    for ends, state in ((True, "A_IDLE"), (False, "A_WAIT_RESPONSE")):
        c = Core(R(amb10_short_response_ends_request=ends))
        c.request(c.step(), "send DB1:DW0:LEN=2")
        c.frame_sent(c.step())
        c.frame_received(c.step(), b"\x00\x00\x00")
        assert c.a_state == state
        assert Code.FRAME_TOO_SHORT in c.codes(c.events())


@reading("amb13_check_byte2")
def test_amb13_byte2():
    assert Core().cmd(C(b2=1)) == [response(0)]
    assert Core(R(amb13_check_byte2=True)).cmd(C(b2=1)) == [response(0x10)]


@reading("amb14_address_16bit")
def test_amb14_address():
    assert Core().cmd(C("E", "E", 1, 4, 1, 0)) == [response(0x0C)]         # address 0104h
    assert Core(R(amb14_address_16bit=False)).cmd(C("E", "E", 1, 4, 1, 0)) == [response(0, data=b"\x44")]


@reading("amb16_exact_chunks")
def test_amb16_chunks():
    split = [C(length=100, data=100), continuation("A", "D", bytes(100))]
    c = Core()
    assert c.cmd(split[0]) == [response(0x34)]
    c = Core(R(amb16_exact_chunks=False))
    assert c.cmd(split[0]) == [response(0)]
    assert c.cmd(split[1]) == [response(0, first=False)]
    assert bytes(c.memory.db[10][:200]) == bytes([0x5A] * 100 + [0] * 100)


@reading("amb17_tres_start")
def test_amb17_tres_start():
    for start, expect in (("acknowledged", 1.0 + 10.0), ("handed_over", 0.0 + 10.0)):
        c = Core(R(amb17_tres_start=start))
        c.request(0.0, "send DB1:DW0:LEN=2")
        c.frame_sent(1.0)
        assert c.next_deadline() == pytest.approx(expect)
    with pytest.raises(ValueError):
        Core(R(amb17_tres_start="never"))


@reading("amb18_passive_timeout_status")
def test_amb18_timeout_status():
    for code in (Code.RESPONSE_TIMEOUT, Code.PARTNER_SEQUENCE_ERROR):
        c = Core(R(amb18_passive_timeout_status=code))
        c.cmd(C(length=100, data=128))
        c.handle_timer(c.next_deadline())
        assert c.codes(c.events()) == [code] and c.p_state == "P_IDLE"


@reading("amb18_first_command_while_waiting")
def test_amb18_first_command_while_waiting():
    c = Core()
    c.cmd(C(length=100, data=128))
    assert c.cmd(C(b5=11)) == [response(0x36)]
    assert bytes(c.memory.db[11][:4]) != bytes([0x5A] * 4)
    c = Core(R(amb18_first_command_while_waiting="execute"))
    c.cmd(C(length=100, data=128))
    assert c.cmd(C(b5=11)) == [response(0)]
    assert bytes(c.memory.db[11][:4]) == bytes([0x5A] * 4)
    assert Code.PARTNER_SEQUENCE_ERROR in c.codes(c.events())


@reading("amb20_cell_fetch_limit_bytes")
def test_amb20_cell_limit():
    assert Core().cmd(C("E", "T", 0, 0, 17, 0))[0][:4] == response(0)
    c = Core(R(amb20_cell_fetch_limit_bytes=32))
    assert c.cmd(C("E", "T", 0, 0, 16, 0))[0][:4] == response(0)
    assert c.cmd(C("E", "Z", 0, 0, 17, 0)) == [response(0x34)]


@reading("amb20_cell_limit_reatel")
def test_amb20_cell_limit_reatel():
    c = Core(R(amb20_cell_fetch_limit_bytes=32, amb20_cell_limit_reatel=0x0C))
    assert c.cmd(C("E", "T", 0, 0, 17, 0)) == [response(0x0C)]
    assert c.codes(c.events()) == [Code.LENGTH_NOT_ALLOWED]


@reading("amb20_serve_dx_fetch")
def test_amb20_dx_fetch():
    assert Core().cmd(C("E", "X", 5, 0, 1, 0)) == [response(0, data=bytes([0x85, 0x86]))]
    assert Core(R(amb20_serve_dx_fetch=False)).cmd(C("E", "X", 5, 0, 1, 0)) == [response(0x10)]


@reading("amb22_cpu0_nibble_without_flag")
def test_amb22_cpu0():
    assert request_header(parse_line("send DB1:DW0:LEN=2:CPU=0")).b10 == 0x0F
    assert request_header(parse_line("send DB1:DW0:LEN=2:CPU=0"), R(amb22_cpu0_nibble_without_flag=0xF)).b10 == 0xFF


@reading("amb22_accepted_cpu_nibbles")
def test_amb22_accepted():
    assert Core().cmd(C(b10=0x4F)) == [response(0)]
    assert Core(R(amb22_accepted_cpu_nibbles=frozenset({1, 0xF}))).cmd(C(b10=0x4F)) == [response(0x0C)]


@reading("amb23_byte9_ff_means_no_flag")
def test_amb23_no_flag():
    assert Core().cmd(C(b9=0xFF, b10=0x13)) == [response(0)]
    assert Core(R(amb23_byte9_ff_means_no_flag=False)).cmd(C(b9=0xFF, b10=0x13)) == [response(0x0C)]


@reading("amb25_extent_beyond_area")
def test_amb25_extent():
    beyond_db, beyond_m = C("E", "D", 10, 250, 7, 0), C("E", "M", 0, 250, 7, 0)
    c = Core()
    assert c.cmd(beyond_db) == [response(0x34)] and c.cmd(beyond_m) == [response(0x34)]
    c = Core(R(amb25_extent_beyond_area="area"))
    assert c.cmd(beyond_db) == [response(0x14)] and c.cmd(beyond_m) == [response(0x0C)]
    assert c.codes(c.events()) == [Code.DB_NUMBER_NOT_ALLOWED, Code.START_ADDRESS_TOO_HIGH]


@reading("amb31_responses_first")
def test_amb31_order():
    for first, want in ((False, "command"), (True, "response")):
        c = Core(R(amb31_responses_first=first))
        c.send_raw(c.step(), b"\x00\x00\x00\x00")           # keeps the link busy
        c.request(c.step(), "send DB1:DW0:LEN=2")              # our command is ready...
        c.frame_received(c.step(), C())                         # ...then the response we owe
        c.frame_sent(c.step())                                  # the link is free again
        nxt = c.out[-1]
        assert ("command" if nxt[2] else "response") == want


@reading("amb32_early_response_ends_request")
def test_amb32_early_response():
    for ends, running in ((False, "send:DB1:DW0:LEN=2"), (True, "fetch:E:0:LEN=1")):
        c = Core(R(amb32_early_response_ends_request=ends))
        c.request(c.step(), "send DB1:DW0:LEN=2")
        c.request(c.step(), "fetch E:0:LEN=1")            # waits its turn
        c.frame_received(c.step(), response(0))          # before our command was acknowledged
        assert c.a_state == "A_SEND_COMMAND" and c.job.label == running
        assert c.codes(c.events()) == [Code.RESPONSE_OUT_OF_SEQUENCE]
        assert len(c.out) == 1                            # the next frame waits for the link


@reading("amb33_error_response_with_data")
def test_amb33():
    for how, code in (("length", Code.RESPONSE_DATA_LENGTH), ("reatel", Code.PARTNER_DB_ACCESS)):
        c = Core(R(amb33_error_response_with_data=how))
        c.request(c.step(), "fetch DB1:DW0:LEN=2")
        c.frame_sent(c.step())
        c.frame_received(c.step(), response(0x14, data=b"\x00\x00"))
        assert c.codes(c.events())[-1] == code


@reading("amb34_pad_byte_areas")
def test_amb34():
    assert request_header(parse_line("fetch M:0:LEN=5")).length == 5
    assert request_header(parse_line("fetch M:0:LEN=5"), R(amb34_pad_byte_areas=True)).length == 6


@reading("n1_bad_id_reply_frame_id")
def test_n1():
    assert Core().cmd(C(b1=0x42)) == [response(0x10)]
    assert Core(R(n1_bad_id_reply_frame_id=0xFF)).cmd(C(b1=0x42)) == [response(0x10, first=False)]


@reading("n2_check_order")
def test_n2_order():
    bad_type_and_cpu = C("A", "M", b10=0x5F)
    assert Core().cmd(bad_type_and_cpu) == [response(0x10)]
    order = ("byte2", "byte3", "cpu", "byte4", "short", "cpu_stop", "block", "address", "length", "flag", "data", "lock")
    assert Core(R(n2_check_order=order)).cmd(bad_type_and_cpu) == [response(0x0C)]
    with pytest.raises(ValueError):
        Core(R(n2_check_order=("byte3", "colour")))


@reading("n3_continuation_count_status")
def test_n3():
    for code in (Code.FRAME_LENGTH_DIFFERS, Code.SEND_LENGTH_DIFFERS):
        c = Core(R(n3_continuation_count_status=code))
        c.cmd(C(length=100, data=128))
        assert c.cmd(continuation("A", "D", bytes(71))) == [response(0x34, first=False)]
        assert c.codes(c.events()) == [code]


@reading("n4_write_per_frame")
def test_n4():
    for per_frame in (True, False):
        c = Core(R(n4_write_per_frame=per_frame))
        c.cmd(C(length=100, data=128))
        assert (bytes(c.memory.db[10][:4]) == bytes([0x5A] * 4)) is per_frame
        c.cmd(continuation("A", "D", bytes(72)))
        assert bytes(c.memory.db[10][:4]) == bytes([0x5A] * 4)
        assert bytes(c.memory.db[10][128:200]) == bytes(72)


@reading("n5_len_over_1024_status")
@reading("n6_db0_status")
def test_n5_n6_are_tested_with_the_local_checks():
    from ptpcert.procedures.rk512.model.requests import local_check
    assert local_check(parse_line("send DB1:DW0:LEN=2000"), R(n5_len_over_1024_status=Code.LEN_ILLEGAL)) == Code.LEN_ILLEGAL
    assert local_check(parse_line("send DB0:DW0:LEN=2"), R(n6_db0_status=Code.INVALID_FB_PARAMETERS)) == Code.INVALID_FB_PARAMETERS


@reading("n7_pipelined_command_aborts")
def test_n7():
    for aborts, state in ((True, "P_IDLE"), (False, "P_WAIT_CONTINUATION")):
        c = Core(R(n7_pipelined_command_aborts=aborts))
        c.frame_received(c.step(), C(length=100, data=128))     # our response is with the link...
        c.frame_received(c.step(), continuation("A", "D", bytes(72)))   # ...and the next comes
        assert c.out[-1] == response(0) and len(c.out) == 1
        c.frame_sent(c.step())                                  # our response acknowledged
        assert c.out[-1] == response(0x36, first=False)
        c.frame_sent(c.step())
        assert c.p_state == state


def test_every_reading_is_tested():
    fields = {f.name for f in dataclasses.fields(Rk512Readings)}
    assert TESTED == fields, sorted(fields ^ TESTED)
