"""A fake IUT that cannot start: it says why on stderr and exits with status 3."""
import sys

sys.stderr.write("fake IUT: cannot open its configuration\n")
sys.exit(3)
