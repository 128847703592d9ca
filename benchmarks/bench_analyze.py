"""Line analysis throughput (ptpcert analyze): exchanges judged per second from a capture
file, one core. Prints figures; exits 1 when the rate is below the target (1,000 exchanges
per second), so CI can run it as a check.

    python benchmarks/bench_analyze.py [--exchanges 3000] [--format pcap|hexlog|json]

The capture: two conforming 3964R model stations (model.link, 9600 8E1, CDT and ADT 20 ms)
exchange blocks of 1..32 bytes rich in control characters (every DLE doubled on the line),
both directions, the low-priority station sending back what it receives (echo), each
byte a chunk of its own at the time its stop bit ends, as a recorder reading every
character would write it. It is written to a file and the measured part is what
``ptpcert analyze`` does: load the file and judge both seats (the timing resolution of a
recorder reading one character at a time: a character time plus 2 ms).

Rates are per second of this process's CPU time (time.process_time), so that a busy
machine shares its cores without changing the figure much; the wall-clock rate is printed
beside it.
"""

from __future__ import annotations

import argparse
import random
import sys
import tempfile
import time
from pathlib import Path

from ptpcert import analysis as A
from ptpcert import capture as C
from ptpcert import results as R
from ptpcert.model.link import Link
from ptpcert.registry import by_name
from ptpcert.procedures.p3964.model import codec
from ptpcert.procedures.p3964.model.params import Params3964
from ptpcert.procedures.p3964.model.station import Station3964

TARGET = 1000.0
PA = Params3964(priority="high", cdt_ms=20, adt_ms=20)
PB = Params3964(priority="low", cdt_ms=20, adt_ms=20)


def make_capture(n_jobs: int, seed: int = 1) -> C.Capture:
    """A recording of ``n_jobs`` send jobs (a's blocks are echoed by b: two exchanges)."""
    a, b = Station3964(PA, name="a"), Station3964(PB, name="b")
    link = Link(a, b, echo={"b"})
    link.power_on(0.0)
    link.run_until_quiet(1.0)
    rnd = random.Random(seed)
    alphabet = [codec.DLE, codec.STX, codec.ETX, codec.NAK, 0x41, 0x00, 0xFF, 0x31]
    t = link.now + 0.01
    for i in range(n_jobs):
        payload = bytes(rnd.choice(alphabet) for _ in range(rnd.randrange(1, 33)))
        link.request(link.a if i % 4 else link.b, payload, at=t)
        link.run_until_quiet(t + 30)
        t = link.now + rnd.choice([0.001, 0.005, 0.05])
    chunks = []
    for w in link.wire:
        st = link.a if w.src == link.a.name else link.b
        chunks.append(C.Chunk(round(w.start + st.params.char_time, 6), "a" if st is link.a else "b",
                              bytes([w.byte])))
    return C.Capture(chunks, {"a": "model a", "b": "model b"}, C.LineSettings(9600, 8, "even", 1),
                     end=round(link.now + 0.1, 6))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--exchanges", type=int, default=3000, help="about how many exchanges the capture holds")
    ap.add_argument("--format", default="pcap", choices=["pcap", "hexlog", "json"])
    args = ap.parse_args(argv)
    # a's jobs are echoed (two exchanges), b's are not: 4 jobs give 7 exchanges
    cap = make_capture(max(1, args.exchanges * 4 // 7))
    kit = by_name("3964R").analyzer(PA, PB, apps={"a": "none", "b": "echo"})
    resolution = PA.char_time + 0.002
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / f"bench.{args.format}"
        C.save(cap, str(path), args.format)
        size = path.stat().st_size
        c0, w0 = time.process_time(), time.perf_counter()
        loaded = C.load(str(path))
        an = A.analyze(loaded, kit, resolution=resolution)
        cpu, wall = time.process_time() - c0, time.perf_counter() - w0
    n = len(an.exchanges)
    bad = [f for f in an.findings if f.grade == R.FAIL]
    rate = n / cpu
    print(f"capture: {len(cap.chunks)} chunks, {size} bytes ({args.format}), {n} exchanges, "
          f"{cap.end:.1f} s of line")
    print(f"analyze: {rate:,.0f} exchanges/s (CPU time {cpu:.2f} s; wall clock {n / wall:,.0f}/s)")
    print(f"target: {TARGET:,.0f} exchanges/s: {'met' if rate >= TARGET else 'NOT met'}")
    if bad:
        print(f"error: the conforming capture has {len(bad)} failing findings, e.g. {bad[0].message}")
        return 1
    return 0 if rate >= TARGET else 1


if __name__ == "__main__":
    sys.exit(main())
