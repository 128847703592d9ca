"""Parameters of the ASCII driver (§2.3.3: Tables 2-7, 2-8, 2-9, 2-10): defaults, every rule
refused with a one-line error naming the key and the rule, profile keys, and a station in
STOP after a bad parameter set (16#020F)."""

import pytest

from ptpcert.model.codes import Code
from ptpcert.model.errors import ParameterError
from ptpcert.model.events import SendFailed, Status
from ptpcert.procedures.ascii.model import AsciiParams, AsciiStation
from ptpcert.procedures.ascii.model.params import MIN_CDT_MS, default_cdt_ms


def test_defaults_are_the_manuals():
    p = AsciiParams()
    assert (p.baud_rate, p.data_bits, p.parity, p.stop_bits) == (9600, 8, "even", 1)   # Table 2-8
    assert (p.end_criterion, p.cdt_ms, p.end_chars, p.fixed_length) == ("cdt", 4, (0x03,), 240)  # Table 2-7
    assert (p.flow_control, p.xon, p.xoff, p.xon_wait_ms) == ("none", 0x11, 0x13, 20000)  # Table 2-9
    assert (p.rts_off_delay_ms, p.data_output_wait_ms) == (10, 10)
    assert (p.buffer_frames, p.prevent_overwrite) == (250, True)   # Table 2-10


@pytest.mark.parametrize("baud", sorted(MIN_CDT_MS))
def test_default_cdt_is_raised_to_the_baud_minimum(baud):
    # Q3: 4 ms is below the minimum at 300..4800 bit/s
    p = AsciiParams(baud_rate=baud)
    assert p.cdt_ms == max(4, MIN_CDT_MS[baud]) == default_cdt_ms(baud)


def test_default_cdt_follows_a_new_baud_rate():
    assert AsciiParams().with_(baud_rate=1200).cdt_ms == 32
    assert AsciiParams(cdt_ms=50).with_(baud_rate=1200).cdt_ms == 50


@pytest.mark.parametrize("bits, parity, stop, n", [(7, "none", 1, 9), (8, "even", 1, 11), (8, "odd", 2, 12), (7, "even", 2, 11)])
def test_character_time(bits, parity, stop, n):
    p = AsciiParams(baud_rate=19200, data_bits=bits, parity=parity, stop_bits=stop)
    assert p.bits_per_char == n and p.char_time == pytest.approx(n / 19200)


def refused(key, **kw):
    with pytest.raises(ParameterError) as e:
        AsciiParams(**kw)
    assert e.value.name == key
    msg = str(e.value)
    assert "\n" not in msg and key in msg
    return msg


# every rule, with the key it names and a word of the rule it breaks
RULES = [
    ("baud_rate", dict(baud_rate=14400), "Table 2-8"),
    ("baud_rate", dict(baud_rate=38400, interface="tty"), "19200"),
    ("data_bits", dict(data_bits=6), "7 or 8"),
    ("parity", dict(parity="mark"), "none, odd, even"),
    ("stop_bits", dict(stop_bits=3), "1 or 2"),
    ("cdt_ms", dict(cdt_ms=3), "minimum at 9600 bit/s is 4 ms"),
    ("cdt_ms", dict(baud_rate=300, cdt_ms=100), "130 ms"),
    ("cdt_ms", dict(cdt_ms=1), "Table 2-7"),
    ("cdt_ms", dict(cdt_ms=700000), "655350"),
    ("end_criterion", dict(end_criterion="timeout"), "Table 2-7"),
    ("end_chars", dict(end_criterion="end_chars", end_chars=()), "one or two"),
    ("end_chars", dict(end_criterion="end_chars", end_chars=(1, 2, 3)), "one or two"),
    ("end_chars", dict(end_criterion="end_chars", end_chars=(0x100,)), "00..FF"),
    ("end_chars", dict(end_criterion="end_chars", end_chars=(0x83,), data_bits=7), "00..7F"),
    ("end_chars", dict(end_criterion="end_chars", end_chars=(0x0D, 0x8A), data_bits=7), "7 data bits"),
    ("end_chars", dict(end_criterion="end_chars", end_chars=(0x11,), flow_control="xon_xoff"), "XON or XOFF"),
    ("fixed_length", dict(end_criterion="fixed_length", fixed_length=0), "1..1024"),
    ("fixed_length", dict(end_criterion="fixed_length", fixed_length=1025), "1..1024"),
    ("send_variant", dict(end_criterion="end_chars", send_variant="auto"), "up_to_end"),
    ("send_pause", dict(send_pause=False), "only the fixed-length pause"),
    ("flow_control", dict(flow_control="dtr_dsr"), "Table 2-9"),
    ("flow_control", dict(flow_control="xon_xoff", interface="rs485"), "RS 485"),
    ("flow_control", dict(flow_control="rts_cts", interface="tty"), "RS 232C"),
    ("flow_control", dict(flow_control="auto_v24", interface="rs422"), "RS 232C"),
    ("xon", dict(flow_control="xon_xoff", xon=0x91, data_bits=7), "00..7F"),
    ("xoff", dict(flow_control="xon_xoff", xoff=0x93, data_bits=7), "00..7F"),
    ("xoff", dict(flow_control="xon_xoff", xon=0x11, xoff=0x11), "different"),
    ("xon_wait_ms", dict(flow_control="xon_xoff", xon_wait_ms=10), "20..655350"),
    ("xon_wait_ms", dict(flow_control="rts_cts", xon_wait_ms=2005), "steps of 10"),
    ("rts_off_delay_ms", dict(flow_control="auto_v24", rts_off_delay_ms=5), "steps of 10"),
    ("data_output_wait_ms", dict(flow_control="auto_v24", data_output_wait_ms=-10), "0..655350"),
    ("buffer_frames", dict(buffer_frames=0), "1..250"),
    ("buffer_frames", dict(buffer_frames=251), "1..250"),
    ("prevent_overwrite", dict(prevent_overwrite=False), "buffer_frames = 1"),
    ("prevent_overwrite", dict(prevent_overwrite=False, buffer_frames=2), "Table 2-10"),
    ("interface", dict(interface="usb"), "rs232c"),
]


