"""The 3964/3964R conformance suite: cases generated for the IUT's profile, grouped as the
manual is. Each module is one group; each case is a vector (harness.scenario.Vector) that
cites its rule. The golden vectors in ../vectors run with them."""

from __future__ import annotations

from ptpcert.model import Params3964
from ptpcert.scenario import Vector

GROUP_MODULES: tuple[str, ...] = ("startup", "idle", "receive", "send", "release", "conflict", "line", "timing")


def cases(params: Params3964) -> list[Vector]:
    """Every case of the suite for an IUT with these parameters."""
    import importlib

    out: list[Vector] = []
    for name in GROUP_MODULES:
        out += importlib.import_module(f"ptpcert.conformance.{name}").cases(params)
    return out
