"""Whether an RK 512 case can run against the IUT a profile describes: the roles and the
request script it needs, the memory it uses, what the profile declares about an open point
the case accepts either way, and whether its frames fit the IUT's T_RES (:mod:`.fit`)."""

from __future__ import annotations

from dataclasses import replace

from ptpcert.scenario import expand

from .fit import tres_shortfall
from .iut import script_lines

#: the link's attempt counts a case may need at least (``needs``), and why
_ATTEMPT_NEEDS = {"setup_attempts": "a crossing STX uses up the IUT's first setup attempt (Fig. 2-8 counts "
                                    "its next STX as the 2nd, open point A21): whether it tries again after it "
                                    "is open"}


def unsupported_reason(proc, vector, profile, capabilities, factory) -> str | None:
    """Why the case cannot run against the profile's IUT (None: it can)."""
    if profile is None:
        return None
    p = profile.params
    role = vector.iut_role
    if role in ("receiver", "both", "idle") and "passive" not in p.roles:
        return "tests the IUT in the passive role; the profile's [rk512] roles do not include \"passive\""
    if script_lines(vector) or role in ("sender", "both"):
        if "active" not in p.roles:
            return "tests the IUT in the active role; the profile's [rk512] roles do not include \"active\""
        if p.requests != "script":
            return "needs the IUT to run a request script; the profile has [rk512] requests = \"none\""
        if not getattr(factory, "virtual", False):
            from ptpcert.transport.base import SETUPS
            if SETUPS not in capabilities:
                return "needs the IUT started with a request script; this transport does not start the IUT"
            if "{requests}" not in getattr(factory, "command", "{requests}"):
                return "needs a request script; the IUT command has no {requests} to put its path in"
    needs = vector.extra.get("needs", {})
    for key in ("db_bytes", "byte_area_bytes", "cell_area_cells"):
        if key in needs and needs[key] > getattr(p, key):
            return f"needs {key} >= {needs[key]}; the profile's [rk512] has {getattr(p, key)}"
    for key, why in _ATTEMPT_NEEDS.items():
        if key in needs and needs[key] > getattr(p, key):
            return f"needs {key} >= {needs[key]} ({why}); the profile's [iut] has {getattr(p, key)}"
    if "expressible" in needs and needs["expressible"] in p.inexpressible_requests:
        return (f"needs a request with {needs['expressible']}; the profile's [rk512] inexpressible_requests "
                "says the IUT's request interface cannot express it")
    for key, rng in (("db", p.db_range), ("dx", p.dx_range)):
        for n in needs.get(key, []):
            if not rng or not rng[0] <= n <= rng[1]:
                return f"needs {key.upper()} {n}; the profile's [rk512] {key}_range is {list(rng)}"
    if needs.get("pattern") and p.memory != "pattern":
        return "needs the IUT's memory to start with the pattern ([rk512] memory = \"pattern\")"
    limit = p.cell_fetch_limit_bytes
    if limit is not None and needs.get("cell_fetch_bytes", 0) > limit:
        return (f"needs a partner FETCH of {needs['cell_fetch_bytes']} bytes of timers or counters served; the "
                f"profile's [rk512] cell_fetch_limit_bytes is {limit}")
    for key in needs.get("silent", []):   # a vector that accepts either reading of an open point
        value = getattr(p, key, None)
        if value is not None:
            shown = str(value).lower() if isinstance(value, bool) else value
            return (f"accepts either behaviour the manual allows where the profile is silent; the profile "
                    f"declares [rk512] {key} = {shown}, which the suite's cases require")
    return _tres_shortfall(proc, vector, p)


def _tres_shortfall(proc, vector, p) -> str | None:
    """The case's frames and pauses do not fit the IUT's T_RES at its baud rate
    (:mod:`.fit`)."""
    fixed = {name: getattr(vector.params, name) for name in vector.binds}
    try:
        params = p.with_(**fixed) if fixed else p
    except ValueError:
        params = p
    env = {**proc.timer_env(params), "CHAR": params.char_time, "STARTUP": 0.0}
    return tres_shortfall(expand(replace(vector, params=params)), params, env)