@pytest.mark.parametrize("key, kw, rule", RULES, ids=[f"{k}-{i}" for i, (k, _, _) in enumerate(RULES)])
def test_each_rule_is_refused_naming_key_and_rule(key, kw, rule):
    assert rule in refused(key, **kw)


@pytest.mark.parametrize("kw", [
    dict(cdt_ms=4), dict(cdt_ms=655350), dict(baud_rate=300, cdt_ms=130), dict(cdt_ms=7),
    dict(end_criterion="end_chars", end_chars=(0x0D, 0x0A)),
    dict(end_criterion="end_chars", end_chars=[0x7F], data_bits=7),
    dict(end_criterion="fixed_length", fixed_length=1024, send_pause=False),
    dict(prevent_overwrite=False, buffer_frames=1),
    dict(flow_control="xon_xoff", xon=0x7F, xoff=0x00, data_bits=7),
    dict(flow_control="rts_cts", xon_wait_ms=655350),
    dict(flow_control="auto_v24", rts_off_delay_ms=0, data_output_wait_ms=0),
    dict(interface="tty", baud_rate=19200, flow_control="xon_xoff"),
])
def test_allowed_settings(kw):
    AsciiParams(**kw)


def test_settings_the_configuration_does_not_use_are_not_checked():
    # Table 2-7 footnotes 1, 3; Table 2-9 footnotes 1, 3, 4: greyed out, not refused
    p = AsciiParams(end_criterion="cdt", end_chars=(0x83,), data_bits=7, fixed_length=5000,
                    xon=0x11, xoff=0x11, xon_wait_ms=1, rts_off_delay_ms=3)
    assert p.end_criterion == "cdt"


def test_profile_keys_map_to_fields():
    iut = {"procedure": "ASCII", "character_delay_ms": 20, "baud_rate": 9600, "data_bits": 7,
           "parity": "odd", "stop_bits": 2, "send_trigger": "echo", "line_conditions": "parmrk",
           "status_from_stderr": True}
    ascii = {"end_criterion": "end_chars", "end_chars": [0x03], "fixed_length": 240,
             "send_variant": "len_append_end", "send_pause": True, "flow_control": "xon_xoff",
             "xon": 0x11, "xoff": 0x13, "xon_wait_ms": 2000, "buffer_frames": 250,
             "prevent_overwrite": True}
    p = AsciiParams.from_profile(iut, ascii)
    assert (p.cdt_ms, p.data_bits, p.parity, p.stop_bits) == (20, 7, "odd", 2)
    assert p.end_chars == (0x03,) and p.send_variant == "len_append_end" and p.xon_wait_ms == 2000


def test_profile_error_names_the_profile_key():
    with pytest.raises(ParameterError) as e:
        AsciiParams.from_profile({"character_delay_ms": 1}, {})
    assert e.value.name == "character_delay_ms"
    with pytest.raises(ParameterError) as e:
        AsciiParams.from_profile({}, {"buffer_frame": 3})
    assert e.value.name == "ascii.buffer_frame"


def test_round_trip_through_a_dict():
    p = AsciiParams(end_criterion="end_chars", end_chars=(0x0D, 0x0A), flow_control="rts_cts")
    assert AsciiParams.from_dict(p.to_dict()) == p
    with pytest.raises(ParameterError):
        AsciiParams.from_dict({"cdt": 4})


# =========================================================== a bad parameter set: 16#020F
def test_bad_settings_put_the_station_in_stop():
    bad = {"flow_control": "xon_xoff", "xon": 0x11, "xoff": 0x11, "baud_rate": 19200}
    st = AsciiStation(bad, name="iut")
    assert st.parameter_error is not None and st.parameter_error.name == "xoff"
    assert st.params.baud_rate == 19200           # the line is still timed right
    st.power_on(0.0)
    assert st.pop_output() == [] and st.pop_signals() == []
    (e,) = st.pop_events()
    assert isinstance(e, Status) and e.code == Code.PARAMS_REJECTED
    st.receive(0.01, b"\x41\x03")
    st.handle_timer(1.0)
    assert st.pop_events() == []
    assert not st.request_send(1.0, b"AB")
    events = st.pop_events()
    assert [e.code for e in events if isinstance(e, Status)] == [Code.NOT_ALLOWED_IN_MODE]
    assert [e.code for e in events if isinstance(e, SendFailed)] == [Code.NOT_ALLOWED_IN_MODE]
    st.handle_timer(2.0)
    assert st.pop_output() == []


def test_good_settings_as_a_mapping():
    st = AsciiStation({"end_criterion": "end_chars", "end_chars": [0x0D, 0x0A]})
    assert st.parameter_error is None and st.params.end_chars == (0x0D, 0x0A)
