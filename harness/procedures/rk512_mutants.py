"""Deliberately broken variants of the RK 512 reference (filled in below)."""

from __future__ import annotations

from ..procedure import Mutant

MUTANTS: dict[str, Mutant] = {}
