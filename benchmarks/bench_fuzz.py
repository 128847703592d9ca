"""Fuzzing throughput. Prints figures; asserts nothing.

    python benchmarks/bench_fuzz.py [--examples 200] [--seconds 30]

* level 1: examples per second of the model-against-model state machine
  (tests/test_fuzz_model.py, virtual time), and steps per second within them;
* level 2: examples per second of `ptpcert fuzz` against the reference implementation as a
  real process over exec: at 20 ms timers (each example is a real exchange on the pipe).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from hypothesis import settings
from hypothesis.stateful import run_state_machine_as_test

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))


def level1(examples: int) -> None:
    import test_fuzz_model as m

    steps = {"n": 0}
    orig = m.TwoStations.check_outcomes

    def counting(self, final):
        steps["n"] += 1
        return orig(self, final)

    m.TwoStations.check_outcomes = counting
    s = settings(settings.get_profile("ptpcert-quick"), max_examples=examples, derandomize=False)
    t = time.perf_counter()
    run_state_machine_as_test(m.TwoStations, settings=s)
    dt = time.perf_counter() - t
    print(f"level 1 (model against model, virtual time): {examples} examples in {dt:.1f} s = "
          f"{examples / dt:.1f} examples/s, {steps['n'] / dt:.0f} invariant checks/s")


def level2(seconds: float) -> None:
    from ptpcert.fuzz import Campaign
    from ptpcert.profile import reference_profile
    from ptpcert.runner import RunOptions, Runner
    from ptpcert.transport import make_factory

    prof = reference_profile()
    factory = make_factory(f"exec:{sys.executable} -m ptpcert.cli iut --cdt-ms 20 --adt-ms 20 --parmrk", prof)
    camp = Campaign(prof, Runner(factory, prof, RunOptions(check_status=False)), seconds, 1)
    t = time.perf_counter()
    camp.run()
    dt = time.perf_counter() - t
    factory.shutdown()
    print(f"level 2 (ptpcert iut over exec:, 20 ms timers): {camp.examples} examples in {dt:.1f} s = "
          f"{camp.examples / dt:.1f} examples/s, {len(camp.findings)} finding(s)")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--examples", type=int, default=200)
    ap.add_argument("--seconds", type=float, default=30.0)
    args = ap.parse_args()
    level1(args.examples)
    level2(args.seconds)


if __name__ == "__main__":
    main()
