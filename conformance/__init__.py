"""The conformance suite users run against their IUT: cases generated for the IUT's
profile, one package per procedure (``p3964``, ``rk512``, ``ascii``), one module per group of
the manual. Each procedure names the module of its suite (``Procedure.suite``, a procedure
from another distribution names its own); :func:`cases` loads it. Only the command line
(and the pytest plugin) hands these cases to the runner."""

from __future__ import annotations

from importlib import import_module

from ptpcert.profile import Profile
from ptpcert.scenario import Vector


def cases(profile: Profile) -> list[Vector]:
    """Every case of the suite for the IUT this profile describes (empty where its procedure
    has no suite)."""
    proc = profile.procedure
    if not proc.suite:
        return []
    return list(import_module(proc.suite).cases(profile))
