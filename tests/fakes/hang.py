"""A fake IUT that sends its start-up NAK, then ignores its input, EOF and SIGTERM.
It writes its pid to the file named in argv[1] so that a test can check it was killed."""
import os
import signal
import sys
import time

signal.signal(signal.SIGTERM, signal.SIG_IGN)
with open(sys.argv[1], "a") as f:
    f.write(f"{os.getpid()}\n")
os.write(1, b"\x15")
while True:
    time.sleep(1)
