"""Deliberately broken variants of the reference implementation (filled in by the suite)."""

from __future__ import annotations

from dataclasses import dataclass

from .model import Params3964, Station3964

MUTANTS: dict = {}


def make_mutant(name: str, params: Params3964) -> Station3964:
    raise KeyError(name)
