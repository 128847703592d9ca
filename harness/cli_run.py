"""Commands that run an IUT: ``run``, ``iut``, ``report`` (filled in by later modules)."""

from __future__ import annotations


def add_commands(sub) -> None:
    pass
