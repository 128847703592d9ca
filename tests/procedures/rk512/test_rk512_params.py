"""RK 512 parameters (the [rk512] profile table), the partner CPU's memory with its
"pattern" start contents and coordination flags, and the request-script format."""

import pytest

from ptpcert.model.codes import Code
from ptpcert.model.errors import ParameterError
from ptpcert.procedures.p3964.model.params import Params3964
from ptpcert.procedures.rk512.model import Memory, Rk512Params, default_response_time_ms, figure_response_time_ms
from ptpcert.procedures.rk512.model.codec import Area
from ptpcert.procedures.rk512.model.readings import RK512_READINGS, Rk512Readings
from ptpcert.procedures.rk512.model.requests import (
    Request,
    ScriptError,
    Wait,
    default_data,
    local_check,
    parse_line,
    parse_request,
    parse_script,
)


# -- parameters ----------------------------------------------------------------------------
def test_defaults_follow_the_profile_example():
    p = Rk512Params()
    assert (p.link, p.roles, p.requests, p.memory) == ("3964R", ("passive", "active"), "script", "pattern")
    assert (p.db_range, p.dx_range, p.db_bytes, p.byte_area_bytes, p.cell_area_cells) == ((1, 199), (1, 199), 512, 256, 256)
    assert p.line == Params3964()
    assert p.char_time == Params3964().char_time and p.cdt == 0.22 and p.adt == 2.0


@pytest.mark.parametrize("baud,ms", [(None, 5000), (76800, 5000), (1200, 5000), (600, 7000), (300, 10000)])
def test_default_t_res_is_the_prose_and_the_figures_give_the_shortest(baud, ms):
    # §2.2.3 prose: 10 s at 300..76800 bit/s (the default); Figs. 2-18/2-19: "T_RES = 5 s
    # (7 s, 10 s)" - the shortest a partner may use where the profile is silent (AMB-02)
    assert default_response_time_ms(baud) == 10000
    assert figure_response_time_ms(baud) == ms
    p = Rk512Params(line=Params3964(baud_rate=baud))
    assert p.t_res == 10.0 and p.t_res_min == ms / 1000
    declared = Rk512Params(line=Params3964(baud_rate=baud), response_time_ms=7500)
    assert declared.t_res == declared.t_res_min == 7.5


def test_t_res_given():
    assert Rk512Params(response_time_ms=10000).t_res == 10.0


def test_link_3964():
    p = Rk512Params(link="3964")
    assert p.line.procedure == "3964" and p.line.adt_ms == 550
    assert Rk512Params().with_(link="3964").line.procedure == "3964"


@pytest.mark.parametrize("kw,name", [
    (dict(link="RK512"), "link"),
    (dict(link="3964", line=Params3964()), "line"),
    (dict(line=Params3964(data_bits=7)), "line.data_bits"),
    (dict(response_time_ms=0), "response_time_ms"),
    (dict(roles=[]), "roles"),
    (dict(roles=["master"]), "roles"),
    (dict(roles=["active", "active"]), "roles"),
    (dict(requests="always"), "requests"),
    (dict(memory="random"), "memory"),
    (dict(db_range=[0, 10]), "db_range"),
    (dict(db_range=[10, 5]), "db_range"),
    (dict(db_range=[1, 256]), "db_range"),
    (dict(db_range=[]), "db_range"),
    (dict(dx_range=[1]), "dx_range"),
    (dict(db_bytes=511), "db_bytes"),
    (dict(db_bytes=0), "db_bytes"),
    (dict(byte_area_bytes=0), "byte_area_bytes"),
    (dict(cell_area_cells=True), "cell_area_cells"),
])
def test_invalid_parameters_name_the_field(kw, name):
    with pytest.raises(ParameterError) as exc:
        Rk512Params(**kw)
    assert exc.value.name == name


def test_profile_table_one_to_one():
    table = {"link": "3964R", "response_time_ms": 5000, "roles": ["passive", "active"], "requests": "script",
             "memory": "pattern", "db_range": [1, 199], "dx_range": [], "db_bytes": 512,
             "byte_area_bytes": 256, "cell_area_cells": 256}
    p = Rk512Params.from_dict(table, Params3964(priority="high"))
    assert p.to_dict() == table
    assert p.dx_range == () and p.line.priority == "high"
    with pytest.raises(ParameterError) as exc:
        Rk512Params.from_dict({"links": "3964R"})
    assert exc.value.name == "links"
    # the [rk512] link decides the procedure of the line parameters
    assert Rk512Params.from_dict({"link": "3964"}, Params3964()).line.procedure == "3964"


