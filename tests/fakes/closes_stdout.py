"""A fake IUT that sends its start-up NAK, closes its output (stdout) and keeps running
until its input ends."""
import os

os.write(1, b"\x15")
os.close(1)
while os.read(0, 4096):
    pass
