"""The schema of an IUT profile's keys: for every key of a procedure's profile (in ``[iut]`` or
in a table of its own) its kind, the values the manual allows (choices, or a range in steps),
its default, the manual's table that sets it, and where it applies.

One schema serves three ends, so they cannot drift apart: the profile loader checks every
key's value against it (:func:`problem`, before the procedure checks the keys together), the
property tests draw profiles from it (:mod:`ptpcert.fuzz.profiles`), and the documentation
lists the keys from it. A procedure declares its keys
(:meth:`ptpcert.procedure.Procedure.profile_schema`); :data:`COMMON` are the keys every
procedure's ``[iut]`` table has.

A leaf of the import graph: standard library only.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Mapping

#: the default of a key that must be given
REQUIRED = object()

#: the kinds of value a key takes
KINDS = ("int", "number", "bool", "choice", "byte", "bytes", "pair", "subset", "str")


@dataclass(frozen=True)
class Key:
    """One key of a profile.

    ``kind``: ``int`` (``lo``..``hi`` in steps of ``step`` from ``lo``... or from 0 where
    ``step_from_zero``), ``number`` (a finite number ``lo``..``hi``), ``bool``, ``choice``
    (one of ``choices``), ``byte`` (a character code 0..255), ``bytes`` (a list of
    ``size[0]``..``size[1]`` character codes), ``pair`` (``[first, last]`` with
    ``lo <= first <= last <= hi``; ``[]`` too where ``size[0]`` is 0), ``subset`` (a
    non-empty list of distinct ``choices``; ``[]`` too where ``size[0]`` is 0), ``str``.
    ``when``: the key applies only where other keys of the profile have one of the given
    values (elsewhere it is ignored, as the parameter tool greys it out); a key that does not apply is still checked for its kind.
    """

    name: str
    table: str
    kind: str
    doc: str
    ref: str = ""
    default: Any = REQUIRED
    choices: tuple[Any, ...] = ()
    lo: float | None = None
    hi: float | None = None
    step: int = 1
    size: tuple[int, int] = (1, 1)
    unit: str = ""
    when: Mapping[str, tuple[Any, ...]] = field(default_factory=dict)
    #: the lowest value depends on another key: (that key, its value -> the lowest value
    #: where it rises above ``lo``), e.g. a timer's minimum at low baud rates
    floor: tuple[str, Mapping[Any, int]] | None = None

    def low(self, values: Mapping[str, Any]) -> float | None:
        """The lowest value allowed where the other keys have ``values``."""
        if self.floor is None:
            return self.lo
        other, by = self.floor
        return max(self.lo, by.get(values.get(other), self.lo))

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"key {self.name}: kind {self.kind!r} (allowed: {', '.join(KINDS)})")

    @property
    def required(self) -> bool:
        return self.default is REQUIRED

    @property
    def path(self) -> str:
        """``table.name`` as errors name the key."""
        return f"{self.table}.{self.name}"

    def applies(self, values: Mapping[str, Any]) -> bool:
        """Whether the key applies to a profile whose keys have ``values`` (by name; a key
        left out has its default)."""
        return all(values.get(k) in allowed for k, allowed in self.when.items())

    def domain(self) -> str:
        """The values allowed, in words."""
        unit = f" {self.unit}" if self.unit else ""
        if self.kind == "int":
            if self.step != 1:
                return f"{_num(self.lo)}..{_num(self.hi)}{unit} in steps of {self.step}{unit}"
            return f"an integer {_num(self.lo)}..{_num(self.hi)}{unit}"
        if self.kind == "number":
            return f"a number {_num(self.lo)}..{_num(self.hi)}{unit}"
        if self.kind == "bool":
            return "true or false"
        if self.kind == "choice":
            return "one of " + ", ".join(_show(c) for c in self.choices)
        if self.kind == "byte":
            return "a character code 0x00..0xFF"
        if self.kind == "bytes":
            n = f"{self.size[0]}" if self.size[0] == self.size[1] else f"{self.size[0]} to {self.size[1]}"
            return f"a list of {n} character codes 0x00..0xFF"
        if self.kind == "pair":
            empty = ", or [] for none" if self.size[0] == 0 else ""
            return f"[first, last] with {_num(self.lo)} <= first <= last <= {_num(self.hi)}{empty}"
        if self.kind == "subset":
            some = "a list" if self.size[0] == 0 else "a non-empty list"
            return f"{some} of " + ", ".join(_show(c) for c in self.choices) + " (each once)"
        return "a string"


def _num(v: float | None) -> str:
    return "-" if v is None else (str(int(v)) if float(v).is_integer() else str(v))


def _show(v: Any) -> str:
    return f'"{v}"' if isinstance(v, str) else str(v).lower() if isinstance(v, bool) else str(v)


def _is_int(v: Any) -> bool:
    return isinstance(v, int) and not isinstance(v, bool)


def problem(key: Key, value: Any) -> str | None:
    """What is wrong with ``value`` for ``key`` (one line, naming the allowed values and the
    manual's table), or None where it is allowed."""
    ok = True
    k = key.kind
    if k == "int":
        ok = (_is_int(value) and key.lo <= value <= key.hi
              and (key.step == 1 or (value - (key.lo if key.lo % key.step else 0)) % key.step == 0))
    elif k == "number":
        ok = (isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
              and key.lo <= value <= key.hi)
    elif k == "bool":
        ok = isinstance(value, bool)
    elif k == "choice":
        ok = any(value == c and type(value) is type(c) for c in key.choices)
    elif k == "byte":
        ok = _is_int(value) and 0 <= value <= 0xFF
    elif k == "bytes":
        ok = (isinstance(value, list) and key.size[0] <= len(value) <= key.size[1]
              and all(_is_int(v) and 0 <= v <= 0xFF for v in value))
    elif k == "pair":
        ok = (isinstance(value, list) and ((value == [] and key.size[0] == 0)
              or (len(value) == 2 and all(_is_int(v) for v in value) and key.lo <= value[0] <= value[1] <= key.hi)))
    elif k == "subset":
        ok = (isinstance(value, list) and (value or key.size[0] == 0) and len(set(map(repr, value))) == len(value)
              and all(any(v == c and type(v) is type(c) for c in key.choices) for v in value))
    elif k == "str":
        ok = isinstance(value, str)
    if ok:
        return None
    ref = f" ({key.ref})" if key.ref else ""
    if k == "choice":
        return f"{_shown(key, value)} is not allowed; allowed values: " + ", ".join(_show(c) for c in key.choices) + ref
    return f"{_shown(key, value)} is not allowed: {key.domain()}{ref}"


def missing(key: Key) -> str:
    """The message for a required key left out."""
    return f"missing ({'one of ' + ', '.join(map(str, key.choices)) if key.kind == 'choice' else 'required'})"


def _shown(key: Key, value: Any) -> str:
    if key.kind == "byte" and _is_int(value):
        return f"0x{value:02X}"
    if key.kind == "bytes" and isinstance(value, list):
        return "[" + ", ".join(f"0x{v:02X}" if _is_int(v) else repr(v) for v in value) + "]"
    return repr(value)


#: the [iut] keys every procedure's profile has (beside ``procedure``, which selects it)
COMMON: tuple[Key, ...] = (
    Key("send_trigger", "iut", "choice", "how the IUT can be made to send: it sends back every block it "
        "receives (echo), or nothing makes it send (none); a procedure may allow fewer",
        choices=("echo", "none")),
    Key("line_conditions", "iut", "choice", "whether the IUT reads line conditions (BREAK, a character "
        "with a parity or framing error) marked in-band as POSIX PARMRK marks them, over exec:/pty:",
        choices=("parmrk", "none")),
    Key("status_from_stderr", "iut", "bool", "whether the IUT prints each STATUS event it raises as a "
        "line 'STATUS 16#XXXX' on its standard error"),
    Key("timer_tolerance_ms", "iut", "number", "how much later than due an output that a timer of the "
        "IUT causes may come (the vendor's declared accuracy): widens only the late side of those windows",
        default=0, lo=0, hi=60_000, unit="ms"),
)


#: the optional ``[iut.identity]`` table: who made the IUT and which one it is, as a test
#: report names the implementation (ISO/IEC 9646's PICS); shown in every report, carried
#: in the evidence bundle. Free text each, none required.
IDENTITY: tuple[Key, ...] = (
    Key("vendor", "iut.identity", "str", "who makes the IUT", default=""),
    Key("product", "iut.identity", "str", "the IUT's product name or order number", default=""),
    Key("version", "iut.identity", "str", "the IUT's firmware or software version", default=""),
    Key("serial", "iut.identity", "str", "the serial number of the unit tested", default=""),
    Key("text", "iut.identity", "str", "anything else a reader of the certificate should know", default=""),
)
