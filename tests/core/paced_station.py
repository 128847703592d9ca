"""A station for the capture-timing tests: runs a command (the reference without pacing,
``ptpcert iut --baud 0``) and relays its output one byte per ``--gap-ms`` milliseconds, as
an implementation that writes to a pipe at its own pace (no baud rate) does. Its input goes
to the command unchanged. Usage: ``python paced_station.py --gap-ms 1 -- COMMAND...``."""

from __future__ import annotations

import os
import select
import subprocess
import sys
import time


def main(argv: list[str]) -> int:
    gap = float(argv[argv.index("--gap-ms") + 1]) / 1000.0
    cmd = argv[argv.index("--") + 1:]
    child = subprocess.Popen(cmd, stdin=subprocess.PIPE, stdout=subprocess.PIPE, bufsize=0)
    fin, fout = sys.stdin.fileno(), child.stdout.fileno()
    queue = bytearray()
    due = 0.0
    while True:
        timeout = None if not queue else max(0.0, due - time.monotonic())
        r, _, _ = select.select([fin, fout], [], [], timeout)
        if fin in r:
            data = os.read(fin, 65536)
            if not data:
                break
            child.stdin.write(data)
        if fout in r:
            data = os.read(fout, 65536)
            if not data:
                break
            if not queue:
                due = max(due, time.monotonic())
            queue += data
        now = time.monotonic()
        while queue and due <= now:
            os.write(1, queue[:1])
            del queue[:1]
            due = max(due + gap, now) if queue else now + gap
    child.kill()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
