"""RK 512 model throughput: SEND requests of 1024 bytes (8 frames and 8 responses each)
completed per second in virtual time, one core. Prints figures; asserts nothing.

    python benchmarks/bench_rk512.py [--seconds 3]

(a) the RK 512 layers alone, two cores over the ideal frame link (model.rk512.FrameLink);
(b) two full stations, RK 512 over the 3964R link model (model.link.Link), with no line
    timing (whole blocks arrive at one instant) and at 9600 8E1 (one event per character).

Rates are per second of this process's CPU time (time.process_time), so that a busy machine
shares its cores without changing the figures much; the wall-clock rate is printed beside.
"""

from __future__ import annotations

import argparse
import time

from ptpcert.model.link import Link
from ptpcert.procedures.p3964.model.params import Params3964
from ptpcert.procedures.rk512.model import FrameLink, RequestResult, Rk512Core, Rk512Params, Rk512Station
from ptpcert.procedures.rk512.model.requests import parse_request

REQ = parse_request("send", "DB10:DW0:LEN=1024")
#: DBs of 2 KB: the issue's profile example (512 bytes) cannot hold a 1024-byte request.
PARAMS = dict(db_bytes=2048)


def _count_ok(events, name: str) -> int:
    return sum(1 for n, e in events if n == name and isinstance(e, RequestResult) and e.ok)


def frame_link(seconds: float) -> tuple[float, float, int]:
    a, b = Rk512Core(Rk512Params(**PARAMS), name="a"), Rk512Core(Rk512Params(**PARAMS), name="b")
    link = FrameLink(a, b, record=False)
    link.power_on(0.0)
    n = 0
    c0, w0 = time.process_time(), time.perf_counter()
    while True:
        for _ in range(200):
            link.request(a, REQ)
            link.run_until_quiet(link.now + 100.0)
            n += 1
        if time.process_time() - c0 >= seconds:
            break
    cpu, wall = time.process_time() - c0, time.perf_counter() - w0
    assert _count_ok(link.events, "a") == n, "every request must succeed once"
    return n / cpu, n / wall, n


def full_stations(baud, seconds: float) -> tuple[float, float, int]:
    a = Rk512Station(Rk512Params(line=Params3964(priority="high", baud_rate=baud), **PARAMS), name="a")
    b = Rk512Station(Rk512Params(line=Params3964(priority="low", baud_rate=baud), **PARAMS), name="b")
    link = Link(a, b, record_wire=False)
    link.power_on(0.0)
    link.run_until_quiet(1.0)
    n = 0
    c0, w0 = time.process_time(), time.perf_counter()
    while True:
        for _ in range(20):
            a.request(link.now, REQ)
            link.run_until_quiet(link.now + 100.0)
            n += 1
        if time.process_time() - c0 >= seconds:
            break
    cpu, wall = time.process_time() - c0, time.perf_counter() - w0
    assert _count_ok(link.events, "a") == n, "every request must succeed once"
    return n / cpu, n / wall, n


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=3.0)
    args = ap.parse_args()
    print("RK 512 model throughput, SEND of 1024 bytes to DB 10 (8 frames), one core")
    print(f"  {'':<46} {'per CPU second':>16} {'wall clock':>12}")
    runs = [("(a) RK 512 layers, ideal frame link", lambda: frame_link(args.seconds))]
    for label, baud in (("(b) stations over 3964R, no line timing", None),
                        ("(b) stations over 3964R, 9600 8E1", 9600)):
        runs.append((label, lambda baud=baud: full_stations(baud, args.seconds)))
    for label, run in runs:
        cpu, wall, n = run()
        print(f"  {label:<46} {cpu:>10,.0f} req/s {wall:>8,.0f} req/s  ({n} requests)")

if __name__ == "__main__":
    main()
