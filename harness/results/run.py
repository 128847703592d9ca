"""The results of a run: :class:`RunResult`, the one object every view renders (the JSON
results are its own form; JUnit, HTML and the console summary are views of it,
:mod:`ptpcert.report`), with the run's counts, verdict and exit status and its distinct
deviations.

Part of :mod:`ptpcert.results`; it sits on the cases (:mod:`~ptpcert.results.cases`), their
signatures (:mod:`~ptpcert.results.failures`) and the reading checks
(:mod:`~ptpcert.results.reading`).
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass, field, fields
from pathlib import Path
from typing import Any

from ptpcert.results.cases import ERROR, FAIL, PASS, VERDICTS, XPASS, CaseResult
from ptpcert.results.failures import root_causes
from ptpcert.results.files import write_atomic
from ptpcert.results.reading import SCHEMA, ResultsError, cases_from_dict, check_run, read_document


@dataclass
class RunResult:
    """The results of one run: what ran against which IUT and profile, and each case's
    :class:`~ptpcert.results.cases.CaseResult`."""

    tool_version: str
    started: str
    finished: str = ""
    iut: str = ""
    #: the procedure, for people ("3964/3964R", "RK 512", "ASCII driver")
    procedure: str = ""
    profile: dict[str, Any] = field(default_factory=dict)
    profile_path: str = ""
    vector_set: str = ""
    vector_set_hash: str = ""
    cases: list[CaseResult] = field(default_factory=list)
    interrupted: bool = False
    wall_time: float = 0.0
    html_path: str = ""
    #: the harness's scheduling class for the run (:mod:`ptpcert.priority`), for people
    harness_scheduling: str = ""
    #: the IUT's identity from the profile's ``[iut.identity]`` (vendor, product, version,
    #: serial, text: those given), shown in every report
    iut_identity: dict[str, str] = field(default_factory=dict)
    #: ``ptpcert run --shard K/N``: "K/N" where the run is one shard of its selection (its
    #: vector set hash is then the whole selection's, the same in every shard)
    shard: str = ""
    #: ``ptpcert report --merge``: the shards ("K/N") or files the results were merged from
    merged_from: list[str] = field(default_factory=list)
    schema: str = SCHEMA
    #: the failures grouped by root cause (see :func:`root_causes`); empty while a run is
    #: under way (the views then compute them), filled in the JSON so that a re-rendered
    #: report shows the groups the run found
    root_causes: list[dict[str, Any]] = field(default_factory=list)

    def fill_missing(self, cases, verdict: str, message: str) -> None:
        """Every case of ``cases`` (vectors: id, title, reference, rule, group, iut_role,
        source) without a result gets one: ``verdict`` with ``message``."""
        done = {c.id for c in self.cases}
        for v in cases:
            if v.id not in done:
                self.cases.append(CaseResult(v.id, v.title, v.reference, v.rule, v.group, v.iut_role,
                                             verdict=verdict, message=message, source=v.source))

    def deviations(self) -> list[dict[str, Any]]:
        """The distinct deviations: the stored groups, or those of the cases as they stand."""
        return self.root_causes or root_causes(self.cases)

    def counts(self) -> dict[str, int]:
        out = {v: 0 for v in VERDICTS}
        for c in self.cases:
            out[c.verdict] = out.get(c.verdict, 0) + 1
        return out

    @property
    def verdict(self) -> str:
        n = self.counts()
        if n[FAIL] or n[XPASS]:
            return FAIL
        if n[ERROR] or self.interrupted:
            return ERROR
        return PASS

    def exit_status(self) -> int:
        v = self.verdict
        return 1 if v == FAIL else 2 if v == ERROR else 0

    # -- JSON -------------------------------------------------------------------------
    def to_dict(self) -> dict[str, Any]:
        d = asdict(self)
        d["root_causes"] = self.deviations()
        d["counts"] = self.counts()
        d["verdict"] = self.verdict
        return d

    def to_json(self) -> str:
        return json.dumps(self.to_dict(), indent=1)

    def write_json(self, path: str | Path) -> None:
        write_atomic(path, self.to_json())

    @classmethod
    def from_dict(cls, d: Any) -> "RunResult":
        """A results object from its JSON form (either schema). Raises :class:`ResultsError`
        naming the key and what is allowed, so that no saved file can make a view fail."""
        check_run(d, fields(cls))
        cases = cases_from_dict(d)
        fields_ = {k: v for k, v in d.items() if k in cls.__dataclass_fields__ and k != "cases"}
        fields_["schema"] = SCHEMA
        return cls(cases=cases, **fields_)

    @classmethod
    def read_json(cls, path: str | Path) -> "RunResult":
        """The results object a file holds. Raises :class:`ResultsError` naming the file and
        what is wrong in it."""
        data = read_document(path)
        try:
            return cls.from_dict(data)
        except ResultsError as exc:
            raise ResultsError(f"{path}: {exc}") from None
