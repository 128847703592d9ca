"""The manual's rules as data: one catalogue per procedure (the ``rules.toml`` of the
procedure's package, :meth:`ptpcert.procedure.Procedure.rules_file`), for the traceability
matrix.

A :class:`Catalogue` holds a procedure's :class:`Rule` s, each with a stable id (``3964.RX.BCC-CHECK``),
the manual's section, figure or table, one sentence in our own words, where it applies
(variant, priority, character frame), the open points it depends on, and - for the few rules
that a tester on the line cannot see - why it is untestable. Cases, vectors and the model's
transition table cite rule ids; ``ptpcert rules`` prints the matrix and checks that every
testable rule has a case (:mod:`ptpcert.traceability`). The catalogue also gives each open
point of the manual (``A1`` ...) in short, with the grade a case gives an IUT that takes
another defensible reading (:class:`Reading`; the full text is ``docs/readings.md``).

Standard library and the procedure registry only: the reports read it too.
"""

from __future__ import annotations

import re
import tomllib
from dataclasses import dataclass, field
from typing import Any, Iterable, Iterator

from .. import registry
from ..procedure import Procedure

#: the roles a rule may bind where a catalogue does not list its own (``roles = [...]``; the
#: 3964 ones); "any" is always allowed
ROLES = ("sender", "receiver", "idle", "any")
PROVENANCE = ("S", "F", "I", "O")
#: how a case grades an IUT that takes another reading of an open point than the model:
#: pass / non-strict / informational (accepted, with that grade); fail (the other reading is
#: a slip of the source, not defensible); profile (the profile states the value, e.g. a
#: default); none (no effect on the line)
READING_GRADES = ("pass", "non-strict", "informational", "fail", "profile", "none")
_ID = re.compile(r"^[0-9A-Z]+(\.[0-9A-Z][0-9A-Z\-]*)+$")
#: an open point is named as its procedure names it (3964: A1.., the ASCII driver: Q1.. and d_hold ...)
_READING = re.compile(r"^[A-Za-z][A-Za-z0-9_\-]*$")


class CatalogueError(ValueError):
    """A catalogue file is broken (a packaging or editing fault)."""


@dataclass(frozen=True)
class Rule:
    id: str
    ref: str
    text: str
    provenance: str
    role: str
    #: where the rule applies (and is checked): each dimension's allowed values
    applies: dict[str, tuple[Any, ...]] = field(default_factory=dict)
    readings: tuple[str, ...] = ()
    #: why the rule cannot be checked on the line; empty: it is checked
    untestable: str = ""
    notes: str = ""

    @property
    def testable(self) -> bool:
        return not self.untestable

    def applies_to(self, setting: dict[str, Any]) -> bool:
        """Whether the rule applies to an IUT with these settings (procedure, priority,
        data_bits; a dimension missing from ``setting`` matches). Where the setting holds
        several values of a dimension (the roles an IUT plays), the rule applies when the
        IUT has every value the rule lists (a rule of both roles needs both)."""
        for dim, values in self.applies.items():
            if dim not in setting:
                continue
            have = setting[dim]
            if isinstance(have, (list, tuple, set, frozenset)):
                if not set(values) <= set(have):
                    return False
            elif have not in values:
                return False
        return True

    def scope(self) -> str:
        """Where it applies, for people ("3964R only, priority low"); "" when everywhere."""
        parts = []
        for dim, values in self.applies.items():
            if dim == "procedure":
                parts.append(" and ".join(values) + " only")
            elif dim == "priority":
                parts.append("priority " + " and ".join(values))
            elif dim == "data_bits":
                parts.append(" and ".join(map(str, values)) + " data bits")
            else:
                parts.append(dim.replace("_", " ") + " " + " and ".join(map(str, values)))
        return ", ".join(parts)


@dataclass(frozen=True)
class Reading:
    """One open point of the manual, in short."""

    id: str
    question: str
    model: str          # the reading the reference model takes
    grade: str          # how a case grades an IUT that takes another defensible reading


@dataclass(frozen=True)
class Catalogue:
    procedure: str      # the procedure's id (ptpcert.procedure.Procedure.id)
    title: str
    prefix: str         # every rule id starts with it and a dot
    manual: str
    rules: tuple[Rule, ...]
    readings: dict[str, Reading] = field(default_factory=dict)
    #: the settings of an IUT a rule may be restricted to (profile keys) and their values
    dimensions: dict[str, tuple[Any, ...]] = field(default_factory=dict)
    #: the roles a rule may bind (the catalogue's ``roles``)
    roles: tuple[str, ...] = ROLES

    def __iter__(self) -> Iterator[Rule]:
        return iter(self.rules)

    def __len__(self) -> int:
        return len(self.rules)

    def __contains__(self, rule_id: object) -> bool:
        return rule_id in self._by_id

    @property
    def _by_id(self) -> dict[str, Rule]:
        cached = self.__dict__.get("_index")
        if cached is None:
            cached = {r.id: r for r in self.rules}
            object.__setattr__(self, "_index", cached)
        return cached

    def get(self, rule_id: str) -> Rule:
        try:
            return self._by_id[rule_id]
        except KeyError:
            raise KeyError(f"{rule_id!r} is not a rule of the {self.title} catalogue") from None

    def unknown(self, ids: Iterable[str]) -> list[str]:
        """The ids of ``ids`` that are not rules of this catalogue."""
        return [i for i in ids if i not in self._by_id]


EMPTY = Catalogue(procedure="", title="", prefix="", manual="", rules=())


def _list(raw: dict[str, Any], key: str, where: str) -> tuple:
    v = raw.get(key, [])
    if not isinstance(v, list):
        raise CatalogueError(f"{where}: {key} must be a list")
    return tuple(v)


