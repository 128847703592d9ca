"""The RK 512 IUT as the host drives it and as the vectors declare it: the station with the
application that reports as an RK 512 IUT does (:func:`iut_host`: STATUS lines, and
RESULT/FETCHED lines for its requests), a vector's request script (:func:`script_lines`)
and set-up as the host's arguments (:func:`setup_host_args`), and whether a line the IUT
reported is the one a vector expects (:func:`line_matches`).

The description (:mod:`.description`) builds its hosts, IUT commands and judgements of the
reports from these. The RK 512 model is imported inside the functions, so that loading the
description does not load it.
"""

from __future__ import annotations

from typing import Any


def iut_host(station, script="", **kw):
    """The RK 512 station with its application, reporting as an RK 512 IUT does: besides
    the STATUS lines, ``RESULT``/``FETCHED`` lines for the requests (``report_line``)."""
    from ptpcert.procedures.rk512.model import Rk512Host
    from ptpcert.procedures.rk512.model.events import RequestResult, interface_lines

    class Rk512IutHost(Rk512Host):
        def report_line(self, event) -> str | None:
            if isinstance(event, RequestResult):
                return "\n".join(interface_lines(event))
            return None

    return Rk512IutHost(station, script, **kw)


def script_lines(vector) -> list[str]:
    """The request-script lines of a vector (``extra.requests``)."""
    if vector is None:
        return []
    reqs = vector.extra.get("requests", [])
    if isinstance(reqs, str):
        reqs = reqs.splitlines()
    return [str(x) for x in reqs]


def setup_host_args(vector) -> dict[str, Any]:
    """The set-up of a vector as the host's arguments (cpu_stop, cf_set)."""
    from ptpcert.procedures.rk512.model import parse_cf_set
    out: dict[str, Any] = {"cpu_stop": False, "cf_set": []}
    if vector is None or vector.setup is None:
        return out
    name, args = vector.setup
    if name == "cpu_stop":
        out["cpu_stop"] = True
    elif name == "flag_set":
        byte, bit, ms = parse_cf_set(f"{args.get('flag', '')}@{args.get('reset_ms', 0)}")
        out["cf_set"] = [(byte, bit, ms)]
    return out


def line_matches(pattern: str, line: str) -> bool:
    """Whether the IUT's RESULT/FETCHED ``line`` is the expected ``pattern``: one of its
    alternatives (separated by `` || ``), blanks and case aside; an alternative ending in
    `` *`` accepts any hex data after its head."""
    for alt in pattern.split(" || "):
        alt = " ".join(alt.split()).upper()
        have = " ".join(line.split()).upper()
        if alt.endswith(" *"):
            head = alt[:-2]
            if have.startswith(head + " ") and all(c in "0123456789ABCDEF" for c in have[len(head) + 1:]):
                return True
        elif alt == have:
            return True
    return False
