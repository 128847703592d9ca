"""The cases a run executes: the golden vectors of the profile's procedure plus the
conformance suite generated for the profile, selected by id globs and ordered as the manual
is. This module sits at the command line's level: it is the one place (with the pytest
plugin) that hands the suite's cases to the runner."""

from __future__ import annotations

import fnmatch

from .profile import Profile
from .scenario import Vector


def load_suite(profile: Profile, vectors: list[Vector], *, include_suite: bool = True,
               select: list[str] | None = None) -> list[Vector]:
    """The vectors of ``profile``'s procedure, plus (``include_suite``) the suite's cases,
    selected by ``select`` (id globs). Ids must be unique."""
    proc = profile.procedure
    out = [v for v in vectors if v.procedure == proc.id]
    if include_suite:
        from . import conformance
        out = out + conformance.cases(profile)
    seen: dict[str, Vector] = {}
    for v in out:
        if v.id in seen:
            raise ValueError(f"case id {v.id} is used twice ({seen[v.id].source or 'suite'} and {v.source or 'suite'})")
        seen[v.id] = v
    if select:
        out = [v for v in out if any(fnmatch.fnmatchcase(v.id, g) for g in select)]
    return order(out, proc.groups)


def order(vectors: list[Vector], groups: tuple[str, ...]) -> list[Vector]:
    """The manual's order of groups (for 3964: start-up, idle, receive, send, release,
    repetition, conflict, BREAK, character errors, timing); the suite's cases before the
    golden vectors of a group."""
    rank = {g: i for i, g in enumerate(groups)}
    return sorted(vectors, key=lambda v: (rank.get(v.group, len(rank)), not v.id.startswith("SUITE."), v.id))


def check_expected_failures(profile: Profile, cases: list[Vector]) -> None:
    """Every id the profile's ``[expected_failures]`` lists names a case of ``cases`` (the
    whole suite and every vector of the run, before any selection): an id with a typo would
    otherwise silently disable the expectation. Raises ValueError naming the id and the
    nearest real ids."""
    import difflib

    ids = [v.id for v in cases]
    known = set(ids)
    for xid in profile.expected_failures:
        if xid in known:
            continue
        near = difflib.get_close_matches(xid, ids, n=3, cutoff=0.6)
        hint = f"nearest: {', '.join(near)}" if near else "no case id is close to it"
        raise ValueError(f"{profile.path or 'profile'}: expected_failures: {xid!r} matches no case of "
                         f"{profile.procedure.title} in this run ({hint})")


# -- shards: one run split over several machines (``ptpcert run --shard K/N``) --------------
def forced_waits(profile: Profile, cases: list[Vector]) -> dict[str, float]:
    """Each case's forced waits (seconds): the time the protocol itself makes the case take
    (:attr:`ptpcert.results.CaseResult.forced_wait`), measured by running the case against
    the reference model in virtual time (``sim:``). That depends on the profile and the case
    alone, never on the machine or the IUT, so every shard of a run computes the same
    figures. A case the model cannot run (unsupported for the profile) weighs 0, as it
    takes no time against a real IUT either."""
    from .runner import Runner, RunOptions
    from .transport import make_factory

    factory = make_factory("sim:", profile)
    try:
        runner = Runner(factory, profile, RunOptions(echo=profile.echo, check_status=False))
        return {v.id: round(max(runner.run_case(v).forced_wait, 0.0), 6) for v in cases}
    finally:
        factory.shutdown()


def plan_shards(weights: dict[str, float], n: int) -> list[list[str]]:
    """``weights`` (case id: seconds) split into ``n`` shards of about equal weight: the
    heaviest case first (ties by id) into the lightest shard so far (ties: the one with
    fewer cases, then the first). Deterministic; every case in exactly one shard; the
    heaviest shard is at most the heaviest case heavier than the lightest."""
    loads = [0.0] * n
    shards: list[list[str]] = [[] for _ in range(n)]
    for cid in sorted(weights, key=lambda c: (-weights[c], c)):
        i = min(range(n), key=lambda j: (loads[j], len(shards[j]), j))
        shards[i].append(cid)
        loads[i] += weights[cid]
    return shards


def shard_of(profile: Profile, cases: list[Vector], k: int, n: int,
             weights: dict[str, float] | None = None) -> tuple[list[Vector], float, float]:
    """Shard ``k`` of ``n`` of ``cases`` (in their order), its forced waits and those of all
    ``cases`` (seconds). ``weights``: the :func:`forced_waits` of these cases (or more), where
    known."""
    weights = forced_waits(profile, cases) if weights is None else {v.id: weights[v.id] for v in cases}
    mine = set(plan_shards(weights, n)[k - 1])
    return [v for v in cases if v.id in mine], sum(weights[c] for c in mine), sum(weights.values())