def parse(raw: dict[str, Any], source: str = "<catalogue>") -> Catalogue:
    """A catalogue from its TOML table; every fault names the rule and the field."""
    for key in ("procedure", "title", "prefix", "manual"):
        if not isinstance(raw.get(key), str) or not raw[key]:
            raise CatalogueError(f"{source}: {key} missing")
    prefix = raw["prefix"]
    dims_raw = raw.get("dimensions", {})
    if not isinstance(dims_raw, dict) or any(not isinstance(v, (list, tuple)) or not v for v in dims_raw.values()):
        raise CatalogueError(f"{source}: [dimensions] is a table of profile key = [its values]")
    dimensions = {k: tuple(v) for k, v in dims_raw.items()}
    roles_raw = raw.get("roles", list(ROLES))
    if not isinstance(roles_raw, list) or not roles_raw or not all(isinstance(x, str) and x for x in roles_raw):
        raise CatalogueError(f"{source}: roles is a list of the roles a rule may bind")
    roles = tuple(dict.fromkeys([*roles_raw, "any"]))
    rules: list[Rule] = []
    seen: set[str] = set()
    readings_raw = raw.get("reading", {})
    for i, r in enumerate(raw.get("rule", [])):
        rid = r.get("id", "")
        where = f"{source}: rule[{i}] {rid}"
        if not isinstance(rid, str) or not _ID.match(rid) or not rid.startswith(prefix + "."):
            raise CatalogueError(f"{where}: id must be {prefix}.AREA.NAME in capitals")
        if rid in seen:
            raise CatalogueError(f"{where}: id used twice")
        seen.add(rid)
        unknown = set(r) - {"id", "ref", "text", "provenance", "role", "readings", "untestable", "notes",
                            *dimensions}
        if unknown:
            raise CatalogueError(f"{where}: unknown field {sorted(unknown)[0]}")
        for key in ("ref", "text", "provenance", "role"):
            if not isinstance(r.get(key), str) or not r[key].strip():
                raise CatalogueError(f"{where}: {key} missing")
        if not r["text"].rstrip().endswith("."):
            raise CatalogueError(f"{where}: text must be one sentence ending with a full stop")
        if r["role"] not in roles:
            raise CatalogueError(f"{where}: role {r['role']!r} (allowed: {', '.join(roles)})")
        if any(p not in PROVENANCE for p in r["provenance"].split()):
            raise CatalogueError(f"{where}: provenance is letters of {' '.join(PROVENANCE)}")
        applies = {}
        for dim, values in dimensions.items():
            if dim in r:
                got = _list(r, dim, where)
                if not got or any(v not in values for v in got):
                    raise CatalogueError(f"{where}: {dim} must list values of {values}")
                applies[dim] = got
        readings = _list(r, "readings", where)
        bad = [a for a in readings if a not in readings_raw]
        if bad:
            raise CatalogueError(f"{where}: reading {bad[0]} is not in the catalogue's [reading] tables")
        untestable = r.get("untestable", "")
        if not isinstance(untestable, str):
            raise CatalogueError(f"{where}: untestable must be the reason, a string")
        rules.append(Rule(rid, r["ref"].strip(), r["text"].strip(), r["provenance"], r["role"], applies,
                          readings, untestable.strip(), r.get("notes", "").strip()))
    readings: dict[str, Reading] = {}
    for rid, x in readings_raw.items():
        where = f"{source}: reading {rid}"
        if not _READING.match(rid):
            raise CatalogueError(f"{where}: open points are named by a letter and letters, digits, _ or - (A1, Q3, d_hold)")
        for key in ("question", "model", "grade"):
            if not isinstance(x.get(key), str) or not x[key]:
                raise CatalogueError(f"{where}: {key} missing")
        if x["grade"] not in READING_GRADES:
            raise CatalogueError(f"{where}: grade {x['grade']!r} (allowed: {', '.join(READING_GRADES)})")
        readings[rid] = Reading(rid, x["question"], x["model"], x["grade"])
    return Catalogue(raw["procedure"], raw["title"], prefix, raw["manual"], tuple(rules), readings, dimensions,
                     roles)


_CACHE: dict[str, Catalogue] = {}


def for_procedure(procedure: Procedure | str) -> Catalogue:
    """The catalogue of a procedure (its description, or its id such as ``p3964``), read once
    from its ``rules.toml``; :data:`EMPTY` where it has none."""
    proc = registry.by_id(procedure) if isinstance(procedure, str) else procedure
    cached = _CACHE.get(proc.id)
    if cached is not None:
        return cached
    entry = proc.rules_file()
    if entry is None:
        cat = EMPTY
    else:
        where = f"{proc.id}/{entry.name}"
        try:
            raw = tomllib.loads(entry.read_text("utf-8"))
        except tomllib.TOMLDecodeError as exc:
            raise CatalogueError(f"{where}: not valid TOML: {exc}") from None
        cat = parse(raw, where)
        if cat.procedure != proc.id:
            raise CatalogueError(f"{where}: procedure = {cat.procedure!r}, but the file is {proc.title}'s "
                                 f"(id {proc.id!r})")
    return _CACHE.setdefault(proc.id, cat)


def catalogues() -> tuple[Catalogue, ...]:
    """Every catalogue of the procedures ptpcert knows (one per procedure that has one)."""
    return tuple(c for c in (for_procedure(p) for p in registry.procedures()) if c is not EMPTY)


def for_rule(rule_id: str) -> Catalogue | None:
    """The catalogue a rule id belongs to (by its prefix), or None."""
    for c in catalogues():
        if rule_id.startswith(c.prefix + "."):
            return c
    return None


__all__ = ["Catalogue", "CatalogueError", "EMPTY", "READING_GRADES", "Reading", "Rule",
           "catalogues", "for_procedure", "for_rule", "parse"]
