"""Harness timing precision and overhead. Prints figures; asserts nothing.

    python benchmarks/bench_harness.py [--samples 300] [--no-suite] [--schemes exec,pty,rfc2217,socket]

1. Precision over exec:, pty:, rfc2217:// and socket:// (p50 / p99 / max, milliseconds),
   measured against a peer process (benchmarks/timestamp_peer.py) that timestamps with the
   same monotonic clock. For rfc2217:// and socket:// the peer sits on a pseudo-terminal
   behind tests/fakes/port_server.py (an RFC 2217 server on pyserial's PortManager, or a raw
   TCP server) on 127.0.0.1, so the figures include a network serial server's hops, not a
   real network's or UART's.
   * send latency: when the peer read the tester's byte - when the harness stamped it as
     sent (how late the tester's bytes reach the line after the harness thinks they left);
   * injected gap: the tester sends a byte a fixed time after the previous echo arrived;
     error = the gap the peer saw - the gap the runner meant;
   * arrival stamp: when the runner stamped the echo - when the peer wrote it (how late
     arrivals are timestamped).
   All go through the runner's own step interpreter (CaseRun), as in a real case.
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
from contextlib import ExitStack, contextmanager
from dataclasses import replace
from pathlib import Path

from ptpcert.results import wire_events
from ptpcert.runner import RunOptions, Runner, realtime_tolerance
from ptpcert.scenario import Expr, Step, Vector
from ptpcert.transport import make_factory
from ptpcert.procedures.p3964.description import reference_profile

ROOT = Path(__file__).resolve().parent.parent
PY = sys.executable
GAP_MS = 15.0


def pct(xs: list[float], p: float) -> float:
    xs = sorted(xs)
    k = min(len(xs) - 1, max(0, int(round(p / 100 * (len(xs) - 1)))))
    return xs[k]


@contextmanager
def served(mode: str, command: str):
    """The peer on a pty behind tests/fakes/port_server.py; yields the server's TCP port."""
    proc = subprocess.Popen([PY, str(ROOT / "tests" / "fakes" / "port_server.py"), mode, command],
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, cwd=ROOT)
    try:
        line = proc.stdout.readline().decode()
        if not line.startswith("PORT "):
            raise SystemExit(f"bench_harness: the port server did not start ({line!r})")
        yield int(line.split()[1])
    finally:
        proc.terminate()   # the server stops the peer with SIGTERM: it writes its log
        proc.wait(15)


def precision(scheme: str, samples: int) -> tuple[dict[str, list[float]], str]:
    log = Path(tempfile.mkstemp(suffix=".log")[1])
    peer = f"{PY} {ROOT / 'benchmarks' / 'timestamp_peer.py'} {log}"
    profile = reference_profile(line_conditions="none", status_from_stderr=False)
    steps = []
    for _ in range(samples):
        steps.append(Step("send", b"\x41"))
        steps.append(Step("send", b"\x42", at=Expr(f"{GAP_MS}ms")))
        steps.append(Step("expect", b"\x41\x42", after=Expr("-100ms"), within=Expr("100ms"), max_gap=Expr("100ms")))
    v = Vector(procedure="p3964", id="BENCH.TIMING", title="timing", reference="-", rule="-", group="timing",
               iut_role="idle", params=profile.params, steps=tuple(steps))
    with ExitStack() as stack:
        if scheme == "exec":
            url = f"exec:{peer}"
        elif scheme == "pty":
            url = f"pty:{peer} {{port}}"
        else:
            port = stack.enter_context(served("raw" if scheme == "socket" else "rfc2217", f"{peer} {{port}}"))
            url = f"{scheme}://127.0.0.1:{port}"
        factory = make_factory(url, profile, prespawn=0)
        # a late stimulus must be measured, not void the case: no stimulus limit here
        tol = replace(realtime_tolerance(profile.procedure, profile.params), stimulus=3600.0)
        runner = Runner(factory, profile, RunOptions(tolerance=tol, timing_retries=0, confirm_late=False,
                                                     echo=False, check_status=False))
        res = runner.run_case(v)
        factory.shutdown()
    rows = [tuple(map(float, line.split()[:3])) for line in log.read_text().splitlines()]
    log.unlink()
    char = profile.params.char_time
    wire = wire_events(res.transcript)
    sent = [t for t, d, kind, _, _ in wire if kind == "byte" and d == "tester"]
    # the peer's start-up NAK is lost on a persistent line (no client yet) or read before the steps
    echoes = [t for t, d, kind, b, _ in wire if kind == "byte" and d == "iut" and b in (0x41, 0x42)]
    n = min(len(rows), len(echoes), len(sent)) // 2 * 2
    return {
        "send latency": [(rows[k][0] - (res.origin + sent[k])) * 1000 for k in range(n)],
        "injected gap": [((rows[k + 1][0] - rows[k][0]) - (GAP_MS / 1000 + char)) * 1000 for k in range(0, n, 2)],
        "arrival stamp": [((res.origin + echoes[k]) - rows[k][1]) * 1000 for k in range(n)],
    }, f"{res.verdict}, {n} bytes"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=300)
    ap.add_argument("--no-suite", action="store_true")
    ap.add_argument("--schemes", default="exec,pty,rfc2217,socket", help="comma-separated: exec,pty,rfc2217,socket")
    args = ap.parse_args()
    print(f"timing precision, {args.samples} samples each (ms)")
    for scheme in args.schemes.split(","):
        figures, how = precision(scheme, args.samples)
        for name, xs in figures.items():
            print(f"  {scheme:<8} {name:<14} p50 {statistics.median(xs):7.3f}   p99 {pct(xs, 99):7.3f}   "
                  f"max {max(xs):7.3f}" + (f"   (case {how})" if name == "arrival stamp" else ""))
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
