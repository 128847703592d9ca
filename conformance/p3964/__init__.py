"""The 3964/3964R conformance suite: cases generated for the IUT's parameters, grouped as
the manual is (§2.1, §2.2, Figs. 2-5 to 2-12). Each module is one group of the manual; each case
is a vector (ptpcert.scenario.Vector) that cites the ids of the rules it checks (the rules
catalogue, ``ptpcert rules``). The golden vectors run with them."""

from __future__ import annotations

from ptpcert.profile import Profile
from ptpcert.scenario import Vector

from . import conflict, counters, frame, idle, line, receive, release, send, startup, timing

GROUP_MODULES = (startup, frame, idle, receive, send, release, counters, conflict, line, timing)


def cases(profile: Profile) -> list[Vector]:
    """Every case of the suite for the IUT this profile describes."""
    out: list[Vector] = []
    for module in GROUP_MODULES:
        out += module.cases(profile.params)
    return out
