"""The model pieces every procedure shares: the STATUS codes (Tables 8-1, 8-2), the events a
station reports, the serial line's settings, the model's errors and two stations wired back to
back in virtual time. Each procedure's own model (codec, parameters, readings of the open
points, transition table, station) is a package of its own under ``ptpcert.procedures``.
Standard library only; no clocks, no I/O."""