# -- memory ---------------------------------------------------------------------------------
def test_pattern_memory():
    p = Rk512Params(db_range=(3, 5), dx_range=(7, 7), db_bytes=300, byte_area_bytes=40, cell_area_cells=10)
    m = Memory(p)
    assert sorted(m.db) == [3, 4, 5] and sorted(m.dx) == [7]
    for n in (3, 5):
        assert m.db[n] == bytes((n + i) & 0xFF for i in range(300))
    assert m.dx[7] == bytes((7 + i + 0x80) & 0xFF for i in range(300))
    assert m.areas[Area.E] == bytes((0x40 + i) & 0xFF for i in range(40))
    assert m.areas[Area.A] == bytes((0xC0 + i) & 0xFF for i in range(40))
    assert m.areas[Area.T] == bytes((0x20 + i) & 0xFF for i in range(20))
    assert m.areas[Area.Z] == bytes((0x60 + i) & 0xFF for i in range(20))
    assert m.areas[Area.M] == bytes(40)
    assert m.buffer(Area.DB, 6) is None and m.buffer(Area.DX, 1) is None
    assert m.running


def test_no_dx():
    assert Memory(Rk512Params(dx_range=[])).dx == {}


def test_memory_read_write_and_flags():
    m = Memory(Rk512Params(), fill="zero")
    assert m.db[10] == bytes(512)
    m.write(Area.DB, 10, 4, b"\x01\x02")
    assert m.read(Area.DB, 10, 3, 4) == b"\x00\x01\x02\x00"
    with pytest.raises(IndexError):
        m.read(Area.DB, 10, 510, 4)
    with pytest.raises(IndexError):
        m.write(Area.DB, 200, 0, b"\x01")
    assert m.flag(12, 3) == 0
    m.set_flag(12, 3)
    assert m.flag(12, 3) == 1 and m.areas[Area.M][12] == 0x08   # flag B.b is bit b of flag byte B
    m.set_flag(12, 3, 0)
    assert m.areas[Area.M][12] == 0
    assert m.flag_exists(255, 7) and not m.flag_exists(256, 0) and not m.flag_exists(1, 8)
    snap = m.snapshot()
    m.write(Area.M, 0, 0, b"\xff")
    assert snap["M"][0] == 0


# -- request scripts ----------------------------------------------------------------------------
def test_the_issue_example_script():
    items = parse_script("""
        send DB10:DW0:LEN=200            # SEND 200 bytes to the partner's DB 10 from DW 0
        fetch E:0:LEN=10                 # FETCH 10 bytes of inputs from byte 0
        send DX7:OFF=6:LEN=5:CF=12.3:CPU=2:DATA=0102031004
        wait 500                         # ms before the next request
    """)
    r1, r2, r3, w = items
    assert (r1.op, r1.area, r1.number, r1.address, r1.length) == ("send", Area.DB, 10, 0, 200)
    assert r1.label == "send:DB10:DW0:LEN=200" and r1.line == 2
    assert (r2.op, r2.area, r2.address, r2.length) == ("fetch", Area.E, 0, 10)
    assert r2.label == "fetch:E:0:LEN=10"
    assert (r3.area, r3.number, r3.address, r3.cf, r3.cpu, r3.data) == (Area.DX, 7, 6, (12, 3), 2, bytes.fromhex("0102031004"))
    assert r3.label == "send:DX7:OFF=6:LEN=5:CF=12.3:CPU=2:DATA=0102031004"
    assert w == Wait(500, 5)


def test_default_send_data():
    # byte i = (SEED + 7 i) & FFh, SEED 10h: the first byte is already a DLE
    r = parse_request("send", "DB1:DW0:LEN=600")
    assert r.payload == bytes((0x10 + 7 * i) & 0xFF for i in range(600))
    assert r.payload[0] == 0x10
    assert parse_request("send", "DB1:DW0:LEN=3:SEED=0").payload == bytes([0, 7, 14])
    assert parse_request("send", "DB1:DW0:LEN=2:SEED=0xFF").payload == bytes([0xFF, 0x06])
    assert default_data(0) == b""


def test_spec_forms():
    assert parse_request("fetch", "db10:dw3:len=4").address == 6
    assert parse_request("fetch", "DB10:OFF=7:LEN=4").address == 7      # rounded down in the header
    r = parse_request("fetch", "Z:5:LEN=20:CPU=none")
    assert (r.area, r.address, r.cpu) == (Area.Z, 5, None)
    assert parse_request("send", "DB1:DW0:LEN=2:CF=255.0").cf == (255, 0)
    assert parse_line("   # only a comment") is None and parse_line("") is None
    assert parse_line("WAIT 0") == Wait(0)


