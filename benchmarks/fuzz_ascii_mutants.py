"""How fast the ASCII fuzzer finds each broken variant. Prints a table; asserts nothing.

    python benchmarks/fuzz_ascii_mutants.py                  # every variant, 90 s each, in sim:
    python benchmarks/fuzz_ascii_mutants.py --budget 30 --only cdt-half xoff-ignored
    python benchmarks/fuzz_ascii_mutants.py --exec            # variants as real processes (ptpcert iut)

For each variant, ``ptpcert fuzz``'s campaign runs against it with the profile its broken rule
needs (the reference implementation's, both setups included) until its first finding, which is
confirmed and shrunk as in a real campaign, or until the budget is spent.
"""

from __future__ import annotations

import argparse
import sys
import time

from ptpcert.fuzz import Campaign
from ptpcert.procedures.ascii.description import iut_command, reference_profile
from ptpcert.procedures.ascii.mutants import MUTANTS
from ptpcert.runner import Runner, RunOptions
from ptpcert.transport import make_factory


class _First(Exception):
    pass


def hunt(name: str, budget: float, seed: int, real: bool) -> tuple[float | None, int, str]:
    """Seconds to the first finding (None: not found), examples run, the finding's rule."""
    m = MUTANTS[name]
    settings = dict(m.profile)
    if real and settings.get("end_criterion") == "cdt":
        settings.setdefault("character_delay_ms", 50)
    prof = reference_profile(**settings)
    url = f"exec:{iut_command(prof.params, mutant=name)}" if real else f"sim:?mutant={name}"
    factory = make_factory(url, prof)
    found: list[str] = []

    def progress(line: str) -> None:
        if line.startswith("FINDING"):
            found.append(line.splitlines()[0].split(": ", 1)[-1])
            raise _First

    camp = Campaign(prof, Runner(factory, prof, RunOptions(check_status=False)), budget, seed,
                    progress=progress)
    t = time.monotonic()
    try:
        camp.run()
    except _First:
        pass
    finally:
        factory.shutdown()
    took = time.monotonic() - t
    return (took if found else None), camp.examples, found[0] if found else ""


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--budget", type=float, default=90.0, help="seconds per variant (default 90)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--exec", action="store_true", help="the variants as real processes over exec:")
    ap.add_argument("--only", nargs="*", help="only these variants")
    args = ap.parse_args()
    names = [n for n in MUTANTS if not args.only or n in args.only]
    rows = []
    t0 = time.monotonic()
    print(f"{'variant':<28} {'found after':>12} {'examples':>9}  finding", flush=True)
    for name in names:
        took, examples, rule = hunt(name, args.budget, args.seed, args.exec)
        rows.append((name, took))
        shown = f"{took:9.1f} s" if took is not None else "   not found"
        print(f"{name:<28} {shown:>12} {examples:>9}  {rule[:90]}", flush=True)
    found = [r for r in rows if r[1] is not None]
    print(f"\n{len(found)} of {len(rows)} variants found within {args.budget:.0f} s each "
          f"({100 * len(found) / max(1, len(rows)):.0f} %); {time.monotonic() - t0:.0f} s in all", flush=True)


if __name__ == "__main__":
    sys.exit(main())
