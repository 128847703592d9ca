"""A fake IUT that floods the line with bytes as fast as it can."""
import os

os.write(1, b"\x15")
while True:
    try:
        os.write(1, b"A" * 4096)
    except BrokenPipeError:
        break
