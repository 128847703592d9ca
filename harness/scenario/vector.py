"""The vector data model: one test case as a timed two-party transcript.

A :class:`Vector` says who the IUT is (its role and start), which parameters apply, the
steps of the transcript (:class:`ptpcert.scenario.steps.Step`) and what must hold at the
end (:class:`Expected`: the STATUS events of either side, :class:`StatusSpec`, and the
blocks delivered and sent). Besides the data, this module holds what is computed from a
vector alone: its TOML table (:meth:`Vector.to_toml`, which
:func:`ptpcert.scenario.toml_out.dump_vector` formats), its digest and that of a set of
vectors (:func:`vector_set_hash`), the values of its timer names (:func:`timer_env`) and its
steps with the procedure's macro steps expanded (:func:`expand`). The procedure itself is
found through :mod:`ptpcert.registry`; building a vector from a TOML file, with checks, is
:mod:`ptpcert.scenario.load`'s job.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, field
from typing import Any, Iterable

from ..registry import by_id
from .hexnotation import vector_hex
from .steps import Step, unmarked_since

IUT_ROLES = ("receiver", "sender", "both", "idle")
STARTS = ("idle", "power-on")
#: capabilities any vector may require; a procedure adds its own (Procedure.requirements)
BASE_REQUIREMENTS = ("line_conditions", "restart")


@dataclass(frozen=True)
class StatusSpec:
    """Expected STATUS events: each entry of ``required`` is a set of alternatives of which
    at least one must be raised; anything raised must be in ``allowed``. Each entry of
    ``soft`` is what a conforming IUT raises under the reading the model takes of an open
    point of the manual: missing, it grades the case informational, never failed."""

    required: tuple[frozenset[int], ...] = ()
    optional: frozenset[int] = frozenset()
    soft: tuple[frozenset[int], ...] = ()

    @property
    def allowed(self) -> frozenset[int]:
        out = set(self.optional)
        for group in self.required + self.soft:
            out |= group
        return frozenset(out)

    def soft_missing(self, observed: Iterable[int]) -> list[str]:
        """The ``soft`` entries none of whose codes was raised."""
        seen = set(observed)
        return [" or ".join(f"16#{c:04X}" for c in sorted(g)) for g in self.soft if not g & seen]

    def judge(self, observed: Iterable[int]) -> list[str]:
        """Problems with ``observed`` (empty: acceptable)."""
        seen = list(observed)
        problems = []
        for group in self.required:
            if not group & set(seen):
                problems.append("missing " + " or ".join(f"16#{c:04X}" for c in sorted(group)))
        extra = sorted({c for c in seen if c not in self.allowed})
        if extra:
            problems.append("unexpected " + ", ".join(f"16#{c:04X}" for c in extra))
        return problems

    def to_toml(self) -> list[str]:
        return ["|".join(f"16#{c:04X}" for c in sorted(g)) for g in self.required]

    def describe(self) -> str:
        req = self.to_toml()
        s = ", ".join(req) if req else "none"
        if self.soft:
            s += " (by the model's reading of an open point also " + ", ".join(
                "|".join(f"16#{c:04X}" for c in sorted(g)) for g in self.soft) + ")"
        if self.optional:
            s += " (may also raise " + ", ".join(f"16#{c:04X}" for c in sorted(self.optional)) + ")"
        return s


@dataclass(frozen=True)
class Expected:
    iut_status: StatusSpec = StatusSpec()
    tester_status: StatusSpec = StatusSpec()
    delivered: tuple[bytes, ...] = ()   # blocks the IUT delivers to its application, in order
    sent: tuple[bytes, ...] = ()        # blocks the IUT's send jobs complete (DONE), in order
    echo_after: tuple[bytes, ...] = ()  # blocks an echo IUT sends back after the steps


@dataclass(frozen=True)
class Vector:
    id: str
    title: str
    reference: str
    rule: str
    group: str
    iut_role: str
    params: Any                          # the procedure's parameters
    steps: tuple[Step, ...]
    expected: Expected = Expected()
    start: str = "idle"
    requires: frozenset[str] = frozenset()
    readings: tuple[str, ...] = ()       # ambiguities (A-numbers) the vector depends on
    provenance: str = ""                 # [S] stated, [F] figure, [I] inferred, [O] open point
    notes: str = ""
    source: str = ""                     # file the vector was loaded from
    #: parameters the vector's bytes depend on; a profile must match them to run it
    binds: tuple[str, ...] = ("procedure",)
    #: tester-side parameters when they differ from the IUT's (e.g. configuration mismatch)
    tester_params: Any | None = None
    #: the case works close to a timer's edge: a failure is confirmed by a second run
    timing_sensitive: bool = False
    #: the procedure (its id, :attr:`ptpcert.procedure.Procedure.id`); see ptpcert.registry
    procedure: str = field(kw_only=True)
    #: the IUT setup the case needs (a name of [iut.setups] and its arguments), or None
    setup: tuple[str, dict[str, Any]] | None = None
    #: procedure-specific data (e.g. RK 512 requests and results), a TOML table
    extra: dict[str, Any] = field(default_factory=dict)
    #: ids of the manual's rules the vector checks (the procedure's catalogue, ptpcert.rules)
    rules: tuple[str, ...] = ()
    #: why the case cannot be built for the profile it was generated for ("" where it can):
    #: such a case stays in the suite, so that the report lists it as unsupported with the
    #: reason instead of leaving it out without a word; its steps are not run
    not_buildable: str = ""

    def __post_init__(self) -> None:
        i = unmarked_since(self.steps)
        if i is not None:
            raise ValueError(f"case {self.id}: steps[{i}] ({self.steps[i].kind}) measures since = \"mark\" but no "
                             "step before it sets mark = true")

    @property
    def proc(self):
        """The procedure's description (:class:`ptpcert.procedure.Procedure`)."""
        return by_id(self.procedure)

    @property
    def needs(self) -> frozenset[str]:
        """Capabilities the vector needs: declared plus those its steps imply."""
        out = set(self.requires)
        if any(s.kind in ("send_error", "break") for s in self.steps):
            out.add("line_conditions")
        if self.start == "power-on":
            out.add("restart")
        return frozenset(out)

    def digest(self) -> str:
        return hashlib.sha256(repr(self.to_toml()).encode()).hexdigest()[:12]

    # -------------------------------------------------------------- writing
    def to_toml(self) -> dict[str, Any]:
        d: dict[str, Any] = {
            "id": self.id, "title": self.title, "reference": self.reference, "rule": self.rule,
            "group": self.group, "iut_role": self.iut_role,
        }
        if self.start != "idle":
            d["start"] = self.start
        if self.requires:
            d["requires"] = sorted(self.requires)
        if self.rules:
            d["rules"] = list(self.rules)
        if self.readings:
            d["readings"] = list(self.readings)
        if self.provenance:
            d["provenance"] = self.provenance
        if self.notes:
            d["notes"] = self.notes
        if self.binds != ("procedure",):
            d["binds"] = list(self.binds)
        if self.timing_sensitive:
            d["timing_sensitive"] = True
        params = self.proc.params_table(self.params)
        if params.get("procedure") not in self.proc.names:   # the parameters do not name it
            d["procedure"] = self.proc.names[0]
        if self.setup is not None:
            name, args = self.setup
            d["setup"] = {"name": name, **args} if args else name
        d["params"] = params
        if self.tester_params is not None:
            d["tester_params"] = self.proc.params_table(self.tester_params)
        if self.extra:
            d["extra"] = dict(self.extra)
        e = self.expected
        exp: dict[str, Any] = {"iut_status": e.iut_status.to_toml()}
        if e.iut_status.optional:
            exp["iut_status_optional"] = [f"16#{c:04X}" for c in sorted(e.iut_status.optional)]
        if e.iut_status.soft:
            exp["iut_status_soft"] = ["|".join(f"16#{c:04X}" for c in sorted(g)) for g in e.iut_status.soft]
        exp["tester_status"] = e.tester_status.to_toml()
        if e.tester_status.optional:
            exp["tester_status_optional"] = [f"16#{c:04X}" for c in sorted(e.tester_status.optional)]
        for name in ("delivered", "sent", "echo_after"):
            v = getattr(e, name)
            if v:
                exp[name] = [vector_hex(x) for x in v]
        d["expected"] = exp
        d["steps"] = [s.to_toml() for s in self.steps]
        return d


def timer_env(vector: Vector, params: Any = None, startup: float = 0.0) -> dict[str, float]:
    """Values of the names in ``vector``'s time expressions, with ``params`` (default: the
    vector's own)."""
    env = dict(vector.proc.timer_env(vector.params if params is None else params))
    env["STARTUP"] = startup
    return env


def expand(vector: Vector) -> tuple[Step, ...]:
    """Replace the procedure's macro steps (e.g. ``prime``) by the send/expect steps they
    stand for."""
    out: list[Step] = []
    proc = vector.proc
    for s in vector.steps:
        if s.is_macro:
            out += proc.expand(s, vector.params)
        else:
            out.append(s)
    return tuple(out)


def vector_set_hash(vectors: Iterable[Vector]) -> str:
    """A short fingerprint of a set of vectors (their ids and digests, in any order): the
    results of a run record it, so that they say which vectors they were judged against."""
    h = hashlib.sha256()
    for v in sorted(vectors, key=lambda v: v.id):
        h.update(v.id.encode())
        h.update(v.digest().encode())
    return h.hexdigest()[:16]
