"""Deliberately broken variants of the ASCII driver's reference model, each breaking one rule."""

from __future__ import annotations

from .procedure import Mutant

MUTANTS: dict[str, Mutant] = {}
