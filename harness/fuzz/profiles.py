"""Profiles drawn from the profile schema (:mod:`ptpcert.schema`): a hypothesis strategy of
IUT profiles (as the dicts a profile file holds) for one procedure, every key the procedure
declares drawn within the values the schema allows, or left out to take its default. A key
added to a schema later is drawn without a change here.

The draws lean towards what a test can afford and a user is likely to write (short timers,
small areas) while still reaching every end of every range now and then. What the schema
allows key by key may still be refused as a whole (a CDT under the baud rate's minimum, XON
equal to XOFF): the property that uses these profiles accepts a refusal in one line, or
demands that the reference configured from the profile pass every case.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

from hypothesis import strategies as st

from ..schema import COMMON, Key


def _int(key: Key, small: int | None) -> st.SearchStrategy[int]:
    lo, hi, step = int(key.lo), int(key.hi), key.step
    first = lo if step == 1 or lo % step == 0 else lo + (step - lo % step)
    count = (hi - first) // step

    def at(i: int) -> int:
        return first + i * step
    near = st.integers(0, min(count, max(0, (small or 0) // step))).map(at) if small else st.nothing()
    ends = st.sampled_from(sorted({first, at(count)}))
    return st.one_of(near, near, near, ends, st.integers(0, count).map(at))


def value_of(key: Key, small: int | None = None) -> st.SearchStrategy[Any]:
    """A value the schema allows for ``key``; ``small``: most draws of an integer lie within
    this much of its lowest value."""
    k = key.kind
    if k == "int":
        return _int(key, small)
    if k == "number":
        return st.floats(key.lo, key.hi, allow_nan=False, allow_infinity=False)
    if k == "bool":
        return st.booleans()
    if k == "choice":
        return st.sampled_from(key.choices)
    if k == "byte":
        return st.integers(0, 0xFF)
    if k == "bytes":
        return st.lists(st.integers(0, 0xFF), min_size=key.size[0], max_size=key.size[1])
    if k == "pair":
        pair = st.tuples(st.integers(int(key.lo), int(key.hi)), st.integers(int(key.lo), int(key.hi))).map(
            lambda t: sorted(t))
        return st.one_of(st.just([]), pair) if key.size[0] == 0 else pair
    if k == "subset":
        return st.lists(st.sampled_from(key.choices), min_size=min(1, key.size[0]), max_size=len(key.choices),
                        unique=True)
    return st.text(max_size=20)


def _in_order(keys) -> list[Key]:
    """The keys, each after the keys its ``when`` and ``floor`` name (so that those are drawn
    first), otherwise in the schema's order."""
    by_name = {k.name: k for k in keys}
    out: list[Key] = []

    def visit(k: Key, path: tuple[str, ...] = ()) -> None:
        if k in out or k.name in path:
            return
        for dep in list(k.when) + ([k.floor[0]] if k.floor else []):
            if dep in by_name:
                visit(by_name[dep], path + (k.name,))
        out.append(k)
    for k in keys:
        visit(k)
    return out


def _defaults(proc) -> dict[str, Any]:
    return {k.name: k.default for k in proc.profile_schema() if not k.required}


#: how far above its lowest value a drawn integer usually lies, by unit: timers of a few
#: hundred ms keep runs short; areas of a few hundred bytes reach the edges of small memories
SMALL = {"ms": 500, "bytes": 300, "": 20}


@st.composite
def profile_dicts(draw, proc, *, setups: dict[str, str] | None = None, timer_tolerance: bool = False) -> dict:
    """A profile of ``proc`` as the tables of a profile file: ``[iut]`` with the procedure's
    name and every key of its schema (and the common ones), its own tables. ``setups``: the
    ``[iut.setups]`` the IUT offers (drawn in or out). Each optional key is left out now and
    then, to take its default."""
    raw: dict[str, dict[str, Any]] = {"iut": {"procedure": draw(st.sampled_from(proc.names))}}
    for t in proc.tables:
        raw[t] = {}
    for key in COMMON:
        if key.name == "send_trigger":
            raw["iut"][key.name] = draw(st.sampled_from(proc.send_triggers))
        elif key.name == "timer_tolerance_ms":
            if timer_tolerance and draw(st.booleans()):
                raw["iut"][key.name] = draw(st.integers(0, 50))
        else:
            raw["iut"][key.name] = draw(value_of(key))
    drawn: dict[str, Any] = {}
    for key in _in_order(proc.profile_schema()):
        # a key that applies only with another's value is drawn where it applies (a schema
        # lists it after the keys it depends on); an optional key is often left at its default
        if not key.required and (not key.applies({**_defaults(proc), **drawn}) or draw(st.booleans())):
            continue
        if key.floor is not None:   # its minimum depends on a key drawn before it
            key = replace(key, lo=key.low({**_defaults(proc), **drawn}))
        value = draw(value_of(key, SMALL.get(key.unit, SMALL[""])))
        drawn[key.name] = value
        raw.setdefault(key.table, {})[key.name] = value
    if setups and draw(st.booleans()):
        raw["iut"]["setups"] = dict(setups)
    return {t: v for t, v in raw.items() if v or t == "iut"}
