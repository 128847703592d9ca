"""A fake IUT that floods the line with bytes as fast as it can.

    flood.py [--bytes N] [--random] [--seed S] [--chunk N]

After its start-up NAK it writes ``--bytes`` bytes in all (default: without end), letters
``A`` or, with ``--random``, random bytes (seeded, so a run can be repeated), ``--chunk``
bytes per write (default 4096). Then it waits for the end of its input, so that the
harness, not the fake, ends the case."""
import argparse
import os
import random
import sys

ap = argparse.ArgumentParser()
ap.add_argument("--bytes", type=int, default=0, help="bytes in all (0: without end)")
ap.add_argument("--random", action="store_true", help="random bytes instead of 'A'")
ap.add_argument("--seed", type=int, default=1)
ap.add_argument("--chunk", type=int, default=4096)
args, _ = ap.parse_known_args()   # the words of a profile setup (--buffer full) are ignored
rng = random.Random(args.seed)

os.write(1, b"\x15")
left = args.bytes if args.bytes > 0 else None
try:
    while left is None or left > 0:
        n = args.chunk if left is None else min(args.chunk, left)
        data = rng.randbytes(n) if args.random else b"A" * n
        os.write(1, data)
        if left is not None:
            left -= n
    while os.read(0, 4096):
        pass
except (BrokenPipeError, OSError):
    pass
sys.exit(0)
