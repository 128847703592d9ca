"""A fake IUT that sends its start-up NAK, then dies on the first byte it receives."""
import os
import sys

os.write(1, b"\x15")
os.read(0, 1)
sys.stderr.write("fake IUT: crashing now\n")
sys.stderr.flush()
os._exit(3)
