"""Results of shards joined into one (``ptpcert report --merge``): the shards of one run
(``ptpcert run --shard K/N`` on N machines) become the results an unsharded run of the same
selection would have given, each case's result as its shard judged it.

Part of :mod:`ptpcert.results`; standard library only. What may be merged is checked first,
each refusal one :class:`~ptpcert.results.reading.ResultsError` naming the files: the same
procedure, profile, tool and vector set (an unsharded run's vector set hash is that of its
selection, and so is every shard's), no case twice, and where the inputs are shards, each
shard of the N once.
"""

from __future__ import annotations

import datetime as _dt
from typing import Callable, Sequence

from ptpcert.results.reading import ResultsError
from ptpcert.results.run import RunResult

SHARD_ALLOWED = "allowed: K/N with whole numbers 1 <= K <= N, e.g. 2/4"


def parse_shard(text: str) -> tuple[int, int]:
    """``K/N``: shard K of N, 1 <= K <= N. Raises ValueError saying what is allowed."""
    k, sep, n = str(text).strip().partition("/")
    try:
        if not sep:
            raise ValueError
        kk, nn = int(k), int(n)
    except ValueError:
        raise ValueError(f"{text!r} is not a shard ({SHARD_ALLOWED})") from None
    if nn < 1 or not 1 <= kk <= nn:
        raise ValueError(f"{text!r} is no shard of a run ({SHARD_ALLOWED})")
    return kk, nn


def _same(named: Sequence[tuple[str, RunResult]], what: str, get: Callable[[RunResult], object]) -> None:
    first_name, first = named[0]
    for name, run in named[1:]:
        if get(run) != get(first):
            raise ResultsError(f"{name} and {first_name} are results of different {what} "
                               f"({get(run)!r}, {get(first)!r}); only the shards of one run merge")


def _profile_difference(a: dict, b: dict) -> str | None:
    for key in sorted(set(a) | set(b)):
        if a.get(key) != b.get(key):
            return f"{key} = {a.get(key)!r} and {b.get(key)!r}"
    return None


def _check_shards(named: Sequence[tuple[str, RunResult]]) -> list[str]:
    """The shards' labels in order; refuses a mix of shards and whole runs, shards of
    different N, a shard given twice and a missing one."""
    sharded = [name for name, run in named if run.shard]
    if not sharded:
        return []
    if len(sharded) < len(named):
        whole = next(name for name, run in named if not run.shard)
        raise ResultsError(f"{whole} is a whole run and {sharded[0]} a shard; merge the N shards of one run")
    seen: dict[int, str] = {}
    total = None
    for name, run in named:
        try:
            k, n = parse_shard(run.shard)
        except ValueError as exc:
            raise ResultsError(f"{name}: shard: {exc}") from None
        if total is not None and n != total[0]:
            raise ResultsError(f"{name} is shard {k}/{n} and {total[1]} one of {total[0]}; "
                               "merge the shards of one split")
        total = total or (n, name)
        if k in seen:
            raise ResultsError(f"{name} and {seen[k]} are both shard {k}/{n}")
        seen[k] = name
    n = total[0]
    missing = [f"{k}/{n}" for k in range(1, n + 1) if k not in seen]
    if missing:
        raise ResultsError(f"shard{'s' if len(missing) > 1 else ''} {', '.join(missing)} missing "
                           f"(given: {', '.join(f'{k}/{n}' for k in sorted(seen))})")
    return [f"{k}/{n}" for k in sorted(seen)]


def _when(text: str) -> tuple[int, _dt.datetime | str]:
    """A sortable form of a report's time stamp (ISO 8601; another text sorts after)."""
    try:
        t = _dt.datetime.fromisoformat(text)
        return (0, t if t.tzinfo else t.replace(tzinfo=_dt.timezone.utc))
    except ValueError:
        return (1, text)


def merge_runs(named: Sequence[tuple[str, RunResult]],
               order: Callable[[list], list] | None = None) -> RunResult:
    """One results object from ``named`` ((file name, results), at least one): every case
    once, in ``order`` (a function that sorts the cases as the unsharded run would have
    them; None: as given). Raises :class:`ResultsError` when they are not parts of one run."""
    if not named:
        raise ResultsError("nothing to merge; give the results files of the shards")
    _same(named, "procedures", lambda r: r.procedure)
    first_name, first = named[0]
    for name, run in named[1:]:
        diff = _profile_difference(run.profile, first.profile)
        if diff:
            raise ResultsError(f"{name} and {first_name} are results of different profiles ({diff}); "
                               "only the shards of one run merge")
    _same(named, "ptpcert versions", lambda r: r.tool_version)
    _same(named, "vector sets (suites or selections)", lambda r: (r.vector_set, r.vector_set_hash))
    shards = _check_shards(named)
    where: dict[str, str] = {}
    for name, run in named:
        for c in run.cases:
            if c.id in where:
                raise ResultsError(f"case {c.id} is in both {where[c.id]} and {name}; "
                                   "merge results whose cases do not overlap")
            where[c.id] = name
    cases = [c for _, run in named for c in run.cases]
    runs = [run for _, run in named]
    started = [r.started for r in runs if r.started]
    finished = [r.finished for r in runs if r.finished]
    return RunResult(
        tool_version=first.tool_version,
        started=min(started, key=_when) if started else "",
        finished=max(finished, key=_when) if finished else "",
        iut=" | ".join(dict.fromkeys(r.iut for r in runs if r.iut)),
        procedure=first.procedure, profile=first.profile,
        profile_path=" | ".join(dict.fromkeys(r.profile_path for r in runs if r.profile_path)),
        vector_set=first.vector_set, vector_set_hash=first.vector_set_hash,
        cases=order(cases) if order else cases,
        interrupted=any(r.interrupted for r in runs),
        # the shards ran side by side: the run took as long as its longest shard
        wall_time=max(r.wall_time for r in runs),
        harness_scheduling=" | ".join(dict.fromkeys(r.harness_scheduling for r in runs if r.harness_scheduling)),
        merged_from=shards or [name for name, _ in named])
