"""The set of cases a run executes: the golden vectors plus the conformance suite,
selected by id globs and ordered so that long waits come last."""

from __future__ import annotations

import fnmatch

from .model import Params3964
from .scenario import GROUPS, Vector


def load_suite(params: Params3964, vectors: list[Vector], *, include_suite: bool = True,
               select: list[str] | None = None) -> list[Vector]:
    if include_suite:
        import ptpcert.conformance as conformance
        vectors = vectors + conformance.cases(params)
    seen: dict[str, Vector] = {}
    for v in vectors:
        if v.id in seen:
            raise ValueError(f"case id {v.id} is used twice ({seen[v.id].source or 'suite'} and {v.source or 'suite'})")
        seen[v.id] = v
    if select:
        vectors = [v for v in vectors if any(fnmatch.fnmatchcase(v.id, g) for g in select)]
    return order(vectors)


def order(vectors: list[Vector]) -> list[Vector]:
    """The manual's order: start-up, idle, receive, send, release, repetition, conflict,
    BREAK, character errors, timing; the suite's cases before the golden vectors of a group."""
    rank = {g: i for i, g in enumerate(GROUPS)}
    return sorted(vectors, key=lambda v: (rank.get(v.group, len(rank)), not v.id.startswith("SUITE."), v.id))
