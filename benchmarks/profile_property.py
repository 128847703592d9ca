"""The long run of the profile property (tests/core/test_every_profile.py): N profiles drawn
from the profile schema per procedure, each either refused in one line or passed by the
reference configured from it (sim:, every case and golden vector). Prints how many profiles
it tried, how many were refused and ran, and the shrunk profile of the first failure.

    python benchmarks/profile_property.py --examples 500 [--procedure RK512] [--seed 1]
"""

from __future__ import annotations

import argparse
import collections
import sys
import time
from pathlib import Path

from hypothesis import HealthCheck, given, seed, settings

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "core"))

from profile_property import judge, to_toml  # noqa: E402

from ptpcert.fuzz.profiles import profile_dicts  # noqa: E402
from ptpcert.registry import by_name, procedures  # noqa: E402


def run(proc, examples: int, seed_: int) -> bool:
    counts: collections.Counter = collections.Counter()
    failure: list = []
    t0 = time.monotonic()

    @seed(seed_)
    @settings(max_examples=examples, deadline=None, database=None, derandomize=False,
              suppress_health_check=list(HealthCheck))
    @given(profile_dicts(proc, setups=dict(proc.reference_setups)))
    def check(raw):
        kind, problems = judge(raw)
        counts[kind] += 1
        if kind == "refused":
            assert "\n" not in problems[0]
            counts["refused: " + problems[0].split(": ")[1]] += 1
            return
        if problems:
            failure[:] = [raw, problems]
        assert not problems
    ok = True
    try:
        check()
    except AssertionError:
        ok = False
    print(f"{proc.title}: {counts['run'] + counts['refused']} profiles drawn in {time.monotonic() - t0:.0f} s: "
          f"{counts['run']} run, {counts['refused']} refused")
    for k, n in sorted(counts.items()):
        if k.startswith("refused: "):
            print(f"    {n:4d} {k}")
    if not ok:
        raw, problems = failure
        print("  FAILS under the shrunk profile:\n" + "\n".join("    " + line for line in to_toml(raw).splitlines()))
        print("\n".join("    " + p for p in problems[:30]))
    return ok


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--examples", type=int, default=500, help="profiles per procedure (default 500)")
    ap.add_argument("--procedure", action="append", help="only this procedure (repeatable)")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    procs = [by_name(n) for n in args.procedure] if args.procedure else [p for p in procedures() if p.suite]
    ok = all([run(p, args.examples, args.seed) for p in procs])
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
