"""The RK 512 conformance suite: cases generated for the IUT's profile, grouped as the
manual is (§2.2.3, Figs. 2-13 to 2-19; §6.3.2; §8.3/8.4): the link below RK 512, the IUT
passive (it serves the tester's SEND and FETCH), the IUT active (it issues the requests of
its request script), and both at once (quasi-full-duplex). Every case cites its rule and
depends only on the RK 512 interface: the profile, the request script, the wire and the
STATUS/RESULT/FETCHED lines."""

from __future__ import annotations

from ptpcert.profile import Profile
from ptpcert.scenario import Vector

from . import active, link, passive_cpu, passive_fetch, passive_header, passive_send, passive_sequence, passive_timing
from ._build import Ctx

GROUP_MODULES = (link, passive_send, passive_fetch, passive_header, passive_sequence, passive_timing,
                 passive_cpu, active)


def cases(profile: Profile) -> list[Vector]:
    """Every case of the suite for the IUT this profile describes."""
    c = Ctx.of(profile.params)
    out: list[Vector] = []
    for module in GROUP_MODULES:
        out += module.cases(c)
    return out
