"""The character frame an IUT really set up, where the line lets the harness see it, against
the one its profile declares (§2.1 Asynchronous transmission; Table 2-5).

An IUT behind ``pty:`` opens the pseudo-terminal and sets its baud rate and frame with
termios, as it would on a serial port; the harness holds the other end and can read those
settings (``termios.tcgetattr`` on the terminal side). :func:`read_frame` turns them into the
profile's terms and :func:`compare` names every difference. Some kernels keep only part of
the frame on a pseudo-terminal (the baud rate and stop bits, while data bits and parity are
forced to 8 and none); :func:`pty_keeps` finds out which fields this system keeps, and only
those are compared. On a real serial port the frame shows on the line instead: the suite's
case ``SUITE.FRAME.PROFILE-FRAME`` sends characters that only the profile's frame receives
intact.

A case asks for the comparison with ``extra.check_line_settings = true``; the transport
offers the settings through ``line_settings()`` (the pty transport does).
Standard library only.
"""

from __future__ import annotations

from functools import lru_cache
from typing import Any

FIELDS = ("baud_rate", "data_bits", "parity", "stop_bits")


def _speeds() -> dict[int, int]:
    import termios
    out = {}
    for rate in (300, 600, 1200, 2400, 4800, 9600, 19200, 38400, 57600, 76800, 115200):
        const = getattr(termios, f"B{rate}", None)
        if const is not None:
            out[const] = rate
    return out


def frame_of_termios(attrs: list) -> dict[str, Any]:
    """A termios attribute list (``tcgetattr``) as the profile's keys."""
    import termios
    cflag, ispeed = attrs[2], attrs[4]
    size = cflag & termios.CSIZE
    bits = {termios.CS5: 5, termios.CS6: 6, termios.CS7: 7, termios.CS8: 8}.get(size, 8)
    if not cflag & termios.PARENB:
        parity = "none"
    else:
        parity = "odd" if cflag & termios.PARODD else "even"
    return {"baud_rate": _speeds().get(ispeed), "data_bits": bits, "parity": parity,
            "stop_bits": 2 if cflag & termios.CSTOPB else 1}


def read_frame(fd: int) -> dict[str, Any]:
    """The frame of the terminal behind ``fd``."""
    import termios
    return frame_of_termios(termios.tcgetattr(fd))


@lru_cache(maxsize=None)
def pty_keeps() -> frozenset[str]:
    """The fields of the frame this system's pseudo-terminals keep when a program sets them
    (found out on a fresh pty: some kernels force 8 data bits and no parity)."""
    import os
    import termios
    master, slave = os.openpty()
    try:
        attrs = termios.tcgetattr(slave)
        want = {"baud_rate": 1200, "data_bits": 7, "parity": "odd", "stop_bits": 2}
        cflag = attrs[2] & ~(termios.CSIZE | termios.PARENB | termios.PARODD | termios.CSTOPB)
        speed = termios.B1200
        kept = set()
        for name, bits in (("stop_bits", termios.CSTOPB), ("data_bits", termios.CS7),
                           ("parity", termios.PARENB | termios.PARODD)):
            trial = list(attrs)
            trial[2] = cflag | termios.CS8 | bits if name != "data_bits" else cflag | bits
            try:
                termios.tcsetattr(slave, termios.TCSANOW, trial)
            except termios.error:
                continue
            if frame_of_termios(termios.tcgetattr(slave))[name] == want[name]:
                kept.add(name)
        trial = list(attrs)
        trial[4] = trial[5] = speed
        try:
            termios.tcsetattr(slave, termios.TCSANOW, trial)
            if frame_of_termios(termios.tcgetattr(slave))["baud_rate"] == 1200:
                kept.add("baud_rate")
        except termios.error:
            pass
        return frozenset(kept)
    finally:
        os.close(master)
        os.close(slave)


def compare(declared: Any, actual: dict[str, Any], fields=FIELDS) -> list[str]:
    """Every field of ``fields`` where the IUT's frame ``actual`` differs from the profile's
    (``declared``: an object with the profile's line settings, e.g. Params3964), in words."""
    problems = []
    for name in fields:
        want, have = getattr(declared, name, None), actual.get(name)
        if want is None or have is None:
            continue   # not set in the profile (no pacing) or not representable by termios
        if want != have:
            problems.append(f"{name.replace('_', ' ')} {have} where the profile says {want}")
    return problems


def check_pty(fd: int, declared: Any) -> tuple[list[str], tuple[str, ...]]:
    """The differences between the frame set on the pty behind ``fd`` and the profile's, and
    the fields this system let us compare."""
    fields = tuple(f for f in FIELDS if f in pty_keeps())
    return compare(declared, read_frame(fd), fields), fields
