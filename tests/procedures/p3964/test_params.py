"""Parameters: the manual's defaults, ranges, 10 ms steps and baud-rate minimums (§11)."""

import pytest

from ptpcert.model.errors import ParameterError
from ptpcert.procedures.p3964.model.params import Params3964


def test_defaults_are_the_manuals():
    p = Params3964()
    assert (p.procedure, p.priority, p.cdt_ms, p.adt_ms) == ("3964R", "low", 220, 2000)
    assert (p.setup_attempts, p.transmission_attempts) == (6, 6)
    assert (p.baud_rate, p.data_bits, p.parity, p.stop_bits) == (9600, 8, "even", 1)
    assert Params3964(procedure="3964").adt_ms == 550  # A1
    assert p.bits_per_char == 11
    assert p.char_time == pytest.approx(11 / 9600)


@pytest.mark.parametrize("baud,minimum", [(300, 60), (600, 40), (1200, 30), (2400, 20), (76800, 20)])
def test_baud_dependent_minimum(baud, minimum):
    Params3964(baud_rate=baud, cdt_ms=minimum, adt_ms=minimum)
    with pytest.raises(ParameterError) as e:
        Params3964(baud_rate=baud, cdt_ms=minimum - 10)
    assert e.value.name == "cdt_ms" and str(minimum) in str(e.value)


@pytest.mark.parametrize("field,value,fragment", [
    ("cdt_ms", 25, "steps of 10"),
    ("adt_ms", 655360, "655350"),
    ("setup_attempts", 0, "1..255"),
    ("transmission_attempts", 256, "1..255"),
    ("baud_rate", 115200, "76800"),
    ("parity", "mark", "none, odd, even"),
    ("data_bits", 6, "7 or 8"),
    ("stop_bits", 3, "1 or 2"),
    ("priority", "medium", "low, high"),
    ("procedure", "3964S", "3964R"),
])
def test_invalid_settings_name_parameter_value_and_range(field, value, fragment):
    with pytest.raises(ParameterError) as e:
        Params3964(**{field: value})
    msg = str(e.value)
    assert e.value.name == field and field in msg and repr(value) in msg and fragment in msg


def test_character_time_follows_the_frame():
    assert Params3964(baud_rate=300, data_bits=7, parity="none", stop_bits=1, cdt_ms=60, adt_ms=60).bits_per_char == 9
    assert Params3964(data_bits=8, parity="odd", stop_bits=2).bits_per_char == 12
    assert Params3964(baud_rate=None).char_time == 0.0


def test_with_and_dict_roundtrip():
    p = Params3964(priority="high", cdt_ms=20, adt_ms=20)
    assert Params3964.from_dict(p.to_dict()) == p
    assert p.with_(procedure="3964").adt_ms == 20
    assert Params3964().with_(procedure="3964").adt_ms == 550
    with pytest.raises(ParameterError, match="not a parameter"):
        Params3964.from_dict({"cdt": 20})


def test_one_list_of_status_codes_shared_by_model_and_catalogue():
    from ptpcert.model.codes import Code
    from ptpcert.status import catalogue
    assert {int(c) for c in Code} == set(catalogue())
    assert Code(0x0708).text == "16#0708" and Code.LINE_BREAK.event_class == 0x08
