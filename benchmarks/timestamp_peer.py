"""A measuring peer for bench_harness.py: sends a NAK at start (so the harness sees it
start up), then echoes every byte at once and logs, per byte, when it arrived and when the
echo was written (CLOCK_MONOTONIC, shared by all processes of the machine)."""

import os
import select
import signal
import sys
import time


def main() -> None:
    log_path = sys.argv[1]
    port = sys.argv[2] if len(sys.argv) > 2 else None
    if port:
        import tty
        fd_in = fd_out = os.open(port, os.O_RDWR | os.O_NOCTTY)
        tty.setraw(fd_in)
    else:
        fd_in, fd_out = 0, 1
    rows = []
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(0))   # stopped by a port server: keep the log
    os.write(fd_out, b"\x15")
    try:
        while True:
            select.select([fd_in], [], [])
            data = os.read(fd_in, 4096)
            t_a = time.monotonic()
            if not data:
                break
            os.write(fd_out, data)
            t_s = time.monotonic()
            rows += [(t_a, t_s, b) for b in data]
    except OSError:
        pass
    finally:
        with open(log_path, "w") as f:
            for t_a, t_s, b in rows:
                f.write(f"{t_a:.9f} {t_s:.9f} {b}\n")


if __name__ == "__main__":
    main()
