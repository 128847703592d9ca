"""Model throughput: complete block exchanges per second between two model stations in
virtual time, 64-byte payloads (3964R), and the level-1 fuzzer's examples per second. Prints
figures; asserts nothing.

    python benchmarks/bench_model.py [--seconds 3] [--repeat 3] [--examples 100] [--seed 0] [--show-failure]

Two line models: "no line timing" (characters take no time: whole blocks arrive at one
instant) and "9600 8E1" (every character is a separate event 1.146 ms apart; the link
hands a block's data to a receiver that only stores it in one call, see
``Link._stream``). The machine running this is often shared: the rates are per second of
this process's CPU time (``time.process_time``), the best of ``--repeat`` runs, and the
wall-clock rate is shown beside them.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
import traceback
from pathlib import Path

from ptpcert.model.events import Delivered
from ptpcert.model.link import Link
from ptpcert.procedures.p3964.model.params import Params3964
from ptpcert.procedures.p3964.model.station import Station3964

ROOT = Path(__file__).resolve().parent.parent


def exchanges_per_second(baud, seconds: float, payload: bytes) -> tuple[float, float, int]:
    """(exchanges per CPU second, per wall second, exchanges) for about ``seconds`` of CPU."""
    a = Station3964(Params3964(baud_rate=baud, priority="low"), name="a")
    b = Station3964(Params3964(baud_rate=baud, priority="high"), name="b")
    link = Link(a, b, record_wire=False)
    link.power_on(0.0)
    link.run_until_quiet(1.0)
    n = 0
    c0, w0 = time.process_time(), time.perf_counter()
    while True:
        for _ in range(200):
            link.request(a, payload)
            link.run_until_quiet(link.now + 100.0)
            n += 1
        if time.process_time() - c0 >= seconds:
            break
    cpu, wall = time.process_time() - c0, time.perf_counter() - w0
    delivered = sum(1 for name, e in link.events if name == "b" and isinstance(e, Delivered))
    assert delivered == n, "every request must be delivered once"
    return n / cpu, n / wall, n


def level1(examples: int, seed: int) -> tuple[float, float, float] | None:
    """The level-1 fuzzer (tests/procedures/p3964/test_fuzz_model.py, ``fuzz``) for ``examples`` examples
    from a fixed seed, so that the repeats and a later version of the test run the same
    examples (as far as hypothesis keeps to a seed). (examples per CPU second, per wall
    second, invariant checks per CPU second: one at the start of an example and one after
    each of its steps), or None when an example fails: that is a finding, not a figure (it is
    not shrunk here; ``--seed N --show-failure`` shrinks and prints it)."""
    sys.path.insert(0, str(ROOT / "tests" / "procedures" / "p3964"))
    import test_fuzz_model as m
    from hypothesis import Phase, Verbosity, settings

    from ptpcert.fuzz.settings import register_profiles
    register_profiles()
    s = settings(settings.get_profile("ptpcert-quick"), max_examples=examples, database=None,
                 phases=(Phase.explicit, Phase.generate) + ((Phase.shrink,) if SHOW_FAILURE else ()),
                 verbosity=Verbosity.normal if SHOW_FAILURE else Verbosity.quiet)
    checks = [0]
    holds = m.TwoStations.protocol_holds

    def counted(self):
        checks[0] += 1
        return holds(self)

    m.TwoStations.protocol_holds = counted
    c0, w0 = time.process_time(), time.perf_counter()
    try:
        m.fuzz(s, seed=seed)
    except Exception as e:  # noqa: BLE001 - any failure of the fuzzer is reported, not measured
        where = traceback.extract_tb(e.__traceback__)[-1]
        print(f"  level-1 fuzzer, seed {seed}: an example FAILED: {type(e).__name__} in {where.name}: {where.line}")
        if SHOW_FAILURE:
            print("\n".join(getattr(e, "__notes__", [])))   # the program, as hypothesis prints it
        return None
    finally:
        m.TwoStations.protocol_holds = holds
    cpu = time.process_time() - c0
    return examples / cpu, examples / (time.perf_counter() - w0), checks[0] / cpu


SHOW_FAILURE = False


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=3.0, help="CPU seconds per measurement (default 3)")
    ap.add_argument("--repeat", type=int, default=3, help="measurements per figure; the best is shown (default 3)")
    ap.add_argument("--examples", type=int, default=100, help="level-1 fuzzer examples per measurement (default 100)")
    ap.add_argument("--seed", type=int, default=0,
                    help="the level-1 fuzzer's seed (default 0; the next one if its examples find a failure)")
    ap.add_argument("--show-failure", action="store_true",
                    help="shrink and print the level-1 fuzzer's failing example (can take minutes)")
    args = ap.parse_args()
    payload = bytes(range(0x20, 0x60))  # 64 bytes
    print(f"model throughput, 64-byte payloads, 3964R, one core (load average {os.getloadavg()[0]:.1f}); "
          f"best of {args.repeat}, per CPU second (wall clock in brackets)")
    for label, baud in (("no line timing", None), ("9600 8E1 (per-character events)", 9600)):
        best = max(exchanges_per_second(baud, args.seconds, payload) for _ in range(args.repeat))
        print(f"  {label:<34} {best[0]:>10,.0f} exchanges/s  ({best[1]:,.0f}/s wall, {best[2]} exchanges)")
    global SHOW_FAILURE
    SHOW_FAILURE = args.show_failure
    # a seed whose examples find a failure gives no figure: the next seed is measured
    for seed in range(args.seed, args.seed + 5):
        runs = []
        for _ in range(args.repeat):
            runs.append(level1(args.examples, seed))
            if runs[-1] is None:
                break
        if all(runs):
            best = max(runs)
            print(f"  {'level-1 fuzzer (model against model)':<34} {best[0]:>10,.1f} examples/s   ({best[1]:,.1f}/s wall, "
                  f"{args.examples} examples of 40 steps, seed {seed}; {best[2]:,.0f} invariant checks/s)")
            break


if __name__ == "__main__":
    main()
