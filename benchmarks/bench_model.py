"""Model throughput: complete block exchanges per second between two model stations in
virtual time, 64-byte payloads (3964R). Prints figures; asserts nothing.

    python benchmarks/bench_model.py [--seconds 3]

Two line models: "no line timing" (characters take no time: whole blocks arrive at one
instant) and "9600 8E1" (every character is a separate event 1.146 ms apart).
"""

from __future__ import annotations

import argparse
import time

from ptpcert.model import Params3964, Station3964
from ptpcert.model.events import Delivered
from ptpcert.model.link import Link


def exchanges_per_second(baud, seconds: float, payload: bytes) -> tuple[float, int]:
    a = Station3964(Params3964(baud_rate=baud, priority="low"), name="a")
    b = Station3964(Params3964(baud_rate=baud, priority="high"), name="b")
    link = Link(a, b, record_wire=False)
    link.power_on(0.0)
    link.run_until_quiet(1.0)
    n = 0
    t0 = time.perf_counter()
    while True:
        for _ in range(200):
            link.request(a, payload)
            link.run_until_quiet(link.now + 100.0)
            n += 1
        if time.perf_counter() - t0 >= seconds:
            break
    elapsed = time.perf_counter() - t0
    delivered = sum(1 for name, e in link.events if name == "b" and isinstance(e, Delivered))
    assert delivered == n, "every request must be delivered once"
    return n / elapsed, n


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=3.0)
    args = ap.parse_args()
    payload = bytes(range(0x20, 0x60))  # 64 bytes
    print("model throughput, 64-byte payloads, 3964R, one core")
    for label, baud in (("no line timing", None), ("9600 8E1 (per-character events)", 9600)):
        rate, n = exchanges_per_second(baud, args.seconds, payload)
        print(f"  {label:<34} {rate:>10,.0f} exchanges/s  ({n} exchanges)")


if __name__ == "__main__":
    main()
