"""A fake IUT that never says anything (no start-up NAK) and exits at EOF."""
import os
import sys

while os.read(0, 1024):
    pass
sys.exit(0)
