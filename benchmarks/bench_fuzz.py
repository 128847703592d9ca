"""Fuzzing throughput. Prints figures; asserts nothing.

    python benchmarks/bench_fuzz.py [--examples 200] [--seconds 30] [--workers 4]

* level 1: examples per second of the model-against-model state machine
  (tests/procedures/p3964/test_fuzz_model.py, virtual time), and steps per second within them;
* level 2: examples per second of `ptpcert fuzz` against the reference implementation as a
  real process over exec: at 20 ms timers (each example is a real exchange on the pipe),
  with 1 worker and with 4 (`--workers`), and the ratio.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from hypothesis import settings

from ptpcert.fuzz.settings import register_profiles

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests" / "procedures" / "p3964"))


def level1(examples: int) -> None:
    import test_fuzz_model as m

    steps = {"n": 0}
    orig = m.TwoStations.protocol_holds

    def counting(self):
        steps["n"] += 1
        return orig(self)

    m.TwoStations.protocol_holds = counting
    register_profiles()
    s = settings(settings.get_profile("ptpcert-quick"), max_examples=examples, derandomize=False)
    t = time.perf_counter()
    try:
        m.fuzz(s)
    finally:
        m.TwoStations.protocol_holds = orig
    dt = time.perf_counter() - t
    print(f"level 1 (model against model, virtual time): {examples} examples in {dt:.1f} s = "
          f"{examples / dt:.1f} examples/s, {steps['n'] / dt:.0f} invariant checks/s")


def level2(seconds: float, workers: int) -> float:
    """Examples per second of `ptpcert fuzz --workers N` (fuzz.run_workers: each worker a
    process with its own reference IUT over exec:, 20 ms timers)."""
    import os
    from ptpcert.fuzz import WorkerSpec, run_workers

    profile = ROOT / "conformance" / "profiles" / "reference-20ms.toml"
    iut = f"exec:{sys.executable} -m ptpcert.cli iut --cdt-ms 20 --adt-ms 20 --parmrk"
    load = os.getloadavg()[0]
    res = run_workers(WorkerSpec(iut, str(profile), seconds, 1, workers=workers))
    rate = res.examples / res.elapsed
    print(f"level 2 (ptpcert iut over exec:, 20 ms timers, {workers} worker{'s' * (workers > 1)}): "
          f"{res.examples} examples in {res.elapsed:.1f} s = {rate:.1f} examples/s, "
          f"{len(res.findings)} finding(s), load average {load:.1f}" + (f", errors {res.errors}" if res.errors else ""))
    return rate


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--examples", type=int, default=200)
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--workers", type=int, default=4, help="workers of the second level-2 run (default 4)")
    args = ap.parse_args()
    ap_workers = args.workers
    if args.examples > 0:     # --examples 0: level 2 only
        level1(args.examples)
    one = level2(args.seconds, 1)
    many = level2(args.seconds, ap_workers)
    print(f"level 2: {ap_workers} workers / 1 worker = {many / max(one, 1e-9):.2f}")


if __name__ == "__main__":
    main()
