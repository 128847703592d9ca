"""The character frame an IUT sets on a pseudo-terminal, read back and compared with the
profile (ptpcert.transport.line_frame): what SUITE.FRAME.PROFILE-FRAME asks the harness to check with
extra.check_line_settings. The stand-in is the reference IUT set to another frame than its
profile, as issue 10's 8N1 implementation was."""

import os
import sys
import termios
import time
from pathlib import Path

import pytest

from ptpcert.procedures.p3964.description import reference_profile
from ptpcert.transport.line_frame import FIELDS, check_pty, compare, frame_of_termios, pty_keeps, read_frame

ROOT = Path(__file__).resolve().parents[2]
PROFILE = reference_profile().params      # 9600 bit/s, 8 data bits, even parity, 1 stop bit


def _attrs(cs, parenb=False, parodd=False, cstopb=False, speed=termios.B9600):
    cflag = cs | (termios.PARENB if parenb else 0) | (termios.PARODD if parodd else 0) | (termios.CSTOPB if cstopb else 0)
    return [0, 0, cflag, 0, speed, speed, []]


def test_termios_in_the_profiles_terms():
    assert frame_of_termios(_attrs(termios.CS8, parenb=True)) == \
        {"baud_rate": 9600, "data_bits": 8, "parity": "even", "stop_bits": 1}
    assert frame_of_termios(_attrs(termios.CS7, parenb=True, parodd=True, cstopb=True, speed=termios.B1200)) == \
        {"baud_rate": 1200, "data_bits": 7, "parity": "odd", "stop_bits": 2}
    assert frame_of_termios(_attrs(termios.CS8))["parity"] == "none"


def test_compare_names_each_difference():
    eight_n_one = {"baud_rate": 9600, "data_bits": 8, "parity": "none", "stop_bits": 1}
    assert compare(PROFILE, eight_n_one) == ["parity none where the profile says even"]
    assert compare(PROFILE, eight_n_one, fields=("baud_rate", "stop_bits")) == []
    assert compare(PROFILE, {**eight_n_one, "parity": "even"}) == []


def test_this_systems_ptys_keep_at_least_the_baud_rate():
    kept = pty_keeps()
    assert kept <= set(FIELDS) and "baud_rate" in kept


@pytest.mark.parametrize("frame,differs", [
    (dict(parity="E", stopbits=1), ()),
    (dict(parity="N", stopbits=2), ("stop bits", "parity")),
    (dict(parity="N", stopbits=1), ("parity",)),
])
def test_a_stand_in_with_another_frame_is_found_where_the_pty_keeps_it(frame, differs):
    import serial
    master, slave = os.openpty()
    try:
        port = serial.Serial(os.ttyname(slave), 9600, bytesize=8, **frame)
        problems, fields = check_pty(slave, PROFILE)
        port.close()
    finally:
        os.close(master)
        os.close(slave)
    expected = [d for d in differs if d.replace(" ", "_") in fields]
    assert [p.split(" ")[0] + (" bits" if p.startswith("stop") else "") for p in problems] == expected, problems


@pytest.mark.realtime
def test_the_pty_transport_reads_what_the_iut_set(tmp_path):
    from ptpcert.transport.process import PtyTransport
    cmd = f"{sys.executable} -m ptpcert.cli iut --cdt-ms 20 --adt-ms 20 --parmrk --parity none --stop-bits 2 --port {{port}}"
    t = PtyTransport(cmd, parmrk=True, status=True)
    t.open()
    try:
        t.read(t.now() + 2.0)          # the start-up NAK: the IUT has set up its port
        time.sleep(0.2)
        got = t.line_settings()
    finally:
        t.close()
    assert got is not None and got.get("baud_rate", 9600) == 9600
    if "stop_bits" in got:
        assert got["stop_bits"] == 2
        assert "stop bits 2 where the profile says 1" in compare(PROFILE, got, fields=tuple(got))
