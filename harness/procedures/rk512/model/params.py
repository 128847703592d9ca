"""Parameters of an RK 512 station (CP 341 manual §2.2.3, §2.3.2, §6.3.2).

:class:`Rk512Params` is frozen and validated on construction. Its fields are the keys of
the ``[rk512]`` table of an IUT profile, one to one, plus the link's own parameter set
(``line``, a :class:`~ptpcert.procedures.p3964.model.params.Params3964`: RK 512 uses 3964(R) with the same
parameters as stand-alone 3964(R), §2.3.2). Invalid settings raise
:class:`~ptpcert.model.errors.ParameterError` naming the field and the rule.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields, replace
from typing import Any

from ptpcert.model.errors import ParameterError
from ptpcert.procedures.p3964.model.params import Params3964

LINKS = ("3964R", "3964")
ROLES = ("passive", "active")
REQUEST_MODES = ("script", "none")
MEMORY_MODES = ("pattern", "unknown")
#: the invalid requests of the local checks (§6.3.2 Tables 6-4 to 6-6; Table 8-1 class 05,
#: Table 8-2 16#1E41) by name: a length over 1024 or of 0, DB 0, a coordination-flag bit over
#: 7, a CPU over 4, a SEND to the flags. A typed request interface may be unable to express
#: some of them (the profile's ``inexpressible_requests``).
INVALID_REQUESTS = ("len-1025", "len-0", "db-0", "flag-bit-8", "cpu-5", "send-to-flags")
_MAX_AREA = 65536
_LINE_FIELDS = frozenset(f.name for f in fields(Params3964) if f.init)


def default_response_time_ms(baud_rate: int | None) -> int:
    """T_RES when the profile gives none: 10 s at every rate, as the CP 341's prose gives it
    (§2.2.3 "Response message frame": "for 300 to 76800 bit/s the monitoring time is 10
    s"). Figs. 2-18/2-19 print "T_RES = 5 s (7 s, 10 s)" depending on the rate
    (:func:`figure_response_time_ms`): a partner may time out that early, so where a
    profile is silent the cases accept either (open point AMB-02)."""
    return 10000


def figure_response_time_ms(baud_rate: int | None) -> int:
    """The shortest T_RES a conforming partner may use where the profile gives none: the
    figures' "5 s (7 s, 10 s)" read as 5 s at 1200 bit/s and above, 7 s at 600 bit/s and
    10 s at 300 bit/s (open point AMB-02)."""
    if baud_rate is None or baud_rate >= 1200:
        return 5000
    return 7000 if baud_rate >= 600 else 10000


#: the characters of the shortest exchange a requester's T_RES must cover: the response's STX,
#: the DLE, the 4-byte response with DLE ETX and BCC, the DLE, and two characters' leeway
SHORTEST_RESPONSE_CHARS = 12


def shortest_response_ms(line: Params3964) -> int:
    """The shortest T_RES with which any request can be answered at the line's rate."""
    return math.ceil(1000 * SHORTEST_RESPONSE_CHARS * line.char_time)


def _int(name: str, v: Any, lo: int, hi: int) -> int:
    if not isinstance(v, int) or isinstance(v, bool) or not lo <= v <= hi:
        raise ParameterError(name, v, f"an integer {lo}..{hi}")
    return v


def _range(name: str, v: Any, allow_empty: bool) -> tuple[int, ...]:
    v = tuple(v) if isinstance(v, (list, tuple)) else v
    if v == () and allow_empty:
        return ()
    ok = (isinstance(v, tuple) and len(v) == 2
          and all(isinstance(x, int) and not isinstance(x, bool) for x in v)
          and 1 <= v[0] <= v[1] <= 255)
    if not ok:
        more = ", or [] for none" if allow_empty else ""
        raise ParameterError(name, v, f"[first, last] block numbers with 1 <= first <= last <= 255{more}")
    return v


@dataclass(frozen=True)
class Rk512Params:
    """One RK 512 station. Defaults are the manual's and the issue's profile example.

    * ``link``: the procedure below RK 512, "3964R" (the standard) or "3964" (no BCC: not
      excluded by the manual, open point AMB-27);
    * ``line``: the link's parameter set (priority, CDT, ADT, attempts, baud rate, character
      frame); built from ``link`` when not given, and it must agree with ``link``;
    * ``response_time_ms``: T_RES, the response monitoring time, on both sides (§2.2.3,
      Figs. 2-18/2-19); None: :func:`default_response_time_ms`;
    * ``roles``: the roles the station can be tested in ("passive": it serves SEND/FETCH;
      "active": it issues them);
    * ``requests``: how a tester makes it request ("script" or "none");
    * ``memory``: "pattern" (the start contents of :mod:`.memory`) or "unknown";
    * ``db_range``/``dx_range``: the DB and DX numbers that exist (inclusive; ``()``: no DX);
    * ``db_bytes``: the size of every DB/DX; ``byte_area_bytes``: the size of the M, E and
      A areas; ``cell_area_cells``: the number of timers and of counters (2 bytes each);
    * ``cell_fetch_limit_bytes``: the most bytes of timers or counters a partner's FETCH is
      served (a CP 341: 32, §6.3.2 "Providing data"); ``serves_dx_fetch``: whether a
      partner's FETCH from a DX is served (Table 6-10 lists no DX source). None: not
      declared, the readings of open point AMB-20 decide (cases accept both).
    * ``inexpressible_requests``: the invalid requests (of :data:`INVALID_REQUESTS`) the
      station's request interface cannot even express (a fact about its interface, not a
      parameter of the manual).
    """

    link: str = "3964R"
    line: Params3964 | None = None
    response_time_ms: int | None = None
    roles: tuple[str, ...] = ROLES
    requests: str = "script"
    memory: str = "pattern"
    db_range: tuple[int, ...] = (1, 199)
    dx_range: tuple[int, ...] = (1, 199)
    db_bytes: int = 512
    byte_area_bytes: int = 256
    cell_area_cells: int = 256
    cell_fetch_limit_bytes: int | None = None
    serves_dx_fetch: bool | None = None
    inexpressible_requests: tuple[str, ...] = ()
    # Derived, filled in by __post_init__.
    t_res: float = field(init=False, repr=False, compare=False)
    #: the shortest T_RES the IUT may have: ``t_res`` where the profile declares it, else
    #: the figures' value for the baud rate (AMB-02)
    t_res_min: float = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if self.link not in LINKS:
            raise ParameterError("link", self.link, "one of 3964R, 3964")
        if self.line is None:
            object.__setattr__(self, "line", Params3964(procedure=self.link))
        elif not isinstance(self.line, Params3964):
            raise ParameterError("line", self.line, "a Params3964")
        elif self.line.procedure != self.link:
            raise ParameterError("line", self.line.procedure,
                                 f"the link parameters' procedure must be the link, {self.link}")
        if self.line.data_bits != 8:
            raise ParameterError("line.data_bits", self.line.data_bits, "8: fixed for RK 512 (§2.3.2)")
        if self.response_time_ms is not None:
            _int("response_time_ms", self.response_time_ms, 10, 3_600_000)
        roles = tuple(self.roles) if isinstance(self.roles, (list, tuple)) else self.roles
        if (not isinstance(roles, tuple) or not roles or len(set(roles)) != len(roles)
                or any(r not in ROLES for r in roles)):
            raise ParameterError("roles", self.roles, "a non-empty list of passive, active")
        object.__setattr__(self, "roles", roles)
        if self.requests not in REQUEST_MODES:
            raise ParameterError("requests", self.requests, "one of script, none")
        if self.memory not in MEMORY_MODES:
            raise ParameterError("memory", self.memory, "one of pattern, unknown")
        object.__setattr__(self, "db_range", _range("db_range", self.db_range, allow_empty=False))
        object.__setattr__(self, "dx_range", _range("dx_range", self.dx_range, allow_empty=True))
        _int("db_bytes", self.db_bytes, 2, _MAX_AREA)
        if self.db_bytes % 2:
            raise ParameterError("db_bytes", self.db_bytes, "an even number of bytes (whole data words)")
        _int("byte_area_bytes", self.byte_area_bytes, 1, _MAX_AREA)
        _int("cell_area_cells", self.cell_area_cells, 1, _MAX_AREA // 2)
        if self.cell_fetch_limit_bytes is not None:
            _int("cell_fetch_limit_bytes", self.cell_fetch_limit_bytes, 2, 1024)
            if self.cell_fetch_limit_bytes % 2:
                raise ParameterError("cell_fetch_limit_bytes", self.cell_fetch_limit_bytes,
                                     "an even number of bytes (2 per timer or counter)")
        if self.serves_dx_fetch is not None and not isinstance(self.serves_dx_fetch, bool):
            raise ParameterError("serves_dx_fetch", self.serves_dx_fetch, "true or false")
        bad = tuple(self.inexpressible_requests) if isinstance(self.inexpressible_requests, (list, tuple)) else None
        if bad is None or len(set(bad)) != len(bad) or any(b not in INVALID_REQUESTS for b in bad):
            raise ParameterError("inexpressible_requests", self.inexpressible_requests,
                                 "a list of " + ", ".join(INVALID_REQUESTS) + " (each once)")
        object.__setattr__(self, "inexpressible_requests", bad)
        ms = self.response_time_ms
        if ms is not None and ms < shortest_response_ms(self.line):
            raise ParameterError("response_time_ms", ms, f"at least {shortest_response_ms(self.line)} ms at "
                                 f"{self.line.baud_rate or 'this'} bit/s: the shortest response (4 bytes) must "
                                 "arrive within T_RES (§2.2.3 Figs. 2-18, 2-19)")
        if ms is None:
            ms = default_response_time_ms(self.line.baud_rate)
        object.__setattr__(self, "t_res", ms / 1000.0)
        low = ms if self.response_time_ms is not None else min(ms, figure_response_time_ms(self.line.baud_rate))
        object.__setattr__(self, "t_res_min", low / 1000.0)

    def __getattr__(self, name: str) -> Any:
        # the link's parameters by their names (priority, cdt_ms, setup_attempts...), so that
        # a vector may bind them like a 3964R vector does
        if name in _LINE_FIELDS:
            return getattr(self.line, name)
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    # -- the link's timing, for drivers that see only this object --------------------------
    @property
    def char_time(self) -> float:
        return self.line.char_time

    @property
    def cdt(self) -> float:
        return self.line.cdt

    @property
    def adt(self) -> float:
        return self.line.adt

    @property
    def priority(self) -> str:
        return self.line.priority

    @property
    def procedure(self) -> str:
        return self.line.procedure

    def with_(self, **changes: Any) -> "Rk512Params":
        """A copy with some fields changed (re-validated). Changing ``link`` alone carries
        the line parameters over to the new procedure. The link's own parameters may be
        changed by their names too (``priority``, ``cdt_ms``...; ``procedure`` is the
        link)."""
        line_changes = {k: changes.pop(k) for k in list(changes) if k in _LINE_FIELDS}
        if "procedure" in line_changes:
            changes.setdefault("link", line_changes.pop("procedure"))
        if "link" in changes and "line" not in changes and self.line.procedure != changes["link"]:
            changes["line"] = self.line.with_(procedure=changes["link"])
        if line_changes:
            changes["line"] = changes.get("line", self.line).with_(**line_changes)
        return replace(self, **changes)

    def to_dict(self) -> dict[str, Any]:
        """The ``[rk512]`` profile table (the line parameters are not part of it)."""
        out = {}
        for f in fields(self):
            if f.init and f.name != "line":
                v = getattr(self, f.name)
                out[f.name] = list(v) if isinstance(v, tuple) else v
        for key in ("response_time_ms", "cell_fetch_limit_bytes", "serves_dx_fetch"):
            if out[key] is None:   # not declared: the manual's open reading stands
                del out[key]
        if not out["inexpressible_requests"]:
            del out["inexpressible_requests"]
        return out

    @classmethod
    def from_dict(cls, table: dict[str, Any], line: Params3964 | None = None) -> "Rk512Params":
        """From an ``[rk512]`` profile table (keys as the fields, ``line`` excepted) and the
        link's parameters (built from the ``[iut]`` table by the profile loader)."""
        known = {f.name for f in fields(cls) if f.init and f.name != "line"}
        unknown = sorted(set(table) - known)
        if unknown:
            raise ParameterError(unknown[0], table[unknown[0]], "not an [rk512] key; known: " + ", ".join(sorted(known)))
        data = dict(table)
        if line is not None:
            link = data.get("link", "3964R")
            if line.procedure != link:
                line = line.with_(procedure=link)
            data["line"] = line
        return cls(**data)
