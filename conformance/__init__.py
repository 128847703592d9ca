"""The conformance suite users run against their IUT: cases generated for the IUT's
profile, one package per procedure, one module per group of the manual. Only the command
line (and the pytest plugin) hands these cases to the runner."""

from __future__ import annotations

from ptpcert.profile import Profile
from ptpcert.scenario import Vector

from . import ascii, p3964, rk512


def cases(profile: Profile) -> list[Vector]:
    """Every case of the suite for the IUT this profile describes."""
    pid = profile.procedure.id
    if pid == "3964r":
        return p3964.cases(profile.params)
    if pid == "ascii":
        return ascii.cases(profile.params)
    if pid == "rk512":
        return rk512.cases(profile)
    raise ValueError(f"no conformance suite for procedure {profile.procedure.title}")
