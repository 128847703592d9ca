"""Writing vectors as TOML files that load back unchanged.

:func:`dump_vector` formats the table of :meth:`ptpcert.scenario.vector.Vector.to_toml` as
a vector file: the top-level keys, the steps one inline table a line, then the tables of
parameters, expected outcome and procedure-specific data, after an optional comment
header. What it writes is stable to the byte: a fuzz finding is named by the hash of its
file and written for ``ptpcert run --vectors``, and the golden vectors a generator writes
are compared with the files committed; :func:`ptpcert.scenario.load.load_vector_text` reads
them back into the same vector. Only the small subset of TOML that vectors use is written.
"""

from __future__ import annotations

from typing import Any

from .vector import Vector


def _toml_value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'
    if isinstance(v, list):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{k} = {_toml_value(x)}" for k, x in v.items()) + " }"
    raise TypeError(type(v))


def dump_vector(vector: Vector, header: str = "") -> str:
    """The vector as a TOML file that :func:`load_vector` reads back unchanged."""
    d = vector.to_toml()
    lines = []
    if header:
        lines += ["# " + line if line else "#" for line in header.splitlines()]
        lines.append("")
    for key, value in d.items():
        if key in ("params", "tester_params", "expected", "steps", "extra"):
            continue
        lines.append(f"{key} = {_toml_value(value)}")
    lines.append("steps = [")
    for s in d["steps"]:
        lines.append(f"  {_toml_value(s)},")
    lines.append("]")
    for table in ("params", "tester_params", "expected", "extra"):
        if table in d:
            lines.append("")
            lines.append(f"[{table}]")
            for key, value in d[table].items():
                lines.append(f"{key} = {_toml_value(value)}")
    return "\n".join(lines) + "\n"
