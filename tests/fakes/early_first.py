"""A fake IUT that times out early on its first K starts, like a station whose process was
scheduled late on a loaded machine, and conforms from then on.

    early_first.py COUNTER_FILE K [ptpcert iut options...]

Each start appends a line to COUNTER_FILE; the first K starts run the reference
implementation as the ``cdt-half`` mutant (its receiver times out after half the CDT), the
later ones run it unbroken."""
import os
import sys

counter, k, rest = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
with open(counter, "a+") as f:
    f.seek(0)
    n = len(f.read().splitlines()) + 1
    f.write(f"{os.getpid()}\n")
args = [sys.executable, "-m", "ptpcert.cli", "iut", *rest]
if n <= k:
    args += ["--mutant", "cdt-half"]
os.execv(sys.executable, args)
