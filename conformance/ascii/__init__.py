"""The ASCII driver's conformance suite: cases generated for the IUT's parameters, grouped as
the manual is (§2.2.4; Figs. 2-20 to 2-24; Tables 2-7 to 2-10): the end criterion the profile
sets (delimiting, merging, discarding, error reporting), sending, flow control, the receive
buffer and line conditions. Each module is one group; each case cites its rule."""

from __future__ import annotations

from ptpcert.profile import Profile
from ptpcert.scenario import Vector

from . import buffer, cdt, end_chars, fixed_length, flow, line, send

GROUP_MODULES = (cdt, end_chars, fixed_length, send, flow, buffer, line)


def cases(profile: Profile) -> list[Vector]:
    """Every case of the suite for the IUT this profile describes."""
    out: list[Vector] = []
    for module in GROUP_MODULES:
        out += module.cases(profile.params)
    return out
