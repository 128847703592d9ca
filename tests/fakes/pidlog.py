"""Start an IUT and note its process id: ``pidlog.py PIDFILE COMMAND...`` appends this
process's id to PIDFILE and replaces itself by COMMAND (same process), so that a test can
check afterwards that no IUT outlived the harness."""
import os
import sys

with open(sys.argv[1], "a") as f:
    f.write(f"{os.getpid()}\n")
os.execvp(sys.argv[2], sys.argv[2:])
