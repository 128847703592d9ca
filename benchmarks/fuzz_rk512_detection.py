"""How fast the RK 512 fuzzer finds each broken variant. Prints a table; asserts nothing.

    python benchmarks/fuzz_rk512_detection.py [--budget 90] [--seed 1] [--only NAME ...]

Each broken variant of ``ptpcert iut --procedure RK512 --list-mutants`` is fuzzed in
virtual time (``sim:?mutant=NAME``) with a fresh campaign, until the first finding or the
budget (seconds of wall clock, per variant). The profile: 3964R, the IUT low priority,
20 ms link timers, T_RES 500 ms, both roles with request scripts, the memory pattern.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests" / "procedures" / "rk512"))


class _Stop(Exception):
    pass


def detect(name: str, budget: float, seed: int, profile) -> tuple[float | None, int, str]:
    from ptpcert.fuzz import Campaign
    from ptpcert.runner import RunOptions, Runner
    from ptpcert.transport import make_factory

    factory = make_factory(f"sim:?mutant={name}", profile)
    runner = Runner(factory, profile, RunOptions(check_status=True))
    found: dict = {}
    t0 = time.monotonic()

    def progress(line: str) -> None:
        if line.startswith("FINDING"):
            found["t"] = time.monotonic() - t0
            found["rule"] = line.split(": ", 1)[-1].splitlines()[0]
            raise _Stop

    camp = Campaign(profile, runner, budget, seed, progress=progress)
    try:
        camp.run()
    except _Stop:
        pass
    return found.get("t"), camp.examples, found.get("rule", "")


def main() -> None:
    from ptpcert.registry import by_id
    from rk512_profiles import rk_profile

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--budget", type=float, default=90.0, help="seconds per variant (default 90)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--only", nargs="*")
    args = ap.parse_args()
    mutants = by_id("rk512").mutants()
    rows = []
    t_all = time.monotonic()
    for name, m in mutants.items():
        if args.only and name not in args.only:
            continue
        prof = rk_profile(t_res=500, db_bytes=512, byte_area_bytes=256, cell_area_cells=256, **m.profile)
        t, n, rule = detect(name, args.budget, args.seed, prof)
        rows.append((name, t, n))
        shown = f"{t:6.1f} s" if t is not None else "   -    "
        print(f"{name:32} {shown}  {n:5} examples  {rule[:90]}", flush=True)
    found = [r for r in rows if r[1] is not None]
    print(f"\n{len(found)} of {len(rows)} variants found within {args.budget:.0f} s each "
          f"({100 * len(found) / max(1, len(rows)):.0f} %); {time.monotonic() - t_all:.0f} s in all")


if __name__ == "__main__":
    main()
