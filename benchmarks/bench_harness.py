"""Harness timing precision and overhead. Prints figures; asserts nothing.

    python benchmarks/bench_harness.py [--samples 300] [--no-suite]

1. Precision on exec: and pty: (p50 / p99, milliseconds), measured against a peer process
   that timestamps with the same monotonic clock:
   * injected gap: the tester sends a byte a fixed time after the previous echo arrived;
     error = when the peer read it - when the runner meant it to arrive;
   * measured response time: error = when the runner saw the echo - when the peer wrote it.
   Both go through the runner's own step interpreter (CaseRun), as in a real case.
2. Overhead: the full suite against the reference implementation over exec: at 20 ms
   timers; wall time divided by the sum of the waits the protocol itself forces.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from ptpcert.results import wire_events
from ptpcert.runner import RunOptions, Runner
from ptpcert.scenario import Expr, Step, Vector
from ptpcert.transport import make_factory
from ptpcert.profile import reference_profile

ROOT = Path(__file__).resolve().parent.parent
PY = sys.executable
GAP_MS = 15.0


def pct(xs: list[float], p: float) -> float:
    xs = sorted(xs)
    k = min(len(xs) - 1, max(0, int(round(p / 100 * (len(xs) - 1)))))
    return xs[k]


def precision(scheme: str, samples: int) -> tuple[list[float], list[float], str]:
    log = Path(tempfile.mkstemp(suffix=".log")[1])
    peer = f"{PY} {ROOT / 'benchmarks' / 'timestamp_peer.py'} {log}"
    url = f"exec:{peer}" if scheme == "exec" else f"pty:{peer} {{port}}"
    profile = reference_profile(line_conditions="none", status_from_stderr=False)
    steps = []
    for _ in range(samples):
        steps.append(Step("send", b"\x41"))
        steps.append(Step("send", b"\x42", at=Expr(f"{GAP_MS}ms")))
        steps.append(Step("expect", b"\x41\x42", after=Expr("-100ms"), within=Expr("100ms"), max_gap=Expr("100ms")))
    v = Vector(id="BENCH.TIMING", title="timing", reference="-", rule="-", group="timing",
               iut_role="idle", params=profile.params, steps=tuple(steps))
    factory = make_factory(url, profile, prespawn=0)
    runner = Runner(factory, profile, RunOptions(timing_retries=0, confirm_late=False, echo=False,
                                                 check_status=False))
    res = runner.run_case(v)
    factory.shutdown()
    rows = [tuple(map(float, line.split()[:2])) for line in log.read_text().splitlines()]
    log.unlink()
    char = profile.params.char_time
    echoes = [t for t, d, kind, _, _ in wire_events(res.transcript) if kind == "byte" and d == "iut"][1:]
    n = min(len(rows), len(echoes)) // 2 * 2
    gap_err = [((rows[k + 1][0] - rows[k][0]) - (GAP_MS / 1000 + char)) * 1000 for k in range(0, n, 2)]
    resp_err = [((res.origin + echoes[k]) - rows[k][1]) * 1000 for k in range(n)]
    return gap_err, resp_err, res.verdict


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=300)
    ap.add_argument("--no-suite", action="store_true")
    args = ap.parse_args()
    print(f"timing precision, {args.samples} samples each (ms)")
    for scheme in ("exec", "pty"):
        gap, resp, verdict = precision(scheme, args.samples)
        print(f"  {scheme:<5} injected gap error    p50 {statistics.median(gap):7.3f}   p99 {pct(gap, 99):7.3f}   max {max(gap):7.3f}")
        print(f"  {scheme:<5} response time error   p50 {statistics.median(resp):7.3f}   p99 {pct(resp, 99):7.3f}   max {max(resp):7.3f}   (case {verdict})")
    if args.no_suite:
        return
    out = Path(tempfile.mkdtemp()) / "r.json"
    t = time.monotonic()
    subprocess.run([PY, "-m", "ptpcert.cli", "run", "--iut", f"exec:{PY} -m ptpcert.cli iut --cdt-ms 20 --adt-ms 20 --parmrk",
                    "--profile", str(ROOT / "conformance/profiles/reference-20ms.toml"), "--json", str(out), "-q"],
                   cwd=ROOT, stdout=subprocess.DEVNULL)
    wall = time.monotonic() - t
    d = json.loads(out.read_text())
    forced = sum(c["forced_wait"] for c in d["cases"])
    ran = [c for c in d["cases"] if c["verdict"] not in ("unsupported", "not-run")]
    print(f"full suite over exec: at 20 ms timers: {len(ran)} cases run, verdict {d['verdict']}")
    print(f"  wall time {wall:.1f} s (runner {d['wall_time']:.1f} s), protocol-forced waits {forced:.1f} s, "
          f"ratio {d['wall_time'] / forced:.2f}")


if __name__ == "__main__":
    main()
