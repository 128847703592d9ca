"""The traceability matrix: every rule of a procedure's catalogue (:mod:`ptpcert.rules`) with
the cases and golden vectors that check it, for every setting of the IUT the rule applies to.

A *setting* is one IUT configuration the matrix is computed for (3964: procedure 3964 or
3964R, priority low or high, and a 7-bit character frame): the suite generated for it plus
the golden vectors that run under it. A testable rule is *checked* when, in every setting it
applies to, at least one case or vector cites it; it is *missing* otherwise. An untestable
rule (a reason in the catalogue) needs no case. ``ptpcert rules`` prints the matrix; ``--check``
ends with ``N rules, C checked, U untestable, M missing``.

The cases are handed in (the command line generates the suite); nothing here imports it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Iterable

from ptpcert.rules import Catalogue, Rule
from ptpcert.scenario import Vector

CHECKED, UNTESTABLE, MISSING = "checked", "untestable", "missing"
#: a testable rule that applies to none of the matrix's settings (e.g. a 3964-only rule in the
#: matrix of one 3964R IUT's profile): nothing to check there
NOT_APPLICABLE = "not applicable"


@dataclass(frozen=True)
class Setting:
    """One IUT configuration: a label for people and the values of the catalogue's dimensions
    (``procedure``, ``priority``, ``data_bits``)."""

    label: str
    values: dict[str, Any]


@dataclass
class Citation:
    """A case or vector that cites a rule: what it checks, and under which settings it runs."""

    id: str
    title: str
    source: str
    settings: list[str] = field(default_factory=list)


@dataclass
class Entry:
    """One rule's row of the matrix."""

    rule: Rule
    citations: list[Citation] = field(default_factory=list)
    applies: list[str] = field(default_factory=list)   # settings the rule applies to
    missing: list[str] = field(default_factory=list)   # ... where no case cites it

    @property
    def status(self) -> str:
        if not self.rule.testable:
            return UNTESTABLE
        if not self.applies and not self.citations:
            return NOT_APPLICABLE
        return MISSING if self.missing or not self.citations else CHECKED


@dataclass
class Matrix:
    catalogue: Catalogue
    settings: list[Setting]
    entries: list[Entry]
    #: (case id, rule id) pairs where a case cites an id the catalogue does not have
    unknown: list[tuple[str, str]] = field(default_factory=list)

    def count(self, status: str) -> int:
        return sum(1 for e in self.entries if e.status == status)

    @property
    def cited_untestable(self) -> list[Entry]:
        """Untestable rules that cases cite anyway (one of the two is wrong)."""
        return [e for e in self.entries if e.status == UNTESTABLE and e.citations]

    @property
    def ok(self) -> bool:
        return not (self.count(MISSING) or self.unknown or self.cited_untestable)

    def summary(self) -> str:
        na = self.count(NOT_APPLICABLE)
        return (f"{len(self.entries)} rules, {self.count(CHECKED)} checked, {self.count(UNTESTABLE)} untestable, "
                f"{self.count(MISSING)} missing" + (f", {na} not applicable here" if na else ""))

    def entry(self, rule_id: str) -> Entry:
        for e in self.entries:
            if e.rule.id == rule_id:
                return e
        raise KeyError(rule_id)


def runs_under(v: Vector, params: Any) -> bool:
    """A golden vector runs under an IUT with ``params`` when the parameters it binds agree
    (the others come from the profile)."""
    return all(getattr(v.params, name) == getattr(params, name) for name in v.binds)


def build(catalogue: Catalogue, suites: Iterable[tuple[Setting, list[Vector]]]) -> Matrix:
    """The matrix of ``catalogue`` from the cases of each setting (``suites``: the setting and
    every case and vector that runs under it)."""
    suites = list(suites)
    entries = {r.id: Entry(r) for r in catalogue}
    cites: dict[str, dict[str, Citation]] = {r.id: {} for r in catalogue}
    unknown: set[tuple[str, str]] = set()
    for setting, cases in suites:
        for v in cases:
            for rid in v.rules:
                if rid not in entries:
                    unknown.add((v.id, rid))
                    continue
                c = cites[rid].setdefault(v.id, Citation(v.id, v.title, v.source))
                if setting.label not in c.settings:
                    c.settings.append(setting.label)
    for rid, e in entries.items():
        e.citations = sorted(cites[rid].values(), key=lambda c: (not c.id.startswith("SUITE."), c.id))
        e.applies = [s.label for s, _ in suites if e.rule.applies_to(s.values)]
        if e.rule.testable:
            covered = {label for c in e.citations for label in c.settings}
            e.missing = [label for label in e.applies if label not in covered]
    return Matrix(catalogue, [s for s, _ in suites], list(entries.values()), sorted(unknown))


def render_text(m: Matrix, *, only_problems: bool = False, verbose: bool = True) -> str:
    """The matrix as text: per rule its status, reference, sentence, and the cases with what
    they check and where they run; then the summary line."""
    all_settings = [s.label for s in m.settings]
    lines = [f"{m.catalogue.title} rules ({m.catalogue.manual}): rule -> cases and vectors -> what is checked",
             "settings: " + " | ".join(all_settings), ""]
    for e in m.entries:
        r = e.rule
        problem = e.status == MISSING or (e.status == UNTESTABLE and e.citations)
        if only_problems and not problem:
            continue
        scope = f" [{r.scope()}]" if r.scope() else ""
        lines.append(f"{r.id}  {e.status}{scope}  ({r.ref})")
        if verbose:
            lines.append(f"    {r.text}")
            if r.readings:
                lines.append(f"    open points: {', '.join(r.readings)}")
        if e.status == UNTESTABLE:
            lines.append(f"    untestable: {r.untestable}")
            for c in e.citations:
                lines.append(f"    but cited by {c.id}: either the case or the catalogue is wrong")
        else:
            for c in e.citations:
                where = "" if set(e.applies) <= set(c.settings) else "   (" + ", ".join(c.settings) + ")"
                lines.append(f"    {c.id:<44} {c.title}{where}")
            if e.missing:
                lines.append("    MISSING: no case in " + ", ".join(e.missing))
        if verbose or problem:
            lines.append("")
    for case_id, rid in m.unknown:
        lines.append(f"{case_id} cites {rid}, which is not a rule of the {m.catalogue.title} catalogue")
    if m.unknown:
        lines.append("")
    lines.append(m.summary())
    return "\n".join(lines) + "\n"


def to_dict(m: Matrix) -> dict[str, Any]:
    """The matrix as plain data (JSON)."""
    return {
        "procedure": m.catalogue.procedure, "title": m.catalogue.title, "manual": m.catalogue.manual,
        "settings": [{"label": s.label, **s.values} for s in m.settings],
        "rules": [{
            "id": e.rule.id, "status": e.status, "reference": e.rule.ref, "text": e.rule.text,
            "provenance": e.rule.provenance, "role": e.rule.role, "scope": e.rule.scope(),
            "readings": list(e.rule.readings), "untestable": e.rule.untestable,
            "applies": e.applies, "missing": e.missing,
            "cases": [{"id": c.id, "title": c.title, "settings": c.settings} for c in e.citations],
        } for e in m.entries],
        "unknown": [{"case": c, "rule": r} for c, r in m.unknown],
        "summary": m.summary(),
    }