@pytest.mark.parametrize("line,message", [
    ("sned DB1:DW0:LEN=1", "'sned' is not send, fetch or wait"),
    ("send", "send needs AREA:ADDRESS:LEN=n"),
    ("send DQ1:DW0:LEN=1", "area 'DQ1': DBn, DXn, M, E, A, T or Z"),
    ("send DB1", "DB1 needs an address after the area"),
    ("send DB1:7:LEN=1", "address '7' of DB1: DWn or OFF=n"),
    ("send DB1:DWx:LEN=1", "data word 'x' is not a decimal number"),
    ("fetch M:-1:LEN=1", "M address '-1' is not a decimal number"),
    ("send DB1:DW0", "LEN=n is missing"),
    ("send DB1:DW0:LEN=", "LEN '' is not a decimal number"),
    ("send DB1:DW0:LEN=2:LEN=3", "LEN is given twice"),
    ("send DB1:DW0:LEN=2:COLOR=3", "unknown option 'COLOR': LEN, CF, CPU, DATA or SEED"),
    ("send DB1:DW0:LEN=2:CF", "'CF' is not KEY=value (LEN, CF, CPU, DATA, SEED)"),
    ("send DB1:DW0:LEN=2:CF=12", "CF=12: byte.bit, e.g. CF=12.3"),
    ("send DB1:DW0:LEN=2:CPU=one", "CPU 'one' is not a decimal number"),
    ("send DB1:DW0:LEN=2:DATA=123", "DATA=123: an even number of hex digits"),
    ("send DB1:DW0:LEN=2:DATA=12", "DATA has 1 bytes, LEN=2"),
    ("fetch DB1:DW0:LEN=2:DATA=1234", "DATA is for send only"),
    ("send DB1:DW0:LEN=2:DATA=1234:SEED=1", "SEED and DATA exclude each other"),
    ("send DB1:DW0:LEN=2:SEED=300", "SEED=300: a number 0..255"),
    ("fetch DB1:DW0:LEN=2:SEED=1", "SEED is for send only"),
    ("send DB1:DW0:LEN=2 fetch", "one SPEC per line; 'DB1:DW0:LEN=2 fetch' has spaces in it"),
    ("wait", "wait needs a number of milliseconds"),
    ("wait 1.5", "wait time (ms) '1.5' is not a decimal number"),
])
def test_parser_errors_name_line_and_fault(line, message):
    with pytest.raises(ScriptError) as exc:
        parse_script("# header\n\n" + line + "\n")
    assert exc.value.line == 3
    assert exc.value.message == message
    assert str(exc.value) == f"line 3: {message}"


# -- the active side's local checks (nothing reaches the wire) ----------------------------------
@pytest.mark.parametrize("spec,code", [
    ("send DB10:DW0:LEN=1024", None),
    ("send DB10:DW0:LEN=0", Code.LEN_ILLEGAL),
    ("send DB10:DW0:LEN=1025", Code.LENGTH_INVALID_FOR_CP),
    ("send M:0:LEN=2", Code.INVALID_FB_PARAMETERS),
    ("send DB0:DW0:LEN=2", Code.ADDRESS_OUT_OF_RANGE),
    ("send DB256:DW0:LEN=2", Code.ADDRESS_OUT_OF_RANGE),
    ("send DB1:DW256:LEN=2", Code.ADDRESS_OUT_OF_RANGE),
    ("send DB1:OFF=511:LEN=2", None),                    # rounded down to DW 255
    ("fetch M:256:LEN=1", Code.ADDRESS_OUT_OF_RANGE),
    ("fetch M:255:LEN=1", None),
    ("send DB1:DW0:LEN=2:CF=1.8", Code.INVALID_FLAG_BIT),
    ("send DB1:DW0:LEN=2:CF=256.1", Code.INVALID_FB_PARAMETERS),
    ("send DB1:DW0:LEN=2:CPU=5", Code.CPU_NUMBER_TOO_HIGH),
    ("send DB1:DW0:LEN=2:CPU=0", None),
    ("fetch T:0:LEN=2:CPU=none", None),
])
def test_local_checks(spec, code):
    assert local_check(parse_line(spec)) == code


def test_local_check_readings():
    r = Rk512Readings(n5_len_over_1024_status=Code.LEN_ILLEGAL, n6_db0_status=Code.INVALID_FB_PARAMETERS)
    assert local_check(parse_line("send DB1:DW0:LEN=2000"), r) == Code.LEN_ILLEGAL
    assert local_check(parse_line("send DB0:DW0:LEN=2"), r) == Code.INVALID_FB_PARAMETERS
    assert RK512_READINGS.n5_len_over_1024_status == Code.LENGTH_INVALID_FOR_CP


def test_canonical_label_of_a_request_built_in_code():
    r = Request("send", Area.DB, 10, 6, 4, cf=(3, 1), cpu=None, data=b"\x01\x02\x03\x04")
    assert r.label == "send:DB10:DW3:LEN=4:CF=3.1:CPU=none:DATA=01020304"
    assert parse_request("send", r.label.split(":", 1)[1]) == Request("send", Area.DB, 10, 6, 4, (3, 1), None,
                                                                      b"\x01\x02\x03\x04", spec=r.label.split(":", 1)[1])
